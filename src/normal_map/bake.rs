//! Baking: a mesh scene's camera-space normals as a normal image in the NPM3D assignment's format,
//! so that `pointshade normalmap` can shade any mesh the way the assignment shaded its dragon.
//!
//! One camera ray through the centre of each pixel (a normal image stores one normal per pixel:
//! averaging normals over samples would make them shorter at silhouettes, so the film's spp and
//! sampler are not used). The normal written is the shading normal the shader would use — turned
//! towards the viewer for two-sided materials when it faces away, as the shader turns it —
//! expressed in the camera's frame: x to the right of the image, y up, z towards the viewer.

use glam::Vec3;
use rayon::prelude::*;

use crate::accel::Bvh;
use crate::scene::camera::Camera;
use crate::scene::Scene;
use crate::surface::primary::{surface_point, PointOptions};

/// Camera-space unit normals of every pixel, row-major; `None` where the ray hits nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedNormals {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// One normal per pixel, or `None` for background.
    pub normals: Vec<Option<Vec3>>,
}

impl BakedNormals {
    /// Number of pixels that hit the geometry.
    pub fn hits(&self) -> usize {
        self.normals.iter().filter(|n| n.is_some()).count()
    }
}

/// Traces one primary ray per pixel centre of `scene`'s film through `bvh` and records the
/// camera-space shading normal of each hit.
pub fn bake_normals(scene: &Scene, bvh: &Bvh) -> Result<BakedNormals, String> {
    let (w, h) = (scene.film.width, scene.film.height);
    let camera = Camera::new(scene.camera, w, h)?;
    let (left, up, forward) = camera.frame();
    let mut normals = vec![None; w as usize * h as usize];
    normals.par_chunks_mut(w as usize).enumerate().for_each(|(y, row)| {
        for (x, out) in row.iter_mut().enumerate() {
            let ray = camera.ray((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let Some(hit) = bvh.intersect(ray.origin, ray.direction, ray.t_max) else {
                continue;
            };
            let sp = surface_point(&scene.mesh, &hit, ray.direction, PointOptions::default());
            let mut n = sp.shading_normal;
            if scene.materials[sp.material as usize].two_sided && n.dot(sp.to_viewer) < 0.0 {
                n = -n;
            }
            // Image right is −left; towards the viewer is −forward.
            *out = Some(Vec3::new(-n.dot(left), n.dot(up), -n.dot(forward)));
        }
    });
    Ok(BakedNormals {
        width: w,
        height: h,
        normals,
    })
}
