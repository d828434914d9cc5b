//! What the explorer's plots show, evaluated by the shader's own functions: f_r in the plane of
//! incidence with its Cook-Torrance terms, f_r over the hemisphere, the directional albedo
//! against θ_i, and a sphere shaded in the normal-map mode. Directions are in the local frame of
//! a surface whose normal is +z; angles are in degrees.

use std::path::Path;

use glam::Vec3;
use rayon::prelude::*;

use crate::light::{Falloff, Light, LightKind};
use crate::material::{BrdfModel, Material};
use crate::normal_map;
use crate::normal_map::image::{NormalImage, Samples, UnitSample};
use crate::normal_map::scene_file::{NormalMapScene, Preset};
use crate::output::{encode, Format};
use crate::shading::shader::{brdf_value, cook_torrance_terms};

/// The unit direction at polar angle `theta` from +z and azimuth `phi` from +x, in degrees.
pub fn direction(theta: f64, phi: f64) -> [f64; 3] {
    let (st, ct) = theta.to_radians().sin_cos();
    let (sp, cp) = phi.to_radians().sin_cos();
    [st * cp, st * sp, ct]
}

/// Rec. 709 luminance, the one number the lobe and albedo plots draw of an RGB value.
pub fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// f_r and its terms along the plane of incidence.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarCurves {
    /// θ_o from −90° to 90°: positive on ω_i's side of the normal, so the mirror direction is at
    /// −θ_i.
    pub theta_o: Vec<f64>,
    /// f_r at each θ_o.
    pub f_r: Vec<[f64; 3]>,
    /// f_r · cos θ_o.
    pub f_r_cos: Vec<[f64; 3]>,
    /// D, G and F at each θ_o, for a Cook-Torrance material.
    pub terms: Option<TermCurves>,
}

/// The Cook-Torrance terms along the plane of incidence: D, G and F (per channel).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TermCurves {
    /// D(ω_h) at each θ_o.
    pub d: Vec<f64>,
    /// G(ω_i, ω_o) at each θ_o.
    pub g: Vec<f64>,
    /// F(ω_i·ω_h) at each θ_o.
    pub f: Vec<[f64; 3]>,
}

/// f_r of `material` towards `wi` (a unit direction) for `samples` directions ω_o evenly spaced
/// in the plane that holds the normal and ω_i (the x–z plane at normal incidence).
pub fn polar(material: &Material, wi: [f64; 3], samples: usize) -> PolarCurves {
    let n = [0.0, 0.0, 1.0];
    let phi = match wi[0].hypot(wi[1]) > 1e-12 {
        true => wi[1].atan2(wi[0]).to_degrees(),
        false => 0.0,
    };
    let steps = samples.max(2) - 1;
    let theta_o: Vec<f64> = (0..=steps).map(|s| -90.0 + 180.0 * s as f64 / steps as f64).collect();
    let mut curves = PolarCurves {
        theta_o: theta_o.clone(),
        f_r: Vec::with_capacity(samples),
        f_r_cos: Vec::with_capacity(samples),
        terms: matches!(material.model, BrdfModel::CookTorrance(_)).then(Default::default),
    };
    for &t in &theta_o {
        let wo = direction(t, phi);
        let f = brdf_value(material, n, wi, wo);
        curves.f_r.push(f);
        curves.f_r_cos.push(f.map(|c| c * wo[2].max(0.0)));
        if let (Some(curves), Some(terms)) = (&mut curves.terms, cook_torrance_terms(material, n, wi, wo)) {
            curves.d.push(terms.d);
            curves.g.push(terms.g);
            curves.f.push(terms.f);
        }
    }
    curves
}

/// Luminance of f_r over the hemisphere of ω_o for `wi`: at θ_o = 90°·j/`theta_steps` (j from 0
/// to `theta_steps`) and φ_o = 360°·k/`phi_steps` (k below `phi_steps`), row-major in j.
pub fn lobe(material: &Material, wi: [f64; 3], theta_steps: usize, phi_steps: usize) -> Vec<f64> {
    let n = [0.0, 0.0, 1.0];
    (0..=theta_steps)
        .flat_map(|j| (0..phi_steps).map(move |k| (j, k)))
        .map(|(j, k)| {
            let wo = direction(
                90.0 * j as f64 / theta_steps.max(1) as f64,
                360.0 * k as f64 / phi_steps.max(1) as f64,
            );
            luminance(brdf_value(material, n, wi, wo))
        })
        .collect()
}

/// Cells of each half-vector grid [`albedo`] sums over, along θ_h and along φ_h.
const ALBEDO_CELLS: (usize, usize) = (128, 128);

