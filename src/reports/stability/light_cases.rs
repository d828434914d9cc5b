//! Light cases: the shader (f32) against the closed form in f64 from the same f32 inputs, for a
//! light at the shaded point, a light inside a closed mesh, and huge and tiny intensities.
//!
//! Documented values: a point at the light's position (r = 0), or so close that r² underflows,
//! receives nothing (the direction is undefined; 0 rather than ∞); irradiance saturates at
//! f32::MAX instead of overflowing, and so does the sum over lights — so huge intensities give a
//! finite, very large radiance, never ∞ or NaN.

use glam::Vec3;

use super::case::{num, rel_err, Case, REL_TOL};
use crate::accel::shadow::SceneExtent;
use crate::accel::shadow::{NoOcclusion, Occluder};
use crate::accel::{Bvh, BvhPreset};
use crate::light::{Falloff, Light, LightKind};
use crate::material::Material;
use crate::scene::procedural;
use crate::shading::convention::ShadingConvention;
use crate::shading::shader::Shader;
use crate::surface::SurfacePoint;

const ALBEDO: f32 = 0.6;

fn point_light(at: Vec3, intensity: f32) -> Light {
    Light {
        kind: LightKind::Point { position: at },
        power: Vec3::splat(intensity),
        falloff: Falloff::InverseSquare,
    }
}

/// A Lambert point at `p` with normal `n`, seen from along the normal.
fn surface(p: Vec3, n: Vec3) -> SurfacePoint {
    SurfacePoint {
        position: p,
        shadow_lift: 0.0,
        geometric_normal: n,
        shading_normal: n,
        uv: Default::default(),
        uv1: Default::default(),
        material: 0,
        to_viewer: n,
    }
}

/// Lambert radiance in f64 from the same f32 inputs: albedo/π · I/d² · cos θ_i.
fn closed_form(sp: &SurfacePoint, lights: &[Light]) -> f64 {
    lights
        .iter()
        .map(|l| {
            let LightKind::Point { position } = l.kind else {
                unreachable!()
            };
            let d = position.as_dvec3() - sp.position.as_dvec3();
            let r2 = d.length_squared();
            if r2 == 0.0 {
                return 0.0;
            }
            let cos = (sp.shading_normal.as_dvec3().dot(d) / r2.sqrt()).max(0.0);
            ALBEDO as f64 / std::f64::consts::PI * l.power.x as f64 / r2 * cos
        })
        .sum()
}

fn shade<O: Occluder>(sp: &SurfacePoint, lights: &[Light], occluder: Option<&O>, unit: f32) -> f64 {
    let materials = [Material::lambert("m", [ALBEDO; 3])];
    let shader = Shader {
        materials: &materials,
        lights,
        occluder,
        extent: SceneExtent {
            unit,
            ..SceneExtent::UNIT
        },
        shadow_offset: Default::default(),
        convention: ShadingConvention::Physical,
        textures: None,
        emission: false,
    };
    shader.shade(sp, &mut 0).x as f64
}

