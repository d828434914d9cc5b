//! Tangent generation for primitives that have a normal texture but no `TANGENT` attribute, with
//! MikkTSpace (the algorithm glTF names; `bevy_mikktspace` reproduces the reference C code).
//!
//! MikkTSpace's bitangent is sign·(N × T) along +v of the coordinates it is given. glTF's v grows
//! downwards in the image while the normal texture's +Y points up, so the coordinates are given
//! as (u, 1 − v): the tangents and signs are then those of tools that bake with v up (Blender,
//! which writes glTF files with exactly these tangents), and B = w·(N × T) points up the image.

use glam::{Vec2, Vec3, Vec4};

/// One tangent per vertex (xyz unit, w = ±1) for a mesh whose triangles share no vertex (every
/// vertex belongs to exactly one triangle corner). Vertices MikkTSpace gives no tangent (a
/// degenerate triangle without neighbours) get zero, which disables normal mapping there.
pub fn generate_tangents(positions: &[Vec3], normals: &[Vec3], uvs: &[Vec2], triangles: &[[u32; 3]]) -> Vec<Vec4> {
    let mut geometry = Geometry {
        positions,
        normals,
        uvs,
        triangles,
        tangents: vec![Vec4::ZERO; positions.len()],
    };
    // The error type has no variants: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut geometry);
    geometry.tangents
}

struct Geometry<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    tangents: Vec<Vec4>,
}

impl Geometry<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.triangles[face][vert] as usize
    }
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs[self.vertex(face, vert)];
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent(&mut self, tangent: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        let v = self.vertex(face, vert);
        self.tangents[v] = match tangent {
            Some(t) => {
                let xyz = Vec3::from(t.tangent()).normalize_or_zero();
                if xyz == Vec3::ZERO || !xyz.is_finite() {
                    Vec4::ZERO
                } else {
                    xyz.extend(t.tangent_encoded()[3])
                }
            }
            None => Vec4::ZERO,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_facing_z_with_v_down_the_image_gets_tangent_x_and_positive_sign() {
        // Image top (v = 0) at y = 1, u along +x: bitangent = N × T must be +y, up the image.
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let uvs: Vec<Vec2> = positions.iter().map(|p| Vec2::new(p.x, 1.0 - p.y)).collect();
        let normals = vec![Vec3::Z; 6];
        let tangents = generate_tangents(&positions, &normals, &uvs, &[[0, 1, 2], [3, 4, 5]]);
        for t in tangents {
            assert!((t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-5, "{t}");
        }
    }

    #[test]
    fn mirrored_uvs_get_a_negative_sign() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        // u runs along −x: the layout is mirrored.
        let uvs = vec![Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0), Vec2::new(1.0, 0.0)];
        let tangents = generate_tangents(&positions, &[Vec3::Z; 3], &uvs, &[[0, 1, 2]]);
        for t in tangents {
            assert!((t - Vec4::new(-1.0, 0.0, 0.0, -1.0)).length() < 1e-5, "{t}");
            // Bitangent w·N × T = −(z × −x) = +y: still up the image.
            assert!((t.w * Vec3::Z.cross(t.truncate()) - Vec3::Y).length() < 1e-5);
        }
    }
}
