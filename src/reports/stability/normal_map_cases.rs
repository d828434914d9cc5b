//! The normal-map `tp` preset's degenerate and ordinary pixels: the float64 shading path the
//! `normalmap` command runs ([`shade_min_max_pixel`]) against the same generic code — the assignment's
//! dot products ([`clamped_dots`]) and [`Material::eval`] — composed again, in f64, with
//! glam's vector operations.
//!
//! Documented values (docs/normal-maps.md, "Normal-map mode"): background and n = 0 give 0; a zero
//! Cook-Torrance denominator (n·ω_o = 0) leaves the diffuse part alone; ω_i + ω_o = 0 has no half
//! vector and adds the diffuse part alone; a flat image (min = max) is refused before any
//! division.
//!
//! [`Material::eval`]: crate::material::Material::eval

use glam::{DVec3, Vec3};

use super::case::{num, rel_err, Case, Rng, REL_TOL};
use crate::light::LightKind;
use crate::normal_map::pixels::{MinMaxScaling, Viewer};
use crate::normal_map::scene_file::{NormalMapScene, Preset};
use crate::normal_map::shade_min_max_pixel;
use crate::scene::file::ModelName;
use crate::shading::convention::{clamped_dots, UnitForm};

/// Pixels with max(r, g, b) at or below this are background in the tp preset (4/255).
const BACKGROUND: f64 = 4.0 / 255.0;

/// The tp radiance of one pixel in f64: decoding, positions, lights and the shader's sum written
/// out again, calling the generic dot-product and BRDF code in f64.
fn tp_pixel_f64(scene: &NormalMapScene, (min, max): (f32, f32), rgb: [f32; 3], row: u32, col: u32) -> DVec3 {
    let c = rgb.map(f64::from);
    if c[0].max(c[1]).max(c[2]) <= BACKGROUND {
        return DVec3::ZERO;
    }
    let (min, max) = (min as f64, max as f64);
    let n = c.map(|v| (v - min) / (max - min));
    let x = DVec3::new(row as f64, col as f64, 0.0);
    let wo = match scene.viewer {
        Viewer::Direction(d) => d.as_dvec3(),
        Viewer::Position(p) => (p.as_dvec3() - x).normalize_or_zero(),
    };
    let specular = scene.material.has_specular();
    let mut radiance = DVec3::ZERO;
    for light in &scene.lights {
        let from_light = match light.kind {
            LightKind::Point { position } | LightKind::Spot { position, .. } => {
                (x - position.as_dvec3()).normalize_or_zero()
            }
            LightKind::Directional { direction } => direction.as_dvec3(),
        };
        if from_light == DVec3::ZERO {
            continue;
        }
        let a = clamped_dots(
            n,
            from_light.to_array(),
            wo.to_array(),
            specular.then_some(UnitForm::Quotients),
        );
        let f = if a.half_vector {
            scene.material.eval(&a.dots)
        } else {
            scene.material.diffuse::<f64>()
        };
        radiance += DVec3::from(f) * light.power.as_dvec3() * a.dots.n_dot_i;
    }
    radiance
}

fn scene(model: ModelName) -> NormalMapScene {
    NormalMapScene::from_preset(std::path::Path::new("stability"), Preset::Tp, model)
}