enum Expect {
    /// f32 shader within `REL_TOL` of the f64 closed form.
    ClosedForm,
    /// This documented value (exactly, or ≥ it for "at least").
    Value(f64),
    /// Finite and at least this large (saturation), singular.
    AtLeast(f64, &'static str),
}

fn case(name: &str, inputs: &str, got: f64, reference: f64, expect: Expect) -> Case {
    let mut c = Case::new("light", name, inputs);
    c.count(got);
    c.f32_value = num(got);
    c.f64_value = num(reference);
    c.require_clean();
    match expect {
        Expect::ClosedForm => {
            let rel = rel_err(got, reference);
            c.rel_err = Some(rel);
            if rel > REL_TOL {
                c.fail(format!("relative error {rel:.1e} > {REL_TOL:.0e}"));
            }
        }
        Expect::Value(v) => {
            c.rel_err = Some(rel_err(got, reference));
            if got != v {
                c.fail(format!("expected the documented {}", num(v)));
            }
        }
        Expect::AtLeast(v, why) => {
            if !(got >= v) {
                c.fail(format!("expected a finite value ≥ {}", num(v)));
            }
            c.singular = Some(why.into());
        }
    }
    c
}

/// Every light case.
pub fn run() -> Vec<Case> {
    let mut out = Vec::new();
    let none: Option<&NoOcclusion> = None;
    let p = Vec3::new(0.3, 0.0, -0.2);
    let up = surface(p, Vec3::Y);

    let at = [point_light(p, 5.0)];
    out.push(case(
        "light at the shaded point",
        "r = 0",
        shade(&up, &at, none, 1.0),
        0.0,
        Expect::Value(0.0),
    ));
    let nearly = [point_light(p + Vec3::Y * 1e-30, 5.0)];
    out.push(case(
        "light at r²-underflow distance",
        "r = 1e-30",
        shade(&up, &nearly, none, 1.0),
        0.0,
        Expect::Value(0.0),
    ));
    let close = [point_light(p + Vec3::Y * 1e-3, 5.0)];
    let reference = closed_form(&up, &close);
    out.push(case(
        "light very close",
        "r = 1e-3",
        shade(&up, &close, none, 1.0),
        reference,
        Expect::ClosedForm,
    ));

    // A light inside a closed sphere: the inner surface is lit, the outer surface is not.
    let mesh = procedural::icosphere(4).into_triangle_mesh();
    let bvh = Bvh::build(&mesh, BvhPreset::DEFAULT);
    let inside = [point_light(Vec3::new(0.1, -0.2, 0.05), 3.0)];
    let on = mesh.positions[17];
    let inner = surface(on, -on.normalize());
    let reference = closed_form(&inner, &inside);
    out.push(case(
        "light inside a closed mesh, inner wall",
        "unit icosphere, light off-centre",
        shade(&inner, &inside, Some(&bvh), bvh.scene_unit()),
        reference,
        Expect::ClosedForm,
    ));
    let leaked = shade(&surface(on, on.normalize()), &inside, Some(&bvh), bvh.scene_unit());
    out.push(case(
        "light inside a closed mesh, outer wall",
        "unit icosphere",
        leaked,
        0.0,
        Expect::Value(0.0),
    ));

    for (name, intensity, r) in [
        ("tiny intensity", 1e-30f32, 1.0f32),
        ("subnormal irradiance", 1e-38, 3.0),
        ("huge intensity, far", 1e30, 1e10),
        ("moderate intensity, r = 1e-15", 1.0, 1e-15),
    ] {
        let lights = [point_light(p + Vec3::new(0.3, 1.0, 0.1).normalize() * r, intensity)];
        let inputs = format!("I = {intensity:e}, r = {r:e}");
        out.push(case(
            name,
            &inputs,
            shade(&up, &lights, none, 1.0),
            closed_form(&up, &lights),
            Expect::ClosedForm,
        ));
    }
    let huge = [point_light(p + Vec3::Y * 1e-6, 1e30)];
    out.push(case(
        "huge intensity at r = 1e-6",
        "I = 1e30 (E = 1e42 > f32::MAX)",
        shade(&up, &huge, none, 1.0),
        closed_form(&up, &huge),
        Expect::AtLeast(
            1e37,
            "irradiance saturates at f32::MAX (documented) instead of overflowing to ∞",
        ),
    ));
    let many: Vec<Light> = (0..8)
        .map(|k| point_light(p + Vec3::new(0.0, 1.0, 0.01 * k as f32), 3e38))
        .collect();
    out.push(case(
        "eight lights of 3e38",
        "sum overflows f32",
        shade(&up, &many, none, 1.0),
        closed_form(&up, &many),
        Expect::AtLeast(1e38, "radiance summed over lights saturates at f32::MAX (documented)"),
    ));
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_light_case_passes() {
        for c in super::run() {
            assert!(c.passed(), "{} ({}): {:?}", c.name, c.inputs, c.failure);
        }
    }
}
