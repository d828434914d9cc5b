//! `pointshade compare` on synthetic EXRs with known errors, NaN and Inf pixels, and bad input.

use crate::support::{self, Scratch};

use std::path::Path;

use glam::Vec3;
use pointshade::film::Image;
use pointshade::output::{encode, Format};

fn dir(name: &str) -> Scratch {
    Scratch::new(&format!("compare-{name}"))
}

fn write(path: &Path, values: &[f32], width: u32) {
    let img = Image {
        width,
        height: values.len() as u32 / width,
        pixels: values.iter().map(|&v| Vec3::splat(v)).collect(),
    };
    std::fs::write(path, encode(&img, Format::Exr, 0.0).unwrap()).unwrap();
}

fn run(args: &[&std::ffi::OsStr]) -> (Option<i32>, String, String) {
    let out = support::command().arg("compare").args(args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `exr` (whose data window starts at (0, 0)) with its dataWindow attribute saying
/// `width`×`height` (the attribute: name, type "box2i", size 16, then x_min, y_min, x_max, y_max
/// as little-endian i32).
fn with_data_window(exr: &[u8], width: i32, height: i32) -> Vec<u8> {
    let key = b"dataWindow\0box2i\0";
    let at = exr
        .windows(key.len())
        .position(|w| w == key)
        .expect("a dataWindow attribute")
        + key.len()
        + 4;
    let mut out = exr.to_vec();
    out[at + 8..at + 12].copy_from_slice(&(width - 1).to_le_bytes());
    out[at + 12..at + 16].copy_from_slice(&(height - 1).to_le_bytes());
    out
}

/// `compare OURS REFERENCE OPTION PATH`.
fn run_with(ours: &Path, reference: &Path, option: &str, path: &Path) -> (Option<i32>, String, String) {
    run(&[
        ours.as_os_str(),
        reference.as_os_str(),
        option.as_ref(),
        path.as_os_str(),
    ])
}

#[test]
fn reports_known_errors_and_non_finite_pixels_and_writes_a_heat_map() {
    let d = dir("known");
    let (ours, reference, heat) = (d.join("ours.exr"), d.join("ref.exr"), d.join("heat.png"));
    write(&ours, &[1.0, 2.0, f32::NAN, 4.0, 5.0, 6.5], 3);
    write(&reference, &[1.0, 2.0, 3.0, f32::INFINITY, 5.0, 6.0], 3);
    // By default a NaN is no match and no pixel to leave out: it is an error naming the image
    // (compare printed RMSE 0 and exit 0 for an image of NaN).
    let (code, stdout, stderr) = run_with(&ours, &reference, "--heatmap", &heat);
    assert_eq!(code, Some(2), "{stdout}");
    assert!(
        stderr.starts_with(&format!(
            "error: {}: 1 pixel(s) are not finite, the first at (2, 0): [NaN, NaN, NaN]",
            ours.display()
        )),
        "{stderr}"
    );
    assert!(!heat.exists(), "no heat map after an error");
    let (code, _, stderr) = run(&[reference.as_os_str(), reference.as_os_str()]);
    assert_eq!(code, Some(2));
    assert!(stderr.contains("the first at (0, 1): [inf, inf, inf]"), "{stderr}");
    // Counted as mismatches on request.
    let (code, stdout, stderr) = run(&[
        ours.as_os_str(),
        reference.as_os_str(),
        "--heatmap".as_ref(),
        heat.as_os_str(),
        "--count-non-finite".as_ref(),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("within 1e-3           50.0000%"), "{stdout}");
    assert!(
        stdout.contains("non-finite pixels     1 in ours, 1 in the reference"),
        "{stdout}"
    );
    // The worst finite pixel is (2, 1): 6.5 vs 6 → 1/12 relative.
    assert!(stdout.contains("(   2,    1): 8.333e-2"), "{stdout}");
    let h = image::open(&heat).unwrap().into_rgb8();
    assert_eq!(h.dimensions(), (3, 2));
    assert_eq!(h.get_pixel(2, 0).0, [255, 255, 255], "NaN pixel is white");
    assert_eq!(h.get_pixel(0, 0).0, [0, 0, 0], "exact pixel is black");
}

#[test]
fn size_mismatch_and_unreadable_files_are_one_line_errors() {
    let d = dir("bad");
    let (a, b, junk) = (d.join("a.exr"), d.join("b.exr"), d.join("junk.exr"));
    write(&a, &[1.0; 4], 2);
    write(&b, &[1.0; 6], 3);
    std::fs::write(&junk, b"not an image").unwrap();
    // A header whose data window claims 2^28 × 2^20 pixels: refused from the header, where the
    // decoder tried to allocate them and aborted the process (found by corrupting EXR bytes).
    let huge = d.join("huge.exr");
    std::fs::write(&huge, with_data_window(&std::fs::read(&a).unwrap(), 1 << 28, 1 << 20)).unwrap();
    for (x, y, expect) in [
        (&a, &b, "differs"),
        (&a, &junk, "junk.exr"),
        (&a, &d.join("missing.exr"), "missing.exr"),
        (&huge, &a, "huge.exr: its data window of 268435456×1048576 is too large"),
    ] {
        let (code, _, stderr) = run(&[x.as_os_str(), y.as_os_str()]);
        assert_eq!(code, Some(2));
        let lines: Vec<_> = stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{stderr}");
        assert!(lines[0].starts_with("error:") && lines[0].contains(expect), "{stderr}");
    }
}

#[test]
fn group_by_splits_the_squared_error_by_label_and_refuses_bad_label_images() {
    let d = dir("groups");
    let (ours, reference, counts) = (d.join("ours.exr"), d.join("ref.exr"), d.join("counts.exr"));
    write(&ours, &[1.0, 2.0, 3.5, 4.0], 2);
    write(&reference, &[1.0, 2.5, 3.0, 4.0], 2);
    // Pixels 0 and 3 took one sample, 1 and 2 sixteen: all the error is in the second group.
    write(&counts, &[1.0, 16.0, 16.0, 1.0], 2);
    let (code, stdout, stderr) = run_with(&ours, &reference, "--group-by", &counts);
    assert_eq!(code, Some(0), "{stderr}");
    let row = |value: &str| {
        stdout
            .lines()
            .map(|l| l.split_whitespace().collect::<Vec<_>>())
            .find(|f| f.len() == 4 && f[0] == value)
            .unwrap_or_else(|| panic!("no row for {value}: {stdout}"))
            .join(" ")
    };
    assert_eq!(row("1"), "1 2 0.0000e0 0.0%");
    assert_eq!(row("16"), "16 2 5.0000e-1 100.0%");
    let (small, ramp) = (d.join("small.exr"), d.join("ramp.exr"));
    write(&small, &[1.0, 16.0], 2);
    let values: Vec<f32> = (0..4 * 40).map(|i| i as f32).collect();
    write(&ramp, &values, 40);
    write(&ours, &[1.0; 160], 40);
    write(&reference, &[1.0; 160], 40);
    for (labels, expect) in [
        (&small, "differs"),
        (&ramp, "distinct values"),
        (&d.join("none.exr"), "none.exr"),
    ] {
        let (code, _, stderr) = run_with(&ours, &reference, "--group-by", labels);
        assert_eq!(code, Some(2), "{stderr}");
        let lines: Vec<_> = stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{stderr}");
        assert!(lines[0].starts_with("error:") && lines[0].contains(expect), "{stderr}");
    }
    // The 160 values of the ramp in two intervals, [0, 100) and [100, ∞).
    let edges = |text: &str| {
        let args = [
            ours.as_os_str(),
            reference.as_os_str(),
            "--group-by".as_ref(),
            ramp.as_os_str(),
        ];
        run(&[&args[..], &["--group-edges".as_ref(), text.as_ref()]].concat())
    };
    let (code, stdout, stderr) = edges("0,100");
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stdout.contains("  0        100") && stdout.contains("  100         60"),
        "{stdout}"
    );
    for bad in ["100,0", "0,x", "0,inf"] {
        let (code, _, stderr) = edges(bad);
        assert_eq!(code, Some(2), "{stderr}");
        assert!(
            stderr.starts_with("error: --group-edges") && stderr.lines().count() == 1,
            "{stderr}"
        );
    }
}
