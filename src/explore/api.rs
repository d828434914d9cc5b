//! The explorer's HTTP API (docs/explore.md, "The HTTP API"): a request's method, path and body
//! in, a [`Reply`] out. The server (`server.rs`) reads requests and writes replies; nothing here
//! touches a socket, and nothing serves a file: the page is embedded, the scene held.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use serde::Deserialize;
use serde_json::{json, Value};

use super::plots::{albedo, direction, lit_sphere, lobe, polar};
use super::session::{Explorer, Mode};
use super::state::{Keys, State};

/// How long the Mitsuba comparison's Mitsuba may run (its first run compiles its kernels, a few
/// seconds; a preview-sized scene renders in well under one): a Mitsuba that hangs is stopped
/// and reported rather than holding a server thread for ever.
const MITSUBA_TIME_LIMIT: std::time::Duration = std::time::Duration::from_secs(120);

/// Largest request body accepted, in bytes: a state is a few kilobytes.
pub const MAX_BODY: usize = 64 * 1024;

const PAGE: &str = include_str!("page/index.html");
const SCRIPT: &str = include_str!("page/explore.js");
const STYLE: &str = include_str!("page/explore.css");

/// An answer: status, content type and body.
#[derive(Debug)]
pub struct Reply {
    /// HTTP status code.
    pub status: u16,
    /// `Content-Type`.
    pub content_type: &'static str,
    /// The body.
    pub body: Vec<u8>,
}

impl Reply {
    fn json(value: Value) -> Reply {
        Reply {
            status: 200,
            content_type: "application/json",
            body: value.to_string().into_bytes(),
        }
    }

    fn text(content_type: &'static str, text: impl Into<String>) -> Reply {
        Reply {
            status: 200,
            content_type,
            body: text.into().into_bytes(),
        }
    }

    fn png(body: Vec<u8>) -> Reply {
        Reply {
            status: 200,
            content_type: "image/png",
            body,
        }
    }

    /// `status` with `{"error": message}`.
    pub fn error(status: u16, message: impl std::fmt::Display) -> Reply {
        Reply {
            status,
            content_type: "application/json",
            body: json!({ "error": message.to_string() }).to_string().into_bytes(),
        }
    }
}

/// What every request shares: the session, and the stop flag of the render in flight (a newer
/// render request sets it, so that an edit cancels the render it makes stale).
pub struct Shared {
    explorer: Mutex<Explorer>,
    in_flight: Mutex<Option<Arc<AtomicBool>>>,
}

impl Shared {
    /// Shares `explorer` among the server's threads.
    pub fn new(explorer: Explorer) -> Shared {
        Shared {
            explorer: Mutex::new(explorer),
            in_flight: Mutex::new(None),
        }
    }

