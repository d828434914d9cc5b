//! Normal-map scenes: a normal image, a preset, and the lights, viewer and material to shade it
//! with — from the command line (`pointshade normalmap IMAGE --brdf B`) or from a TOML file with
//! a `[normal_map]` section (docs/normal-maps.md, "Normal-map mode").
//!
//! The two presets:
//! - `tp` reproduces the NPM3D TP4 report: light at [0, 1, 1], colour 0.5, intensity 1, no
//!   falloff (L_i = colour × intensity); viewer at [1, 300, 1]; albedo [0.4, 0.7, 0.4], k_d = 1,
//!   Blinn-Phong k_s = 1, s = 1, Cook-Torrance α = 0.7, metallic, specular colour
//!   [0.98, 0.82, 0.76], n = 5; the assignment's shading convention and min-max 8-bit output.
//! - `physical` (the default): a point light with inverse-square falloff above-left in front of
//!   the image, an orthographic view along −z, the scene-file material defaults with the report's
//!   albedo but one-sided; physical shading, sRGB PNG with exposure or linear EXR.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;
use toml::Spanned;

use crate::brdf::{FresnelTerm, MaskingShadowing, MicrofacetDistribution};
use crate::error::InputResult;
use crate::light::{Falloff, Light, LightKind};
use crate::material::{BlinnPhong, CookTorrance, Material};
use crate::normal_map::pixels::{PixelPositions, Viewer};
use crate::scene::file::values::{resolve, three, three_opt, vec3};
pub use crate::scene::file::ModelName;
use crate::scene::file::{light, material, LightSection, MaterialDefaults, MaterialSection, TomlSource};
use crate::shading::convention::ShadingConvention;

/// The `tp` preset's Cook-Torrance, the NPM3D TP4 assignment's: GGX, Schlick–Smith and Schlick;
/// α = 0.7, metallic with the specular colour [0.98, 0.82, 0.76] as F0, and n = 5 for a
/// dielectric. η and κ are Mitsuba's "none" (F ≡ 1), as in [`CookTorrance::DEFAULT`].
pub const TP_COOK_TORRANCE: CookTorrance = CookTorrance {
    alpha: 0.7,
    d: MicrofacetDistribution::Ggx,
    g: MaskingShadowing::SchlickSmith,
    f: FresnelTerm::Schlick,
    metallic: true,
    specular_color: [0.98, 0.82, 0.76],
    ior: 5.0,
    eta: [0.0; 3],
    k: [1.0; 3],
};

/// A set of conventions and defaults for shading a normal image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// The NPM3D TP4 report's images, reproduced exactly.
    Tp,
    /// Physically meaningful shading of a normal image.
    #[default]
    Physical,
}

impl Preset {
    /// The name on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Tp => "tp",
            Preset::Physical => "physical",
        }
    }

    /// How the shader forms its dot products.
    pub fn convention(self) -> ShadingConvention {
        match self {
            Preset::Tp => ShadingConvention::Clamped,
            Preset::Physical => ShadingConvention::Physical,
        }
    }

    /// Where pixels sit in space.
    pub fn positions(self) -> PixelPositions {
        match self {
            Preset::Tp => PixelPositions::RowColumn,
            Preset::Physical => PixelPositions::ImagePlane,
        }
    }

    /// Falloff of lights that do not say.
    pub fn falloff(self) -> Falloff {
        match self {
            Preset::Tp => Falloff::None,
            Preset::Physical => Falloff::InverseSquare,
        }
    }

    /// The viewer when the scene has no `[camera]`.
    pub fn viewer(self) -> Viewer {
        match self {
            Preset::Tp => Viewer::Position(Vec3::new(1.0, 300.0, 1.0)),
            Preset::Physical => Viewer::ALONG_Z,
        }
    }

    /// The lights when the scene has no `[[light]]`.
    pub fn lights(self) -> Vec<Light> {
        match self {
            Preset::Tp => vec![Light {
                kind: LightKind::Point {
                    position: Vec3::new(0.0, 1.0, 1.0),
                },
                power: Vec3::splat(0.5) * 1.0,
                falloff: Falloff::None,
            }],
            // Above-left in front of the image (height 2 units), √17 from its centre, with the
            // irradiance 2 there that the automatic key light of mesh renders delivers.
            Preset::Physical => vec![Light {
                kind: LightKind::Point {
                    position: Vec3::new(-2.0, 2.0, 3.0),
                },
                power: Vec3::splat(2.0 * 17.0),
                falloff: Falloff::InverseSquare,
            }],
        }
    }

    /// Defaults of the material parameters a scene does not give.
    pub fn material_defaults(self) -> MaterialDefaults {
        const REPORT_ALBEDO: [f32; 3] = [0.4, 0.7, 0.4];
        match self {
            Preset::Tp => MaterialDefaults {
                albedo: REPORT_ALBEDO,
                kd: 1.0,
                two_sided: true,
                blinn_phong: BlinnPhong {
                    ks: 1.0,
                    shininess: 1.0,
                    color: [1.0; 3],
                },
                cook_torrance: TP_COOK_TORRANCE,
            },
            // One-sided: a decoded normal facing away from the viewer (noise at silhouettes, the
            // near-black surround of normal.png) shades black instead of being turned around.
            Preset::Physical => MaterialDefaults {
                albedo: REPORT_ALBEDO,
                two_sided: false,
                ..MaterialDefaults::SCENE
            },
        }
    }
}

