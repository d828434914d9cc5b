//! Normal-map scene files and options: a scene file shades as the command line does, the plan
//! shows no rays, the image does not depend on the thread count, and bad options and scene files
//! are refused with one line.

use super::{fails, ok, s, shade, shared_normal_map};
use crate::support::{pointshade, Scratch};

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn scene_file_gives_the_same_image_as_the_command_line() {
    let input = shared_normal_map("nmap2.png");
    let dir = Scratch::new("normalmap-scenefile");
    let scene = dir.write(
        "tp.toml",
        &format!(
            "[normal_map]\nimage = \"{}\"\npreset = \"tp\"\nbrdf = \"cook-torrance\"\n",
            s(&input)
        ),
    );
    let (a, b) = (dir.path("a.png"), dir.path("b.png"));
    ok(&["normalmap", s(&scene), "-o", s(&a), "--quiet"]);
    shade(&input, "tp", "cook-torrance", &b, &[]);
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // --brdf on the command line replaces the file's brdf.
    let c = dir.path("c.png");
    ok(&["normalmap", s(&scene), "--brdf", "lambert", "-o", s(&c), "--quiet"]);
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&c).unwrap());
}

#[test]
fn plan_shows_no_bvh_and_no_rays() {
    let dir = Scratch::new("normalmap-plan");
    let input = dir.path("n.png");
    image::RgbImage::from_pixel(4, 4, image::Rgb([100, 150, 250]))
        .save(&input)
        .unwrap();
    let out = dir.path("o.png");
    for preset in ["tp", "physical"] {
        let o = ok(&[
            "normalmap",
            s(&input),
            "--preset",
            preset,
            "--brdf",
            "blinn-phong",
            "-o",
            s(&out),
            "--explain",
        ]);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("[skip] bvh + primary rays"), "{text}");
        assert!(text.contains("[skip] shadow rays"), "{text}");
        assert!(text.contains("rays: 0 primary, at most 0 shadow"), "{text}");
        assert!(
            text.contains(if preset == "tp" { "clamped:" } else { "physical:" }),
            "{text}"
        );
        let summary = String::from_utf8_lossy(&o.stderr);
        assert!(summary.contains("16 surface points, 0 rays"), "{summary}");
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn image_does_not_depend_on_the_thread_count() {
    let input = shared_normal_map("normal.png");
    let dir = Scratch::new("normalmap-threads");
    let (a, b) = (dir.path("a.png"), dir.path("b.exr"));
    let (c, d) = (dir.path("c.png"), dir.path("d.exr"));
    for (png, exr, threads) in [(&a, &b, "1"), (&c, &d, "3")] {
        for out in [png, exr] {
            shade(&input, "tp", "cook-torrance", out, &["--threads", threads]);
        }
    }
    assert_eq!(std::fs::read(a).unwrap(), std::fs::read(c).unwrap());
    assert_eq!(std::fs::read(b).unwrap(), std::fs::read(d).unwrap());
}

#[test]
fn bad_options_and_scene_files_are_refused_with_one_line() {
    let dir = Scratch::new("normalmap-badopts");
    let input = dir.path("n.png");
    image::RgbImage::from_pixel(4, 4, image::Rgb([100, 150, 250]))
        .save(&input)
        .unwrap();
    let i = s(&input);
    fails(&dir, &["normalmap", i], &["--brdf", "required"]);
    fails(&dir, &["normalmap", i, "--brdf", "phong"], &["--brdf", "phong"]);
    fails(
        &dir,
        &["normalmap", i, "--brdf", "lambert", "--preset", "exact"],
        &["--preset", "exact"],
    );
    fails(
        &dir,
        &["normalmap", i, "--brdf", "lambert", "--preset", "tp", "--exposure", "1"],
        &["--exposure"],
    );
    fails(
        &dir,
        &["normalmap", i, "--brdf", "lambert", "--exposure", "nan"],
        &["--exposure"],
    );
    let scene = dir.write(
        "s.toml",
        "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\nwidht = 3\n",
    );
    fails(&dir, &["normalmap", s(&scene)], &["s.toml", "line 4", "widht"]);
    let scene = dir.write("p.toml", "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n");
    fails(&dir, &["normalmap", s(&scene), "--preset", "tp"], &["--preset"]);
    let missing = dir.write("m.toml", "[normal_map]\nimage = \"absent.png\"\nbrdf = \"lambert\"\n");
    fails(&dir, &["normalmap", s(&missing)], &["absent.png"]);
    let nan = dir.write(
        "nan.toml",
        "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n[[light]]\ntype = \"point\"\nposition = [0.0, nan, 1.0]\n",
    );
    fails(&dir, &["normalmap", s(&nan)], &["nan.toml", "line 4", "position"]);
    // `render` refuses a normal-map scene and says which command shades it.
    fails(
        &dir,
        &["render", s(&scene)],
        &["p.toml", "line 1", "pointshade normalmap"],
    );
    // bake writes PNG only, and needs a mesh scene.
    let r = pointshade(&["bake", s(&scene), "-o", s(&dir.path("n.exr"))]);
    assert_eq!(r.status.code(), Some(2));
    fails(&dir, &["bake", s(&scene)], &["p.toml", "normalmap"]);
}
