//! The plan: which stages this scene needs, decided once before rendering.
//!
//! Nothing is computed "just in case" on the per-pixel path: the renderer consults the plan, and
//! `--explain` prints it — every stage kept or skipped, with the reason, and the rays of each kind.

use std::fmt::Write as _;
use std::path::Path;

use crate::material::{BrdfModel, Material};
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};
use crate::scene::Scene;
use crate::surface::primary::PointOptions;

/// An extra image written beside the render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    /// Shading normal (world space, as the shader saw it).
    Normal,
    /// World-space position.
    Position,
    /// Distance from the camera along the primary ray.
    Depth,
    /// Diffuse albedo times kd.
    Albedo,
    /// Samples each pixel took, in every channel: the film's spp, or what the adaptive sampler
    /// decided — a map of where it spent its samples. Not a per-sample value: the driver writes
    /// it from the counts.
    Samples,
}

impl Aov {
    /// Every AOV.
    pub const ALL: [Aov; 5] = [Aov::Normal, Aov::Position, Aov::Depth, Aov::Albedo, Aov::Samples];
    /// Their names, in the same order.
    pub const NAMES: &'static [&'static str] = &["normal", "position", "depth", "albedo", "samples"];

    /// Whether the AOV is a mean over the pixel's samples (summed sample by sample in the
    /// surface stage); `samples` is a property of the pixel, written from its count.
    pub fn per_sample(self) -> bool {
        self != Aov::Samples
    }

    /// Name on the command line and in file names.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Normal => "normal",
            Aov::Position => "position",
            Aov::Depth => "depth",
            Aov::Albedo => "albedo",
            Aov::Samples => "samples",
        }
    }

    /// Parses a comma-separated list (`normal,depth`); the error lists the valid names.
    pub fn parse_list(list: &str) -> Result<Vec<Aov>, String> {
        let mut out = Vec::new();
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let aov = Aov::ALL
                .into_iter()
                .find(|a| a.name() == name)
                .ok_or_else(|| format!("unknown AOV '{name}' (expected normal, position, depth, albedo or samples)"))?;
            if !out.contains(&aov) {
                out.push(aov);
            }
        }
        Ok(out)
    }
}

/// One stage of the pipeline and whether this scene runs it.
#[derive(Clone, Debug, PartialEq)]
pub struct StageDecision {
    /// Stage name.
    pub stage: &'static str,
    /// Whether it runs.
    pub kept: bool,
    /// Why.
    pub why: String,
}

/// What a render of this scene will do.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderPlan {
    /// Build a BVH and trace primary rays (the scene has geometry).
    pub trace_rays: bool,
    /// Trace shadow rays.
    pub shadows: bool,
    /// Some rendered material has a specular lobe.
    pub specular: bool,
    /// Interpolate texture coordinates (some rendered material samples a texture).
    pub uvs: bool,
    /// Sample base colour, metallic-roughness and emissive textures in the shader.
    pub textures: bool,
    /// Perturb shading normals by normal textures in the surface stage.
    pub normal_textures: bool,
    /// Add emitted radiance (some rendered material emits).
    pub emission: bool,
    /// Rays pass through cut-outs (some rendered material has glTF `alphaMode` MASK): the BVH
    /// gets an [`crate::accel::alpha::AlphaMask`].
    pub cutouts: bool,
    /// AOV buffers to fill.
    pub aovs: Vec<Aov>,
    /// Every decision, for `--explain`.
    pub stages: Vec<StageDecision>,
    /// Primary rays the render traces: exactly, for fixed sampling; at most, for adaptive.
    pub primary_rays: u64,
    /// The adaptive sampler decides per pixel how many samples it takes.
    pub adaptive: bool,
    /// Shadow rays leave from the smooth surface of the vertex normals, not the flat triangle.
    pub smooth_shadow_origins: bool,
    /// Upper bound on shadow rays (one per primary hit and light in front of the surface).
    pub max_shadow_rays: u64,
}

