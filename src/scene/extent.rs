//! How far from its origin a scene may reach: pointshade computes in f32, where the squared
//! length of a difference of coordinates beyond about 5e18 overflows (every normalisation, every
//! inverse-square falloff). A scene that reaches further is refused at load, naming the vertex,
//! camera or light that lies too far, instead of rendering black or failing later with a
//! message about something else.

use glam::Vec3;

use crate::light::LightKind;
use crate::scene::Scene;

/// The largest |coordinate| of a vertex, the camera or a light, relative to the scene's origin
/// ([`Scene::origin`]): differences stay below 2e18 per axis, their squared lengths below
/// 1.2e37, well inside f32's 3.4e38.
pub const MAX_COORDINATE: f32 = 1e18;

/// Whether `p` is finite and within [`MAX_COORDINATE`] on every axis.
fn within(p: Vec3) -> bool {
    p.abs().max_element() <= MAX_COORDINATE
}

/// `p` written for the user: world coordinates (the scene's origin added back), short.
fn world(scene: &Scene, p: Vec3) -> String {
    let w = scene.origin + p.as_dvec3();
    format!("({:.3e}, {:.3e}, {:.3e})", w.x, w.y, w.z)
}

/// The sentence every refusal ends with.
fn beyond(scene: &Scene) -> String {
    let origin = if scene.origin == glam::DVec3::ZERO {
        String::new()
    } else {
        format!(" of the scene's origin {}", world(scene, Vec3::ZERO))
    };
    format!(
        "beyond {MAX_COORDINATE:e}{origin} on some axis, where squared distances overflow in \
         f32: scale the scene down"
    )
}

/// The first vertex of `scene`'s mesh that lies beyond [`MAX_COORDINATE`] (or is not finite),
/// named with the mesh file of the object it belongs to.
pub fn check_geometry(scene: &Scene) -> Result<(), String> {
    let Some(i) = scene.mesh.positions.iter().position(|&p| !within(p)) else {
        return Ok(());
    };
    let p = scene.mesh.positions[i];
    let object = scene
        .mesh
        .triangles
        .iter()
        .position(|t| t.contains(&(i as u32)))
        .and_then(|t| scene.objects.iter().find(|o| o.triangles.contains(&t)));
    let of = match object {
        Some(o) if o.mesh != scene.source => format!(" (of {})", o.mesh.display()),
        _ => String::new(),
    };
    Err(format!("vertex {i}{of} lies at {}, {}", world(scene, p), beyond(scene)))
}

/// The camera's position and target within [`MAX_COORDINATE`].
pub fn check_camera(scene: &Scene) -> Result<(), String> {
    let c = &scene.camera;
    for (what, p) in [("position", c.position), ("look_at", c.look_at)] {
        if !within(p) {
            return Err(format!(
                "the camera's {what} lies at {}, {}",
                world(scene, p),
                beyond(scene)
            ));
        }
    }
    Ok(())
}

/// Every positional light within [`MAX_COORDINATE`].
pub fn check_lights(scene: &Scene) -> Result<(), String> {
    for (k, light) in scene.lights.iter().enumerate() {
        let position = match light.kind {
            LightKind::Point { position } | LightKind::Spot { position, .. } => position,
            LightKind::Directional { .. } => continue,
        };
        if !within(position) {
            let which = if scene.default_lights {
                format!("the automatic light {}", k + 1)
            } else {
                format!("light {}", k + 1)
            };
            return Err(format!("{which} lies at {}, {}", world(scene, position), beyond(scene)));
        }
    }
    Ok(())
}

/// [`check_geometry`], [`check_camera`] and [`check_lights`].
pub fn check(scene: &Scene) -> Result<(), String> {
    check_geometry(scene)?;
    check_camera(scene)?;
    check_lights(scene)
}
