use super::*;
use crate::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use crate::light::{Falloff, LightKind, SpotProfile};
use crate::material::BrdfModel;
use crate::material::{BlinnPhong, CookTorrance};
use glam::Vec2;

/// Every model and term combination the shader can meet.
pub(super) fn materials() -> Vec<Material> {
    let mut all = vec![Material::lambert("lambert", [0.4, 0.7, 0.4])];
    let mut bp = all[0].clone();
    bp.model = BrdfModel::BlinnPhong(BlinnPhong {
        ks: 0.8,
        shininess: 40.0,
        color: [1.0, 0.9, 0.8],
    });
    all.push(bp);
    for d in MicrofacetDistribution::ALL {
        for g in MaskingShadowing::ALL {
            for f in FresnelTerm::ALL {
                let mut m = all[0].clone();
                m.model = BrdfModel::CookTorrance(CookTorrance {
                    d: *d,
                    g: *g,
                    f: *f,
                    alpha: 0.3,
                    metallic: true,
                    specular_color: [0.98, 0.82, 0.76],
                    ..CookTorrance::DEFAULT
                });
                all.push(m);
            }
        }
    }
    all.push(Material::gltf_pbr("pbr", [0.8, 0.5, 0.2], 0.6, 0.4));
    all
}

/// Points with every kind of input: ordinary ones, n = 0, a normal longer than 1, the light
/// at the point, the viewer at the point, and ω_i = −ω_o (no half vector).
pub(super) fn points() -> Vec<SurfacePoint> {
    let light = Vec3::new(0.0, 1.0, 1.0);
    let point = |position: Vec3, n: Vec3, to_viewer: Vec3| SurfacePoint {
        position,
        shadow_lift: 0.0,
        geometric_normal: Vec3::Z,
        shading_normal: n,
        uv: Vec2::ZERO,
        uv1: Vec2::ZERO,
        material: 0,
        to_viewer,
    };
    let mut v: Vec<SurfacePoint> = (0..21)
        .map(|k| {
            let t = k as f32 * 0.3;
            let n = Vec3::new(t.sin() * 0.6, t.cos() * 0.5, 0.7 + 0.1 * t);
            point(
                Vec3::new(t, 2.0 - t, 0.1 * t),
                n,
                Vec3::new(0.3, t.cos(), 0.8).normalize(),
            )
        })
        .collect();
    v.push(point(Vec3::new(3.0, 1.0, 0.0), Vec3::ZERO, Vec3::Z));
    v.push(point(Vec3::new(3.0, 1.0, 0.0), Vec3::new(0.9, 1.1, 0.8), Vec3::Z));
    v.push(point(light, Vec3::Z, Vec3::Z));
    v.push(point(Vec3::ZERO, Vec3::Z, Vec3::ZERO));
    v.push(point(Vec3::new(2.0, 0.5, 0.0), Vec3::new(f32::NAN, 0.0, 1.0), Vec3::Z));
    // Normals facing away from the viewer (a two-sided material turns them around).
    v.push(point(Vec3::new(1.0, 3.0, 0.5), Vec3::new(0.1, -0.2, -0.9), Vec3::Z));
    v.push(point(
        Vec3::new(-1.0, 2.0, 0.0),
        Vec3::new(0.0, 0.6, -0.8),
        Vec3::new(0.0, 0.6, 0.8),
    ));
    // ω_i (from the light towards the point) = −ω_o.
    let p = Vec3::new(0.0, 0.0, 0.0);
    v.push(point(p, Vec3::Y, (light - p).normalize()));
    v
}

