//! Aiming a scene's camera from the command line: `--view azimuth,elevation[,distance]` around
//! the automatic framing, `--look-from`, `--look-at` and `--fov`; automatic lights follow.

use std::path::Path;
use std::process::Output;

use crate::support::{self, Scratch};

/// The shipped 20×20 plane in y = 0 (normal +y, two-sided light grey), rendered 49×37 (so that
/// a pixel's centre is the image's) with `extra`, with its normal and depth AOVs, into `out.exr`
/// (and `out.normal.exr`, `out.depth.exr`) of the folder returned.
fn render(name: &str, extra: &[&str]) -> (Output, Scratch) {
    let dir = Scratch::new(&format!("aim-{name}"));
    let out = dir.path("out.exr");
    let plane = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/plane.obj");
    let r = support::command()
        .arg("render")
        .arg(&plane)
        .arg("-o")
        .arg(&out)
        .args([
            "--width",
            "49",
            "--height",
            "37",
            "--spp",
            "1",
            "--sampler",
            "grid",
            "--aov",
            "normal,depth",
        ])
        .args(extra)
        .output()
        .unwrap();
    (r, dir)
}

fn exr(path: &Path) -> Vec<f32> {
    image::open(path).unwrap().into_rgb32f().into_raw()
}

/// Radiance, normal and depth at the centre pixel (one sample at its centre: the grid sampler),
/// and the depth four pixels above and below it.
fn centre(name: &str, extra: &[&str]) -> ([f32; 3], [f32; 3], f32, [f32; 2]) {
    let (r, dir) = render(name, extra);
    assert!(r.status.success(), "{name}: {}", String::from_utf8_lossy(&r.stderr));
    let out = dir.path("out.exr");
    let at = |row: usize| 3 * (row * 49 + 24);
    let pixel = |p: &Path| {
        let v = exr(p);
        let i = at(18);
        [v[i], v[i + 1], v[i + 2]]
    };
    let depths = exr(&out.with_file_name("out.depth.exr"));
    let depth = |row: usize| depths[at(row)];
    (
        pixel(&out),
        pixel(&out.with_file_name("out.normal.exr")),
        depth(18),
        [depth(14), depth(22)],
    )
}

#[test]
fn view_moves_the_camera_around_the_framing_and_the_automatic_lights_follow() {
    let (above, n, d_above, [upper, lower]) = centre("above", &["--view", "30,40"]);
    assert!((n[1] - 1.0).abs() < 1e-6, "the plane's normal: {n:?}");
    assert!(above[0] > 0.0, "lit from above");
    // Looking down, the upper part of the image sees the plane farther away; looking up from
    // below, nearer.
    assert!(
        upper > d_above && d_above > lower,
        "from above: {upper} {d_above} {lower}"
    );
    // From below the two-sided plane shows its back. Lights left where the front view put them
    // (above the plane) would leave it exactly black; re-aimed from the camera below, the fill
    // light (low, on the camera's side) lights it.
    let (below, _, d_below, [upper, lower]) = centre("below", &["--view", "30,-40"]);
    assert!(
        upper < d_below && d_below < lower,
        "from below: {upper} {d_below} {lower}"
    );
    assert!(below[0] > 0.0, "lit from below: {below:?}");
    // The centre pixel looks at the box's centre, at the framing distance times the third value.
    assert!((d_below - d_above).abs() < 1e-4 * d_above, "{d_below} {d_above}");
    let (_, _, d_far, _) = centre("far", &["--view", "30,40,2"]);
    assert!(
        (d_far / d_above - 2.0).abs() < 1e-5,
        "twice as far: {d_far} against {d_above}"
    );
}

#[test]
fn look_from_look_at_and_fov_set_the_camera() {
    // Straight down would make the up direction (+y) the view axis: a one-line error.
    let (r, _) = render("down", &["--look-from", "0,10,0", "--look-at", "0,0,0"]);
    assert!(!r.status.success());
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(
        stderr.contains("--look-at") && stderr.contains("up is parallel"),
        "{stderr}"
    );
    // From (0, 3, 4) at the origin the centre pixel is 5 units away.
    let (_, n, d, _) = centre("from", &["--look-from", "0,3,4", "--look-at", "0,0,0"]);
    assert!((d - 5.0).abs() < 1e-4, "{d}");
    assert!((n[1] - 1.0).abs() < 1e-6);
    // A narrower field of view sees a smaller part of the plane around the same centre: the
    // corner pixel, off the plane at 90°, is on it at 20°.
    let corner = |extra: &[&str], name: &str| {
        let (r, dir) = render(name, extra);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        exr(&dir.path("out.depth.exr"))[0]
    };
    let wide = corner(&["--look-from", "0,3,4", "--look-at", "0,0,0", "--fov", "150"], "wide");
    let narrow = corner(&["--look-from", "0,3,4", "--look-at", "0,0,0", "--fov", "20"], "narrow");
    assert!(
        wide == 0.0 || wide > 50.0,
        "the wide view's corner sees past the plane's edge: {wide}"
    );
    assert!(
        narrow > 0.0 && narrow < 10.0,
        "the narrow view's corner is on the plane: {narrow}"
    );
}

#[test]
fn bad_aims_are_one_line_errors_naming_the_option() {
    for (args, option, problem) in [
        (&["--view", "30"][..], "--view", "azimuth,elevation"),
        (&["--view", "30,90"][..], "--view", "strictly between -90 and 90"),
        (&["--view", "30,20,0"][..], "--view", "distance"),
        (&["--view", "a,b"][..], "--view", "azimuth,elevation"),
        (&["--look-from", "1,2"][..], "--look-from", "x,y,z"),
        (
            &["--look-from", "0,0,0", "--look-at", "0,0,0"][..],
            "--look-at",
            "must differ",
        ),
        (&["--fov", "0"][..], "--fov", "(0, 180)"),
    ] {
        let (r, dir) = render(&format!("bad-{}", args.join("_").replace(['-', ','], "")), args);
        let out = dir.path("out.exr");
        support::assert_one_line_error(&r, &[option, problem], &[&out]);
    }
}