impl RenderPlan {
    /// Decides the stages for `scene` with the requested AOVs.
    pub fn new(scene: &Scene, aovs: &[Aov]) -> Self {
        let mut stages = Vec::new();
        let mut decide = |stage, kept: bool, why: String| {
            stages.push(StageDecision { stage, kept, why });
            kept
        };
        let triangles = scene.mesh.triangle_count();
        let trace_rays = decide(
            "bvh + primary rays",
            triangles > 0,
            if triangles > 0 {
                format!("{triangles} triangles")
            } else {
                "the scene has no geometry: every pixel is background".into()
            },
        );
        let shadows = decide(
            "shadow rays",
            trace_rays && scene.shadows && !scene.lights.is_empty(),
            if !scene.shadows {
                "shadows = false in the scene".into()
            } else if scene.lights.is_empty() {
                "no lights".into()
            } else if !trace_rays {
                "no geometry to cast shadows".into()
            } else {
                format!(
                    "{} light(s), one ray per light in front of each shaded point",
                    scene.lights.len()
                )
            },
        );
        // The mesh is scanned (normals_bend) once, and only when nothing else rules the stage out.
        let smooth_shadow_origins = shadows
            && scene.shadow_offset == ShadowOffset::ErrorBound
            && scene.shadow_terminator == ShadowTerminator::Smooth
            && scene.mesh.normals_bend();
        let smooth_shadow_origins = decide(
            "smooth shadow origins",
            smooth_shadow_origins,
            if !shadows {
                "no shadow rays".into()
            } else if scene.shadow_offset == ShadowOffset::Mitsuba {
                "the mitsuba offset starts on the flat triangle, as Mitsuba does".into()
            } else if scene.shadow_terminator == ShadowTerminator::Flat {
                "shadow_terminator = flat".into()
            } else if !smooth_shadow_origins {
                "every vertex normal is its triangle's normal: nothing to smooth".into()
            } else {
                "vertex normals bend over flat triangles: shadow rays leave from the smooth surface they \
                 describe (no shadow terminator)"
                    .into()
            },
        );
        let used: Vec<_> = (scene.materials.iter())
            .zip(scene.mesh.materials_used(scene.materials.len()))
            .filter_map(|(m, used)| used.then_some(m))
            .collect();
        let specular_names: Vec<_> = used
            .iter()
            .filter(|m| m.has_specular())
            .map(|m| m.name.as_str())
            .collect();
        let specular = decide(
            "specular BRDF terms",
            !specular_names.is_empty(),
            if specular_names.is_empty() {
                "every rendered material is Lambert".into()
            } else {
                format!("materials with a specular lobe: {}", specular_names.join(", "))
            },
        );
        let textures = trace_rays && used.iter().any(|m| samples_in_shader(m));
        let textures = decide(
            "material textures",
            textures,
            if textures {
                texture_summary(&used, scene)
            } else {
                "no rendered material has a texture that modulates its BRDF or emission".into()
            },
        );
        let normal_names = names_where(&used, |m| m.textures.normal.is_some());
        let normal_textures = decide(
            "normal textures",
            trace_rays && !normal_names.is_empty() && scene.mesh.tangents.is_some(),
            if normal_names.is_empty() {
                "no rendered material has a normal texture".into()
            } else if scene.mesh.tangents.is_none() {
                format!("the mesh has no tangents for {}", normal_names.join(", "))
            } else {
                format!(
                    "tangent-space normals perturb the shading normal of {}",
                    normal_names.join(", ")
                )
            },
        );
        let uvs = decide(
            "texture coordinates",
            textures || normal_textures,
            if textures || normal_textures {
                let sets = if scene.mesh.uvs1.is_some() {
                    "sets 0 and 1"
                } else {
                    "set 0"
                };
                format!("interpolated ({sets}) for the textures")
            } else {
                "no material samples a texture".into()
            },
        );
        let emissive_names = names_where(&used, Material::emits);
        let emission = decide(
            "emission",
            trace_rays && !emissive_names.is_empty(),
            if emissive_names.is_empty() {
                "no rendered material emits".into()
            } else {
                format!("emissive materials: {}", emissive_names.join(", "))
            },
        );
        let cutout_names = names_where(&used, |m| m.cutout().is_some());
        let cutouts = decide(
            "cut-outs (alpha mask)",
            trace_rays && !cutout_names.is_empty(),
            if cutout_names.is_empty() {
                "no rendered material has alphaMode MASK".into()
            } else {
                format!(
                    "camera and shadow rays pass where alpha < alphaCutoff: {}",
                    cutout_names.join(", ")
                )
            },
        );
        let aov_list = aovs.iter().map(|a| a.name()).collect::<Vec<_>>().join(", ");
        decide(
            "AOV buffers",
            !aovs.is_empty() && trace_rays,
            if aovs.is_empty() {
                "none requested (--aov)".into()
            } else {
                format!("requested: {aov_list}")
            },
        );
        let primary_rays = if trace_rays { primary_ray_bound(&scene.film) } else { 0 };
        let max_shadow_rays = if shadows {
            primary_rays * scene.lights.len() as u64
        } else {
            0
        };
        RenderPlan {
            trace_rays,
            shadows,
            specular,
            uvs,
            textures,
            normal_textures,
            emission,
            cutouts,
            aovs: if trace_rays { aovs.to_vec() } else { Vec::new() },
            stages,
            primary_rays,
            adaptive: scene.film.sampler.is_adaptive(),
            smooth_shadow_origins,
            max_shadow_rays,
        }
    }