/// A point light, a spot light of each profile and a directional light.
pub(super) fn lights() -> [Light; 4] {
    [
        Light {
            kind: LightKind::Point {
                position: Vec3::new(0.0, 1.0, 1.0),
            },
            power: Vec3::splat(0.5),
            falloff: Falloff::None,
        },
        Light {
            kind: LightKind::Spot {
                position: Vec3::new(1.0, 4.0, 2.0),
                direction: Vec3::new(0.0, -1.0, -0.2).normalize(),
                cos_inner: 0.9,
                cos_outer: 0.5,
                profile: SpotProfile::Gltf,
            },
            power: Vec3::new(3.0, 2.0, 1.0),
            falloff: Falloff::InverseSquareWithin { range: 6.0 },
        },
        Light {
            kind: LightKind::Spot {
                position: Vec3::new(-1.0, 4.0, 2.0),
                direction: Vec3::new(0.0, -1.0, -0.2).normalize(),
                cos_inner: 0.9,
                cos_outer: 0.5,
                profile: SpotProfile::Mitsuba,
            },
            power: Vec3::new(1.0, 2.0, 3.0),
            falloff: Falloff::InverseSquare,
        },
        Light {
            kind: LightKind::Directional {
                direction: Vec3::new(0.2, -1.0, -0.3).normalize(),
            },
            power: Vec3::ONE,
            falloff: Falloff::InverseSquare,
        },
    ]
}

/// Blocks a segment by a fixed rule of its origin and direction (about half of them), and
/// counts the segments it was asked about.
pub(super) struct HalfOccluder(pub(super) std::sync::atomic::AtomicUsize);

impl Occluder for HalfOccluder {
    fn occluded(&self, ray: &ShadowRay) -> bool {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        (ray.origin.x + 2.0 * ray.direction.y).sin() > 0.0
    }
}

/// Every third material of [`materials`], each one-sided and two-sided.
pub(super) fn batch_materials() -> Vec<Material> {
    let mut materials: Vec<Material> = materials().into_iter().step_by(3).collect();
    let n = materials.len();
    for k in 0..n {
        let mut other = materials[k].clone();
        other.two_sided = !other.two_sided;
        materials.push(other);
    }
    materials
}

/// The physical shader of `materials` under `lights`, with `occluder`.
pub(super) fn physical<'a, O: Occluder>(
    materials: &'a [Material],
    lights: &'a [Light],
    occluder: &'a O,
) -> Shader<'a, O> {
    Shader {
        materials,
        lights,
        occluder: Some(occluder),
        extent: SceneExtent::UNIT,
        convention: ShadingConvention::Physical,
        textures: None,
        emission: false,
        shadow_offset: Default::default(),
    }
}

/// Asserts that `got[k]` is, bit for bit, what `shade` gives `batch[k]`.
pub(super) fn assert_shaded_as_one_by_one(shader: &Shader<HalfOccluder>, batch: &[SurfacePoint], got: &[Vec3]) {
    for (p, got) in batch.iter().zip(got) {
        let one = shader.shade(p, &mut 0);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        assert_eq!(bits(*got), bits(one), "{p:?}");
    }
}

/// `brdf_value` is the f_r the shader uses: under one directional light, every point's
/// radiance is f_r · E · cos θ_i with f_r from `brdf_value`, bit for bit, for every model,
/// both sides and the degenerate points.
#[test]
fn brdf_value_is_what_the_shader_multiplies() {
    let light = &lights()[3..];
    for material in batch_materials() {
        let materials = [material];
        let shader = physical(&materials, light, &crate::accel::shadow::NoOcclusion);
        for p in points() {
            let ls = light[0]
                .sample(p.position)
                .expect("a directional light reaches everywhere");
            let n = p.shading_normal;
            let f = brdf_value(&materials[0], n.to_array(), ls.wi.to_array(), p.to_viewer.to_array());
            let n = if materials[0].two_sided && n.dot(p.to_viewer) < 0.0 {
                -n
            } else {
                n
            };
            let cos_i = n.dot(ls.wi).max(0.0);
            let expected = Vec3::from(reflected_radiance(f, ls.irradiance.to_array(), cos_i));
            let got = shader.shade(&p, &mut 0);
            assert_eq!(
                got.to_array().map(f32::to_bits),
                expected.to_array().map(f32::to_bits),
                "{p:?}"
            );
        }
    }
}

