//! The normal-map mode end to end: `pointshade normalmap` (tp and physical presets, scene files),
//! `pointshade bake`, the tp preset's degenerate pixels, and bad input. The helpers the topics
//! share are here.
//!
//! The tp images are checked against an independent float64 evaluation of the report's formulas
//! (`tp`: it does not call the shader or the BRDF module). Tests that need ../shared/data are
//! ignored without it ("needs ../shared/data").

mod image_path;
mod images;
mod physical;
mod scene_files;
mod tp;

use crate::support::{self, Scratch};

use std::path::{Path, PathBuf};
use std::process::Output;

const BRDFS: [&str; 3] = ["lambert", "blinn-phong", "cook-torrance"];

fn shared_normal_map(name: &str) -> PathBuf {
    support::shared_data("normalmaps").join(name)
}

fn ok(args: &[&str]) -> Output {
    let out = support::pointshade(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `pointshade normalmap INPUT --preset PRESET --brdf BRDF -o OUT --quiet EXTRA…`, which must succeed.
fn shade(input: &Path, preset: &str, brdf: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "normalmap",
        s(input),
        "--preset",
        preset,
        "--brdf",
        brdf,
        "-o",
        s(out),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    ok(&args)
}

/// Runs `ARGS -o DIR/out.png`, which must fail as bad input does
/// ([`support::assert_input_error`]): one error line naming each of `expect`, exit code 2, no
/// output file and no temporary file left in `dir`.
fn fails(dir: &Scratch, args: &[&str], expect: &[&str]) {
    let out = dir.path("out.png");
    let mut all: Vec<&str> = args.to_vec();
    all.extend(["-o", s(&out)]);
    support::assert_input_error(&support::pointshade(&all), expect, &[&out]);
}
