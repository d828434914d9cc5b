//! glTF cameras → [`CameraSpec`]s.
//!
//! A glTF camera looks down −Z of its node with +Y up; only the node's rotation and translation
//! count (scale is ignored: the axes are normalised). Perspective cameras keep their vertical
//! field of view `yfov`; `aspectRatio`, or `xmag/ymag` for orthographic ones, sets the image's
//! width for its height unless the command line says otherwise. `znear`/`zfar` become the clip
//! distances along the view axis.

use glam::{Mat4, Vec3};

use crate::error::InputResult;
use crate::scene::camera::{Camera, CameraSpec, FovAxis, Projection};
use crate::scene::gltf::document::GltfDocument;

/// A camera of the file, placed by a node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfCamera {
    /// Index of the camera in the file.
    pub index: usize,
    /// Where it is and how it projects.
    pub spec: CameraSpec,
    /// Width / height the camera was made for, if it says.
    pub aspect: Option<f32>,
}

/// The camera `camera` placed by a node with world matrix `world`.
pub fn camera_at(d: &GltfDocument, camera: &::gltf::Camera, world: Mat4) -> InputResult<GltfCamera> {
    let index = camera.index();
    let err = |problem: String| d.error(format!("camera {index}: {problem}"));
    let position = world.w_axis.truncate();
    let forward = (-world.z_axis.truncate()).normalize_or_zero();
    let up = world.y_axis.truncate().normalize_or_zero();
    if forward == Vec3::ZERO || up == Vec3::ZERO || forward.cross(up).length() < 1e-6 {
        return Err(err("its node's transform collapses the view or up direction".into()));
    }
    let positive = |name: &str, v: f32| {
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(err(format!("{name} must be a finite number > 0, got {v}")))
        }
    };
    let (projection, near, far, aspect) = match camera.projection() {
        ::gltf::camera::Projection::Perspective(p) => {
            let yfov = positive("yfov", p.yfov())?;
            if yfov >= std::f32::consts::PI {
                return Err(err(format!("yfov must be below π, got {yfov}")));
            }
            let aspect = p.aspect_ratio().map(|a| positive("aspectRatio", a)).transpose()?;
            let projection = Projection::Perspective {
                fov_degrees: yfov.to_degrees(),
                fov_axis: FovAxis::Y,
            };
            (projection, p.znear(), p.zfar().unwrap_or(f32::INFINITY), aspect)
        }
        ::gltf::camera::Projection::Orthographic(o) => {
            let (xmag, ymag) = (positive("xmag", o.xmag().abs())?, positive("ymag", o.ymag().abs())?);
            (
                Projection::Orthographic { scale: ymag },
                o.znear(),
                o.zfar(),
                Some(xmag / ymag),
            )
        }
    };
    let spec = CameraSpec {
        position,
        look_at: position + forward,
        up,
        projection,
        near_clip: near,
        far_clip: far,
    };
    Camera::new(spec, 1, 1).map_err(err)?;
    Ok(GltfCamera { index, spec, aspect })
}

/// The widest and the tallest aspect ratio a camera may set the film to: 100:1 and 1:100.
pub const ASPECT_LIMIT: f32 = 100.0;

/// Image width for a camera of aspect ratio `aspect` at the given height, or, for an aspect
/// beyond [`ASPECT_LIMIT`] either way (`aspectRatio` 1e9 would make a film of 4.8e11 × 480
/// pixels), a warning that it is not used.
pub fn film_width(height: u32, aspect: f32, camera: usize) -> Result<u32, String> {
    if (1.0 / ASPECT_LIMIT..=ASPECT_LIMIT).contains(&aspect) {
        Ok(((height as f32 * aspect).round() as u32).max(1))
    } else {
        Err(format!(
            "camera {camera}: its aspect ratio {aspect:e} (aspectRatio, or xmag/ymag) is beyond \
             {ASPECT_LIMIT}:1 either way and is not used: the film keeps its default size \
             (--width and --height set it)"
        ))
    }
}
