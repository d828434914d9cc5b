//! A scene as Mitsuba 3 XML, for rendering references of the same scene.
//!
//! Everything is exported with Mitsuba's exact conventions (mitsuba3.md): perspective or
//! orthographic sensor, `direct` integrator with one emitter sample and no BSDF samples, box
//! filter, float32 `hdrfilm`, `stratified` sampler without jitter for the grid sampler. OBJ meshes
//! of one material are referenced, not copied; every other object (glTF meshes, OBJ files whose
//! faces use several materials, meshes given as arrays) is written as one binary PLY per material ([`super::ply`]), the
//! world-space triangles and normals pointshade renders. Materials map to Mitsuba's own BSDFs where one computes exactly
//! pointshade's model (Lambert → `diffuse`; Cook-Torrance with GGX, separable Smith and conductor
//! or constant Fresnel and no diffuse part → `roughconductor`), and to the `pointshade` BSDF
//! plugin (validation/pointshade_bsdf.py, pointshade's formulas re-implemented in Dr.Jit)
//! otherwise, so every model can be validated. What Mitsuba cannot express is listed in
//! [`MitsubaExport::differences`] ("no Mitsuba equivalent").

//!
//! One file per kind of Mitsuba plugin the export writes, as Mitsuba names them: sensor.rs
//! (with its film and sampler), bsdf.rs (Mitsuba's own BSDFs), pointshade_bsdf.rs (the plugin),
//! emitter.rs and shape.rs; this file assembles the documents.

mod bsdf;
mod emitter;
mod pointshade_bsdf;
mod sensor;
mod shape;

use std::fmt::Write as _;

use super::ply::{self, VertexAttributes};
use super::textures;
use crate::material::BrdfModel;
use crate::scene::Scene;
use crate::validation::xml::{rgb, xml_escape};
pub use bsdf::BsdfChoice;
use bsdf::{albedo_bitmap, bsdf};
use emitter::emitter;
use sensor::sensor;
use shape::{ply_shape, shape};

/// A scene exported for Mitsuba.
#[derive(Clone, Debug, PartialEq)]
pub struct MitsubaExport {
    /// The scene with all its lights.
    pub scene: String,
    /// The scene once per light, each with only that light: Mitsuba picks one light per sample,
    /// so a deterministic reference renders each and sums the images.
    pub per_light: Vec<String>,
    /// Where Mitsuba cannot compute pointshade's model, one line each; empty = exact.
    pub differences: Vec<String>,
    /// How each material was mapped (native BSDF or plugin), one line each.
    pub material_notes: Vec<String>,
    /// The emitted radiance the camera sees, where some material emits: the scene without lights
    /// and with black BSDFs, whose emissive surfaces are `area` emitters. It completes the sum of
    /// [`Self::per_light`] (pointshade adds emission to what its lights reflect).
    pub emission: Option<String>,
    /// Files the scenes reference by file name, to be written beside them: (file name,
    /// contents). PLY meshes and texture images.
    pub meshes: Vec<(String, Vec<u8>)>,
}

impl MitsubaExport {
    /// The documents whose renders sum to pointshade's image, each with the suffix its file
    /// takes (`{stem}.{suffix}.xml`): `light{k}` per light, then `emission` if some material
    /// emits.
    pub fn passes(&self) -> Vec<(String, &str)> {
        let lights = self
            .per_light
            .iter()
            .enumerate()
            .map(|(k, xml)| (format!("light{k}"), xml.as_str()));
        let emission = self.emission.iter().map(|xml| ("emission".to_string(), xml.as_str()));
        lights.chain(emission).collect()
    }
}