/// Compares f32 and f64 for one pixel; `expect` is the documented value where there is one.
fn pixel_case(
    name: &str,
    model: ModelName,
    scaling: (f32, f32),
    rgb: [f32; 3],
    row: u32,
    col: u32,
    expect: Option<DVec3>,
) -> Case {
    let s = scene(model);
    let mut case = Case::new(
        "normal-map",
        format!("tp {} {name}", model.name()),
        format!("rgb {rgb:?} at ({row}, {col})"),
    );
    let tp = MinMaxScaling::new(scaling.0 as f64, scaling.1 as f64).expect("the cases use min < max");
    let ours = shade_min_max_pixel(&s, tp, rgb.map(f64::from), row, col);
    let reference = tp_pixel_f64(&s, scaling, rgb, row, col);
    for c in 0..3 {
        case.count(ours[c]);
    }
    let err = (0..3).map(|c| rel_err(ours[c], reference[c])).fold(0.0, f64::max);
    case.f32_value = num(ours.x);
    case.f64_value = num(reference.x);
    case.rel_err = Some(err);
    if let Some(e) = expect {
        case.singular = Some(format!("documented value {}", num(e.x)));
        if (ours - e).abs().max_element() > 1e-6 * e.abs().max_element().max(1e-30) {
            case.fail(format!("expected {e}, got {ours}"));
        }
    } else if err > REL_TOL {
        case.fail(format!("relative error {err:.2e} > {REL_TOL:.0e}"));
    }
    case.require_clean();
    case
}

/// The tp cases: degenerate pixels with documented values, and `samples` random pixels per model.
pub fn run(samples: u64, seed: u64) -> Vec<Case> {
    let mut cases = Vec::new();
    let unit = (0.0, 1.0);
    let diffuse_only = |model, n: Vec3, wi: Vec3| {
        // L_i · k_d·albedo/π · n·ω_i (the preset's one light, no falloff).
        let s = scene(model);
        DVec3::from(s.material.diffuse::<f64>())
            * s.lights[0].power.as_dvec3()
            * n.as_dvec3().dot(wi.as_dvec3()).clamp(0.0, 1.0)
    };
    for model in ModelName::ALL {
        cases.push(pixel_case(
            "background (max rgb ≤ 4/255)",
            model,
            unit,
            [0.01, 0.0, 0.015],
            100,
            200,
            Some(DVec3::ZERO),
        ));
        cases.push(pixel_case(
            "n = 0 (rgb = image minimum)",
            model,
            (0.2, 0.9),
            [0.2, 0.2, 0.2],
            100,
            200,
            Some(DVec3::ZERO),
        ));
    }
    // The report's camera is at [1, 300, 1] and its light at [0, 1, 1]. At pixel (1, 300) the
    // viewer direction is +z; n = (1, 0, 0) then has n·ω_o = 0: the Cook-Torrance denominator
    // is 0 and only the diffuse part remains.
    let (row, col) = (1u32, 300u32);
    let n = Vec3::new(1.0, 0.0, 0.0);
    let wi = (Vec3::new(row as f32, col as f32, 0.0) - Vec3::new(0.0, 1.0, 1.0)).normalize();
    let expect = diffuse_only(ModelName::CookTorrance, n, wi);
    cases.push(pixel_case(
        "n·ω_o = 0 (denominator 0)",
        ModelName::CookTorrance,
        unit,
        [1.0, 0.0, 0.0],
        row,
        col,
        Some(expect),
    ));
    // ω_i + ω_o = 0: the report's light and camera are both at z = 1, so no pixel (z = 0) lies
    // on a line through both; an orthographic viewer looking back along ω_i makes the case.
    let mut opposite = scene(ModelName::CookTorrance);
    opposite.viewer = Viewer::Direction(-wi); // ω_o = −ω_i exactly
    let tp = MinMaxScaling::new(0.0, 1.0).expect("min < max");
    let ours = shade_min_max_pixel(&opposite, tp, [0.3, 0.2, 0.9], row, col);
    let want = diffuse_only(ModelName::CookTorrance, Vec3::new(0.3, 0.2, 0.9), wi);
    let mut case = Case::new(
        "normal-map",
        "tp cook-torrance ω_i + ω_o = 0 (no half vector)",
        "ω_o = −ω_i",
    );
    case.f32_value = num(ours.x);
    case.f64_value = num(want.x);
    case.rel_err = Some((0..3).map(|c| rel_err(ours[c], want[c])).fold(0.0, f64::max));
    case.singular = Some("documented value: the diffuse part alone".into());
    (0..3).for_each(|c| case.count(ours[c]));
    if case.rel_err.unwrap_or(0.0) > REL_TOL {
        case.fail(format!("expected the diffuse part {want}, got {ours}"));
    }
    case.require_clean();
    cases.push(case);
    // A flat image is refused: no division by max − min = 0.
    let mut flat = Case::new("normal-map", "tp flat image (min = max)", "every RGB value 0.5");
    flat.singular = Some("documented: refused with an error".into());
    match MinMaxScaling::new(0.5, 0.5) {
        Err(_) => flat.f32_value = "error".into(),
        Ok(_) => flat.fail("a flat image was accepted"),
    }
    flat.f64_value = "error".into();
    cases.push(flat);
    // Ordinary pixels: random colours and positions over the report's 768×451 image.
    for model in ModelName::ALL {
        let mut rng = Rng::new(seed, 0x7e_0000 + model as u64);
        let mut case = Case::new(
            "normal-map",
            format!("tp {} random pixels", model.name()),
            format!("{samples} pixels"),
        );
        let s = scene(model);
        let mut worst = (0.0f64, String::new());
        let mut ill_conditioned = 0u64;
        for _ in 0..samples {
            let rgb = [rng.uniform() as f32, rng.uniform() as f32, rng.uniform() as f32];
            let (row, col) = (rng.below(451) as u32, rng.below(768) as u32);
            let ours = shade_min_max_pixel(&s, tp, rgb.map(f64::from), row, col);
            let reference = tp_pixel_f64(&s, unit, rgb, row, col);
            (0..3).for_each(|c| case.count(ours[c]));
            // Ill-conditioned pixels keep their NaN/Inf/negative counts but not the tolerance.
            if ill_conditioned_pixel(&s, rgb, row, col) {
                ill_conditioned += 1;
                continue;
            }
            for c in 0..3 {
                let e = rel_err(ours[c], reference[c]);
                if e > worst.0 && reference.max_element() > 1e-30 {
                    worst = (e, format!("rgb {rgb:?} at ({row}, {col})"));
                }
            }
        }
        case.inputs = format!("{samples} pixels, {ill_conditioned} ill-conditioned");
        case.rel_err = Some(worst.0);
        case.f32_value = "-".into();
        case.f64_value = "-".into();
        if worst.0 > REL_TOL {
            case.fail(format!("relative error {:.2e} at {}", worst.0, worst.1));
        }
        case.require_clean();
        cases.push(case);
    }
    cases
}

