//! Parts of the scene mesh as binary PLY files, for Mitsuba to load what it cannot read itself
//! (glTF meshes, and OBJ files whose faces use several materials).
//!
//! A part is the triangles of one object that use one material, in world space, with the unit
//! vertex normals pointshade shades with and the winding it takes the geometric normal from: what
//! Mitsuba then renders is the geometry pointshade renders, whichever loader made it.

use std::fmt::Write as _;

use crate::scene::mesh::TriangleMesh;

/// The triangles of `mesh` in `triangles`, one part per material they use, in material order:
/// (material, binary little-endian PLY with positions and normals per vertex, vertices shared
/// as in `mesh` and listed in the order the part's triangles first use them). One pass over the
/// triangles, whatever the number of materials.
pub fn parts(mesh: &TriangleMesh, triangles: std::ops::Range<usize>) -> Vec<(u32, Vec<u8>)> {
    let mut by_material: std::collections::BTreeMap<u32, Vec<[u32; 3]>> = Default::default();
    for t in triangles {
        by_material
            .entry(mesh.material_of_triangle[t])
            .or_default()
            .push(mesh.triangles[t]);
    }
    by_material
        .into_iter()
        .map(|(material, chosen)| (material, write(mesh, &chosen)))
        .collect()
}

/// The PLY of the triangles `chosen` (vertex indices into `mesh`).
fn write(mesh: &TriangleMesh, chosen: &[[u32; 3]]) -> Vec<u8> {
    // Renumber the vertices the part uses, in first-use order.
    let mut new_index = std::collections::HashMap::new();
    let mut vertices: Vec<u32> = Vec::new();
    let faces: Vec<[u32; 3]> = chosen
        .iter()
        .map(|tri| {
            tri.map(|v| {
                *new_index.entry(v).or_insert_with(|| {
                    vertices.push(v);
                    vertices.len() as u32 - 1
                })
            })
        })
        .collect();
    let mut header = String::from("ply\nformat binary_little_endian 1.0\ncomment written by pointshade\n");
    let _ = writeln!(header, "element vertex {}", vertices.len());
    for name in ["x", "y", "z", "nx", "ny", "nz"] {
        let _ = writeln!(header, "property float {name}");
    }
    let _ = writeln!(header, "element face {}", faces.len());
    header.push_str("property list uchar int vertex_indices\nend_header\n");
    let mut bytes = header.into_bytes();
    bytes.reserve(vertices.len() * 24 + faces.len() * 13);
    for &v in &vertices {
        let (p, n) = (mesh.positions[v as usize], mesh.normals[v as usize]);
        for c in p.to_array().into_iter().chain(n.to_array()) {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    for face in &faces {
        bytes.push(3);
        for &i in face {
            bytes.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    bytes
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// Two quads (four triangles) of materials 0 and 1, sharing an edge.
    fn mesh() -> TriangleMesh {
        let positions: Vec<Vec3> = (0..6).map(|i| Vec3::new((i % 3) as f32, (i / 3) as f32, 0.5)).collect();
        TriangleMesh {
            normals: vec![Vec3::Z; positions.len()],
            positions,
            triangles: vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]],
            material_of_triangle: vec![0, 0, 1, 1],
            ..TriangleMesh::default()
        }
    }

    /// The header's lines and the binary body of a PLY file.
    fn split(bytes: &[u8]) -> (Vec<String>, &[u8]) {
        let end = b"end_header\n";
        let at = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        let header = String::from_utf8(bytes[..at].to_vec()).unwrap();
        (header.lines().map(str::to_string).collect(), &bytes[at..])
    }

    fn f32_at(body: &[u8], k: usize) -> f32 {
        f32::from_le_bytes(body[4 * k..4 * k + 4].try_into().unwrap())
    }

    #[test]
    fn a_part_holds_the_triangles_of_its_material_with_their_vertices_renumbered() {
        let m = mesh();
        let parts = parts(&m, 0..4);
        assert_eq!(parts.iter().map(|p| p.0).collect::<Vec<_>>(), [0, 1]);
        let (header, body) = split(&parts[1].1);
        assert!(header.contains(&"element vertex 4".to_string()), "{header:?}");
        assert!(header.contains(&"element face 2".to_string()));
        assert_eq!(body.len(), 4 * 24 + 2 * 13);
        // First-use order: 1, 2, 5, 4 become 0, 1, 2, 3; vertex 2 is (2, 0, 0.5).
        assert_eq!([f32_at(body, 6), f32_at(body, 7), f32_at(body, 8)], [2.0, 0.0, 0.5]);
        assert_eq!(f32_at(body, 11), 1.0, "its normal's z");
        let faces = &body[4 * 24..];
        let face = |k: usize| -> Vec<i32> {
            let f = &faces[13 * k..13 * k + 13];
            assert_eq!(f[0], 3);
            (0..3)
                .map(|i| i32::from_le_bytes(f[1 + 4 * i..5 + 4 * i].try_into().unwrap()))
                .collect()
        };
        assert_eq!((face(0), face(1)), (vec![0, 1, 2], vec![0, 2, 3]), "winding kept");
    }

    #[test]
    fn only_the_materials_in_the_range_make_parts() {
        let m = mesh();
        let only_first = parts(&m, 0..2);
        assert_eq!(only_first.len(), 1, "the range holds only material 0");
        assert_eq!(only_first[0].0, 0);
        assert!(parts(&m, 0..0).is_empty());
    }
}
