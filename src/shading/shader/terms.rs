//! The Cook-Torrance terms D, G and F of one (n, ω_i, ω_o), beside f_r: what the Python
//! module's `eval_terms` returns and what the explorer plots as separate curves.

use crate::material::{BrdfModel, Material};

use super::shading_dots;

/// D, G and F of a Cook-Torrance material at one pair of directions, with f_r.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CookTorranceTerms {
    /// The normal distribution D(ω_h) its `d` key names.
    pub d: f64,
    /// The masking-shadowing G(ω_i, ω_o) its `g` key names.
    pub g: f64,
    /// The Fresnel factor F(ω_i·ω_h) its `fresnel` key names, per channel.
    pub f: [f64; 3],
    /// f_r, as [`super::brdf_value`] gives it.
    pub f_r: [f64; 3],
}

/// The terms of `material` (which must be Cook-Torrance, else `None`) for the shading normal `n`
/// and unit directions `wi` (to the light) and `wo` (to the viewer), of the dot products the
/// shader forms: a two-sided material turns `n` towards ω_o first. Where f_r is 0 because a
/// direction is below the surface or there is no shading frame (ω_i = −ω_o), so are D, G and F.
pub fn cook_torrance_terms(material: &Material, n: [f64; 3], wi: [f64; 3], wo: [f64; 3]) -> Option<CookTorranceTerms> {
    let BrdfModel::CookTorrance(ct) = &material.model else {
        return None;
    };
    let Some(dots) = shading_dots(material, n, wi, wo) else {
        return Some(CookTorranceTerms::default());
    };
    let alpha = ct.alpha as f64;
    Some(CookTorranceTerms {
        d: ct.d.eval(dots.n_dot_h, dots.sin2_h, alpha),
        g: ct.g.g(dots.n_dot_i, dots.n_dot_o, alpha),
        f: ct.fresnel(dots.i_dot_h),
        f_r: material.eval(&dots),
    })
}