/// Exports `scene` rendered at `spp` samples with `sampler` (grid → stratified without jitter).
/// The mesh files it writes are named `{mesh_prefix}.object{i}.mat{m}.ply` (the prefix keeps the
/// meshes of different exports into one folder apart).
pub fn export(scene: &Scene, spp: u32, bsdfs: BsdfChoice, mesh_prefix: &str) -> MitsubaExport {
    let mut differences = Vec::new();
    let mut material_notes = Vec::new();
    let mut meshes = textures::image_files(&scene.textures, mesh_prefix);
    let head = format!("{}\n{}\n", integrator(), sensor(scene, spp, &mut differences));
    // The materials as BSDFs, and as black diffuse BSDFs of the same ids for the emission pass.
    let (mut materials, mut black) = (String::new(), String::new());
    for (index, m) in scene.materials.iter().enumerate() {
        let (xml, note) = bsdf(index, m, bsdfs, &scene.textures, mesh_prefix);
        material_notes.push(format!("{}: {note}", m.name));
        if matches!(&m.model, BrdfModel::GltfPbr(p) if p.cutout.is_some()) {
            differences.push(format!(
                "material '{}': alphaMode MASK (Mitsuba's direct integrator does not pass rays through cut-outs)",
                m.name
            ));
        }
        if let Some(r) = albedo_bitmap(m, bsdfs) {
            meshes.push(textures::png_file(&scene.textures, r.image as usize, mesh_prefix));
        }
        let t = &m.textures;
        for (present, statement) in [
            (t.specular.is_some(), "map_Ks"),
            (t.shininess.is_some(), "map_Ns"),
            (t.roughness.is_some(), "map_Pr"),
            (t.metallic.is_some(), "map_Pm"),
        ] {
            if present {
                differences.push(format!(
                    "material '{}': its {statement} texture (the export uses the untextured parameter)",
                    m.name
                ));
            }
        }
        if m.emits() && m.two_sided {
            differences.push(format!(
                "material '{}': emits from both sides (two-sided), Mitsuba's area emitter from the front only",
                m.name
            ));
        }
        let _ = writeln!(materials, "{xml}");
        let _ = writeln!(
            black,
            "  <bsdf id=\"mat{index}\" type=\"diffuse\">{}</bsdf>",
            rgb("reflectance", [0.0; 3])
        );
    }
    // The shapes, without and with the area emitters of emissive materials.
    let (mut shapes, mut emitting) = (String::new(), String::new());
    let mut any_emitter = false;
    let mut add = |xml: &dyn Fn(Option<&str>) -> String, material: u32| {
        let emitter = textures::area_emitter(&scene.materials[material as usize], &scene.textures, mesh_prefix);
        any_emitter |= emitter.is_some();
        let _ = writeln!(shapes, "{}", xml(None));
        let _ = writeln!(emitting, "{}", xml(emitter.as_deref()));
    };
    // What the plugin reads per vertex (nothing for Mitsuba's own bitmap, which reads the OBJ's).
    let attributes = |material: u32| {
        let m = &scene.materials[material as usize];
        match albedo_bitmap(m, bsdfs) {
            Some(_) => VertexAttributes::default(),
            None => textures::vertex_attributes(m, &scene.mesh),
        }
    };
    for (i, object) in scene.objects.iter().enumerate() {
        let used = object.materials(&scene.mesh);
        let is_obj = crate::scene::extension(&object.mesh).as_deref() == Some("obj");
        let plain = used.iter().all(|&m| attributes(m) == VertexAttributes::default());
        if is_obj && !object.from_arrays && used.len() <= 1 && plain {
            let material = used.first().copied().unwrap_or(0);
            add(&|e| shape(&object.mesh, object.transform, material, e), material);
            continue;
        }
        // Mitsuba cannot read the file (or there is none: a mesh given as arrays), would give
        // all of an OBJ's faces one BSDF, or the plugin needs texture coordinates and tangents.
        for &m in used
            .iter()
            .filter(|&&m| albedo_bitmap(&scene.materials[m as usize], bsdfs).is_some())
        {
            differences.push(format!(
                "material '{}': its map_Kd bitmap is exact only on a single-material OBJ, which Mitsuba reads \
                 with its texture coordinates (a PLY part carries none)",
                scene.materials[m as usize].name
            ));
        }
        for (material, bytes) in ply::parts(&scene.mesh, object.triangles.clone(), attributes) {
            let name = format!("{mesh_prefix}.object{i}.mat{material}.ply");
            add(&|e| ply_shape(&name, material, e), material);
            meshes.push((name, bytes));
        }
    }
    let lights: Vec<String> = scene.lights.iter().map(emitter).collect();
    let plugin_lights = lights.iter().any(|l| l.contains(emitter::PLUGIN));
    if !scene.shadows {
        differences.push("shadows = false (Mitsuba always traces shadow rays)".into());
    }
    let document = |body: &str, notes: &[&str], emitters: &[String]| {
        let mut s = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
        let _ = writeln!(
            s,
            "<!-- exported by pointshade from {} -->",
            xml_escape(&scene.source.display().to_string())
        );
        if material_notes.iter().any(|n| n.contains("plugin")) || any_emitter || plugin_lights {
            let _ = writeln!(
                s,
                "<!-- materials of type \"pointshade\", emitters of type \"{}\" and emitted radiance need validation/pointshade_bsdf.py registered -->",
                emitter::PLUGIN
            );
        }
        for d in &differences {
            let _ = writeln!(s, "<!-- no Mitsuba equivalent: {} -->", xml_escape(d));
        }
        for n in notes {
            let _ = writeln!(s, "<!-- {n} -->");
        }
        let _ = writeln!(s, "<scene version=\"3.0.0\">");
        s.push_str(&head);
        s.push_str(body);
        for e in emitters {
            let _ = writeln!(s, "{e}");
        }
        s.push_str("</scene>\n");
        s
    };
    let all_notes: &[&str] = if any_emitter {
        &["Mitsuba also lights surfaces by the emissive ones here, which pointshade does not: the per-light documents and their emission pass render pointshade's image exactly"]
    } else {
        &[]
    };
    MitsubaExport {
        scene: document(&format!("{materials}{emitting}"), all_notes, &lights),
        per_light: lights
            .iter()
            .map(|l| document(&format!("{materials}{shapes}"), &[], std::slice::from_ref(l)))
            .collect(),
        emission: any_emitter.then(|| {
            document(
                &format!("{black}{emitting}"),
                &["the emission pass: black BSDFs, so that only the emission the camera sees directly is left"],
                &[],
            )
        }),
        differences,
        material_notes,
        meshes,
    }
}

fn integrator() -> &'static str {
    concat!(
        "  <integrator type=\"direct\">\n",
        "    <integer name=\"emitter_samples\" value=\"1\"/>\n",
        "    <integer name=\"bsdf_samples\" value=\"0\"/>\n",
        "  </integrator>"
    )
}

#[cfg(test)]
mod tests;