impl std::str::FromStr for Preset {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "tp" => Ok(Preset::Tp),
            "physical" => Ok(Preset::Physical),
            _ => Err(format!("unknown preset '{s}' (expected tp or physical)")),
        }
    }
}

/// Everything `pointshade normalmap` needs besides the image's pixels, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMapScene {
    /// The scene file, or the image itself when there is none.
    pub source: PathBuf,
    /// The normal image.
    pub image: PathBuf,
    /// The preset.
    pub preset: Preset,
    /// Where ω_o points.
    pub viewer: Viewer,
    /// The lights, summed in order.
    pub lights: Vec<Light>,
    /// The one material of every pixel.
    pub material: Material,
    /// Exposure in stops for `physical` PNG output.
    pub exposure: f32,
    /// Decisions made for the user, shown by `--explain`.
    pub notes: Vec<String>,
}

impl NormalMapScene {
    /// `image` shaded with `preset`'s defaults and its material of model `brdf`.
    pub fn from_preset(image: &Path, preset: Preset, brdf: ModelName) -> Self {
        NormalMapScene {
            source: image.to_path_buf(),
            image: image.to_path_buf(),
            preset,
            viewer: preset.viewer(),
            lights: preset.lights(),
            material: preset.material_defaults().material(brdf.name(), brdf),
            exposure: 0.0,
            notes: vec![format!(
                "{} preset defaults: its light, viewer and {} material",
                preset.name(),
                brdf.name()
            )],
        }
    }

    /// Reads a scene file with a `[normal_map]` section. `brdf`, from the command line, replaces
    /// the file's `brdf` (and may not be combined with a file that names its own material).
    pub fn load(path: &Path, brdf: Option<ModelName>) -> InputResult<Self> {
        let source = TomlSource::read(path)?;
        Self::from_source(&source, path.parent().unwrap_or(Path::new(".")), brdf)
    }

    /// [`NormalMapScene::load`] of a scene file's `text` (named `name` in messages, its image
    /// path relative to `dir`): what the Python module's `shade_normal_image` builds.
    pub fn from_text(name: &Path, text: String, dir: &Path, brdf: Option<ModelName>) -> InputResult<Self> {
        Self::from_source(&TomlSource::from_text(name, text), dir, brdf)
    }

