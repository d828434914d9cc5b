//! World-space triangle meshes: the geometry every object of a scene is merged into.

use glam::{Mat3, Mat4, Vec2, Vec3};

/// Triangles in world space with per-vertex shading normals and a material per triangle.
///
/// All objects of a scene are merged into one `TriangleMesh` so the BVH is built once over every
/// triangle. Vertex normals are always present and unit length: files without normals get
/// angle-weighted ones ([`angle_weighted_normals`]), as Mitsuba computes them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Texture coordinates, one per position, if every object has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Vertex indices, counter-clockwise seen from the side the geometric normal points to.
    pub triangles: Vec<[u32; 3]>,
    /// Index into the scene's materials, one per triangle.
    pub material_of_triangle: Vec<u32>,
}

impl TriangleMesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The three vertex positions of triangle `t`.
    pub fn triangle_positions(&self, t: usize) -> [Vec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// Axis-aligned bounds `(min, max)` of all vertices referenced by a triangle, or `None` if empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.triangles.iter().flatten().map(|&i| self.positions[i as usize]);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// Appends `other`, whose material indices are relative to `material_base`.
    pub fn append(&mut self, other: TriangleMesh, material_base: u32) {
        let base = self.positions.len() as u32;
        let had_geometry = !self.positions.is_empty();
        self.uvs = match (self.uvs.take(), other.uvs) {
            (Some(mut a), Some(b)) => {
                a.extend(b);
                Some(a)
            }
            (None, Some(b)) if !had_geometry => Some(b),
            _ => None,
        };
        self.positions.extend(other.positions);
        self.normals.extend(other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
        self.material_of_triangle
            .extend(other.material_of_triangle.iter().map(|m| m + material_base));
    }

    /// Applies an affine transform: positions by `m`, normals by its inverse transpose (then
    /// renormalised). A negative determinant mirrors the mesh, so the winding is reversed to keep
    /// geometric normals on the same side as the shading normals.
    pub fn transform(&mut self, m: Mat4) {
        let normal_matrix = Mat3::from_mat4(m).inverse().transpose();
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = (normal_matrix * *n).normalize_or_zero();
        }
        if Mat3::from_mat4(m).determinant() < 0.0 {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
    }
}

/// Angle-weighted vertex normals: n_v = normalize(Σ over faces at v of n_face · interior angle at v).
///
/// This is what Mitsuba computes for meshes without normals. Degenerate triangles (zero area)
/// contribute nothing; a vertex no triangle gives a direction to gets the zero vector, which the
/// shader treats as "use the geometric normal".
pub fn angle_weighted_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    for tri in triangles {
        let p = tri.map(|i| positions[i as usize]);
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        if face == Vec3::ZERO {
            continue;
        }
        for k in 0..3 {
            let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
            let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
            // acos of a clamped cosine: e1·e2 can exceed 1 by rounding.
            let angle = e1.dot(e2).clamp(-1.0, 1.0).acos();
            sum[tri[k] as usize] += face * angle;
        }
    }
    sum.into_iter().map(Vec3::normalize_or_zero).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad_corner() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        // Two faces meeting at vertex 0 at a right angle: one in the xy plane, one in the xz plane.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(0.0, 0.0, -1.0), // xz face, normal +Y
        ];
        (p, vec![[0, 1, 2], [0, 1, 3]])
    }

    #[test]
    fn angle_weighted_normal_weights_faces_by_their_angle_at_the_vertex() {
        let (p, t) = quad_corner();
        let n = angle_weighted_normals(&p, &t);
        // Both faces have a 90° angle at vertex 0: the normal is the bisector of +Z and +Y.
        assert!((n[0] - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        // Vertex 2 only touches the xy face.
        assert!((n[2] - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn mirroring_transform_keeps_geometric_normal_on_the_shading_normal_side() {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: None,
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
        };
        mesh.transform(Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)));
        let [a, b, c] = mesh.triangle_positions(0);
        let ng = (b - a).cross(c - a).normalize();
        assert!(ng.dot(mesh.normals[0]) > 0.99, "ng {ng} ns {}", mesh.normals[0]);
        assert!((mesh.normals[0] - Vec3::NEG_Z).length() < 1e-6);
    }

    #[test]
    fn append_offsets_indices_and_materials() {
        let tri = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uvs: None,
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
        };
        let mut all = tri.clone();
        all.append(tri, 5);
        assert_eq!(all.triangles[1], [3, 4, 5]);
        assert_eq!(all.material_of_triangle, vec![0, 5]);
        assert_eq!(all.bounds(), Some((Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0))));
    }
}
