//! Materials as BSDFs: Mitsuba's own where one computes exactly pointshade's model (`diffuse`,
//! with a `bitmap` reflectance where exact; `roughconductor`; `twosided` around them), the
//! `pointshade` plugin ([`super::pointshade_bsdf`]) elsewhere.

use super::pointshade_bsdf::plugin_bsdf;
use crate::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use crate::material::{BrdfModel, Material};
use crate::texture::{Filter, TextureImage, TextureRef, Wrap};
use crate::validation::textures;
use crate::validation::xml::{rgb, xml_escape};

/// Which BSDFs the export uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BsdfChoice {
    /// Mitsuba's own BSDF where one is exact, the plugin elsewhere.
    #[default]
    NativeWhereExact,
    /// The plugin for every material (to check the plugin against Mitsuba's own BSDFs).
    PluginEverywhere,
}

/// Whether Mitsuba's `roughconductor` computes exactly this Cook-Torrance lobe.
fn is_roughconductor(m: &Material) -> bool {
    match &m.model {
        BrdfModel::CookTorrance(ct) => {
            m.kd == 0.0
                && ct.d == MicrofacetDistribution::Ggx
                && ct.g == MaskingShadowing::SmithGgx
                && matches!(ct.f, FresnelTerm::Conductor | FresnelTerm::Constant)
                && ct.specular_color.iter().all(|&c| c <= 1.0)
        }
        _ => false,
    }
}

/// The BSDF of material `index` (id `mat{index}`), and how it was mapped.
pub(super) fn bsdf(
    index: usize,
    m: &Material,
    choice: BsdfChoice,
    images: &[TextureImage],
    prefix: &str,
) -> (String, &'static str) {
    let diffuse_reflectance = m.albedo.map(|a| a * m.kd);
    let native = choice == BsdfChoice::NativeWhereExact;
    let (inner, note) = if let Some(r) = albedo_bitmap(m, choice) {
        let wrap = match r.wrap_u {
            Wrap::Repeat => "repeat",
            Wrap::MirroredRepeat => "mirror",
            Wrap::ClampToEdge => "clamp",
        };
        (
            format!(
                "<bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\"><string name=\"filename\" value=\"{}\"/><string name=\"filter_type\" value=\"bilinear\"/><string name=\"wrap_mode\" value=\"{wrap}\"/></texture></bsdf>",
                xml_escape(&textures::png_file_name(prefix, r.image as usize))
            ),
            "Mitsuba diffuse with a bitmap reflectance (exact)",
        )
    } else if native && !m.has_specular() && !m.varies_brdf() && diffuse_reflectance.iter().all(|&r| r <= 1.0) {
        (
            format!(
                "<bsdf type=\"diffuse\">{}</bsdf>",
                rgb("reflectance", diffuse_reflectance)
            ),
            "Mitsuba diffuse (exact)",
        )
    } else if let (true, true, BrdfModel::CookTorrance(ct)) = (native, is_roughconductor(m), &m.model) {
        let (eta, k) = match ct.f {
            FresnelTerm::Conductor => (ct.eta, ct.k),
            // Mitsuba's "none" conductor: η = 0, κ = 1 gives F ≡ 1, then × specular_reflectance.
            _ => ([0.0; 3], [1.0; 3]),
        };
        (
            format!(
                "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"{}\"/>{}{}{}</bsdf>",
                ct.alpha,
                rgb("eta", eta),
                rgb("k", k),
                rgb("specular_reflectance", ct.specular_color)
            ),
            "Mitsuba roughconductor (exact)",
        )
    } else {
        (
            plugin_bsdf(m, images, prefix),
            "pointshade BSDF plugin (exact by construction)",
        )
    };
    let wrapped = if m.two_sided && !textures::plugin_handles_sides(m) {
        format!("<bsdf type=\"twosided\">{inner}</bsdf>")
    } else {
        inner
    };
    // Give the outermost BSDF the id.
    let with_id = wrapped.replacen("<bsdf type=", &format!("<bsdf id=\"mat{index}\" type="), 1);
    (format!("  {with_id}"), note)
}

/// The albedo texture of `m` when Mitsuba's `diffuse` BSDF with a `bitmap` reflectance computes
/// exactly what pointshade does: a Lambert material with k_d·albedo = 1 (the bitmap has no
/// factor), texture-coordinate set 0 (the mesh's, which Mitsuba reads from the OBJ with the same
/// v flip), bilinear filtering, the same wrapping both ways and no transform.
pub(super) fn albedo_bitmap(m: &Material, choice: BsdfChoice) -> Option<TextureRef> {
    let r = m.textures.base_color?;
    let unit = m.albedo.iter().all(|&a| a * m.kd == 1.0);
    let plain = r.tex_coord == 0 && r.filter == Filter::Bilinear && r.transform.is_none() && r.wrap_u == r.wrap_v;
    (choice == BsdfChoice::NativeWhereExact && !m.has_specular() && unit && plain).then_some(r)
}
