//! Rendering to a time budget (`--time-budget`, the film's `time_budget`): the image is bit for
//! bit the fixed render at the sample count the budget reached, or, for the adaptive samplers,
//! the render at the threshold it reached, whatever that count or threshold is.

use crate::support;

use std::path::Path;

use pointshade::film::{Image, SamplerKind};
use pointshade::plan::Aov;
use pointshade::render::Rendered;
use pointshade::scene::Scene;

fn scene(sampler: SamplerKind, spp: u32, budget: Option<f32>) -> Scene {
    let mut s = support::shipped_scene("cook-torrance.toml", (96, 64), sampler, spp);
    s.film.time_budget = budget;
    s.film.validate().unwrap();
    s
}

fn render(s: &Scene) -> Rendered {
    // A per-sample AOV goes through the passes as the radiance does.
    support::render(s, &[Aov::Normal])
}

fn bits(image: &Image) -> Vec<[u32; 3]> {
    image.pixels.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

/// The budgeted render of `sampler` equals the fixed render at the count it reached; returns it.
fn equals_the_fixed_render(sampler: SamplerKind, cap: u32, budget: f32) -> u32 {
    let budgeted = render(&scene(sampler, cap, Some(budget)));
    let n = budgeted.spp;
    assert!((1..=cap).contains(&n), "{sampler:?}: {n} samples, cap {cap}");
    assert!(budgeted.sample_counts.is_none());
    assert_eq!(budgeted.stats.primary_rays, n as u64 * 96 * 64);
    let fixed = render(&scene(sampler, n, None));
    assert_eq!(fixed.spp, n);
    assert!(bits(&budgeted.image) == bits(&fixed.image), "{sampler:?} at {n} spp");
    assert!(
        bits(&budgeted.aovs[0].1) == bits(&fixed.aovs[0].1),
        "{sampler:?} normals at {n} spp"
    );
    n
}

#[test]
fn a_budget_render_is_the_fixed_render_at_the_count_it_reached() {
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        // Whatever count this machine reaches in 50 ms.
        equals_the_fixed_render(sampler, 64, 0.05);
        // An ample budget stops at the cap, here after passes of 1, 1, 2, 4 and 4 samples.
        assert_eq!(equals_the_fixed_render(sampler, 12, 3600.0), 12);
        // A budget spent before the first pass ends leaves that pass alone.
        assert_eq!(equals_the_fixed_render(sampler, 64, 1e-9), 1);
    }
}

/// The budgeted render of adaptive `sampler` (at most `cap` samples per pixel, thresholds down
/// to `finest`) equals the render at the threshold it reached, sample counts included; returns
/// that threshold.
fn equals_the_render_at_its_threshold(sampler: SamplerKind, cap: u32, finest: f32, budget: f32) -> f32 {
    let mut budgeted = scene(sampler, cap, Some(budget));
    budgeted.film.adaptive_threshold = finest;
    let budgeted = render(&budgeted);
    let threshold = budgeted
        .adaptive_threshold
        .expect("adaptive renders say their threshold");
    let ladder = pointshade::render::threshold_ladder(finest);
    assert!(
        ladder.contains(&threshold),
        "{sampler:?}: {threshold} not in {ladder:?}"
    );
    let mut fixed = scene(sampler, cap, None);
    fixed.film.adaptive_threshold = threshold;
    let fixed = render(&fixed);
    assert!(
        bits(&budgeted.image) == bits(&fixed.image),
        "{sampler:?} at {threshold}"
    );
    assert!(
        bits(&budgeted.aovs[0].1) == bits(&fixed.aovs[0].1),
        "{sampler:?} normals at {threshold}"
    );
    assert_eq!(
        budgeted.sample_counts, fixed.sample_counts,
        "{sampler:?} at {threshold}"
    );
    threshold
}

#[test]
fn an_adaptive_budget_render_is_the_render_at_the_threshold_it_reached() {
    for sampler in [SamplerKind::Adaptive, SamplerKind::Cells] {
        // Whatever threshold this machine reaches in 50 ms.
        equals_the_render_at_its_threshold(sampler, 64, 0.002, 0.05);
        // An ample budget reaches the finest; one spent at once stops at the coarsest.
        assert_eq!(equals_the_render_at_its_threshold(sampler, 64, 0.005, 3600.0), 0.005);
        assert_eq!(equals_the_render_at_its_threshold(sampler, 64, 0.005, 1e-9), 0.04);
        // A ladder down to a tiny threshold (over a hundred rungs) predicts its passes without
        // overflowing a duration.
        equals_the_render_at_its_threshold(sampler, 64, 1e-40, 0.1);
    }
}

#[test]
fn a_budget_needs_a_sampler_that_adds_samples_the_whole_film_and_a_sane_number() {
    let mut s = scene(SamplerKind::Sobol, 16, Some(1.0));
    s.film.sampler = SamplerKind::Grid;
    let e = s.film.validate().unwrap_err();
    assert!(e.contains("grid"), "{e}");
    s.film.sampler = SamplerKind::Sobol;
    s.film.crop = Some(pointshade::film::PixelRect {
        x0: 0,
        y0: 0,
        x1: 8,
        y1: 8,
    });
    assert!(s.film.validate().unwrap_err().contains("crop"));
    s.film.crop = None;
    for budget in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e9] {
        s.film.time_budget = Some(budget);
        assert!(s.film.validate().unwrap_err().contains("time_budget"), "{budget}");
    }
}

#[test]
fn a_scene_with_a_budget_exports_to_mitsuba_only_with_a_sample_count() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = support::Scratch::new("budget-export");
    let text = std::fs::read_to_string(root.join("scenes/cook-torrance.toml"))
        .unwrap()
        .replace("[film]\n", "[film]\ntime_budget = 2.0\n")
        .replace("../meshes", root.join("meshes").to_str().unwrap());
    let scene = dir.join("budget.toml");
    std::fs::write(&scene, text).unwrap();
    let xml = dir.join("budget.xml");
    let export = |extra: &[&str]| {
        let args = ["export-mitsuba", scene.to_str().unwrap(), "-o", xml.to_str().unwrap()];
        support::pointshade(&[&args, extra].concat())
    };
    let refused = export(&[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--spp") && stderr.contains("time budget"), "{stderr}");
    assert!(!xml.exists(), "nothing written");
    let counted = export(&["--spp", "16"]);
    assert!(counted.status.success(), "{}", String::from_utf8_lossy(&counted.stderr));
    let written = std::fs::read_to_string(&xml).unwrap();
    assert!(written.contains(r#"name="sample_count" value="16""#), "{written}");
}
