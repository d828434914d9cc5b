//! Normal textures: a surface point's shading normal perturbed by its material's tangent-space
//! normal texture (glTF `normalTexture`), in the surface stage, so that the shader, the AOVs and
//! everything after [`SurfacePoint`] see the final normal.
//!
//! The tangent frame is the glTF one: N = the interpolated shading normal, T = the interpolated
//! vertex tangent made orthogonal to N (Gram–Schmidt), B = w·(N × T) with w the tangent's
//! handedness sign. A texel (r, g, b) ∈ [0, 1]³ encodes the tangent-space normal
//! ((2r − 1)·scale, (2g − 1)·scale, 2b − 1) — +X along T, +Y along B ("up" in the image), +Z
//! along N — and the shading normal becomes normalize(x·T + y·B + z·N).

use glam::{Vec2, Vec3};

use crate::accel::Hit;
use crate::material::Material;
use crate::scene::mesh::TriangleMesh;
use crate::surface::SurfacePoint;
use crate::texture::{ColorSpace, TextureImage};

/// Replaces `point.shading_normal` by the normal its material's normal texture gives at the
/// point. Leaves it unchanged where the material has no normal texture, the vertices have no
/// tangents (zero tangents), or the frame or the result degenerates (zero length).
#[inline]
pub fn apply_normal_texture(
    point: &mut SurfacePoint,
    mesh: &TriangleMesh,
    hit: &Hit,
    materials: &[Material],
    images: &[TextureImage],
) {
    let Some(normal) = materials[point.material as usize].textures.normal else {
        return;
    };
    let Some(tangents) = &mesh.tangents else { return };
    let [i0, i1, i2] = mesh.triangles[hit.triangle as usize].map(|i| i as usize);
    let b0 = 1.0 - hit.b1 - hit.b2;
    let t = b0 * tangents[i0] + hit.b1 * tangents[i1] + hit.b2 * tangents[i2];
    // Handedness: the sign of the interpolated w (the vertices of a triangle normally agree);
    // w = 0 marks vertices without a tangent.
    if t.w == 0.0 {
        return;
    }
    let n = point.shading_normal;
    let tangent = (t.truncate() - n * n.dot(t.truncate())).normalize_or_zero();
    if tangent == Vec3::ZERO {
        return;
    }
    let bitangent = t.w.signum() * n.cross(tangent);
    let uv: Vec2 = if normal.texture.tex_coord == 0 {
        point.uv
    } else {
        point.uv1
    };
    let texel = normal.texture.sample(images, uv, ColorSpace::Linear);
    let x = (2.0 * texel.x - 1.0) * normal.scale;
    let y = (2.0 * texel.y - 1.0) * normal.scale;
    let z = 2.0 * texel.z - 1.0;
    let perturbed = (x * tangent + y * bitangent + z * n).normalize_or_zero();
    if perturbed != Vec3::ZERO && perturbed.is_finite() {
        point.shading_normal = perturbed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{MaterialTextures, NormalTexture};
    use crate::texture::TextureRef;
    use glam::Vec4;

    /// A quad in the xy plane facing +z, u along +x and v along −y (the image's top row at
    /// +y), tangent +x with w = +1, and a material whose normal texture is one texel.
    fn setup(texel: [u8; 4], scale: f32) -> (SurfacePoint, TriangleMesh, Vec<Material>, Vec<TextureImage>) {
        let mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: Some(vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)]),
            tangents: Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 3]),
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
            ..Default::default()
        };
        let mut m = Material::gltf_pbr("m", [1.0; 3], 0.0, 0.5);
        m.textures = MaterialTextures {
            normal: Some(NormalTexture {
                texture: TextureRef::gltf_default(0),
                scale,
            }),
            ..Default::default()
        };
        let image = TextureImage {
            label: "n".into(),
            width: 1,
            height: 1,
            texels: vec![texel],
        };
        let point = SurfacePoint {
            position: Vec3::new(0.25, 0.25, 0.0),
            shadow_lift: 0.0,
            geometric_normal: Vec3::Z,
            shading_normal: Vec3::Z,
            uv: Vec2::new(0.25, 0.75),
            uv1: Vec2::ZERO,
            material: 0,
            to_viewer: Vec3::Z,
        };
        (point, mesh, vec![m], vec![image])
    }

    fn perturbed(texel: [u8; 4], scale: f32) -> Vec3 {
        let (mut p, mesh, materials, images) = setup(texel, scale);
        let hit = Hit {
            triangle: 0,
            t: 1.0,
            b1: 0.25,
            b2: 0.25,
        };
        apply_normal_texture(&mut p, &mesh, &hit, &materials, &images);
        p.shading_normal
    }

    #[test]
    fn flat_texel_keeps_the_normal() {
        // (128, 128, 255) is (0.0039, 0.0039, 1): within half a code step of +Z.
        let n = perturbed([128, 128, 255, 255], 1.0);
        assert!((n - Vec3::Z).length() < 0.01, "{n}");
    }

    #[test]
    fn green_is_up_in_the_image_and_red_is_along_u() {
        // +Y of the texture points where v decreases: world +y here.
        let up = perturbed([128, 255, 128, 255], 1.0);
        assert!(up.y > 0.99, "{up}");
        let right = perturbed([255, 128, 128, 255], 1.0);
        assert!(right.x > 0.99, "{right}");
    }

    #[test]
    fn scale_multiplies_x_and_y() {
        // Texel (0.5 + 0.25, ·, 1): x = 0.5·scale, z = 1.
        let tilt = |scale| {
            let n = perturbed([191, 128, 255, 255], scale);
            n.x / n.z
        };
        assert!((tilt(1.0) - 0.498).abs() < 0.01, "{}", tilt(1.0));
        assert!((tilt(2.0) - 2.0 * tilt(1.0)).abs() < 1e-4);
        assert!((perturbed([191, 128, 255, 255], 0.0) - Vec3::Z).length() < 1e-6);
    }
}
