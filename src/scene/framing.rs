//! Defaults for scenes that do not say: a camera that frames the geometry, a key light and a
//! fill light, a neutral material. Used for bare meshes on the command line and for scene files
//! without a `[camera]` or `[[light]]`.

use std::path::Path;

use glam::Vec3;

use crate::error::{InputError, InputResult};
use crate::film::FilmSettings;
use crate::light::{Falloff, Light, LightKind};
use crate::material::Material;
use crate::scene::camera::{Camera, CameraSpec, FovAxis, Projection};
use crate::scene::extent;
use crate::scene::obj::{load_obj, NO_MATERIAL};
use crate::scene::tangents::complete_tangents;
use crate::scene::textures::decode_used_images;
use crate::scene::Scene;

/// Vertical field of view of the automatic camera, in degrees.
const AUTO_FOV: f32 = 35.0;
/// Where the automatic camera stands, relative to the centre: in front (+Z), a little to the
/// right and above — a three-quarter view of models that face +Z with +Y up, the usual convention.
const VIEW_FROM: Vec3 = Vec3::new(0.45, 0.35, 1.0);
/// Irradiance the key light delivers at the centre of the geometry.
const KEY_IRRADIANCE: f32 = 2.0;

/// The material of faces that have none: light grey Lambert, two-sided.
pub fn default_material() -> Material {
    Material::lambert("default", [0.8, 0.8, 0.8])
}

/// A perspective camera that sees all eight corners of the box `(lo, hi)`, as close as it can
/// (5% margin), for any image at least as wide as it is tall.
pub fn frame_bounds(lo: Vec3, hi: Vec3) -> CameraSpec {
    frame_bounds_from(lo, hi, VIEW_FROM.normalize(), 1.0)
}

/// [`frame_bounds`] seen from the unit direction `back` (from the centre towards the camera,
/// not vertical), at `scale` times the distance that fits the box.
fn frame_bounds_from(lo: Vec3, hi: Vec3, back: Vec3, scale: f32) -> CameraSpec {
    let centre = (lo + hi) * 0.5;
    let right = Vec3::Y.cross(back).normalize();
    let up = back.cross(right);
    let tan_half = (AUTO_FOV.to_radians() * 0.5).tan();
    // A corner at offset r from the centre is inside the vertical (and, for aspect ≥ 1, the
    // horizontal) fov when |r·up| ≤ tan·depth and |r·right| ≤ tan·depth, depth = D − r·back.
    let mut distance = f32::MIN_POSITIVE.sqrt();
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let r = corner - centre;
        let lateral = r.dot(up).abs().max(r.dot(right).abs());
        distance = distance.max(r.dot(back) + lateral / tan_half);
    }
    CameraSpec {
        position: centre + back * distance * 1.05 * scale,
        look_at: centre,
        up: Vec3::Y,
        projection: Projection::Perspective {
            fov_degrees: AUTO_FOV,
            fov_axis: FovAxis::Y,
        },
        near_clip: 0.0,
        far_clip: f32::INFINITY,
    }
}

/// Where `--view` puts the automatic camera: `azimuth` degrees around the vertical (+Y) from the
/// front (+Z; 90 looks from +X), `elevation` degrees above the horizontal, at `distance` times the
/// distance that fits the bounding box. The automatic framing itself is about (24.2, 17.7, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Degrees around +Y, from +Z towards +X.
    pub azimuth: f32,
    /// Degrees above the horizontal, in (−90, 90).
    pub elevation: f32,
    /// Multiple of the framing distance, > 0.
    pub distance: f32,
}

impl View {
    /// The view `azimuth` and `elevation` degrees around the framing, `distance` times as far;
    /// the error says which value is out of range.
    pub fn new(azimuth: f32, elevation: f32, distance: f32) -> Result<View, String> {
        if !azimuth.is_finite() {
            return Err(format!("azimuth must be finite, got {azimuth}"));
        }
        if !(elevation.abs() < 90.0) {
            return Err(format!(
                "elevation must be strictly between -90 and 90 degrees (the camera keeps +Y up), got {elevation}"
            ));
        }
        if !(distance > 0.0 && distance.is_finite()) {
            return Err(format!("distance must be a finite multiple > 0, got {distance}"));
        }
        Ok(View {
            azimuth,
            elevation,
            distance,
        })
    }

