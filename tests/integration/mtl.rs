//! What an OBJ's MTL asks for: `map_Kd`, `map_Ks`, `map_Ns`, `map_Pr` and `map_Pm` texture their
//! parameters through the scene's texture machinery, and every statement pointshade does not use
//! is one warning naming it.

use std::path::Path;
use std::process::Output;

use crate::support::gltf_builder::write_png;
use crate::support::{self, Scratch};

/// meshes/plane.obj (with texture coordinates) behind `mtllib m.mtl` / `usemtl m`, with `mtl` as
/// m.mtl, in a fresh folder; returns the folder, where the test writes the textures and renders
/// `m.obj` ([`render`]).
fn textured_plane(name: &str, mtl: &str, with_uvs: bool) -> Scratch {
    let dir = Scratch::new(&format!("mtl-{name}"));
    let plane = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/plane.obj")).unwrap();
    let plane = if with_uvs {
        plane
    } else {
        // Faces as position//normal, no `vt` lines: a mesh without texture coordinates.
        plane
            .lines()
            .filter(|l| !l.starts_with("vt "))
            .map(|l| match l.strip_prefix("f ") {
                // a/b/c → a//c
                Some(f) => {
                    let corners: Vec<String> = f
                        .split(' ')
                        .map(|c| {
                            let parts: Vec<&str> = c.split('/').collect();
                            format!("{}//{}", parts[0], parts[2])
                        })
                        .collect();
                    format!("f {}", corners.join(" "))
                }
                None => l.to_string(),
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    dir.write("m.obj", &format!("mtllib m.mtl\nusemtl m\n{plane}\n"));
    dir.write("m.mtl", mtl);
    dir
}

/// Renders the textured plane's `m.obj` in `plane` (from [`textured_plane`]) into `out`.
fn render(plane: &Scratch, out: &Path, extra: &[&str]) -> Output {
    support::command()
        .arg("render")
        .arg(plane.path("m.obj"))
        .arg("-o")
        .arg(out)
        .args(["--width", "48", "--height", "36", "--spp", "1"])
        .args(extra)
        .output()
        .unwrap()
}

fn exr(path: &Path) -> Vec<f32> {
    image::open(path).unwrap().into_rgb32f().into_raw()
}

/// sRGB → linear (IEC 61966-2-1) of an 8-bit code.
fn srgb(code: u8) -> f64 {
    let c = code as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn map_kd_multiplies_the_albedo_by_the_decoded_texture() {
    // A uniform texture of sRGB code (200, 120, 40) renders as the albedo Kd × its linear value:
    // the same image as the untextured material with that albedo (to f32 rounding of the
    // bilinear weights), for each model the MTL keys choose.
    for (model, extra) in [
        ("lambert", ""),
        ("blinn-phong", "Ks 0.3 0.3 0.3\nNs 20\n"),
        ("cook-torrance", "Pr 0.4\n"),
    ] {
        let kd = [0.9, 0.5, 0.7];
        let code = [200u8, 120, 40];
        let textured = textured_plane(
            &format!("uniform-{model}"),
            &format!("newmtl m\nKd {} {} {}\n{extra}map_Kd t.png\n", kd[0], kd[1], kd[2]),
            true,
        );
        write_png(&textured.path("t.png"), 2, 2, &[[code[0], code[1], code[2], 255]; 4]);
        let albedo: Vec<f64> = (0..3).map(|c| kd[c] * srgb(code[c])).collect();
        let constant = textured_plane(
            &format!("constant-{model}"),
            &format!("newmtl m\nKd {} {} {}\n{extra}", albedo[0], albedo[1], albedo[2]),
            true,
        );
        let (a, b) = (textured.path("a.exr"), constant.path("b.exr"));
        let r = render(&textured, &a, &["--explain"]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let explain = String::from_utf8_lossy(&r.stdout);
        assert!(
            explain.contains("albedo (MTL map_Kd): m") && explain.contains("map_Kd ('t.png') (2x2)"),
            "--explain lists the texture:\n{explain}"
        );
        assert!(render(&constant, &b, &[]).status.success());
        let (a, b) = (exr(&a), exr(&b));
        let peak = b.iter().cloned().fold(0.0f32, f32::max);
        assert!(peak > 0.0, "{model}: the plane is lit");
        let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
        assert!(worst <= 1e-5 * peak, "{model}: worst difference {worst} of peak {peak}");
    }
}

#[test]
fn map_kd_varies_over_the_surface() {
    // Two texels, black and white, across u: the textured plane has dark and bright pixels where
    // the untextured one is uniformly lit.
    let obj = textured_plane("two-texels", "newmtl m\nKd 1 1 1\nmap_Kd -clamp on t.png\n", true);
    write_png(&obj.path("t.png"), 2, 1, &[[0, 0, 0, 255], [255, 255, 255, 255]]);
    let out = obj.path("out.exr");
    assert!(render(&obj, &out, &["--quiet"]).status.success());
    let lit: Vec<f32> = exr(&out).chunks(3).map(|p| p[0]).filter(|&v| v > 0.0).collect();
    let (lo, hi) = lit
        .iter()
        .fold((f32::MAX, 0.0f32), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    assert!(!lit.is_empty() && hi > 20.0 * lo, "dark and bright parts: {lo} .. {hi}");
}

#[test]
fn every_unused_mtl_statement_is_one_warning_naming_it() {
    let obj = textured_plane(
        "unused",
        "newmtl m\nKa 1 1 1\nKd 0.5 0.5 0.5\nKs 0 0 0\nillum 2\nd 1\nmap_Kd -s 2 2 t.png\nmap_Ks s.png\n\
         map_Ns -imfchan r r.png\nmap_Ka -bm 0.3 a.png\n",
        true,
    );
    write_png(&obj.path("t.png"), 1, 1, &[[128, 128, 128, 255]]);
    let r = render(&obj, &obj.path("out.png"), &[]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let stderr = String::from_utf8_lossy(&r.stderr);
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("MTL statement")).collect();
    for statement in [
        "Ka",
        "Ks",
        "illum",
        "d",
        "map_Ks (the material has no specular lobe)",
        "map_Ka",
        "map_Ns (the material is not Blinn-Phong)",
        "map_Kd option -s",
    ] {
        let named: Vec<_> = warnings
            .iter()
            .filter(|w| w.contains(&format!("MTL statement {statement} is not used")))
            .collect();
        assert_eq!(named.len(), 1, "one warning for {statement}:\n{stderr}");
        assert!(named[0].contains("material(s) m"), "{}", named[0]);
    }
    assert_eq!(warnings.len(), 8, "no warning for what is used (Kd, map_Kd):\n{stderr}");
    // Without texture coordinates map_Kd cannot be looked up: a warning, and no texture.
    let no_uvs = textured_plane("no-uvs", "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd t.png\n", false);
    let r = render(&no_uvs, &no_uvs.path("out.png"), &["--explain"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(String::from_utf8_lossy(&r.stderr).contains("map_Kd (the mesh has no texture coordinates)"));
    assert!(String::from_utf8_lossy(&r.stdout).contains("no rendered material has a texture"));
}

#[test]
fn a_missing_or_broken_map_kd_image_is_a_one_line_error_and_no_output() {
    let obj = textured_plane("missing", "newmtl m\nKd 1 1 1\nmap_Kd nowhere.png\n", true);
    let out = obj.path("out.png");
    let r = render(&obj, &out, &[]);
    support::assert_one_line_error(&r, &["m.obj", "nowhere.png"], &[&out]);
    std::fs::write(obj.path("nowhere.png"), b"not a png").unwrap();
    let r = render(&obj, &out, &[]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success() && !out.exists(), "{stderr}");
    assert!(stderr.contains("cannot decode"), "{stderr}");
    let bad = textured_plane("bad-option", "newmtl m\nKd 1 1 1\nmap_Kd -zz 1 t.png\n", true);
    let r = render(&bad, &bad.path("out.png"), &[]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(
        !r.status.success() && stderr.contains("unknown option '-zz'"),
        "{stderr}"
    );
}

/// The EXR of the textured plane with `mtl`, its images written first (`name` → one RGBA
/// texel), with no warning about the MTL.
fn render_mtl(name: &str, mtl: &str, images: &[(&str, [u8; 4])]) -> Vec<f32> {
    let obj = textured_plane(name, mtl, true);
    for (file, texel) in images {
        write_png(&obj.path(file), 1, 1, &[*texel]);
    }
    let out = obj.path("out.exr");
    let r = render(&obj, &out, &["--quiet"]);
    assert!(r.status.success(), "{name}: {}", String::from_utf8_lossy(&r.stderr));
    assert!(
        !String::from_utf8_lossy(&r.stderr).contains("MTL statement"),
        "{name}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    exr(&out)
}

const WHITE: [u8; 4] = [255, 255, 255, 255];
const BLACK: [u8; 4] = [0, 0, 0, 255];

/// For each texture, a white texel gives the untextured material's image bit for bit (the
/// factor times 1) and a black one the image of the material with that parameter at 0 — and
/// the two differ, so the texture reached the shader.
#[test]
fn each_mtl_texture_multiplies_its_own_parameter() {
    let blinn_phong = "newmtl m\nKd 0.4 0.4 0.4\nKs 0.8 0.8 0.8\nNs 30\n";
    let pbr = "newmtl m\nKd 0.9 0.5 0.3\nPr 0.4\n";
    let cases: [(&str, String, &str, String); 4] = [
        // map_Ks: black removes the lobe (Ks 0 is a Lambert material).
        (
            "map_ks",
            format!("{blinn_phong}map_Ks s.png\n"),
            blinn_phong,
            "newmtl m\nKd 0.4 0.4 0.4\n".into(),
        ),
        // map_Ns: black is exponent 0 (Ns 0).
        (
            "map_ns",
            format!("{blinn_phong}map_Ns s.png\n"),
            blinn_phong,
            blinn_phong.replace("Ns 30", "Ns 0"),
        ),
        // map_Pr: black is roughness 0.
        (
            "map_pr",
            format!("{pbr}map_Pr s.png\n"),
            pbr,
            pbr.replace("Pr 0.4", "Pr 0"),
        ),
        // map_Pm with Pm 1: white is the metal, black the dielectric (Pm 0).
        (
            "map_pm",
            format!("{pbr}Pm 1\nmap_Pm s.png\n"),
            "",
            format!("{pbr}Pm 0\n"),
        ),
    ];
    for (name, textured, plain, zero) in cases {
        let plain = if plain.is_empty() {
            format!("{pbr}Pm 1\n")
        } else {
            plain.to_string()
        };
        let white = render_mtl(&format!("{name}-white"), &textured, &[("s.png", WHITE)]);
        let black = render_mtl(&format!("{name}-black"), &textured, &[("s.png", BLACK)]);
        assert_eq!(
            white,
            render_mtl(&format!("{name}-plain"), &plain, &[]),
            "{name}: white = untextured"
        );
        assert_eq!(
            black,
            render_mtl(&format!("{name}-zero"), &zero, &[]),
            "{name}: black = parameter 0"
        );
        assert_ne!(white, black, "{name}: the texture changes the image");
    }
}

/// `-imfchan` picks the channel a one-channel texture reads; without it the luminance is read.
#[test]
fn a_scalar_texture_reads_the_channel_imfchan_names() {
    let bp = "newmtl m\nKd 0.4 0.4 0.4\nKs 0.8 0.8 0.8\nNs 30\n";
    let red = [255, 0, 0, 255];
    let plain = render_mtl("chan-plain", bp, &[]);
    let zero = render_mtl("chan-zero", &bp.replace("Ns 30", "Ns 0"), &[]);
    assert_eq!(
        render_mtl("chan-r", &format!("{bp}map_Ns -imfchan r s.png\n"), &[("s.png", red)]),
        plain
    );
    assert_eq!(
        render_mtl("chan-g", &format!("{bp}map_Ns -imfchan g s.png\n"), &[("s.png", red)]),
        zero
    );
    let luminance = render_mtl("chan-l", &format!("{bp}map_Ns s.png\n"), &[("s.png", red)]);
    let scaled = render_mtl(
        "chan-scaled",
        &bp.replace("Ns 30", &format!("Ns {}", 30.0f32 * 0.2126)),
        &[],
    );
    assert_eq!(luminance, scaled, "red reads as luminance 0.2126");
    let obj = textured_plane("chan-bad", &format!("{bp}map_Ns -imfchan z s.png\n"), true);
    let r = render(&obj, &obj.path("out.png"), &[]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("-imfchan takes r, g, b, m or l"));
}

/// The normal AOV at the centre of the textured plane (48×36) under `mtl`, with `n.png` one
/// texel `texel`; and the render's warnings about the MTL.
fn centre_normal(name: &str, mtl: &str, texel: [u8; 4]) -> ([f32; 3], String) {
    let obj = textured_plane(name, mtl, true);
    write_png(&obj.path("n.png"), 1, 1, &[texel]);
    let out = obj.path("out.exr");
    let r = render(&obj, &out, &["--aov", "normal"]);
    assert!(r.status.success(), "{name}: {}", String::from_utf8_lossy(&r.stderr));
    let normals = exr(&obj.path("out.normal.exr"));
    let i = 3 * (18 * 48 + 24);
    let warnings = String::from_utf8_lossy(&r.stderr)
        .lines()
        .filter(|l| l.contains("MTL statement"))
        .collect::<Vec<_>>()
        .join("\n");
    ([normals[i], normals[i + 1], normals[i + 2]], warnings)
}

fn assert_near(got: [f32; 3], want: [f32; 3], tolerance: f32, what: &str) {
    let off = (0..3).map(|c| (got[c] - want[c]).abs()).fold(0.0, f32::max);
    assert!(off <= tolerance, "{what}: {got:?}, expected {want:?}");
}

/// `norm` and `map_Bump` are tangent-space normal maps on the plane (facing +y, u along +x, the
/// OBJ's v along −z): +X of the map turns the normal to +x, +Y (up the image, +v) to −z, and
/// `-bm 0` leaves the vertex normal. The OBJ has no tangents: they are generated.
#[test]
fn norm_and_map_bump_are_tangent_space_normal_maps() {
    let lambert = "newmtl m\nKd 0.5 0.5 0.5\n";
    // The level 128 encodes 2·128/255 − 1 = 1/255, not 0: the expected normals carry it.
    let e = 1.0 / 255.0;
    let unit = |v: [f32; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / l)
    };
    let (flat, w) = centre_normal("norm-flat", &format!("{lambert}norm n.png\n"), [128, 128, 255, 255]);
    assert!(w.is_empty(), "{w}");
    assert_near(flat, unit([e, 1.0, -e]), 1e-4, "a flat map keeps the normal");
    let (x, _) = centre_normal("norm-x", &format!("{lambert}norm n.png\n"), [255, 128, 128, 255]);
    assert_near(x, unit([1.0, e, -e]), 1e-4, "+X of the map is +u");
    let (y, _) = centre_normal("bump-y", &format!("{lambert}map_Bump n.png\n"), [128, 255, 128, 255]);
    assert_near(y, unit([e, e, -1.0]), 1e-4, "+Y of the map is +v");
    let (off, _) = centre_normal(
        "bump-off",
        &format!("{lambert}map_Bump -bm 0 n.png\n"),
        [255, 128, 128, 255],
    );
    assert_near(off, [0.0, 1.0, 0.0], 1e-6, "-bm 0 scales X and Y away");
    // Both: norm is the normal map, map_Bump one unused statement.
    let (both, w) = centre_normal(
        "both",
        &format!("{lambert}norm n.png\nmap_Bump m.png\n"),
        [255, 128, 128, 255],
    );
    assert_near(both, x, 0.0, "norm wins");
    assert!(
        w.contains("MTL statement map_Bump (norm gives the normal map) is not used"),
        "{w}"
    );
}
