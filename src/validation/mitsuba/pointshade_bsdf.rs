//! The `pointshade` BSDF plugin's element: every parameter of pointshade's model, for
//! validation/pointshade_bsdf.py, which re-implements its formulas in Dr.Jit, so that every
//! model can be validated.

use std::fmt::Write as _;

use crate::material::{BrdfModel, Material};
use crate::texture::TextureImage;
use crate::validation::textures;
use crate::validation::xml::rgb;

/// `m` as a `pointshade` BSDF, its textures named as the export writes them (`prefix`).
pub(super) fn plugin_bsdf(m: &Material, images: &[TextureImage], prefix: &str) -> String {
    let mut p = format!(
        "<bsdf type=\"pointshade\"><string name=\"model\" value=\"{}\"/>{}<float name=\"kd\" value=\"{}\"/>",
        m.model_name(),
        rgb("albedo", m.albedo),
        m.kd
    );
    if !matches!(m.model, BrdfModel::GltfPbr(_)) {
        p.push_str(&textures::brdf_texture_properties(m, images, prefix));
    }
    match &m.model {
        BrdfModel::Lambert => {}
        BrdfModel::BlinnPhong(bp) => {
            let _ = write!(
                p,
                "<float name=\"ks\" value=\"{}\"/><float name=\"shininess\" value=\"{}\"/>{}",
                bp.ks,
                bp.shininess,
                rgb("specular_color", bp.color)
            );
        }
        BrdfModel::CookTorrance(ct) => {
            let _ = write!(
                p,
                "<float name=\"alpha\" value=\"{}\"/><string name=\"d\" value=\"{}\"/><string name=\"g\" value=\"{}\"/><string name=\"f\" value=\"{}\"/><boolean name=\"metallic\" value=\"{}\"/><float name=\"ior\" value=\"{}\"/>{}{}{}",
                ct.alpha,
                ct.d.name(),
                ct.g.name(),
                ct.f.name(),
                ct.metallic,
                ct.ior,
                rgb("specular_color", ct.specular_color),
                rgb("eta", ct.eta),
                rgb("k", ct.k)
            );
        }
        BrdfModel::GltfPbr(g) => {
            let _ = write!(
                p,
                "<float name=\"metallic\" value=\"{}\"/><float name=\"roughness\" value=\"{}\"/>{}",
                g.metallic,
                g.roughness,
                textures::brdf_texture_properties(m, images, prefix)
            );
            if textures::plugin_handles_sides(m) {
                let _ = write!(p, "<boolean name=\"two_sided\" value=\"{}\"/>", m.two_sided);
            }
        }
    }
    p.push_str("</bsdf>");
    p
}