    /// The unit direction from the centre towards the camera.
    fn back(self) -> Vec3 {
        let (a, e) = (self.azimuth.to_radians(), self.elevation.to_radians());
        Vec3::new(a.sin() * e.cos(), e.sin(), a.cos() * e.cos())
    }
}

/// How the command line aims a scene's camera: [`View`] reframes the bounding box from another
/// direction; `look_from`, `look_at` (world coordinates, as scene files write them) and `fov`
/// (vertical, degrees) then set those parts of the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aim {
    /// `--view`.
    pub view: Option<View>,
    /// `--look-from`.
    pub look_from: Option<glam::DVec3>,
    /// `--look-at`.
    pub look_at: Option<glam::DVec3>,
    /// `--fov`.
    pub fov: Option<f32>,
}

impl Aim {
    /// Applies the aim to `scene`'s camera. Where the scene's lights are the automatic ones they
    /// are aimed again from the new camera, so that the model stays lit from the viewer's side.
    /// The error names the problem (no geometry to frame, a camera looking at itself, …).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), String> {
        if *self == Aim::default() {
            return Ok(());
        }
        let bounds = scene.mesh.bounds();
        if let Some(view) = self.view {
            let (lo, hi) = bounds.ok_or("the scene has no geometry to frame")?;
            scene.camera = frame_bounds_from(lo, hi, view.back(), view.distance);
        }
        let local = |p: glam::DVec3| (p - scene.origin).as_vec3();
        if let Some(p) = self.look_from {
            scene.camera.position = local(p);
        }
        if let Some(p) = self.look_at {
            scene.camera.look_at = local(p);
        }
        if let Some(fov) = self.fov {
            match &mut scene.camera.projection {
                Projection::Perspective { fov_degrees, fov_axis } => (*fov_degrees, *fov_axis) = (fov, FovAxis::Y),
                _ => return Err("the camera is orthographic: it has no field of view".into()),
            }
        }
        // The checks every camera passes (within reach, a frame, a field of view), as a scene
        // file's does.
        extent::check_camera(scene)?;
        Camera::new(scene.camera, 1, 1)?;
        let c = &scene.camera;
        if scene.default_lights {
            if let Some((lo, hi)) = bounds {
                scene.lights = default_lights(lo, hi, &scene.camera);
            }
            extent::check_lights(scene)?;
        }
        scene.notes.push(format!(
            "camera: aimed from the command line at ({}, {}, {}) from ({}, {}, {})",
            c.look_at.x, c.look_at.y, c.look_at.z, c.position.x, c.position.y, c.position.z
        ));
        Ok(())
    }
}

/// A key light above-left of `camera` and a dim fill light low on the right, both aimed at the
/// centre of `(lo, hi)`, with intensities that give irradiance KEY_IRRADIANCE (key) and a fifth
/// of it (fill) at the centre whatever the scene's scale.
pub fn default_lights(lo: Vec3, hi: Vec3, camera: &CameraSpec) -> Vec<Light> {
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(f32::MIN_POSITIVE.sqrt());
    let back = (camera.position - centre).normalize_or(Vec3::Z);
    let right = Vec3::Y.cross(back).normalize_or(Vec3::X);
    let up = back.cross(right);
    let light = |dir: Vec3, irradiance: f32| {
        let d = 3.0 * radius;
        Light {
            kind: LightKind::Point {
                position: centre + dir.normalize() * d,
            },
            power: Vec3::splat(irradiance * d * d),
            falloff: Falloff::InverseSquare,
        }
    };
    vec![
        light(-0.7 * right + 1.0 * up + 0.8 * back, KEY_IRRADIANCE),
        light(1.0 * right - 0.2 * up + 0.9 * back, KEY_IRRADIANCE * 0.2),
    ]
}

