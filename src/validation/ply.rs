//! Parts of the scene mesh as binary PLY files, for Mitsuba to load what it cannot read itself
//! (glTF meshes, and OBJ files whose faces use several materials).
//!
//! A part is the triangles of one object that use one material, in world space, with the unit
//! vertex normals pointshade shades with and the winding it takes the geometric normal from: what
//! Mitsuba then renders is the geometry pointshade renders, whichever loader made it.

use std::fmt::Write as _;

use crate::scene::mesh::TriangleMesh;

/// The triangles of `mesh` in `triangles` whose material is `material`, as a binary
/// little-endian PLY (positions and normals per vertex, vertices shared as in `mesh`, listed in
/// the order the part's triangles first use them). `None` if no triangle matches.
pub fn part(mesh: &TriangleMesh, triangles: std::ops::Range<usize>, material: u32) -> Option<Vec<u8>> {
    let chosen: Vec<[u32; 3]> = triangles
        .filter(|&t| mesh.material_of_triangle[t] == material)
        .map(|t| mesh.triangles[t])
        .collect();
    if chosen.is_empty() {
        return None;
    }
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
    Some(bytes)
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
        let bytes = part(&m, 0..4, 1).unwrap();
        let (header, body) = split(&bytes);
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
    fn a_part_without_triangles_is_none() {
        let m = mesh();
        assert!(part(&m, 0..2, 1).is_none(), "the range holds only material 0");
        assert!(part(&m, 0..4, 7).is_none());
    }
}
