//! A model's material keys with the values they default to, read from the library's own
//! defaults (not a copy of them), for `pointshade.material_keys`.

use pointshade::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use pointshade::material::BrdfModel;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::material_of;

/// The value every key of `model`'s material section takes when it is not written, with the
/// scene files' defaults or the tp preset's (`defaults`): the material the library builds from
/// `model = "…"` alone.
#[pyfunction]
#[pyo3(signature = (model, defaults="scene"))]
pub fn material_defaults<'py>(py: Python<'py>, model: &str, defaults: &str) -> PyResult<Bound<'py, PyDict>> {
    let text = format!("model = {}", toml::Value::String(model.to_string()));
    let m = material_of(&text, defaults)?;
    let out = PyDict::new(py);
    out.set_item("model", model)?;
    out.set_item("albedo", m.albedo)?;
    out.set_item("kd", m.kd)?;
    out.set_item("two_sided", m.two_sided)?;
    match &m.model {
        BrdfModel::BlinnPhong(bp) => {
            out.set_item("ks", bp.ks)?;
            out.set_item("shininess", bp.shininess)?;
            out.set_item("specular_color", bp.color)?;
        }
        BrdfModel::CookTorrance(ct) => {
            out.set_item("roughness", ct.alpha)?;
            out.set_item("d", ct.d.name())?;
            out.set_item("g", ct.g.name())?;
            out.set_item("fresnel", ct.f.name())?;
            out.set_item("specular_color", ct.specular_color)?;
            out.set_item("metallic", ct.metallic)?;
            out.set_item("ior", ct.ior)?;
            out.set_item("eta", ct.eta)?;
            out.set_item("k", ct.k)?;
        }
        BrdfModel::Lambert | BrdfModel::GltfPbr(_) => {}
    }
    Ok(out)
}

/// The names the `d`, `g` and `fresnel` keys take, in the library's order: read from the terms
/// themselves, so a new term reaches `material_keys` without an edit here.
#[pyfunction]
pub fn term_names(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    out.set_item(
        "d",
        MicrofacetDistribution::ALL.iter().map(|t| t.name()).collect::<Vec<_>>(),
    )?;
    out.set_item("g", MaskingShadowing::ALL.iter().map(|t| t.name()).collect::<Vec<_>>())?;
    out.set_item("fresnel", FresnelTerm::ALL.iter().map(|t| t.name()).collect::<Vec<_>>())?;
    Ok(out)
}