/// The directional albedo ∫ f_r cos θ_o dω_o of `material` at each of `theta_i` (degrees), RGB.
///
/// The integral is taken over the half vector ω_h, where a microfacet lobe is compact: ω_o is ω_i
/// reflected about ω_h, dω_o = 4 (ω_i·ω_h) dω_h (Walter et al. 2007, eq. 14). Two grids of equal
/// probability cells share the work, one under the GGX distribution of the material's width α
/// (so that its cells follow a peak however narrow) and one under α = 1 (the whole hemisphere,
/// for the diffuse part): the deterministic form of the balance heuristic (Veach 1997, ch. 9),
/// Σ g/(p₁ + p₂) over both grids' cell centres divided by the cells per grid, with p the
/// densities of ω_h the grids follow, D(ω_h)·cos θ_h. The unit tests hold the result to a
/// Lambert material's albedo and to energy conservation down to α = 0.005.
pub fn albedo(material: &Material, theta_i: &[f64]) -> Vec<[f64; 3]> {
    let alpha = match &material.model {
        BrdfModel::CookTorrance(ct) => (ct.alpha as f64).clamp(1e-3, 1.0),
        // Blinn-Phong's exponent s is like a Beckmann lobe of α² = 2/(s + 2) (Walter et al. 2007).
        BrdfModel::BlinnPhong(bp) => (2.0 / (bp.shininess as f64 + 2.0)).sqrt().clamp(1e-3, 1.0),
        _ => 1.0,
    };
    let widths: &[f64] = match alpha < 1.0 {
        true => &[alpha, 1.0],
        false => &[1.0],
    };
    // D_GGX(ω_h)·cos θ_h, the density of ω_h under the GGX distribution of width `a`.
    let density = |a: f64, cos_h: f64| {
        let s = 1.0 + (a * a - 1.0) * cos_h * cos_h;
        a * a * cos_h / (std::f64::consts::PI * s * s)
    };
    let cells = (ALBEDO_CELLS.0 * ALBEDO_CELLS.1) as f64;
    theta_i
        .par_iter()
        .map(|&t| {
            let wi = direction(t, 0.0);
            let mut sum = [0.0f64; 3];
            for &a in widths {
                half_vector_grid(a, |h| {
                    let i_dot_h = wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2];
                    let wo = [0, 1, 2].map(|c| 2.0 * i_dot_h * h[c] - wi[c]);
                    if i_dot_h <= 0.0 || wo[2] <= 0.0 {
                        return;
                    }
                    let f = brdf_value(material, [0.0, 0.0, 1.0], wi, wo);
                    let p: f64 = widths.iter().map(|&b| density(b, h[2])).sum();
                    let weight = wo[2] * 4.0 * i_dot_h / (p * cells);
                    for c in 0..3 {
                        sum[c] += f[c] * weight;
                    }
                });
            }
            sum
        })
        .collect()
}

/// Calls `cell(ω_h)` at the centre of each cell of a grid of equal-probability cells under the
/// GGX distribution of width `alpha`: tan θ_h = α √(u/(1 − u)) (the distribution's inverse
/// cumulative) and φ_h = 2πv, at evenly spaced u and v.
fn half_vector_grid(alpha: f64, mut cell: impl FnMut([f64; 3])) {
    let (nu, nphi) = ALBEDO_CELLS;
    for e in 0..nu {
        let u = (e as f64 + 0.5) / nu as f64;
        let theta_h = (alpha * (u / (1.0 - u)).sqrt()).atan().to_degrees();
        for k in 0..nphi {
            cell(direction(theta_h, 360.0 * (k as f64 + 0.5) / nphi as f64));
        }
    }
}

/// A `size` × `size` PNG of a unit sphere seen along −z (x right, y up), shaded by `material`
/// under a directional light from `wi` of irradiance π — a white Lambert surface facing it is 1
/// — in the normal-map mode's physical preset, sRGB at exposure 0.
pub fn lit_sphere(material: &Material, wi: [f64; 3], size: u32) -> Result<Vec<u8>, String> {
    let size = size.clamp(8, 1024);
    let half = size as f64 / 2.0;
    let samples: Vec<[UnitSample; 4]> = (0..size * size)
        .map(|i| {
            let (col, row) = (i % size, i / size);
            let x = (col as f64 + 0.5 - half) / half;
            let y = (half - row as f64 - 0.5) / half;
            let r2 = x * x + y * y;
            match r2 < 1.0 {
                true => {
                    let z = (1.0 - r2).sqrt();
                    let s = |v: f64| UnitSample(((v + 1.0) / 2.0) as f32);
                    [s(x), s(y), s(z), UnitSample(1.0)]
                }
                false => [UnitSample(0.5), UnitSample(0.5), UnitSample(1.0), UnitSample(0.0)],
            }
        })
        .collect();
    let source = Path::new("lit sphere");
    let image = NormalImage::from_samples(source, size, size, Samples::Float(samples.into()), true)
        .map_err(|e| e.to_string())?;
    let wi = Vec3::from(wi.map(|c| c as f32));
    let mut scene = NormalMapScene::from_preset(source, Preset::Physical, crate::scene::file::ModelName::Lambert);
    scene.material = material.clone();
    scene.lights = vec![Light {
        kind: LightKind::Directional { direction: -wi },
        power: Vec3::splat(std::f32::consts::PI),
        falloff: Falloff::None,
    }];
    let shaded = normal_map::shade(&scene, &image, "the explorer's lit sphere").map_err(|e| e.to_string())?;
    encode(&shaded.radiance, Format::Png, 0.0)
}

#[cfg(test)]
mod tests;
