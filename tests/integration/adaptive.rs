//! The adaptive samplers (`adaptive`: Sobol rounds; `cells`: subdivided cells): one sample where
//! the image is smooth, more at edges, a lower error than uniform Sobol sampling at the same
//! number of samples, and the same image on any thread count.

use crate::support;

use glam::Vec3;
use pointshade::film::compare::compare;
use pointshade::film::{Image, SamplerKind};
use pointshade::plan::Aov;
use pointshade::render::Rendered;
use pointshade::scene::Scene;

fn render(sampler: SamplerKind, spp: u32) -> Rendered {
    render_lit(sampler, spp, 1.0, 0.0)
}

/// The test scene with its lights' power times `dim`, at `exposure` stops.
fn render_lit(sampler: SamplerKind, spp: u32, dim: f32, exposure: f32) -> Rendered {
    support::render(&lit_scene(sampler, spp, dim, exposure), &[])
}

fn lit_scene(sampler: SamplerKind, spp: u32, dim: f32, exposure: f32) -> Scene {
    let mut s = support::shipped_scene("lambert.toml", (128, 96), sampler, spp);
    s.film.exposure = exposure;
    for light in &mut s.lights {
        light.power *= dim;
    }
    s
}

/// Both adaptive samplers.
const ADAPTIVE: [SamplerKind; 2] = [SamplerKind::Adaptive, SamplerKind::Cells];

fn rmse(a: &Image, reference: &Image) -> f64 {
    compare(a, reference, 1e-3, 0).rmse
}

#[test]
fn smooth_pixels_take_one_sample_and_edges_take_more() {
    for sampler in ADAPTIVE {
        smooth_pixels_take_one_sample_and_edges_take_more_with(sampler);
    }
}

fn smooth_pixels_take_one_sample_and_edges_take_more_with(sampler: SamplerKind) {
    let r = render(sampler, 64);
    let counts = r.sample_counts.as_ref().expect("adaptive renders report their counts");
    let mean = counts.iter().map(|&c| c as f64).sum::<f64>() / counts.len() as f64;
    let ones = counts.iter().filter(|&&c| c == 1).count() as f64 / counts.len() as f64;
    let maxed = counts.iter().filter(|&&c| c >= 48).count();
    // Edges refine with their neighbours (a three-pixel band at this small size); the rest keeps
    // its centre sample.
    assert!(
        ones > 0.7,
        "most pixels (smooth shading, background) keep their centre sample: {ones}"
    );
    assert!(
        maxed > 20,
        "{sampler:?}: silhouette and shadow-edge pixels take the most samples: {maxed}"
    );
    // A refined pixel takes at least 16 samples; at this small size the edge bands are a large
    // share of the image, so the mean is far below 64 but not below 4.
    assert!(mean < 8.0, "{sampler:?}: mean spp {mean}");
    // The sphere's lit interior (smooth Lambert shading) keeps one sample; a row across its
    // silhouette reaches many.
    let at = |x: u32, y: u32| counts[(y * 128 + x) as usize];
    assert!(
        r.image.get(58, 38).min_element() > 0.05,
        "(58, 38) is on the lit sphere"
    );
    assert_eq!(at(58, 38), 1, "smooth interior of the sphere");
    let silhouette = (0..128).map(|x| at(x, 30)).max().unwrap();
    assert!(silhouette >= 16, "a row across the sphere's silhouette: {silhouette}");
    assert_eq!(
        r.stats.primary_rays,
        counts.iter().map(|&c| c as u64).sum::<u64>() + refined_centres(counts)
    );
}

/// Refined pixels also traced their centre sample (counted as a ray, not in the mean).
fn refined_centres(counts: &[u32]) -> u64 {
    counts.iter().filter(|&&c| c > 1).count() as u64
}

#[test]
fn adaptive_error_is_lower_than_uniform_sobol_at_the_same_sample_count() {
    let reference = render(SamplerKind::Grid, 256).image;
    for sampler in ADAPTIVE {
        error_is_lower_than_uniform_sobol_with(sampler, &reference);
    }
}

fn error_is_lower_than_uniform_sobol_with(sampler: SamplerKind, reference: &Image) {
    let adaptive = render(sampler, 64);
    let counts = adaptive.sample_counts.as_ref().unwrap();
    let mean = adaptive.stats.primary_rays as f64 / counts.len() as f64;
    let uniform_spp = mean.ceil() as u32;
    let uniform = render(SamplerKind::Sobol, uniform_spp).image;
    let (a, u) = (rmse(&adaptive.image, reference), rmse(&uniform, reference));
    assert!(
        a < 0.6 * u,
        "{sampler:?} ({mean:.2} spp) RMSE {a:.3e} vs sobol {uniform_spp} spp RMSE {u:.3e}"
    );
}

#[test]
fn adaptive_image_does_not_depend_on_the_thread_count() {
    for sampler in ADAPTIVE {
        let on = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| render(sampler, 16))
        };
        let (one, three) = (on(1), on(3));
        assert_eq!(one.image, three.image, "{sampler:?}");
        assert_eq!(one.sample_counts, three.sample_counts, "{sampler:?}");
    }
}

#[test]
fn a_dim_scene_exposed_up_is_sampled_like_the_bright_one() {
    // Tolerances are absolute below display white (2^-exposure): a scene 16× dimmer, shown 4
    // stops brighter, must refine exactly the same pixels as the original — and without the
    // exposure it would refine fewer (its contrasts fall below the absolute tolerance).
    for sampler in ADAPTIVE {
        let bright = render_lit(sampler, 64, 1.0, 0.0);
        let dim_exposed = render_lit(sampler, 64, 1.0 / 16.0, 4.0);
        let dim = render_lit(sampler, 64, 1.0 / 16.0, 0.0);
        let total = |r: &Rendered| r.sample_counts.as_ref().unwrap().iter().map(|&c| c as u64).sum::<u64>();
        assert_eq!(bright.sample_counts, dim_exposed.sample_counts, "{sampler:?}");
        assert!(
            total(&dim) < total(&bright) * 3 / 4,
            "{sampler:?}: dim at exposure 0: {} samples, bright: {}",
            total(&dim),
            total(&bright)
        );
    }
}

#[test]
fn the_samples_aov_is_the_count_each_pixel_took() {
    for (sampler, spp) in [
        (SamplerKind::Adaptive, 64),
        (SamplerKind::Cells, 64),
        (SamplerKind::Sobol, 4),
    ] {
        let s = lit_scene(sampler, spp, 1.0, 0.0);
        let r = support::render(&s, &[Aov::Samples]);
        let [(Aov::Samples, image)] = &r.aovs[..] else {
            panic!("one samples AOV expected")
        };
        let counts = match &r.sample_counts {
            Some(c) => c.clone(),
            None => vec![spp; image.pixels.len()],
        };
        assert_eq!(counts.len(), image.pixels.len());
        for (i, (&pixel, &count)) in image.pixels.iter().zip(&counts).enumerate() {
            assert_eq!(pixel, Vec3::splat(count as f32), "{sampler:?}, pixel {i}");
        }
        if sampler.is_adaptive() {
            let distinct = counts.iter().collect::<std::collections::BTreeSet<_>>().len();
            assert!(distinct >= 3, "{distinct} distinct counts");
        }
    }
}