/// A scene for a mesh given alone on the command line.
pub fn scene_for_bare_mesh(path: &Path) -> InputResult<Scene> {
    let obj = load_obj(path)?;
    let origin = obj.origin;
    let mut materials = obj.materials;
    let mut mesh = obj.mesh;
    if mesh.material_of_triangle.contains(&NO_MATERIAL) {
        let default = materials.len() as u32;
        materials.push(default_material());
        for m in &mut mesh.material_of_triangle {
            if *m == NO_MATERIAL {
                *m = default;
            }
        }
    }
    complete_tangents(&mut mesh, &materials);
    let textures = decode_used_images(&mut materials, &mesh.material_of_triangle, &obj.images)?;
    let (lo, hi) = mesh.bounds().ok_or_else(|| InputError::new(path, "no geometry"))?;
    let camera = frame_bounds(lo, hi);
    let lights = default_lights(lo, hi, &camera);
    let mut scene = Scene::new(
        path.to_path_buf(),
        FilmSettings::default(),
        camera,
        lights,
        materials,
        textures,
        mesh,
    );
    // The file's coordinates, in the render's frame (relative to the mesh's own origin).
    scene.objects[0].transform = glam::Mat4::from_translation(-origin.as_vec3());
    scene.origin = origin;
    scene.default_lights = true;
    scene.notes = vec![
        "camera: framed automatically on the bounding box".into(),
        "lights: default key + fill lights".into(),
    ];
    scene.warnings = obj.warnings;
    scene.warnings.extend(obj.material_warnings);
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::camera::Camera;

    #[test]
    fn automatic_camera_sees_every_corner_of_the_box_at_any_scale() {
        for &(s, off) in &[(1.0f32, 0.0f32), (1e-4, 0.0), (1e4, 0.0), (1.0, 1e3)] {
            let (lo, hi) = (Vec3::new(-1.0, 0.0, -0.5) * s + off, Vec3::new(2.0, 1.5, 0.5) * s + off);
            let cam = Camera::new(frame_bounds(lo, hi), 640, 480).unwrap();
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                );
                let d = (corner - cam.spec().position).normalize();
                let (fwd, half_y) = (cam.forward(), (AUTO_FOV.to_radians() * 0.5).tan());
                let up = fwd.cross(Vec3::Y.cross(fwd).normalize());
                let right = fwd.cross(Vec3::Y).normalize();
                let z = d.dot(fwd);
                assert!(z > 0.0);
                assert!(
                    (d.dot(up) / z).abs() <= half_y,
                    "corner {i} outside vertically (scale {s})"
                );
                assert!((d.dot(right) / z).abs() <= half_y, "corner {i} outside horizontally");
            }
        }
    }

    #[test]
    fn the_default_view_is_the_automatic_framing_s_and_views_parse_strictly() {
        let (x, y, z) = (VIEW_FROM.x, VIEW_FROM.y, VIEW_FROM.z);
        let view = View {
            azimuth: x.atan2(z).to_degrees(),
            elevation: y.atan2(x.hypot(z)).to_degrees(),
            distance: 1.0,
        };
        assert!(
            (view.azimuth - 24.2).abs() < 0.05 && (view.elevation - 17.7).abs() < 0.05,
            "{view:?}"
        );
        assert!((view.back() - VIEW_FROM.normalize()).length() < 1e-6);
        assert_eq!(View::new(90.0, 0.0, 1.0).unwrap().back().round(), Vec3::X);
        let bad = [
            (1.0, -90.0, 1.0),
            (1.0, f32::NAN, 1.0),
            (f32::INFINITY, 0.0, 1.0),
            (0.0, 0.0, -1.0),
            (0.0, 0.0, 0.0),
        ];
        for (azimuth, elevation, distance) in bad {
            assert!(
                View::new(azimuth, elevation, distance).is_err(),
                "{azimuth},{elevation},{distance}"
            );
        }
    }

    #[test]
    fn key_light_irradiance_at_the_centre_is_scale_independent() {
        for s in [1e-3f32, 1.0, 1e3] {
            let (lo, hi) = (Vec3::splat(-s), Vec3::splat(s));
            let lights = default_lights(lo, hi, &frame_bounds(lo, hi));
            let e = lights[0].sample(Vec3::ZERO).unwrap().irradiance.x;
            assert!((e - KEY_IRRADIANCE).abs() < 1e-3 * KEY_IRRADIANCE, "{e} at scale {s}");
        }
    }
}