    /// What the surface stage computes for each camera-ray hit.
    pub fn point_options(&self) -> PointOptions {
        PointOptions {
            uvs: self.uvs,
            smooth_shadow_origins: self.smooth_shadow_origins,
        }
    }

    /// The plan as text, for `--explain`.
    pub fn explain(&self, scene: &Scene) -> String {
        let f = &scene.film;
        let film = format!("{}x{}, {} spp, {} sampler", f.width, f.height, f.spp, f.sampler.name());
        self.explain_with(&scene.source, &film, &scene.notes)
    }

    /// The plan as text: `source`, the film described as `film`, the scene's notes, then the
    /// stages and the rays.
    pub fn explain_with(&self, source: &Path, film: &str, notes: &[String]) -> String {
        let bound = if self.adaptive { "at most " } else { "" };
        let rays = format!(
            "{bound}{} primary, at most {} shadow",
            self.primary_rays, self.max_shadow_rays
        );
        explain_stages(source, film, notes, &self.stages, &rays)
    }
}

/// A plan as `--explain` prints it: `source`, the film described as `film`, the scene's notes,
/// every stage kept or skipped with the reason, and the rays (mesh renders and the normal-map
/// mode alike).
pub fn explain_stages(source: &Path, film: &str, notes: &[String], stages: &[StageDecision], rays: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "plan for {}", source.display());
    let _ = writeln!(s, "  film: {film}");
    for note in notes {
        let _ = writeln!(s, "  note: {note}");
    }
    for d in stages {
        let _ = writeln!(
            s,
            "  [{}] {:<29} {}",
            if d.kept { "run " } else { "skip" },
            d.stage,
            d.why
        );
    }
    let _ = writeln!(s, "  rays: {rays}");
    s
}

/// Whether the shader looks up a texture of `m` (albedo, base colour, metallic-roughness,
/// emissive).
fn samples_in_shader(m: &Material) -> bool {
    m.varies_brdf() || (m.textures.emissive.is_some() && m.emits())
}

fn is_gltf(m: &Material) -> bool {
    matches!(m.model, BrdfModel::GltfPbr(_))
}

fn names_where(used: &[&Material], keep: impl Fn(&Material) -> bool) -> Vec<String> {
    used.iter().filter(|m| keep(m)).map(|m| m.name.clone()).collect()
}

/// "base colour: a, b; metallic-roughness: a; …; 3 images decoded: name (W×H), …".
fn texture_summary(used: &[&Material], scene: &Scene) -> String {
    type Has = fn(&Material) -> bool;
    let kinds: [(&str, Has); 8] = [
        ("base colour", |m| is_gltf(m) && m.textures.base_color.is_some()),
        ("albedo (MTL map_Kd)", |m| {
            !is_gltf(m) && m.textures.base_color.is_some()
        }),
        ("metallic-roughness", |m| m.textures.metallic_roughness.is_some()),
        ("specular colour (MTL map_Ks)", |m| m.textures.specular.is_some()),
        ("shininess (MTL map_Ns)", |m| m.textures.shininess.is_some()),
        ("roughness (MTL map_Pr)", |m| m.textures.roughness.is_some()),
        ("metallic (MTL map_Pm)", |m| m.textures.metallic.is_some()),
        ("emissive", |m| m.textures.emissive.is_some()),
    ];
    let mut parts = Vec::new();
    for (kind, has) in kinds {
        let names = names_where(used, has);
        if !names.is_empty() {
            parts.push(format!("{kind}: {}", names.join(", ")));
        }
    }
    let images: Vec<_> = scene
        .textures
        .iter()
        .map(|t| format!("{} ({}x{})", t.label, t.width, t.height))
        .collect();
    format!(
        "{}; {} image(s) decoded: {}",
        parts.join("; "),
        images.len(),
        images.join(", ")
    )
}

/// Camera rays a render of `film` traces: spp per pixel of the rendered region; with the adaptive
/// sampler at most that, plus one centre sample per pixel of the region and its two-pixel apron.
fn primary_ray_bound(film: &crate::film::FilmSettings) -> u64 {
    let r = film.region();
    let pixels = r.width() as u64 * r.height() as u64;
    if !film.sampler.is_adaptive() {
        return pixels * film.spp as u64;
    }
    let apron = (r.x1.saturating_add(2).min(film.width) - r.x0.saturating_sub(2)) as u64
        * (r.y1.saturating_add(2).min(film.height) - r.y0.saturating_sub(2)) as u64;
    apron + pixels * film.spp as u64
}