/// Blocks nothing and records every shadow ray.
struct RayRecorder(std::sync::Mutex<Vec<ShadowRay>>);

impl Occluder for RayRecorder {
    fn occluded(&self, ray: &ShadowRay) -> bool {
        self.0.lock().unwrap().push(*ray);
        false
    }
}

impl RayRecorder {
    /// The rays `shade` traced, taken out of the record.
    fn rays(&self, shade: &dyn Fn()) -> Vec<ShadowRay> {
        shade();
        std::mem::take(&mut *self.0.lock().unwrap())
    }
}

#[test]
fn shadow_rays_start_lifted_in_front_of_the_normals_and_unlifted_behind_them() {
    let light = |y: f32| Light {
        kind: LightKind::Point {
            position: Vec3::new(0.0, y, 0.0),
        },
        power: Vec3::ONE,
        falloff: Falloff::InverseSquare,
    };
    // A two-sided surface at the origin facing +y, lifted by 0.25, with a light on each side.
    let (lights, materials) = ([light(5.0), light(-5.0)], [Material::lambert("m", [0.5; 3])]);
    assert!(materials[0].two_sided);
    let occluder = RayRecorder(Default::default());
    let shader = physical(&materials, &lights, &occluder);
    let front = SurfacePoint {
        position: Vec3::ZERO,
        shadow_lift: 0.25,
        geometric_normal: Vec3::Y,
        shading_normal: Vec3::Y,
        uv: Vec2::ZERO,
        uv1: Vec2::ZERO,
        material: 0,
        to_viewer: Vec3::Y,
    };
    // Seen from below, the material turns the normals down: the light below is the lit one,
    // and a lift (towards +y, where the normals bulge) would start its ray through the surface.
    let behind = SurfacePoint {
        to_viewer: Vec3::NEG_Y,
        ..front
    };
    let origins = |shade: &dyn Fn()| -> Vec<Vec3> { occluder.rays(shade).iter().map(|r| r.origin).collect() };
    let lifted = |o: &Vec3| (o.y - 0.25).abs() < 1e-3 && o.x == 0.0 && o.z == 0.0;
    let on_the_surface = |o: &Vec3| o.y < 0.0 && o.y > -1e-3 && o.x == 0.0 && o.z == 0.0;
    // One point at a time…
    let one = origins(&|| {
        shader.shade(&front, &mut 0);
    });
    assert!(one.len() == 1 && lifted(&one[0]), "{one:?}");
    let one = origins(&|| {
        shader.shade(&behind, &mut 0);
    });
    assert!(one.len() == 1 && on_the_surface(&one[0]), "{one:?}");
    // …and eight at a time on lanes, both kinds in one batch.
    let batch: Vec<SurfacePoint> = (0..16).map(|i| if i % 2 == 0 { front } else { behind }).collect();
    let lanes = origins(&|| {
        let mut out = vec![Vec3::ZERO; batch.len()];
        assert!(
            shader.shade_batch_lanes(&batch, &mut out, &mut 0),
            "the batch goes on lanes"
        );
    });
    assert_eq!(lanes.iter().filter(|o| lifted(o)).count(), 8, "{lanes:?}");
    assert_eq!(lanes.iter().filter(|o| on_the_surface(o)).count(), 8, "{lanes:?}");
}