    fn from_source(source: &TomlSource, dir: &Path, brdf: Option<ModelName>) -> InputResult<Self> {
        let path = source.path;
        let at = |span, problem| source.at(span, problem);
        let file: NormalMapFile = source.parse()?;
        let nm_span = file.normal_map.span();
        let nm = file.normal_map.into_inner();
        let preset = nm.preset;
        let mut notes = Vec::new();

        let defaults = preset.material_defaults();
        let material = match (&nm.material, brdf.or(nm.brdf)) {
            (Some(name), None) => {
                let section = file.material.get(name.get_ref()).ok_or_else(|| {
                    at(
                        name.span(),
                        format!(
                            "unknown material '{}' (defined: {})",
                            name.get_ref(),
                            names(&file.material)
                        ),
                    )
                })?;
                material(name.get_ref(), section.get_ref(), &defaults).map_err(|(span, m)| {
                    at(
                        span.unwrap_or(section.span()),
                        format!("material '{}': {m}", name.get_ref()),
                    )
                })?
            }
            (Some(name), Some(b)) => {
                let problem = match brdf {
                    Some(_) => format!("--brdf {} conflicts with material = '{}'", b.name(), name.get_ref()),
                    None => "give either brdf (the preset's material) or material (a [material.NAME]), not both".into(),
                };
                return Err(at(name.span(), problem));
            }
            (None, Some(b)) => {
                notes.push(format!(
                    "material: the {} preset's {} material",
                    preset.name(),
                    b.name()
                ));
                defaults.material(b.name(), b)
            }
            (None, None) => {
                return Err(at(
                    nm_span,
                    "[normal_map] needs brdf = \"lambert\" | \"blinn-phong\" | \"cook-torrance\", or material = NAME"
                        .into(),
                ))
            }
        };
        let used = nm.material.as_ref().map(|n| n.get_ref().as_str());
        if let Some((name, section)) = file.material.iter().find(|(n, _)| Some(n.as_str()) != used) {
            return Err(at(
                section.span(),
                format!("material '{name}' is not used (select it with material = \"{name}\" in [normal_map])"),
            ));
        }

        let lights = if file.light.is_empty() {
            notes.push(format!(
                "lights: none in the scene file, the {} preset's",
                preset.name()
            ));
            preset.lights()
        } else {
            file.light
                .iter()
                .map(|l| light(l.get_ref(), preset.falloff(), glam::DVec3::ZERO).map_err(|m| at(l.span(), m)))
                .collect::<InputResult<_>>()?
        };
        let viewer = match &file.camera {
            Some(c) => viewer(c.get_ref()).map_err(|m| at(c.span(), m))?,
            None => {
                notes.push(format!(
                    "viewer: none in the scene file, the {} preset's",
                    preset.name()
                ));
                preset.viewer()
            }
        };
        let exposure = match &file.film {
            Some(f) => {
                let e = f.get_ref().exposure;
                if preset == Preset::Tp {
                    return Err(at(
                        f.span(),
                        "exposure does not apply to the tp preset (its PNG is min-max normalised)".into(),
                    ));
                }
                if !(e.is_finite() && e.abs() <= 64.0) {
                    return Err(at(
                        f.span(),
                        format!("exposure must be a finite number of stops in [-64, 64], got {e}"),
                    ));
                }
                e
            }
            None => 0.0,
        };
        Ok(NormalMapScene {
            source: path.to_path_buf(),
            image: resolve(dir, &nm.image),
            preset,
            viewer,
            lights,
            material,
            exposure,
            notes,
        })
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NormalMapFile {
    normal_map: Spanned<NormalMapSection>,
    camera: Option<Spanned<ViewerSection>>,
    #[serde(default)]
    light: Vec<Spanned<LightSection>>,
    #[serde(default)]
    material: BTreeMap<String, Spanned<MaterialSection>>,
    film: Option<Spanned<ExposureSection>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NormalMapSection {
    image: String,
    #[serde(default)]
    preset: Preset,
    brdf: Option<ModelName>,
    material: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ViewerSection {
    #[serde(rename = "type", default)]
    kind: ViewerType,
    #[serde(deserialize_with = "three")]
    position: [f32; 3],
    #[serde(default, deserialize_with = "three_opt")]
    look_at: Option<[f32; 3]>,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
enum ViewerType {
    #[default]
    Perspective,
    Orthographic,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ExposureSection {
    exposure: f32,
}

fn viewer(c: &ViewerSection) -> Result<Viewer, String> {
    let position = vec3("position", c.position)?;
    match (&c.kind, c.look_at) {
        (ViewerType::Perspective, None) => Ok(Viewer::Position(position)),
        (ViewerType::Perspective, Some(_)) => Err(
            "look_at does not apply to a perspective viewer of a normal image: ω_o depends only on its position".into(),
        ),
        (ViewerType::Orthographic, Some(look_at)) => {
            let direction = (position - vec3("look_at", look_at)?).normalize_or_zero();
            if direction == Vec3::ZERO || !direction.is_finite() {
                return Err("camera position and look_at must differ".into());
            }
            Ok(Viewer::Direction(direction))
        }
        (ViewerType::Orthographic, None) => {
            Err("an orthographic viewer needs look_at (ω_o points from look_at to position)".into())
        }
    }
}

fn names(materials: &BTreeMap<String, Spanned<MaterialSection>>) -> String {
    if materials.is_empty() {
        "none".into()
    } else {
        materials.keys().cloned().collect::<Vec<_>>().join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::BrdfModel;

    fn scene(name: &str, text: &str) -> InputResult<NormalMapScene> {
        let dir = std::env::temp_dir().join(format!("pointshade-nm-scene-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("scene.toml");
        std::fs::write(&p, text).unwrap();
        let r = NormalMapScene::load(&p, None);
        let _ = std::fs::remove_dir_all(&dir);
        r
    }

    #[test]
    fn tp_preset_has_the_reports_parameters() {
        let s = NormalMapScene::from_preset(Path::new("n.png"), Preset::Tp, ModelName::BlinnPhong);
        assert_eq!(s.viewer, Viewer::Position(Vec3::new(1.0, 300.0, 1.0)));
        assert_eq!(s.lights.len(), 1);
        assert_eq!(s.lights[0].power, Vec3::splat(0.5));
        assert_eq!(s.lights[0].falloff, Falloff::None);
        assert_eq!(s.material.albedo, [0.4, 0.7, 0.4]);
        assert_eq!(
            s.material.model,
            BrdfModel::BlinnPhong(BlinnPhong {
                ks: 1.0,
                shininess: 1.0,
                color: [1.0; 3]
            })
        );
        let ct = NormalMapScene::from_preset(Path::new("n.png"), Preset::Tp, ModelName::CookTorrance);
        assert_eq!(ct.material.model, BrdfModel::CookTorrance(TP_COOK_TORRANCE));
    }

    #[test]
    fn scene_file_overrides_keep_the_presets_other_values() {
        let s = scene(
            "overrides",
            "[normal_map]\nimage = \"n.png\"\npreset = \"tp\"\nmaterial = \"rough\"\n\
             [material.rough]\nmodel = \"cook-torrance\"\nroughness = 0.3\n\
             [[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 1.0]\n\
             [camera]\nposition = [1.0, 200.0, 1.0]\n",
        )
        .unwrap();
        assert_eq!(s.preset, Preset::Tp);
        assert!(s.image.ends_with("n.png"));
        assert_eq!(s.material.albedo, [0.4, 0.7, 0.4], "albedo from the preset");
        let BrdfModel::CookTorrance(ct) = s.material.model else {
            panic!()
        };
        assert_eq!((ct.alpha, ct.specular_color), (0.3, [0.98, 0.82, 0.76]));
        assert_eq!(s.lights[0].falloff, Falloff::None, "tp lights default to no falloff");
        assert_eq!(s.viewer, Viewer::Position(Vec3::new(1.0, 200.0, 1.0)));
    }

    #[test]
    fn strict_errors_name_line_and_column() {
        let e = scene(
            "typo",
            "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\nprest = \"tp\"\n",
        )
        .unwrap_err();
        assert!(e.problem.contains("line 4") && e.problem.contains("prest"), "{e}");
        let e = scene(
            "object",
            "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n[[object]]\nmesh = \"a.obj\"\n",
        )
        .unwrap_err();
        assert!(e.problem.contains("line 4") && e.problem.contains("object"), "{e}");
        let e = scene("nobrdf", "[normal_map]\nimage = \"n.png\"\n").unwrap_err();
        assert!(e.problem.contains("line 1") && e.problem.contains("brdf"), "{e}");
        let e = scene(
            "unused",
            "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n[material.x]\nalbedo = [0.1, 0.2, 0.3]\n",
        )
        .unwrap_err();
        assert!(e.problem.contains("line 4") && e.problem.contains("not used"), "{e}");
        let e = scene(
            "tpexposure",
            "[normal_map]\nimage = \"n.png\"\npreset = \"tp\"\nbrdf = \"lambert\"\n[film]\nexposure = 1.0\n",
        )
        .unwrap_err();
        assert!(e.problem.contains("exposure"), "{e}");
        let e = scene(
            "lookat",
            "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n[camera]\nposition = [0.0, 0.0, 1.0]\nlook_at = [0.0, 0.0, 0.0]\n",
        )
        .unwrap_err();
        assert!(e.problem.contains("line 4") && e.problem.contains("look_at"), "{e}");
    }

    #[test]
    fn orthographic_viewer_points_from_look_at_to_position() {
        let s = scene(
            "ortho",
            "[normal_map]\nimage = \"n.png\"\nbrdf = \"lambert\"\n[camera]\ntype = \"orthographic\"\n\
             position = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n[film]\nexposure = -1.0\n",
        )
        .unwrap();
        assert_eq!(s.viewer, Viewer::Direction(Vec3::Z));
        assert_eq!(s.exposure, -1.0);
        assert_eq!(s.lights[0].falloff, Falloff::InverseSquare);
    }
}
