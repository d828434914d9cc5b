//! The classes a hostile pass over the command line found (issue 42), each through the binary as
//! a user meets it: what crashed, hung, lost a file or called a difference a match.

use crate::support::{self, pointshade, Scratch};

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("hostile-{name}"))
}

/// Runs `args`, which must fail as bad input does ([`support::assert_input_error`]) with the
/// error line containing each of `expect`.
fn fails(args: &[&std::ffi::OsStr], expect: &[&str]) -> String {
    support::assert_input_error(&pointshade(args), expect, &[])
}

fn os<S: AsRef<std::ffi::OsStr> + ?Sized>(s: &S) -> &std::ffi::OsStr {
    s.as_ref()
}

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/lambert.toml")
}

fn render(out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        os("render"),
        scene().into_os_string().leak(),
        os("-o"),
        os(out),
        os("--quiet"),
    ];
    args.extend(extra.iter().map(os));
    pointshade(&args)
}

#[test]
fn a_fan_of_thirty_thousand_triangles_renders() {
    // It overflowed the stack in the BVH's collapse (exit 134), after seconds of building.
    let d = scratch("fan");
    let n = 30_000;
    let mut obj = String::from("v 0 0 0\n");
    for k in 0..=n {
        let a = std::f64::consts::PI * k as f64 / n as f64;
        obj += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for k in 0..n {
        obj += &format!("f 1 {} {}\n", k + 2, k + 3);
    }
    std::fs::write(d.join("fan.obj"), obj).unwrap();
    let out = pointshade(&[
        os("render"),
        os(&d.join("fan.obj")),
        os("-o"),
        os(&d.join("fan.png")),
        os("--width"),
        os("64"),
        os("--height"),
        os("48"),
        os("--quiet"),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn an_aov_that_cannot_be_written_replaces_no_output() {
    let d = scratch("aov");
    let image = d.join("o.exr");
    std::fs::write(&image, b"old image").unwrap();
    std::fs::write(d.join("o.normal.exr"), b"old normals").unwrap();
    std::fs::create_dir(d.join("o.depth.exr")).unwrap();
    let out = render(&image, &["--width", "16", "--height", "12", "--aov", "normal,depth"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("o.depth.exr: cannot write: it is a directory"));
    assert_eq!(std::fs::read(&image).unwrap(), b"old image");
    assert_eq!(std::fs::read(d.join("o.normal.exr")).unwrap(), b"old normals");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 3, "no temporary left");
}

#[test]
fn a_film_larger_than_memory_is_refused_before_it_renders() {
    // 65536 × 4096 with three AOVs needs about 47 GB: refused at once, where it rendered for
    // minutes and aborted on a failed allocation.
    let d = scratch("memory");
    let e = fails(
        &[
            os("render"),
            os(&scene()),
            os("-o"),
            os(&d.join("big.exr")),
            os("--width"),
            os("65536"),
            os("--height"),
            os("4096"),
            os("--spp"),
            os("1"),
            os("--aov"),
            os("normal,depth,albedo"),
        ],
        &["a 65536×4096 film with 3 AOV(s) needs about 47.24 GB at its peak, more than the"],
    );
    assert!(e.contains("GB available") || e.contains("address-space limit"), "{e}");
}

#[test]
fn too_many_threads_are_refused() {
    let d = scratch("threads");
    let out = render(&d.join("x.png"), &["--threads", "100000"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--threads: 100000 is more than"));
}

#[test]
fn devices_and_fifos_are_refused_wherever_a_file_is_named() {
    let d = scratch("fifo");
    let fifo = d.join("pipe.obj");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let fifo_text = fifo.display().to_string();
    // As the mesh, as a texture of an MTL, and as a glTF buffer: each read would block.
    fails(
        &[os("render"), os(&fifo), os("-o"), os(&d.join("a.png"))],
        &["pipe.obj: cannot read: it is a FIFO, not a regular file"],
    );
    fails(
        &[os("render"), os("/dev/zero"), os("-o"), os(&d.join("a.png"))],
        &["/dev/zero"],
    );
    let zero_scene = d.join("zero.toml");
    std::fs::write(&zero_scene, "[[object]]\nmesh = \"/dev/zero\"\n").unwrap();
    fails(
        &[os("render"), os(&zero_scene), os("-o"), os(&d.join("a.png"))],
        &["/dev/zero"],
    );
    std::fs::write(d.join("m.mtl"), format!("newmtl m\nKd 1 1 1\nmap_Kd {fifo_text}\n")).unwrap();
    std::fs::write(
        d.join("tri.obj"),
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    fails(
        &[os("render"), os(&d.join("tri.obj")), os("-o"), os(&d.join("a.png"))],
        &["a FIFO"],
    );
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": fifo_text, "byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}]
    });
    std::fs::write(d.join("a.gltf"), gltf.to_string()).unwrap();
    fails(
        &[os("render"), os(&d.join("a.gltf")), os("-o"), os(&d.join("a.png"))],
        &["a FIFO"],
    );
    assert!(!d.join("a.png").exists());
}

#[test]
fn an_output_that_is_an_input_is_refused() {
    let d = scratch("same");
    let crop = d.join("c.exr");
    assert!(render(&crop, &["--width", "8", "--height", "4"]).status.success());
    let before = std::fs::read(&crop).unwrap();
    fails(
        &[os("merge"), os(&crop), os("-o"), os(&d.join(".").join("c.exr"))],
        &["c.exr: is also an input of this command"],
    );
    assert_eq!(std::fs::read(&crop).unwrap(), before);
}

#[test]
fn temporaries_of_a_killed_write_are_removed_by_the_next() {
    let d = scratch("stale");
    let out = d.join("o.png");
    // What a kill -9 during the write left: a temporary named after a PID no process has.
    let stale = d.join(format!(".o.png.{}.tmp", (1u32 << 22) + 7));
    std::fs::write(&stale, b"half an image").unwrap();
    assert!(render(&out, &["--width", "8", "--height", "6"]).status.success());
    assert!(out.exists() && !stale.exists());
}

#[test]
fn compare_refuses_crops_and_merge_refuses_non_finite_crops() {
    let d = scratch("crops");
    let (full, crop) = (d.join("full.exr"), d.join("crop.exr"));
    assert!(render(&full, &["--width", "16", "--height", "12"]).status.success());
    assert!(
        render(&crop, &["--width", "16", "--height", "12", "--crop", "0,0,8,12"])
            .status
            .success()
    );
    // The crop was padded to its frame with zeros and compared as if it were a frame.
    fails(
        &[os("compare"), os(&crop), os(&full)],
        &["crop.exr: is a crop (columns 0..8, rows 0..12 of a 16×12 frame)"],
    );
    // Header checks come before pixels: a missing half is named without decoding anything.
    fails(
        &[os("merge"), os(&crop), os("-o"), os(&d.join("m.exr"))],
        &["leave pixel (8, 0) of the 16×12 frame uncovered"],
    );
    assert!(!d.join("m.exr").exists());
    // The other half, with a NaN in it: merge wrote it into the frame with exit 0.
    let mut half = pointshade::film::Image::new(8, 12);
    half.pixels[2 * 8 + 3] = glam::Vec3::new(0.5, f32::NAN, 0.5);
    let region = pointshade::film::PixelRect {
        x0: 8,
        y0: 0,
        x1: 16,
        y1: 12,
    };
    let nan = d.join("nan.exr");
    std::fs::write(
        &nan,
        pointshade::output::exr::encode_exr(&half, region, (16, 12)).unwrap(),
    )
    .unwrap();
    fails(
        &[os("merge"), os(&crop), os(&nan), os("-o"), os(&d.join("m.png"))],
        &["nan.exr: pixel (11, 2) of the frame is not finite"],
    );
    assert!(!d.join("m.png").exists());
}
