//! The HTTP API over a real socket: a server on a free port of 127.0.0.1, and a client that
//! writes requests by hand (so that it can also write the ones a browser would not).

use std::io::{Read, Write};
use std::net::TcpStream;

use super::*;
use crate::explore::state::NORMAL_MAP_MATERIAL;

/// Status, `Content-Type` and body of one request sent as `head` (with `Host`) and `body`.
fn send(address: SocketAddr, method: &str, path: &str, host: &str, body: &[u8]) -> (u16, String, Vec<u8>) {
    let mut stream = TcpStream::connect(address).unwrap();
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: {host}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes()).unwrap();
    // The server may answer (413) before reading all of a large body, and close.
    let _ = stream.write_all(body);
    let mut reply = Vec::new();
    let _ = stream.read_to_end(&mut reply);
    let split = reply.windows(4).position(|w| w == b"\r\n\r\n").expect("a header");
    let head = String::from_utf8_lossy(&reply[..split]).to_string();
    let status = head[9..12].parse().unwrap();
    let content_type = head
        .lines()
        .find_map(|l| l.strip_prefix("Content-Type: "))
        .unwrap_or("")
        .to_string();
    (status, content_type, reply[split + 4..].to_vec())
}

struct Running {
    server: Option<Server>,
    host: String,
}

impl Running {
    fn new() -> Running {
        Running::with(Explorer::open(None).unwrap())
    }

    fn with(explorer: Explorer) -> Running {
        let server = Server::start(explorer, 0).unwrap();
        let host = format!("127.0.0.1:{}", server.address().port());
        Running {
            server: Some(server),
            host,
        }
    }

    fn get(&self, path: &str) -> (u16, String, Vec<u8>) {
        self.request("GET", path, b"")
    }

    fn post(&self, path: &str, body: &str) -> (u16, String, Vec<u8>) {
        self.request("POST", path, body.as_bytes())
    }

    fn request(&self, method: &str, path: &str, body: &[u8]) -> (u16, String, Vec<u8>) {
        send(self.server.as_ref().unwrap().address(), method, path, &self.host, body)
    }

    fn state(&self) -> serde_json::Value {
        let (_, _, body) = self.get("/api/session");
        serde_json::from_slice::<serde_json::Value>(&body).unwrap()["state"].clone()
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.server.take().unwrap().stop();
    }
}

fn error_of(body: &[u8]) -> String {
    serde_json::from_slice::<serde_json::Value>(body).unwrap()["error"]
        .as_str()
        .unwrap()
        .to_string()
}

#[test]
fn it_listens_on_the_loopback_address_and_serves_the_page() {
    let r = Running::new();
    assert!(r.server.as_ref().unwrap().address().ip().is_loopback());
    let (status, content_type, body) = r.get("/");
    assert_eq!((status, content_type.as_str()), (200, "text/html; charset=utf-8"));
    assert!(String::from_utf8(body).unwrap().contains("explore.js"));
    let (status, _, body) = r.get("/api/session");
    assert_eq!(status, 200);
    let session: serde_json::Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(session["mode"], "normal-image");
    assert_eq!(session["state"]["preset"], "tp");
}

#[test]
fn render_evaluate_and_save() {
    let r = Running::new();
    let state = r.state().to_string();
    let (status, content_type, png) = r.post("/api/render", &state);
    assert_eq!(
        (status, content_type.as_str()),
        (200, "image/png"),
        "{}",
        String::from_utf8_lossy(&png)
    );
    assert!(png.starts_with(b"\x89PNG"));
    let material = r.state()["materials"][NORMAL_MAP_MATERIAL].clone();
    let request = serde_json::json!({"material": material, "preset": "tp", "theta_i": 30.0, "samples": 91});
    let (status, _, body) = r.post("/api/brdf", &request.to_string());
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    let curves: serde_json::Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(curves["theta_o"].as_array().unwrap().len(), 91);
    assert_eq!(curves["D"].as_array().unwrap().len(), 91);
    for path in ["/api/lobe", "/api/albedo", "/api/sphere"] {
        let (status, _, body) = r.post(path, &request.to_string().replace("\"samples\":91,", ""));
        assert_eq!(status, 200, "{path}: {}", String::from_utf8_lossy(&body));
    }
    let (status, _, text) = r.post("/api/save", &state);
    assert_eq!(status, 200);
    assert!(String::from_utf8(text).unwrap().contains("[normal_map]"));
}

