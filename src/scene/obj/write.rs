//! OBJ text from a mesh's arrays: what `gen-meshes` writes for the procedural shapes in
//! `meshes/` and what the Python module's `Scene.save` writes for meshes given as arrays.
//!
//! Numbers are written in Rust's shortest round-trip form, so reading the file back gives exactly
//! the values written, in the precision they were given (f32 for the procedural shapes, f64 for
//! arrays); indices are 1-based, as OBJ counts.

use std::fmt::{Display, Write as _};

use super::MeshArrays;

/// The arrays of a mesh to write: positions, optional normals and texture coordinates (one of
/// each per position), triangles (0-based), and named groups (a material each) as runs of
/// consecutive triangles, `(name, first triangle)` in triangle order.
pub struct ObjMesh<'a, F> {
    /// Comment lines at the top (without `#`).
    pub header: &'a str,
    /// The material library the groups' materials come from.
    pub mtllib: Option<&'a str>,
    /// Vertex positions.
    pub positions: &'a [[F; 3]],
    /// Vertex normals, if given.
    pub normals: Option<&'a [[F; 3]]>,
    /// Texture coordinates (v up), if given.
    pub uvs: Option<&'a [[F; 2]]>,
    /// Triangles, 0-based.
    pub triangles: &'a [[u32; 3]],
    /// `(material name, first triangle)` of each group.
    pub groups: &'a [(String, usize)],
}

impl<F: Display> ObjMesh<'_, F> {
    /// The OBJ text.
    pub fn to_obj(&self) -> String {
        let mut s = String::new();
        for line in self.header.lines() {
            let _ = writeln!(s, "# {line}");
        }
        if let Some(lib) = self.mtllib {
            let _ = writeln!(s, "mtllib {lib}");
        }
        for [x, y, z] in self.positions {
            let _ = writeln!(s, "v {x} {y} {z}");
        }
        for [x, y, z] in self.normals.iter().copied().flatten() {
            let _ = writeln!(s, "vn {x} {y} {z}");
        }
        for [u, v] in self.uvs.iter().copied().flatten() {
            let _ = writeln!(s, "vt {u} {v}");
        }
        let (uvs, normals) = (self.uvs.is_some(), self.normals.is_some());
        let corner = |i: u32| {
            let i = i + 1;
            match (uvs, normals) {
                (false, false) => format!("{i}"),
                (true, false) => format!("{i}/{i}"),
                (false, true) => format!("{i}//{i}"),
                (true, true) => format!("{i}/{i}/{i}"),
            }
        };
        let mut groups = self.groups.iter().peekable();
        for (k, t) in self.triangles.iter().enumerate() {
            while let Some((name, _)) = groups.next_if(|(_, first)| *first == k) {
                let _ = writeln!(s, "o {name}\nusemtl {name}");
            }
            let _ = writeln!(s, "f {} {} {}", corner(t[0]), corner(t[1]), corner(t[2]));
        }
        s
    }
}

impl MeshArrays {
    /// The OBJ file that loads exactly as these arrays do ([`super::load_mesh_arrays`]).
    pub fn to_obj(&self) -> String {
        fn rows<const N: usize>(flat: &[f64]) -> Vec<[f64; N]> {
            flat.chunks_exact(N).map(|c| std::array::from_fn(|i| c[i])).collect()
        }
        let (positions, normals, uvs) = (
            rows::<3>(&self.positions),
            rows::<3>(&self.normals),
            rows::<2>(&self.uvs),
        );
        let triangles: Vec<[u32; 3]> = self.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        ObjMesh {
            header: "written by pointshade from arrays",
            mtllib: None,
            positions: &positions,
            normals: (!normals.is_empty()).then_some(&normals[..]),
            uvs: (!uvs.is_empty()).then_some(&uvs[..]),
            triangles: &triangles,
            groups: &[],
        }
        .to_obj()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::obj::load_mesh_arrays;

    #[test]
    fn arrays_written_as_obj_load_as_the_arrays_do() {
        let arrays = MeshArrays {
            positions: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 1.0 / 3.0, 1e-7],
            indices: vec![0, 1, 2],
            normals: vec![0.0, 0.0, 1.0, 0.0, 0.6, 0.8, 0.0, 0.0, 1.0],
            uvs: vec![0.0, 0.0, 1.0, 0.0, 0.25, 1.0],
        };
        let dir = std::env::temp_dir().join(format!("pointshade-obj-write-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("m.obj");
        std::fs::write(&path, arrays.to_obj()).unwrap();
        let from_file = crate::scene::obj::load_obj_underived(&path).unwrap().0;
        let (from_arrays, _) = load_mesh_arrays(&path, &arrays).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(from_file.mesh.positions, from_arrays.mesh.positions);
        assert_eq!(from_file.mesh.normals, from_arrays.mesh.normals);
        assert_eq!(from_file.mesh.uvs, from_arrays.mesh.uvs);
        assert_eq!(from_file.mesh.triangles, from_arrays.mesh.triangles);
    }
}
