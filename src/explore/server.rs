//! The explorer's local HTTP server: tiny_http (synchronous, a few small crates) on 127.0.0.1,
//! a few threads taking requests, each answered by `api::respond`.
//!
//! It is a public interface on the machine, so it binds the loopback address only, refuses a
//! `Host` other than its own address (a page elsewhere cannot reach it through a name that
//! resolves to 127.0.0.1), bounds request bodies (64 KiB) and answers every
//! bad request with a status and a message, never by stopping.

use std::io::{Read, Write};
use std::net::{Ipv4Addr, SocketAddr};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

use super::api::{respond, Reply, Shared, MAX_BODY};
use super::session::Explorer;
use crate::render::Workers;

/// Threads taking requests: a render may run while the plots of the same edit are asked for.
const THREADS: usize = 4;

/// A running explorer server.
pub struct Server {
    http: Arc<tiny_http::Server>,
    address: SocketAddr,
    stopping: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
}

impl Server {
    /// Serves `explorer` on 127.0.0.1:`port` (0: a free port the system picks).
    pub fn start(explorer: Explorer, port: u16) -> Result<Server, String> {
        let http = tiny_http::Server::http((Ipv4Addr::LOCALHOST, port))
            .map_err(|e| format!("cannot listen on 127.0.0.1:{port}: {e}"))?;
        let address = http.server_addr().to_ip().ok_or("the server has no IP address")?;
        let http = Arc::new(http);
        let shared = Arc::new(Shared::new(explorer));
        let stopping = Arc::new(AtomicBool::new(false));
        let log = std::env::var_os("POINTSHADE_EXPLORE_LOG").is_some();
        let threads = (0..THREADS)
            .map(|_| {
                let (http, shared, stopping) = (http.clone(), shared.clone(), stopping.clone());
                std::thread::spawn(move || serve(&http, &shared, &stopping, address, log))
            })
            .collect();
        Ok(Server {
            http,
            address,
            stopping,
            threads,
        })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://{}/", self.address)
    }

    /// Serves until the process ends.
    pub fn wait(self) {
        for t in self.threads {
            let _ = t.join();
        }
    }

    /// Stops taking requests (those being answered finish first) and waits for the threads.
    pub fn stop(self) {
        self.stopping.store(true, Ordering::SeqCst);
        for _ in &self.threads {
            self.http.unblock();
        }
        for t in self.threads {
            let _ = t.join();
        }
    }
}

/// Answers requests until the server stops; with `log`, prints each on standard error
/// (`POINTSHADE_EXPLORE_LOG`).
fn serve(http: &tiny_http::Server, shared: &Shared, stopping: &AtomicBool, address: SocketAddr, log: bool) {
    while !stopping.load(Ordering::SeqCst) {
        let Ok(mut request) = http.recv() else {
            continue;
        };
        let started = std::time::Instant::now();
        // On the process's workers, not on rayon's global pool directly: a server started in a
        // forked process (`Workers`) would wait for ever on its parent's threads.
        let reply = match Workers::new(None) {
            Ok(workers) => workers.install(|| answer(&mut request, shared, address)),
            Err(e) => Reply::error(500, e),
        };
        let ms = started.elapsed().as_secs_f64() * 1e3;
        if log {
            eprintln!(
                "{} {} -> {} ({} bytes) in {ms:.1} ms",
                request.method(),
                request.url(),
                reply.status,
                reply.body.len(),
            );
        }
        send(request, reply, ms);
    }
}

/// Writes `reply` with its length and `Connection: close`, so that the client closes the
/// connection once it has read it. tiny_http serves each connection on a thread of a pool that
/// grows only when no thread is idle at the moment a connection arrives; two arriving together
/// can queue the second behind a connection kept alive by the browser, and a page whose five
/// requests go out at once then waited for ever (seen in the browser test). With one request per
/// connection every thread is soon free again. (tiny_http drops a `Connection` header given to
/// its response builder, hence the hand-written head.) `Server-Timing` gives the milliseconds
/// the server took to answer, which the page records beside the time it saw.
fn send(request: tiny_http::Request, reply: Reply, ms: f64) {
    let reason = tiny_http::StatusCode(reply.status).default_reason_phrase();
    let head = format!(
        "HTTP/1.1 {} {reason}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nServer-Timing: answer;dur={ms:.1}\r\nConnection: close\r\n\r\n",
        reply.status,
        reply.content_type,
        reply.body.len()
    );
    let mut writer = request.into_writer();
    // A client that went away is no concern of the server's.
    let _ = writer
        .write_all(head.as_bytes())
        .and_then(|()| writer.write_all(&reply.body))
        .and_then(|()| writer.flush());
}

/// Checks the request's host and size, reads its body and answers it.
fn answer(request: &mut tiny_http::Request, shared: &Shared, address: SocketAddr) -> Reply {
    let host = request
        .headers()
        .iter()
        .find(|h| h.field.equiv("Host"))
        .map(|h| h.value.as_str().to_string());
    let own = [
        format!("127.0.0.1:{}", address.port()),
        format!("localhost:{}", address.port()),
    ];
    if !host.as_ref().is_some_and(|h| own.contains(h)) {
        return Reply::error(403, format!("Host {host:?} is not this server's ({})", own[0]));
    }
    if request.body_length().is_some_and(|n| n > MAX_BODY) {
        return Reply::error(413, format!("a request body is at most {MAX_BODY} bytes"));
    }
    let mut body = Vec::new();
    if let Err(e) = request.as_reader().take(MAX_BODY as u64 + 1).read_to_end(&mut body) {
        return Reply::error(400, format!("reading the request: {e}"));
    }
    if body.len() > MAX_BODY {
        return Reply::error(413, format!("a request body is at most {MAX_BODY} bytes"));
    }
    let method = request.method().as_str().to_string();
    respond(shared, &method, request.url(), &body)
}

#[cfg(test)]
mod tests;
