//! A scene as Mitsuba 3 XML, for rendering references of the same scene.
//!
//! Everything is exported with Mitsuba's exact conventions (mitsuba3.md): perspective or
//! orthographic sensor, `direct` integrator with one emitter sample and no BSDF samples, box
//! filter, float32 `hdrfilm`, `stratified` sampler without jitter for the grid sampler. OBJ meshes
//! of one material are referenced, not copied; every other object (glTF meshes, OBJ files whose
//! faces use several materials) is written as one binary PLY per material ([`super::ply`]), the
//! world-space triangles and normals pointshade renders. Materials map to Mitsuba's own BSDFs where one computes exactly
//! pointshade's model (Lambert → `diffuse`; Cook-Torrance with GGX, separable Smith and conductor
//! or constant Fresnel and no diffuse part → `roughconductor`), and to the `pointshade` BSDF
//! plugin (validation/pointshade_bsdf.py, pointshade's formulas re-implemented in Dr.Jit)
//! otherwise, so every model can be validated. What Mitsuba cannot express is listed in
//! [`MitsubaExport::differences`] ("no Mitsuba equivalent").

use std::fmt::Write as _;
use std::path::Path;

use glam::{Mat4, Vec3};

use super::ply::{self, VertexAttributes};
use super::textures;
use crate::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use crate::film::SamplerKind;
use crate::light::{Falloff, Light, LightKind};
use crate::material::{BrdfModel, Material};
use crate::scene::camera::{FovAxis, Projection};
use crate::scene::Scene;
use crate::texture::{Filter, TextureImage, TextureRef, Wrap};
use crate::validation::xml::rgb;
use crate::validation::xml::xml_escape;

/// Which BSDFs the export uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BsdfChoice {
    /// Mitsuba's own BSDF where one is exact, the plugin elsewhere.
    #[default]
    NativeWhereExact,
    /// The plugin for every material (to check the plugin against Mitsuba's own BSDFs).
    PluginEverywhere,
}

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

