//! One scene rendered at scales 1e-6 … 1e6 and moved to 1e5, compared with the same scene at
//! scale 1 at the origin: shadows must neither gain acne nor lose their contact edges.
//!
//! The scene is a ground quad and a cube resting on it (their contact line is where a fixed
//! shadow-ray epsilon loses the shadow at large coordinates), a glossy Cook-Torrance cube and a
//! Lambert ground, one point light whose intensity scales with the square of the scene so the
//! image stays the same. A case passes when ≥ 99% of its pixels are within 5% of the reference
//! and none is non-finite or negative.

use glam::Vec3;

use super::case::{num, Case};
use crate::accel::Bvh;
use crate::film::{FilmSettings, Image, SamplerKind};
use crate::light::{Falloff, Light, LightKind};
use crate::material::{BrdfModel, CookTorrance, Material};
use crate::plan::RenderPlan;
use crate::scene::camera::{CameraSpec, FovAxis, Projection};
use crate::scene::mesh::TriangleMesh;
use crate::scene::procedural;
use crate::scene::Scene;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// The unit-high cube [−0.5, 0.5] × [0, 1] × [−0.5, 0.5], outward-facing.
fn cube() -> TriangleMesh {
    let p: Vec<Vec3> = (0..8)
        .map(|k| Vec3::new((k & 1) as f32 - 0.5, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32 - 0.5))
        .collect();
    let quads = [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    let mut triangles = Vec::new();
    for q in quads {
        triangles.push([q[0], q[1], q[2]]);
        triangles.push([q[0], q[2], q[3]]);
    }
    TriangleMesh {
        normals: crate::scene::mesh::angle_weighted_normals(&p, &triangles),
        positions: p,
        material_of_triangle: vec![1; triangles.len()],
        triangles,
        ..Default::default()
    }
}

/// The scene scaled by `scale` about the origin, then moved by `offset` on every axis.
pub fn contact_scene(scale: f32, offset: f32) -> Scene {
    let mut mesh = procedural::plane(3.0, 1).into_triangle_mesh();
    mesh.append(cube(), 0);
    let place = |p: Vec3| p * scale + Vec3::splat(offset);
    for p in &mut mesh.positions {
        *p = place(*p);
    }
    let glossy = Material {
        kd: 0.5,
        model: BrdfModel::CookTorrance(CookTorrance {
            alpha: 0.3,
            ..CookTorrance::default()
        }),
        ..Material::lambert("cube", [0.8, 0.3, 0.2])
    };
    Scene::new(
        "stability-contact-scene".into(),
        FilmSettings {
            width: WIDTH,
            height: HEIGHT,
            spp: 1,
            sampler: SamplerKind::Grid,
            ..FilmSettings::default()
        },
        CameraSpec {
            position: place(Vec3::new(2.2, 1.6, 3.0)),
            look_at: place(Vec3::new(0.0, 0.3, 0.0)),
            up: Vec3::Y,
            projection: Projection::Perspective {
                fov_degrees: 45.0,
                fov_axis: FovAxis::Y,
            },
            near_clip: 0.0,
            far_clip: f32::INFINITY,
        },
        vec![Light {
            kind: LightKind::Point {
                position: place(Vec3::new(-1.5, 2.0, 1.2)),
            },
            power: Vec3::splat(20.0 * scale * scale),
            falloff: Falloff::InverseSquare,
        }],
        vec![Material::lambert("ground", [0.7; 3]), glossy],
        Vec::new(),
        mesh,
    )
}

/// `scene` rendered as the stability rows render (its own plan and BVH, no progress).
pub fn render(scene: &Scene) -> Image {
    let plan = RenderPlan::new(scene, &[]);
    let bvh = Bvh::for_scene(scene);
    crate::render::render(scene, &plan, Some(&bvh), &crate::render::progress::Silent)
        .expect("the stability scene is valid")
        .image
}

/// Share of the pixels of `other` within `tolerance` of `reference` (relative to the pixel, with
/// a floor of 1e-3 of the reference's brightest pixel), and its non-finite or negative pixels.
pub fn share_within(reference: &Image, other: &Image, tolerance: f32) -> (f64, u64) {
    let floor = 1e-3 * reference.pixels.iter().map(|p| p.max_element()).fold(0.0, f32::max);
    let (mut within, mut bad) = (0u64, 0u64);
    for (p, q) in reference.pixels.iter().zip(&other.pixels) {
        bad += (!q.is_finite() || q.min_element() < 0.0) as u64;
        within += ((*p - *q).abs().max_element() <= tolerance * p.max_element().max(floor)) as u64;
    }
    (within as f64 / reference.pixels.len().max(1) as f64, bad)
}

/// Share of pixels within 5% of the reference ([`share_within`]), the pixels lit in one image but
/// black in the other, and the non-finite or negative ones.
pub fn compare(reference: &Image, other: &Image) -> (f64, u64, u64, u64) {
    let (share, bad) = share_within(reference, other, 0.05);
    let (mut acne, mut lost) = (0u64, 0u64);
    for (p, q) in reference.pixels.iter().zip(&other.pixels) {
        let (lit_p, lit_q) = (p.max_element() > 0.0, q.max_element() > 0.0);
        acne += (lit_p && !lit_q) as u64;
        lost += (!lit_p && lit_q) as u64;
    }
    (share, acne, lost, bad)
}

/// The reference at scale 1 and the origin, and one row per (scale, offset).
pub fn run(notes: &mut Vec<String>) -> Vec<Case> {
    let reference = render(&contact_scene(1.0, 0.0));
    let black = reference.pixels.iter().filter(|p| p.max_element() == 0.0).count();
    notes.push(format!(
        "contact scene: {WIDTH}x{HEIGHT}, {black} black pixels in the reference (shadows and background)"
    ));
    // Not tried: small scenes far away (scale 1e-2 at 1e5 is 8 ulps of f32 across: the geometry
    // itself cannot be represented, whatever the shadow rays do).
    let settings = [
        (1e-6f32, 0.0f32),
        (1e-3, 0.0),
        (1e3, 0.0),
        (1e6, 0.0),
        (1.0, 1e5),
        (10.0, 1e5),
    ];
    settings
        .iter()
        .map(|&(scale, offset)| {
            let image = render(&contact_scene(scale, offset));
            let (share, acne, lost, bad) = compare(&reference, &image);
            let mut c = Case::new(
                "geometry",
                "scene vs scale 1 at origin",
                format!("scale {scale:e}, offset {offset:e}"),
            );
            c.evals = image.pixels.len() as u64;
            c.nan = image.pixels.iter().filter(|p| p.is_nan()).count() as u64;
            c.inf = image.pixels.iter().filter(|p| !p.is_nan() && !p.is_finite()).count() as u64;
            c.neg = image.pixels.iter().filter(|p| p.min_element() < 0.0).count() as u64;
            c.f32_value = format!("{}% within 5%", num(100.0 * share));
            c.f64_value = format!("≥ 99% ({acne} acne, {lost} lost shadow px)");
            if share < 0.99 {
                c.fail(format!("only {:.2}% of pixels within 5%", 100.0 * share));
            }
            if bad > 0 {
                c.fail(format!("{bad} non-finite or negative pixels"));
            }
            c
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scene_has_contact_shadows_and_matches_itself_far_away() {
        let reference = render(&contact_scene(1.0, 0.0));
        // The cube casts a shadow onto the lit ground: there are black ground pixels.
        let black = reference.pixels.iter().filter(|p| p.max_element() == 0.0).count();
        assert!(black > 500, "{black}");
        let (share, ..) = compare(&reference, &render(&contact_scene(1.0, 1e5)));
        assert!(share >= 0.99, "{share}");
    }

    #[test]
    fn a_scene_without_shadows_does_not_match() {
        // The comparison can fail: the same scene with shadow rays off differs in the shadow.
        let reference = render(&contact_scene(1.0, 0.0));
        let mut scene = contact_scene(1.0, 0.0);
        scene.shadows = false;
        let (share, _, lost, _) = compare(&reference, &render(&scene));
        assert!(share < 0.99 && lost > 100, "{share} {lost}");
    }
}