#[test]
fn with_the_mitsuba_offset_a_directional_lights_ray_ends_where_mitsuba_aims_it() {
    let lights = [Light {
        kind: LightKind::Directional {
            direction: Vec3::new(0.0, -1.0, 0.0),
        },
        power: Vec3::ONE,
        falloff: Falloff::None,
    }];
    let materials = [Material::lambert("m", [0.5; 3])];
    let occluder = RayRecorder(Default::default());
    let mut shader = physical(&materials, &lights, &occluder);
    shader.extent = SceneExtent {
        centre: Vec3::new(0.0, 0.0, 1.0),
        radius: 3.0,
        ..SceneExtent::UNIT
    };
    let point = |x: f32| SurfacePoint {
        position: Vec3::new(x, 0.0, 0.0),
        shadow_lift: 0.0,
        // Tilted, so that the offset origin leaves the line along ω_i.
        geometric_normal: Vec3::new(0.6, 0.8, 0.0),
        shading_normal: Vec3::Y,
        uv: Vec2::ZERO,
        uv1: Vec2::ZERO,
        material: 0,
        to_viewer: Vec3::Y,
    };
    // pointshade's own offset: the ray runs to infinity along ω_i.
    let own = occluder.rays(&|| {
        shader.shade(&point(1.0), &mut 0);
    });
    assert!(own[0].t_max.is_infinite() && own[0].direction == Vec3::Y, "{own:?}");
    // Mitsuba's: towards p + ω_i·2·max(R, |p − c|), from its offset origin, one point at a
    // time and on lanes. Inside the sphere that is 2R = 6; far from it, twice the distance.
    shader.shadow_offset = ShadowOffset::Mitsuba;
    for (x, expected) in [(1.0f32, 6.0f32), (10.0, 2.0 * 101.0f32.sqrt())] {
        let batch = [point(x); 8];
        let rays = occluder.rays(&|| {
            shader.shade(&batch[0], &mut 0);
            assert!(shader.shade_batch_lanes(&batch, &mut [Vec3::ZERO; 8], &mut 0));
        });
        assert_eq!(rays.len(), 9);
        for r in &rays {
            let end = r.origin + r.direction * r.t_max;
            assert!((end - Vec3::new(x, expected, 0.0)).length() < 1e-3 * expected, "{r:?}");
            assert!(r.direction.x.abs() < 1e-3 && r.direction != Vec3::Y, "re-aimed: {r:?}");
        }
    }
}

#[test]
fn a_batch_shades_exactly_as_one_point_at_a_time() {
    let (lights, materials) = (lights(), batch_materials());
    let occluder = HalfOccluder(Default::default());
    let shader = physical(&materials, &lights, &occluder);
    // Every point with every material, material by material (batches of one or two
    // materials: lanes) and point by point (a material per point: point by point).
    let nm = materials.len() as u32;
    let with = |m: u32, p: SurfacePoint| SurfacePoint { material: m, ..p };
    let by_material: Vec<_> = (0..nm)
        .flat_map(|m| points().into_iter().map(move |p| with(m, p)))
        .collect();
    let interleaved: Vec<_> = points()
        .into_iter()
        .flat_map(|p| (0..nm).map(move |m| with(m, p)))
        .collect();
    let (mut blocked, mut open) = (0, 0);
    // Batches of every size up to past two packets.
    for (points, size) in [by_material, interleaved]
        .iter()
        .flat_map(|p| (1..=2 * BATCH + 1).map(move |s| (p, s)))
    {
        for batch in points.chunks(size) {
            let mut got = vec![Vec3::NAN; batch.len()];
            let mut batch_rays = 0;
            shader.shade_batch(batch, &mut got, &mut batch_rays);
            let asked = occluder.0.swap(0, std::sync::atomic::Ordering::Relaxed);
            assert_shaded_as_one_by_one(&shader, batch, &got);
            // The shadow rays the points take one by one.
            let mut one_rays = 0;
            for p in batch {
                shader.shade(p, &mut one_rays);
            }
            assert_eq!(batch_rays, one_rays, "shadow rays counted");
            assert_eq!(asked as u64, batch_rays, "the occluder answered each ray once");
            occluder.0.store(0, std::sync::atomic::Ordering::Relaxed);
            let lit = got.iter().filter(|r| r.max_element() > 0.0).count();
            (open, blocked) = (open + lit, blocked + got.len() - lit);
        }
    }
    assert!(open > 1000 && blocked > 1000, "{open} lit, {blocked} dark");
}