    fn explorer(&self) -> std::sync::MutexGuard<'_, Explorer> {
        // Every call checks its input before it changes the session: a panic leaves it whole.
        self.explorer.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// Answers one request.
pub fn respond(shared: &Shared, method: &str, url: &str, body: &[u8]) -> Reply {
    let path = url.split(['?', '#']).next().unwrap_or("");
    let result = match (method, path) {
        ("GET", "/") => Ok(Reply::text("text/html; charset=utf-8", PAGE)),
        ("GET", "/explore.js") => Ok(Reply::text("text/javascript; charset=utf-8", SCRIPT)),
        ("GET", "/explore.css") => Ok(Reply::text("text/css; charset=utf-8", STYLE)),
        ("GET", "/api/session") => Ok(session(shared)),
        ("GET", "/api/normals.png") => match shared.explorer().normals_png() {
            Some(png) => Ok(Reply::png(png.to_vec())),
            None => Err("a scene has no normal image".to_string()),
        },
        ("POST", "/api/render") => return render(shared, url, body),
        ("POST", "/api/save") => State::from_json(body).and_then(|s| {
            shared
                .explorer()
                .save(&s)
                .map(|t| Reply::text("text/plain; charset=utf-8", t))
        }),
        ("POST", "/api/python") => State::from_json(body).and_then(|s| {
            shared
                .explorer()
                .python(&s)
                .map(|t| Reply::text("text/plain; charset=utf-8", t))
        }),
        ("POST", "/api/pixel") => pixel(shared, body),
        ("POST", "/api/brdf" | "/api/lobe" | "/api/albedo" | "/api/sphere") => plot(path, body),
        ("POST", "/api/mitsuba") => mitsuba(shared, body),
        (_, "/" | "/explore.js" | "/explore.css" | "/api/session" | "/api/normals.png") => {
            return Reply::error(405, format!("{path} takes GET"));
        }
        (_, "/api/render" | "/api/save" | "/api/python" | "/api/pixel" | "/api/mitsuba")
        | (_, "/api/brdf" | "/api/lobe" | "/api/albedo" | "/api/sphere") => {
            return Reply::error(405, format!("{path} takes POST"));
        }
        _ => {
            return Reply::error(
                404,
                format!("{path}: not found (the explorer serves its page and its API, no files)"),
            )
        }
    };
    result.unwrap_or_else(|e| Reply::error(400, e))
}

fn session(shared: &Shared) -> Reply {
    let explorer = shared.explorer();
    let (width, height) = explorer.size();
    Reply::json(json!({
        "mode": match explorer.mode() { Mode::NormalImage => "normal-image", Mode::Scene => "scene" },
        "name": explorer.name(),
        "width": width,
        "height": height,
        "spp": explorer.spp(),
        "state": explorer.initial_state(),
        "presets": explorer.preset_states(),
        "keys": super::keys::schema(),
        "mitsuba": super::mitsuba::status(&explorer),
    }))
}

/// `?spp=N` of a render request: a progressive preview's pass at N samples per pixel.
fn pass_spp(url: &str) -> Result<Option<u32>, String> {
    let Some((_, query)) = url.split_once('?') else {
        return Ok(None);
    };
    let query = query.split('#').next().unwrap_or("");
    match query.split_once('=') {
        Some(("spp", n)) => n
            .parse::<u32>()
            .map(Some)
            .map_err(|_| format!("spp must be a whole number of samples per pixel, got '{n}'")),
        _ if query.is_empty() => Ok(None),
        _ => Err(format!("/api/render takes one query parameter, spp=N; got '{query}'")),
    }
}

fn render(shared: &Shared, url: &str, body: &[u8]) -> Reply {
    let (state, spp) = match State::from_json(body).and_then(|s| Ok((s, pass_spp(url)?))) {
        Ok(s) => s,
        Err(e) => return Reply::error(400, e),
    };
    let stop = Arc::new(AtomicBool::new(false));
    if let Some(older) = shared
        .in_flight
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .replace(stop.clone())
    {
        older.store(true, Ordering::Relaxed);
    }
    let mut explorer = shared.explorer();
    if stop.load(Ordering::Relaxed) {
        return Reply::error(409, "cancelled: a newer render was asked for");
    }
    match explorer.render(&state, spp, Some(&stop)) {
        Ok(png) => Reply::png(png),
        Err(_) if stop.load(Ordering::Relaxed) => Reply::error(409, "cancelled: a newer render was asked for"),
        Err(e) => Reply::error(400, e),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PixelRequest {
    state: State,
    x: u32,
    y: u32,
}

fn pixel(shared: &Shared, body: &[u8]) -> Result<Reply, String> {
    let r: PixelRequest = serde_json::from_slice(body).map_err(|e| format!("pixel request: {e}"))?;
    shared.explorer().pixel(&r.state, r.x, r.y).map(Reply::json)
}

/// A plot request: one material's keys and the incidence (degrees); sizes bounded.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlotRequest {
    material: Keys,
    #[serde(default)]
    preset: Option<String>,
    #[serde(default)]
    theta_i: f64,
    #[serde(default)]
    phi_i: f64,
    #[serde(default = "default_samples")]
    samples: usize,
    #[serde(default = "default_theta_steps")]
    theta_steps: usize,
    #[serde(default = "default_phi_steps")]
    phi_steps: usize,
    #[serde(default = "default_size")]
    size: u32,
}

fn default_samples() -> usize {
    181
}
fn default_theta_steps() -> usize {
    32
}
fn default_phi_steps() -> usize {
    64
}
fn default_size() -> u32 {
    256
}

/// Answers a plot request; it needs no session (the material's keys are all it reads), so plots
/// never wait for a render.
fn plot(path: &str, body: &[u8]) -> Result<Reply, String> {
    let r: PlotRequest = serde_json::from_slice(body).map_err(|e| format!("{path}: {e}"))?;
    if !(r.theta_i.is_finite() && (0.0..=90.0).contains(&r.theta_i) && r.phi_i.is_finite()) {
        return Err(format!(
            "theta_i must be in [0, 90] degrees and phi_i finite, got {} and {}",
            r.theta_i, r.phi_i
        ));
    }
    if !(2..=1441).contains(&r.samples) || !(1..=180).contains(&r.theta_steps) || !(3..=360).contains(&r.phi_steps) {
        return Err("samples must be in [2, 1441], theta_steps in [1, 180], phi_steps in [3, 360]".into());
    }
    if !(8..=1024).contains(&r.size) {
        return Err(format!("size must be in [8, 1024] pixels, got {}", r.size));
    }
    let material = super::keys::material(&r.material, r.preset.as_deref())?;
    let wi = direction(r.theta_i, r.phi_i);
    Ok(match path {
        "/api/brdf" => {
            let c = polar(&material, wi, r.samples);
            let (d, g, f) = match c.terms {
                Some(t) => (json!(t.d), json!(t.g), json!(t.f)),
                None => (Value::Null, Value::Null, Value::Null),
            };
            Reply::json(json!({
                "theta_o": c.theta_o, "f_r": c.f_r, "f_r_cos": c.f_r_cos, "D": d, "G": g, "F": f,
            }))
        }
        "/api/lobe" => Reply::json(json!({
            "theta_steps": r.theta_steps, "phi_steps": r.phi_steps,
            "f_r": lobe(&material, wi, r.theta_steps, r.phi_steps),
        })),
        "/api/albedo" => {
            let theta: Vec<f64> = (0..=18).map(|i| 5.0 * i as f64).collect();
            let a = albedo(&material, &theta);
            Reply::json(json!({ "theta_i": theta, "albedo": a }))
        }
        _ => Reply::png(lit_sphere(&material, wi, r.size)?),
    })
}

/// The Mitsuba comparison of a state ([`super::mitsuba`]); where it cannot run, the reason
/// (`available: false`), as the session reports it. The session is held only to read the edited
/// scene: renders go on while Mitsuba runs.
fn mitsuba(shared: &Shared, body: &[u8]) -> Result<Reply, String> {
    let state = State::from_json(body)?;
    let (scene, runner) = {
        let explorer = shared.explorer();
        let Ok(runner) = super::mitsuba::runner(&explorer) else {
            return Ok(Reply::json(super::mitsuba::status(&explorer)));
        };
        (explorer.edited_scene(&state)?, runner.with_timeout(MITSUBA_TIME_LIMIT))
    };
    super::mitsuba::compare(&runner, &scene, &state).map(Reply::json)
}
