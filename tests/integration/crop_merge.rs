//! Splitting a frame into crops and merging them gives exactly the single-machine render, byte
//! for byte, for fixed and adaptive sampling; bad crops are refused with one-line errors.

use crate::support::{self, Scratch};

use std::path::{Path, PathBuf};
use std::process::Output;

fn dir(name: &str) -> Scratch {
    Scratch::new(&format!("crops-{name}"))
}

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mixed-lights.toml")
}

fn ok(out: Output) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

fn render(sampling: &[&str], out: &Path, crop: Option<&str>) {
    let mut c = support::command();
    c.arg("render")
        .arg(scene())
        .arg("-o")
        .arg(out)
        .args(["--width", "96", "--height", "72", "--quiet"])
        .args(sampling);
    if let Some(crop) = crop {
        c.args(["--crop", crop]);
    }
    ok(c.output().unwrap());
}

fn four_crops_merge_to_the_full_render(sampling: &[&str], name: &str) {
    let d = dir(name);
    render(sampling, &d.join("full.exr"), None);
    render(sampling, &d.join("full.png"), None);
    // Uneven crops, not aligned with the 16-pixel tiles, listed out of order.
    let crops = ["0,0,41,30", "41,0,96,30", "0,30,70,72", "70,30,96,72"];
    let paths: Vec<PathBuf> = crops
        .iter()
        .enumerate()
        .map(|(k, _)| d.join(format!("crop{k}.exr")))
        .collect();
    for (c, p) in crops.iter().zip(&paths) {
        render(sampling, p, Some(c));
    }
    for ext in ["exr", "png"] {
        let merged = d.join(format!("merged.{ext}"));
        ok(support::command()
            .arg("merge")
            .args([&paths[2], &paths[0], &paths[3], &paths[1]])
            .arg("-o")
            .arg(&merged)
            .output()
            .unwrap());
        let (a, b) = (
            std::fs::read(d.join(format!("full.{ext}"))).unwrap(),
            std::fs::read(&merged).unwrap(),
        );
        assert!(a == b, "{name}: merged .{ext} differs from the full render");
    }
}

#[test]
fn crops_of_a_sobol_render_merge_byte_identically() {
    four_crops_merge_to_the_full_render(&["--sampler", "sobol", "--spp", "4"], "sobol");
}

#[test]
fn crops_of_a_one_sample_render_merge_byte_identically() {
    // One sample per pixel: a 4×4 block's camera rays share a packet, and crops cut blocks.
    four_crops_merge_to_the_full_render(&["--sampler", "sobol", "--spp", "1"], "one-sample");
}

#[test]
fn crops_of_an_adaptive_render_merge_byte_identically() {
    // Adaptive decisions read neighbouring pixels: the crops' aprons must make them identical.
    four_crops_merge_to_the_full_render(&["--sampler", "adaptive", "--spp", "16"], "adaptive");
    four_crops_merge_to_the_full_render(&["--sampler", "cells", "--spp", "64"], "cells");
}

/// Runs `args`, which must fail with one line ([`support::assert_one_line_error`]) containing
/// `expect` and write no `no_file`.
fn fails(args: &[&std::ffi::OsStr], expect: &str, no_file: &Path) {
    support::assert_one_line_error(&support::pointshade(args), &[expect], &[no_file]);
}

#[test]
fn bad_crops_and_merges_are_refused() {
    let d = dir("bad");
    let (a, b, c) = (d.join("a.exr"), d.join("b.exr"), d.join("c.exr"));
    render(&["--spp", "1"], &a, Some("0,0,60,72"));
    render(&["--spp", "1"], &b, Some("50,0,96,72"));
    render(&["--spp", "1"], &c, Some("60,0,96,40"));
    let out = d.join("out.exr");
    fails(
        &[
            "merge".as_ref(),
            a.as_os_str(),
            b.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        "overlaps",
        &out,
    );
    fails(
        &[
            "merge".as_ref(),
            a.as_os_str(),
            c.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        "uncovered",
        &out,
    );
    let junk = d.join("junk.exr");
    std::fs::write(&junk, b"no exr").unwrap();
    fails(
        &["merge".as_ref(), junk.as_os_str(), "-o".as_ref(), out.as_os_str()],
        "junk.exr",
        &out,
    );
    let s = scene();
    let png = d.join("x.png");
    fails(
        &[
            "render".as_ref(),
            s.as_os_str(),
            "-o".as_ref(),
            png.as_os_str(),
            "--crop".as_ref(),
            "0,0,10,10".as_ref(),
        ],
        "EXR",
        &png,
    );
    let exr = d.join("x.exr");
    for crop in ["0,0,0,10", "0,0,700,10", "1,2,3"] {
        fails(
            &[
                "render".as_ref(),
                s.as_os_str(),
                "-o".as_ref(),
                exr.as_os_str(),
                "--crop".as_ref(),
                crop.as_ref(),
            ],
            "crop",
            &exr,
        );
    }
}