/// Whether a pixel is ill-conditioned in f32, as the BRDF sweep defines it: n·ω_o within 1e-5
/// of 0 (where the report's guarded Cook-Torrance term jumps, so f32 and f64 may land on either
/// side), or |ω_i + ω_o| < 1e-2 (the half vector of nearly opposite directions: the report's
/// ω_i points away from the light, so every pixel beyond the camera's column along the light's
/// direction has this; its direction is known in f32 only to ~6e-8/|ω_i + ω_o|).
fn ill_conditioned_pixel(s: &NormalMapScene, rgb: [f32; 3], row: u32, col: u32) -> bool {
    let x = DVec3::new(row as f64, col as f64, 0.0);
    let wo = match s.viewer {
        Viewer::Direction(d) => d.as_dvec3(),
        Viewer::Position(p) => (p.as_dvec3() - x).normalize_or_zero(),
    };
    let near_opposite = s.lights.iter().any(|l| match l.kind {
        LightKind::Point { position } | LightKind::Spot { position, .. } => {
            ((x - position.as_dvec3()).normalize_or_zero() + wo).length() < 1e-2
        }
        LightKind::Directional { direction } => (direction.as_dvec3() + wo).length() < 1e-2,
    });
    near_opposite || Vec3::from(rgb).as_dvec3().dot(wo).abs() < 1e-5
}