/// Mitsuba's default near clip, used where pointshade's is 0 (Mitsuba needs > 0).
const MITSUBA_NEAR_CLIP: f32 = 0.01;

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
        if is_obj && used.len() <= 1 && plain {
            let material = used.first().copied().unwrap_or(0);
            add(&|e| shape(&object.mesh, object.transform, material, e), material);
            continue;
        }
        // Mitsuba cannot read the file, would give all of an OBJ's faces one BSDF, or the
        // plugin needs texture coordinates and tangents.
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
    let lights: Vec<String> = scene.lights.iter().map(|l| emitter(l, &mut differences)).collect();
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
        if material_notes.iter().any(|n| n.contains("plugin")) || any_emitter {
            let _ = writeln!(
                s,
                "<!-- materials of type \"pointshade\" and emitted radiance need validation/pointshade_bsdf.py registered -->"
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

fn v3(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

fn sensor(scene: &Scene, spp: u32, differences: &mut Vec<String>) -> String {
    let c = &scene.camera;
    let f = &scene.film;
    let near = if c.near_clip > 0.0 {
        c.near_clip
    } else {
        MITSUBA_NEAR_CLIP
    };
    // Mitsuba needs a finite far plane: beyond everything in the scene, at least its default.
    let far = if c.far_clip.is_finite() {
        c.far_clip
    } else {
        let farthest = scene.mesh.bounds().map_or(0.0, |(lo, hi)| {
            (0..8)
                .map(|i| {
                    let corner = Vec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    );
                    corner.distance(c.position)
                })
                .fold(0.0, f32::max)
        });
        (2.0 * farthest).max(1e4)
    };
    let lookat = format!(
        "<lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>",
        v3(c.position),
        v3(c.look_at),
        v3(c.up)
    );
    let (kind, params, to_world) = match c.projection {
        Projection::Perspective { fov_degrees, fov_axis } => (
            "perspective",
            format!(
                "    <float name=\"fov\" value=\"{fov_degrees}\"/>\n    <string name=\"fov_axis\" value=\"{}\"/>\n",
                match fov_axis {
                    FovAxis::X => "x",
                    FovAxis::Y => "y",
                }
            ),
            format!("      {lookat}\n"),
        ),
        // Mitsuba's orthographic film spans x ∈ [−s, s], y ∈ [−s/aspect, s/aspect] for a to_world
        // scale s: s = half-height · aspect gives pointshade's half-height `scale`.
        Projection::Orthographic { scale } => {
            let s = scale * f.width as f32 / f.height as f32;
            (
                "orthographic",
                String::new(),
                format!("      <scale x=\"{s}\" y=\"{s}\" z=\"1\"/>\n      {lookat}\n"),
            )
        }
    };
    let sampler = match f.sampler {
        SamplerKind::Grid => format!(
            "    <sampler type=\"stratified\">\n      <integer name=\"sample_count\" value=\"{spp}\"/>\n      <boolean name=\"jitter\" value=\"false\"/>\n    </sampler>\n"
        ),
        other => {
            if other == SamplerKind::Sobol {
                differences.push("sobol sampler (exported as Mitsuba's independent sampler)".into());
            }
            format!(
                "    <sampler type=\"independent\">\n      <integer name=\"sample_count\" value=\"{spp}\"/>\n      <integer name=\"seed\" value=\"{}\"/>\n    </sampler>\n",
                f.seed as u32
            )
        }
    };
    format!(
        "  <sensor type=\"{kind}\">\n{params}    <float name=\"near_clip\" value=\"{near}\"/>\n    <float name=\"far_clip\" value=\"{far}\"/>\n    <transform name=\"to_world\">\n{to_world}    </transform>\n{sampler}    <film type=\"hdrfilm\">\n      <integer name=\"width\" value=\"{}\"/>\n      <integer name=\"height\" value=\"{}\"/>\n      <string name=\"pixel_format\" value=\"rgb\"/>\n      <string name=\"component_format\" value=\"float32\"/>\n      <rfilter type=\"box\"/>\n    </film>\n  </sensor>",
        f.width, f.height
    )
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
fn bsdf(
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
fn albedo_bitmap(m: &Material, choice: BsdfChoice) -> Option<TextureRef> {
    let r = m.textures.base_color?;
    let unit = m.albedo.iter().all(|&a| a * m.kd == 1.0);
    let plain = r.tex_coord == 0 && r.filter == Filter::Bilinear && r.transform.is_none() && r.wrap_u == r.wrap_v;
    (choice == BsdfChoice::NativeWhereExact && !m.has_specular() && unit && plain).then_some(r)
}

fn plugin_bsdf(m: &Material, images: &[TextureImage], prefix: &str) -> String {
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

/// A PLY part of the scene mesh, already in world space, by its file name beside the XML.
fn ply_shape(name: &str, material: u32, emitter: Option<&str>) -> String {
    format!(
        "  <shape type=\"ply\">\n    <string name=\"filename\" value=\"{}\"/>\n    <ref id=\"mat{material}\"/>\n{}  </shape>",
        xml_escape(name),
        emitter_line(emitter)
    )
}

fn emitter_line(emitter: Option<&str>) -> String {
    emitter.map_or_else(String::new, |e| format!("    {e}\n"))
}

fn shape(mesh: &Path, transform: Mat4, material: u32, emitter: Option<&str>) -> String {
    let path = std::fs::canonicalize(mesh).unwrap_or_else(|_| mesh.to_path_buf());
    let m = transform.transpose().to_cols_array(); // row-major
    let matrix = m.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(" ");
    format!(
        "  <shape type=\"obj\">\n    <string name=\"filename\" value=\"{}\"/>\n    <transform name=\"to_world\"><matrix value=\"{matrix}\"/></transform>\n    <ref id=\"mat{material}\"/>\n{}  </shape>",
        xml_escape(&path.display().to_string()),
        emitter_line(emitter)
    )
}

fn emitter(light: &Light, differences: &mut Vec<String>) -> String {
    let power = light.power.to_array();
    if light.falloff == Falloff::None && !matches!(light.kind, LightKind::Directional { .. }) {
        differences.push("falloff = \"none\" (exported with Mitsuba's inverse-square falloff)".into());
    }
    if let Falloff::InverseSquareWithin { range } = light.falloff {
        differences.push(format!(
            "a KHR_lights_punctual range of {range} (exported with Mitsuba's unwindowed inverse-square falloff)"
        ));
    }
    match light.kind {
        LightKind::Point { position } => format!(
            "  <emitter type=\"point\"><point name=\"position\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}</emitter>",
            position.x,
            position.y,
            position.z,
            rgb("intensity", power)
        ),
        LightKind::Directional { direction } => format!(
            "  <emitter type=\"directional\"><vector name=\"direction\" x=\"{}\" y=\"{}\" z=\"{}\"/>{}</emitter>",
            direction.x,
            direction.y,
            direction.z,
            rgb("irradiance", power)
        ),
        LightKind::Spot {
            position,
            direction,
            cos_inner,
            cos_outer,
        } => {
            differences.push(
                "spot light cone falloff (Mitsuba's is linear in angle, pointshade's quadratic in cos as \
                 KHR_lights_punctual)"
                    .into(),
            );
            let up = if direction.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
            format!(
                "  <emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/></transform>{}<float name=\"cutoff_angle\" value=\"{}\"/><float name=\"beam_width\" value=\"{}\"/></emitter>",
                v3(position),
                v3(position + direction),
                v3(up),
                rgb("intensity", power),
                cos_outer.acos().to_degrees(),
                cos_inner.acos().to_degrees()
            )
        }
    }
}

#[cfg(test)]
mod tests;