#[test]
fn bad_requests_get_a_status_and_the_scene_files_message_and_the_server_goes_on() {
    let r = Running::new();
    let mut state = r.state();
    state["materials"][NORMAL_MAP_MATERIAL]["roughness"] = serde_json::json!(-1.0);
    let (status, _, body) = r.post("/api/render", &state.to_string());
    assert_eq!(status, 400);
    assert!(
        error_of(&body).contains("roughness must be in [0, 1]"),
        "{}",
        error_of(&body)
    );
    let (status, _, body) = r.post("/api/render", "{not json");
    assert_eq!(status, 400);
    assert!(error_of(&body).starts_with("state: "));
    let (status, _, _) = r.post("/api/brdf", r#"{"material": {}, "theta_i": 95}"#);
    assert_eq!(status, 400);
    let (status, _, _) = r.post("/api/sphere", r#"{"material": {}, "size": 100000}"#);
    assert_eq!(status, 400);
    assert_eq!(r.get("/api/render").0, 405);
    assert_eq!(r.get("/nothing").0, 404);
    let state = r.state().to_string();
    for (query, message) in [
        ("?spp=1", "a normal image is shaded once per pixel"),
        ("?spp=-1", "spp must be a whole number"),
        ("?file=/etc/passwd", "takes one query parameter, spp=N"),
    ] {
        let (status, _, body) = r.post(&format!("/api/render{query}"), &state);
        assert_eq!(status, 400, "{query}");
        assert!(error_of(&body).contains(message), "{query}: {}", error_of(&body));
    }
    assert_eq!(r.post("/api/render", &r.state().to_string()).0, 200);
}

#[test]
fn no_request_reads_a_file() {
    let r = Running::new();
    for path in [
        "/../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/api/../../etc/passwd",
        "/Cargo.toml",
    ] {
        let (status, _, body) = r.get(path);
        assert_eq!(status, 404, "{path}");
        assert!(!String::from_utf8_lossy(&body).contains("root:"), "{path}");
    }
    // A state that names a file: the image, a texture, a mesh. Each key is refused as a scene
    // file's section refuses it.
    let mut state = r.state();
    state["image"] = serde_json::json!("../../etc/passwd");
    let (status, _, body) = r.post("/api/render", &state.to_string());
    assert_eq!(status, 400);
    assert!(error_of(&body).contains("unknown field `image`"), "{}", error_of(&body));
    let mut state = r.state();
    state["materials"][NORMAL_MAP_MATERIAL]["normal_texture"] = serde_json::json!("/etc/passwd");
    for path in ["/api/render", "/api/save", "/api/python"] {
        let (status, _, body) = r.post(path, &state.to_string());
        assert_eq!(status, 400, "{path}");
        assert!(
            error_of(&body).contains("unknown field `normal_texture`"),
            "{path}: {}",
            error_of(&body)
        );
    }
}

#[test]
fn oversized_bodies_and_foreign_hosts_are_refused() {
    let r = Running::new();
    let big = vec![b' '; MAX_BODY + 1];
    assert_eq!(r.request("POST", "/api/render", &big).0, 413);
    let address = r.server.as_ref().unwrap().address();
    let (status, _, body) = send(address, "GET", "/api/session", "attacker.example:80", b"");
    assert_eq!(status, 403, "{}", String::from_utf8_lossy(&body));
    assert_eq!(r.get("/api/session").0, 200);
}

#[test]
fn many_requests_in_a_row_lose_nothing() {
    let r = Running::new();
    let state = r.state();
    let mut images = std::collections::BTreeMap::new();
    for i in 0..40 {
        let mut s = state.clone();
        let roughness = 0.05 + 0.02 * (i % 10) as f64;
        s["materials"][NORMAL_MAP_MATERIAL]["roughness"] = serde_json::json!(roughness);
        let (status, _, png) = r.post("/api/render", &s.to_string());
        assert_eq!(status, 200, "request {i}");
        let previous = images.insert(i % 10, png.clone());
        // The same state gives the same bytes every time.
        assert!(previous.is_none_or(|p| p == png), "request {i}");
    }
    assert_eq!(images.len(), 10);
    let distinct: std::collections::BTreeSet<_> = images.values().collect();
    assert_eq!(distinct.len(), 10);
}

/// A validation folder whose "Mitsuba" is a script that fails with `message`.
fn failing_mitsuba(dir: &std::path::Path, message: &str) {
    use std::os::unix::fs::PermissionsExt;
    let python = dir.join(".venv/bin/python");
    std::fs::create_dir_all(python.parent().unwrap()).unwrap();
    std::fs::write(&python, format!("#!/bin/sh\necho '{message}' >&2\nexit 1\n")).unwrap();
    std::fs::set_permissions(&python, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::write(dir.join("render.py"), "").unwrap();
}

#[test]
fn the_mitsuba_comparison_says_why_it_cannot_run_and_reports_mitsubas_failure() {
    let dir = std::env::temp_dir().join(format!("pointshade-explore-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let ask = |explorer: Explorer| {
        let r = Running::with(explorer);
        let (_, _, session) = r.get("/api/session");
        let session: serde_json::Value = serde_json::from_slice(&session).unwrap();
        let (status, _, body) = r.post("/api/mitsuba", &session["state"].to_string());
        (session["mitsuba"].clone(), status, body)
    };
    // Not installed: the session and the button say how to install it.
    let mut e = Explorer::open(None).unwrap();
    e.set_mitsuba_dir(dir.join("missing"));
    let (status_in_session, status, body) = ask(e);
    assert_eq!(status_in_session["available"], false);
    assert_eq!(status, 200);
    let answer: serde_json::Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(answer["available"], false);
    assert!(answer["message"].as_str().unwrap().contains("install.sh"), "{answer}");

    // Installed, but a normal image has no Mitsuba counterpart.
    failing_mitsuba(&dir, "no llvm here");
    let mut e = Explorer::open(None).unwrap();
    e.set_mitsuba_dir(dir.clone());
    let (_, _, body) = ask(e);
    let answer: serde_json::Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(
        (answer["available"].clone(), answer["installed"].clone()),
        (false.into(), true.into())
    );
    assert!(
        answer["message"].as_str().unwrap().contains("renders scenes"),
        "{answer}"
    );

    // A scene: Mitsuba's failure is a 400 with its last line, and no file is left behind.
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/validation/conductor-sphere.toml");
    let mut e = Explorer::open(Some(&scene)).unwrap();
    e.set_mitsuba_dir(dir.clone());
    let (status_in_session, status, body) = ask(e);
    assert_eq!(status_in_session["available"], true);
    assert_eq!(status, 400);
    assert!(
        error_of(&body).contains("Mitsuba failed: no llvm here"),
        "{}",
        error_of(&body)
    );
    let left = std::fs::read_dir(std::env::temp_dir())
        .unwrap()
        .filter_map(|e| e.ok())
        .any(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with(&format!("pointshade-explore-{}-", std::process::id()))
        });
    assert!(!left, "the comparison's folder is removed");
    std::fs::remove_dir_all(&dir).unwrap();
}
