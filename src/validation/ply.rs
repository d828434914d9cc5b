//! Parts of the scene mesh as binary PLY files, for Mitsuba to load what it cannot read itself
//! (glTF meshes, and OBJ files whose faces use several materials).
//!
//! A part is the triangles of one object that use one material, in world space, with the unit
//! vertex normals pointshade shades with and the winding it takes the geometric normal from: what
//! Mitsuba then renders is the geometry pointshade renders, whichever loader made it.
//!
//! Parts of textured materials also carry what the `pointshade` plugin needs to look textures up
//! as pointshade does ([`VertexAttributes`]). Mitsuba's PLY loader turns a group of one or three
//! properties `name_x, name_y, name_z` into the mesh attribute `vertex_name`, which the plugin
//! interpolates at each hit; plain `u, v` are not written, so Mitsuba's own texture-coordinate
//! conventions never apply.

use std::fmt::Write as _;

use glam::{Vec2, Vec4};

use crate::scene::mesh::TriangleMesh;

/// Per-vertex data a part carries beyond positions and normals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VertexAttributes {
    /// Texture-coordinate sets 0 and 1, as `uv{k}_x, uv{k}_y, uv{k}_z` (z = 0; Mitsuba takes
    /// groups of one or three), zeros where the mesh has no such set.
    pub uv: [bool; 2],
    /// The tangent `tangent_x, tangent_y, tangent_z` and its bitangent sign `handedness_x`
    /// (zeros where the mesh has no tangents: no normal mapping there, as in pointshade).
    pub tangent: bool,
}

impl VertexAttributes {
    /// The PLY property names, in the order they follow the normal.
    fn names(self) -> Vec<String> {
        let mut names = Vec::new();
        for (k, _) in self.uv.iter().enumerate().filter(|(_, &on)| on) {
            names.extend(["x", "y", "z"].map(|c| format!("uv{k}_{c}")));
        }
        if self.tangent {
            names.extend(["tangent_x", "tangent_y", "tangent_z", "handedness_x"].map(String::from));
        }
        names
    }
}

/// The triangles of `mesh` in `triangles`, one part per material they use, in material order:
/// (material, binary little-endian PLY with positions, normals and `attributes(material)` per
/// vertex, vertices shared as in `mesh` and listed in the order the part's triangles first use
/// them). One pass over the triangles, whatever the number of materials.
pub fn parts(
    mesh: &TriangleMesh,
    triangles: std::ops::Range<usize>,
    attributes: impl Fn(u32) -> VertexAttributes,
) -> Vec<(u32, Vec<u8>)> {
    let mut by_material: std::collections::BTreeMap<u32, Vec<[u32; 3]>> = Default::default();
    for t in triangles {
        by_material
            .entry(mesh.material_of_triangle[t])
            .or_default()
            .push(mesh.triangles[t]);
    }
    by_material
        .into_iter()
        .map(|(material, chosen)| (material, write(mesh, &chosen, attributes(material))))
        .collect()
}

/// The PLY of the triangles `chosen` (vertex indices into `mesh`).
fn write(mesh: &TriangleMesh, chosen: &[[u32; 3]], attributes: VertexAttributes) -> Vec<u8> {
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
    let extra = attributes.names();
    for name in ["x", "y", "z", "nx", "ny", "nz"]
        .into_iter()
        .chain(extra.iter().map(String::as_str))
    {
        let _ = writeln!(header, "property float {name}");
    }
    let _ = writeln!(header, "element face {}", faces.len());
    header.push_str("property list uchar int vertex_indices\nend_header\n");
    let mut bytes = header.into_bytes();
    bytes.reserve(vertices.len() * 4 * (6 + extra.len()) + faces.len() * 13);
    let at = |set: &Option<Vec<Vec2>>, v: usize| set.as_ref().map_or(Vec2::ZERO, |uvs| uvs[v]);
    let put = |bytes: &mut Vec<u8>, values: &[f32]| {
        for c in values {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    };
    for &v in &vertices {
        let v = v as usize;
        put(&mut bytes, &mesh.positions[v].to_array());
        put(&mut bytes, &mesh.normals[v].to_array());
        for (k, set) in [&mesh.uvs, &mesh.uvs1].into_iter().enumerate() {
            if attributes.uv[k] {
                put(&mut bytes, &at(set, v).extend(0.0).to_array());
            }
        }
        if attributes.tangent {
            put(
                &mut bytes,
                &mesh.tangents.as_ref().map_or(Vec4::ZERO, |t| t[v]).to_array(),
            );
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
        let parts = parts(&m, 0..4, |_| VertexAttributes::default());
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
        let only_first = parts(&m, 0..2, |_| VertexAttributes::default());
        assert_eq!(only_first.len(), 1, "the range holds only material 0");
        assert_eq!(only_first[0].0, 0);
        assert!(parts(&m, 0..0, |_| VertexAttributes::default()).is_empty());
    }

    #[test]
    fn textured_parts_carry_texture_coordinates_and_tangents_as_mitsuba_attribute_groups() {
        let mut m = mesh();
        m.uvs = Some((0..6).map(|i| Vec2::new(i as f32 / 10.0, 0.5)).collect());
        m.tangents = Some(vec![Vec4::new(1.0, 0.0, 0.0, -1.0); 6]);
        let parts = parts(&m, 0..4, |material| VertexAttributes {
            uv: [material == 1, material == 1],
            tangent: material == 1,
        });
        let (plain, _) = split(&parts[0].1);
        assert!(
            !plain.iter().any(|l| l.contains("uv0")),
            "material 0 asks for nothing: {plain:?}"
        );
        let (header, body) = split(&parts[1].1);
        let properties: Vec<&str> = header
            .iter()
            .filter_map(|l| l.strip_prefix("property float "))
            .collect();
        assert_eq!(
            properties,
            [
                "x",
                "y",
                "z",
                "nx",
                "ny",
                "nz",
                "uv0_x",
                "uv0_y",
                "uv0_z",
                "uv1_x",
                "uv1_y",
                "uv1_z",
                "tangent_x",
                "tangent_y",
                "tangent_z",
                "handedness_x"
            ]
        );
        let stride = properties.len();
        assert_eq!(body.len(), 4 * stride * 4 + 2 * 13);
        // The part's first vertex is the mesh's vertex 1: uv (0.1, 0.5); no second set → zeros.
        let vertex: Vec<f32> = (0..stride).map(|k| f32_at(body, k)).collect();
        assert_eq!(vertex[6..9], [0.1, 0.5, 0.0]);
        assert_eq!(vertex[9..12], [0.0, 0.0, 0.0]);
        assert_eq!(vertex[12..16], [1.0, 0.0, 0.0, -1.0]);
    }
}
