//! Tangent generation for normal-mapped geometry whose file gives none — a glTF primitive
//! without `TANGENT`, any OBJ — with MikkTSpace (the algorithm glTF names; `bevy_mikktspace`
//! reproduces the reference C code).
//!
//! MikkTSpace's bitangent is sign·(N × T) along +v of the coordinates it is given. glTF's v grows
//! downwards in the image while the normal texture's +Y points up, so the coordinates are given
//! as (u, 1 − v): the tangents and signs are then those of tools that bake with v up (Blender,
//! which writes glTF files with exactly these tangents), and B = w·(N × T) points up the image.

use glam::{Vec2, Vec3, Vec4};

use crate::material::Material;
use crate::scene::mesh::TriangleMesh;

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

/// Gives tangents to the triangles of `mesh` whose material has a normal texture and whose
/// corners have none (an OBJ cannot store tangents): those triangles get vertices of their own
/// (copies of their corners) whose tangents MikkTSpace computes from the texture's coordinate
/// set, over those triangles together. Triangles without such a material, or whose coordinate
/// set the mesh lacks, are left as they are (no normal mapping there). Returns how many
/// triangles got tangents.
pub fn complete_tangents(mesh: &mut TriangleMesh, materials: &[Material]) -> usize {
    let mut done = 0;
    for set in [0u8, 1] {
        let Some(uvs) = (if set == 0 {
            mesh.uvs.as_ref()
        } else {
            mesh.uvs1.as_ref()
        }) else {
            continue;
        };
        let has_tangent = |t: &[u32; 3]| {
            mesh.tangents
                .as_ref()
                .is_some_and(|v| t.iter().any(|&i| v[i as usize].w != 0.0))
        };
        let chosen: Vec<usize> = (0..mesh.triangles.len())
            .filter(|&t| {
                let normal = materials
                    .get(mesh.material_of_triangle[t] as usize)
                    .and_then(|m| m.textures.normal);
                normal.is_some_and(|n| n.texture.tex_coord == set) && !has_tangent(&mesh.triangles[t])
            })
            .collect();
        if chosen.is_empty() {
            continue;
        }
        let corners: Vec<usize> = chosen
            .iter()
            .flat_map(|&t| mesh.triangles[t])
            .map(|i| i as usize)
            .collect();
        let pick = |v: &[Vec3]| corners.iter().map(|&i| v[i]).collect::<Vec<_>>();
        let (positions, normals) = (pick(&mesh.positions), pick(&mesh.normals));
        let corner_uvs: Vec<Vec2> = corners.iter().map(|&i| uvs[i]).collect();
        let local: Vec<[u32; 3]> = (0..chosen.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        let tangents = generate_tangents(&positions, &normals, &corner_uvs, &local);
        // The copies go after the existing vertices; the chosen triangles index them.
        let first = mesh.positions.len();
        let extend2 = |v: &mut Option<Vec<Vec2>>| {
            if let Some(v) = v {
                let copies: Vec<Vec2> = corners.iter().map(|&i| v[i]).collect();
                v.extend(copies);
            }
        };
        extend2(&mut mesh.uvs);
        extend2(&mut mesh.uvs1);
        let all = mesh.tangents.get_or_insert_with(|| vec![Vec4::ZERO; first]);
        all.extend(tangents);
        mesh.positions.extend(positions);
        mesh.normals.extend(normals);
        for (k, &t) in chosen.iter().enumerate() {
            let base = (first + 3 * k) as u32;
            mesh.triangles[t] = [base, base + 1, base + 2];
        }
        done += chosen.len();
    }
    done
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
