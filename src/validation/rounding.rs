//! The rounding band of a comparison: how far agreement with Mitsuba can go where images depend
//! on the last bit of the texture coordinates.
//!
//! Two renderers interpolate texture coordinates in their own order of operations (and from
//! barycentrics their own intersection tests computed), so the coordinates a texture is looked
//! up at differ by an ulp or so. At pixel centres that is enough to move a normal-mapped metal
//! highlight by more than the 1e-3 tolerance: on DamagedHelmet, pointshade against *itself* with
//! every vertex's texture coordinates one ulp up or down moves more pixels beyond 1e-3 than
//! disagree with Mitsuba, and more than the 0.1% that the 99.9% requirement allows
//! (docs/performance-log.md).
//!
//! So for scenes whose render samples textures, a pixel also agrees when Mitsuba is within
//! tolerance of pointshade's render with the vertices' texture coordinates one ulp up or one
//! ulp down ([`nudged_texture_coordinates`], [`within_band`]). The band is one ulp wide: any
//! texture mistake worth the name (a flipped v, a missing transform, a wrong tangent sign)
//! moves far more than one ulp and still fails (the README's broken-on-purpose checks).

use crate::film::compare::Comparison;
use crate::plan::RenderPlan;
use crate::scene::Scene;

/// `scene` with every texture coordinate of both sets moved to the next float up (`up`) or
/// down, or `None` when no rendered material samples a texture (then coordinates play no part).
pub fn nudged_texture_coordinates(scene: &Scene, up: bool) -> Option<Scene> {
    let mesh = &scene.mesh;
    if !RenderPlan::new(scene, &[]).uvs || (mesh.uvs.is_none() && mesh.uvs1.is_none()) {
        return None;
    }
    let step = |x: f32| if up { x.next_up() } else { x.next_down() };
    let mut nudged = scene.clone();
    for set in [&mut nudged.mesh.uvs, &mut nudged.mesh.uvs1].into_iter().flatten() {
        for uv in set.iter_mut() {
            *uv = uv.map(step);
        }
    }
    Some(nudged)
}

/// The share of pixels whose relative error is within `c`'s tolerance in `c` or in one of the
/// comparisons `nudged` of the same reference (renders of the nudged scenes).
pub fn within_band(c: &Comparison, nudged: &[Comparison]) -> f64 {
    let within = (0..c.relative_errors.len())
        .filter(|&i| {
            let best = nudged
                .iter()
                .map(|n| n.relative_errors[i])
                .fold(c.relative_errors[i], f32::min);
            best <= c.tolerance
        })
        .count();
    within as f64 / c.relative_errors.len().max(1) as f64
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::film::compare::compare;
    use crate::film::Image;
    use crate::material::Material;
    use crate::reports::stability::scale_cases::contact_scene;
    use crate::texture::{TextureImage, TextureRef};

    fn image(values: &[f32]) -> Image {
        let mut img = Image::new(values.len() as u32, 1);
        for (p, &v) in img.pixels.iter_mut().zip(values) {
            *p = Vec3::splat(v);
        }
        img
    }

    #[test]
    fn a_pixel_agrees_when_a_nudged_render_agrees() {
        let reference = image(&[1.0, 1.0, 1.0, 1.0]);
        let ours = compare(&image(&[1.0, 1.1, 1.1, 1.1]), &reference, 1e-3, 0);
        let up = compare(&image(&[1.1, 1.0, 1.1, 1.1]), &reference, 1e-3, 0);
        let down = compare(&image(&[1.1, 1.1, 1.0, 1.1]), &reference, 1e-3, 0);
        assert_eq!(ours.within_tolerance, 0.25);
        assert_eq!(within_band(&ours, &[up, down]), 0.75);
        assert_eq!(within_band(&ours, &[]), 0.25);
    }

    #[test]
    fn texture_coordinates_move_by_one_ulp_and_only_where_textures_are_sampled() {
        let mut scene = contact_scene(1.0, 0.0);
        let n = scene.mesh.positions.len();
        scene.mesh.uvs = Some((0..n).map(|i| Vec2::new(i as f32 / n as f32, 0.5)).collect());
        // Lambert materials sample no texture: the coordinates play no part.
        assert!(nudged_texture_coordinates(&scene, true).is_none());
        let mut textured = Material::gltf_pbr("textured", [1.0; 3], 0.0, 0.5);
        textured.textures.base_color = Some(TextureRef::gltf_default(0));
        scene.materials[0] = textured;
        scene.textures = vec![TextureImage {
            label: "white".into(),
            width: 1,
            height: 1,
            texels: vec![[255; 4]],
        }];
        let original = scene.mesh.uvs.clone().unwrap();
        for up in [true, false] {
            let nudged = nudged_texture_coordinates(&scene, up).expect("a texture is sampled");
            assert!(nudged.mesh.uvs1.is_none());
            for (a, b) in original.iter().zip(nudged.mesh.uvs.unwrap()) {
                let expected = if up { a.map(f32::next_up) } else { a.map(f32::next_down) };
                assert_eq!(b, expected);
                assert_ne!(b, *a);
            }
        }
        scene.mesh.uvs = None;
        assert!(
            nudged_texture_coordinates(&scene, true).is_none(),
            "no coordinates to move"
        );
    }
}
