//! World-space triangle meshes: the geometry every object of a scene is merged into.

use std::ops::Range;

use glam::{DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};

use crate::scene::unit_vector::{power_of_two_scale, triangle_normal, unit_or_zero};

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
    /// Texture coordinates (set 0, glTF's `TEXCOORD_0`), one per position, if any object has them
    /// (objects without get zeros).
    pub uvs: Option<Vec<Vec2>>,
    /// Second texture-coordinate set (glTF's `TEXCOORD_1`), as `uvs`.
    pub uvs1: Option<Vec<Vec2>>,
    /// Unit tangents (xyz, along +u) with the bitangent sign in w (bitangent = w·normal × tangent),
    /// one per position, if any object has them; zero where a vertex has none (no normal mapping
    /// there).
    pub tangents: Option<Vec<Vec4>>,
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

    /// Whether some vertex normal leans away from its triangle's geometric normal (by more than
    /// about 0.8°): smooth shading over flat facets, where shadow-ray origins have somewhere
    /// to move ([`crate::surface::primary::smooth_origin`]). Stops at the first such triangle.
    pub fn normals_bend(&self) -> bool {
        self.triangles.iter().any(|&[a, b, c]| {
            let [pa, pb, pc] = [a, b, c].map(|i| self.positions[i as usize]);
            let ng = triangle_normal(pa, pb, pc);
            ng != Vec3::ZERO && [a, b, c].iter().any(|&i| self.normals[i as usize].dot(ng) < 0.9999)
        })
    }

    /// Per material of a `material_count`-long list: whether some triangle uses it.
    pub fn materials_used(&self, material_count: usize) -> Vec<bool> {
        let mut used = vec![false; material_count];
        for &m in &self.material_of_triangle {
            used[m as usize] = true;
        }
        used
    }

    /// Axis-aligned bounds `(min, max)` of all vertices referenced by a triangle, or `None` if empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.triangles.iter().flatten().map(|&i| self.positions[i as usize]);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// Appends `other`, whose material indices are relative to `material_base`. An optional
    /// attribute present on one side only is filled with zeros on the other.
    pub fn append(&mut self, other: TriangleMesh, material_base: u32) {
        let base = self.positions.len() as u32;
        let (ours, theirs) = (self.positions.len(), other.positions.len());
        self.uvs = merge_attribute(self.uvs.take(), other.uvs, ours, theirs);
        self.uvs1 = merge_attribute(self.uvs1.take(), other.uvs1, ours, theirs);
        self.tangents = merge_attribute(self.tangents.take(), other.tangents, ours, theirs);
        self.positions.extend(other.positions);
        self.normals.extend(other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
        self.material_of_triangle
            .extend(other.material_of_triangle.iter().map(|m| m + material_base));
    }

    /// Applies an affine transform: positions by `m`, normals by its inverse transpose (then
    /// renormalised), tangents by `m` itself (they are directions in the surface). A negative
    /// determinant mirrors the mesh, so the winding is reversed to keep geometric normals on the
    /// same side as the shading normals, and the bitangent signs flip (a mirror turns the
    /// right-handed frame into a left-handed one).
    pub fn transform(&mut self, m: Mat4) {
        let linear = Mat3::from_mat4(m);
        let (normal_matrix, mirrored) = normal_matrix(linear);
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = unit_or_zero(normal_matrix * *n);
        }
        for t in self.tangents.iter_mut().flatten() {
            let xyz = unit_or_zero(linear * t.truncate());
            let w = if mirrored { -t.w } else { t.w };
            *t = if xyz == Vec3::ZERO { Vec4::ZERO } else { xyz.extend(w) };
        }
        if mirrored {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
    }
}

/// The matrix that carries normals as `linear` carries positions (its inverse transpose, up to a
/// positive factor), and whether `linear` mirrors. Where the inverse overflows or underflows
/// (scales beyond about 1e±12, whose determinant leaves f32's normal range) it is the cofactor
/// matrix of `linear` scaled by a power of two, which has the same directions; elsewhere exactly
/// the inverse transpose.
fn normal_matrix(linear: Mat3) -> (Mat3, bool) {
    let det = linear.determinant();
    let inverse_transpose = linear.inverse().transpose();
    if det.is_normal() && inverse_transpose.is_finite() {
        return (inverse_transpose, det < 0.0);
    }
    let columns = [linear.x_axis, linear.y_axis, linear.z_axis];
    let largest = columns.iter().fold(Vec3::ZERO, |m, c| m.max(c.abs()));
    let s = power_of_two_scale(largest);
    let [c0, c1, c2] = columns.map(|c| c * s);
    let cofactor = Mat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    // (M⁻¹)ᵀ = cofactor / det: with det's sign, a mirror turns normals as the inverse does.
    let scaled_det = c0.dot(c1.cross(c2));
    if !(scaled_det != 0.0 && scaled_det.is_finite()) {
        return (Mat3::ZERO, false);
    }
    (cofactor * scaled_det.signum(), scaled_det < 0.0)
}

/// How many times its own size a mesh's centre may lie from the origin before its float32
/// coordinates are taken relative to that centre instead. At 8× the f32 step of a coordinate is
/// below 1e-6 of the mesh's size; meshes modelled around the origin stay exactly as read.
pub const FAR_FROM_ORIGIN: f64 = 8.0;

/// The origin a mesh's float32 coordinates are taken relative to: zero, or the centre of the
/// bounds of `positions` (read in f64) when that centre is more than [`FAR_FROM_ORIGIN`] times the
/// bounds' largest side from the origin. Survey and scan data in map coordinates (1e5 to 1e7 m)
/// then keep their precision: in f32 a coordinate near 1e6 has a step of 0.0625.
pub fn local_origin(positions: impl Iterator<Item = DVec3>) -> DVec3 {
    let (lo, hi) = positions.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        return DVec3::ZERO;
    }
    let centre = (lo + hi) * 0.5;
    if centre.abs().max_element() > FAR_FROM_ORIGIN * (hi - lo).max_element() {
        centre
    } else {
        DVec3::ZERO
    }
}

/// [`local_origin`] of `mesh`'s bounds placed by `place` (f64): the frame origin a scene's
/// first object asks for, whatever transform puts it in the world.
pub fn placed_origin(mesh: &TriangleMesh, place: impl Fn(DVec3) -> DVec3) -> DVec3 {
    let Some((lo, hi)) = mesh.bounds() else {
        return DVec3::ZERO;
    };
    let corners = (0..8).map(|i| {
        let pick = |bit: u32, a: f32, b: f32| f64::from(if i & bit == 0 { a } else { b });
        place(DVec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        ))
    });
    local_origin(corners)
}

/// A part of a mesh whose file gave no normals: its vertices and its triangles, which use only
/// those vertices. Its normals are derived from the positions, after any transform of the
/// object: Mitsuba derives them from world positions, and a non-uniform scale changes the
/// angles that weight them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DerivedNormals {
    /// The part's vertices.
    pub vertices: Range<usize>,
    /// The part's triangles.
    pub triangles: Range<usize>,
}

impl DerivedNormals {
    /// Appends a part to `parts`, merged with the last one when they are contiguous.
    pub fn push(parts: &mut Vec<DerivedNormals>, part: DerivedNormals) {
        match parts.last_mut() {
            Some(last) if last.vertices.end == part.vertices.start && last.triangles.end == part.triangles.start => {
                last.vertices.end = part.vertices.end;
                last.triangles.end = part.triangles.end;
            }
            _ => parts.push(part),
        }
    }
}

impl TriangleMesh {
    /// Gives the vertices of `parts` angle-weighted normals from the current positions.
    pub fn derive_normals(&mut self, parts: &[DerivedNormals]) {
        for part in parts {
            let normals = angle_weighted_normals(&self.positions, &self.triangles[part.triangles.clone()]);
            self.normals[part.vertices.clone()].copy_from_slice(&normals[part.vertices.clone()]);
        }
    }
}

/// `a` (for `len_a` vertices) followed by `b` (for `len_b`), zero-filling a missing side; `None`
/// when both are missing.
fn merge_attribute<T: Clone + Default>(
    a: Option<Vec<T>>,
    b: Option<Vec<T>>,
    len_a: usize,
    len_b: usize,
) -> Option<Vec<T>> {
    if a.is_none() && b.is_none() {
        return None;
    }
    let mut merged = a.unwrap_or_else(|| vec![T::default(); len_a]);
    merged.extend(b.unwrap_or_else(|| vec![T::default(); len_b]));
    Some(merged)
}

/// Angle-weighted vertex normals: n_v = normalize(Σ over faces at v of n_face · interior angle at v).
///
/// This is what Mitsuba computes for meshes without normals. Degenerate triangles (zero area)
/// contribute nothing; a vertex no triangle gives a direction to gets the zero vector, which the
/// shader treats as "use the geometric normal".
pub fn angle_weighted_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    use rayon::prelude::*;
    // Each triangle's three weighted normals in parallel (the acos dominate), then summed per
    // vertex in triangle order: the result does not depend on the thread count.
    let corners: Vec<[Vec3; 3]> = triangles
        .par_iter()
        .with_min_len(4096)
        .map(|tri| {
            let p = tri.map(|i| positions[i as usize]);
            let face = triangle_normal(p[0], p[1], p[2]);
            if face == Vec3::ZERO {
                return [Vec3::ZERO; 3];
            }
            // The corner at k lies between the unit edges k → k+1 and k → k+2; the second is the
            // negated edge k+2 → k, and negation is exact in every step (subtraction, the
            // normalisation, the dot product), so each edge is normalised once and the result
            // has the bits of normalising all six.
            let edge = [0, 1, 2].map(|k| (p[(k + 1) % 3] - p[k]).normalize_or_zero());
            // acos of a clamped cosine: the dot product can exceed 1 by rounding.
            [0, 1, 2].map(|k| face * (-edge[k].dot(edge[(k + 2) % 3])).clamp(-1.0, 1.0).acos())
        })
        .collect();
    let mut sum = vec![Vec3::ZERO; positions.len()];
    for (tri, weighted) in triangles.iter().zip(&corners) {
        for k in 0..3 {
            sum[tri[k] as usize] += weighted[k];
        }
    }
    sum.into_par_iter().map(Vec3::normalize_or_zero).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_bend_where_a_vertex_normal_leans_off_its_triangle() {
        // One triangle in z = 0, counter-clockwise from +z.
        let mesh = |normals: [Vec3; 3]| TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: normals.to_vec(),
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
            ..Default::default()
        };
        assert!(!mesh([Vec3::Z; 3]).normals_bend(), "flat");
        let leaning = Vec3::new(0.1, 0.0, 1.0).normalize(); // 5.7°
        assert!(mesh([Vec3::Z, leaning, Vec3::Z]).normals_bend());
        let barely = Vec3::new(0.005, 0.0, 1.0).normalize(); // 0.3°, below the 0.8° it asks for
        assert!(!mesh([Vec3::Z, barely, Vec3::Z]).normals_bend());
        assert!(!TriangleMesh::default().normals_bend(), "no triangles");
    }

    #[test]
    fn contiguous_parts_merge_and_only_parts_get_derived_normals() {
        let part = |v: Range<usize>, t: Range<usize>| DerivedNormals {
            vertices: v,
            triangles: t,
        };
        let mut parts = Vec::new();
        DerivedNormals::push(&mut parts, part(0..3, 0..1));
        DerivedNormals::push(&mut parts, part(3..7, 1..3));
        DerivedNormals::push(&mut parts, part(9..12, 4..5));
        assert_eq!(parts, [part(0..7, 0..3), part(9..12, 4..5)]);
        // Two triangles: the first part's normals are derived, the second's stay.
        let (p, t) = quad_corner();
        let mut mesh = TriangleMesh {
            positions: p.clone(),
            normals: vec![Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::X],
            triangles: vec![t[0], [3, 3, 3]],
            ..Default::default()
        };
        mesh.derive_normals(&[part(0..3, 0..1)]);
        let alone = angle_weighted_normals(&p[..3], &t[..1]);
        assert_eq!(mesh.normals, [alone[0], alone[1], alone[2], Vec3::X]);
    }

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
    fn angle_weighted_normals_have_the_bits_of_normalising_every_corners_edges() {
        // The textbook form: both edges of each corner normalised from the positions.
        fn textbook(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
            let mut sum = vec![Vec3::ZERO; positions.len()];
            for tri in triangles {
                let p = tri.map(|i| positions[i as usize]);
                let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                for k in 0..3 {
                    let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                    let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                    sum[tri[k] as usize] += face * e1.dot(e2).clamp(-1.0, 1.0).acos();
                }
            }
            sum.into_iter().map(Vec3::normalize_or_zero).collect()
        }
        // Irregular positions (a hashed jitter), and a triangle with a repeated vertex.
        let unit =
            |i: u32, salt: u32| (i.wrapping_mul(0x9e37_79b9) ^ salt).wrapping_mul(0x85eb_ca6b) as f32 / u32::MAX as f32;
        let mut positions: Vec<Vec3> = (0..4000)
            .map(|i| Vec3::new(unit(i, 1), unit(i, 2), unit(i, 3)) * 7.0 - 3.0)
            .collect();
        positions.extend([Vec3::ONE, Vec3::ONE, Vec3::new(0.0, 0.0, 1e-7)]);
        let mut triangles: Vec<[u32; 3]> = (0..6000)
            .map(|i| [i % 4000, (i * 7 + 1) % 4000, (i * 13 + 5) % 4000])
            .collect();
        triangles.extend([[4000, 4001, 4002], [0, 4002, 4000]]);
        let bits = |v: Vec<Vec3>| v.iter().map(|n| n.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(
            bits(angle_weighted_normals(&positions, &triangles)),
            bits(textbook(&positions, &triangles))
        );
    }

    #[test]
    fn mirroring_transform_keeps_geometric_normal_on_the_shading_normal_side() {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
            ..Default::default()
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
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
            ..Default::default()
        };
        let mut all = tri.clone();
        all.append(tri, 5);
        assert_eq!(all.triangles[1], [3, 4, 5]);
        assert_eq!(all.material_of_triangle, vec![0, 5]);
        assert_eq!(all.bounds(), Some((Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0))));
    }

    #[test]
    fn mirroring_flips_the_bitangent_sign_and_keeps_the_tangent_direction() {
        let mut mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            tangents: Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 3]),
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
            ..Default::default()
        };
        mesh.transform(Mat4::from_scale(Vec3::new(-2.0, 1.0, 1.0)));
        let t = mesh.tangents.as_ref().unwrap()[0];
        assert_eq!(t, Vec4::new(-1.0, 0.0, 0.0, -1.0));
        // The bitangent w·n × t still points along +y, where v decreased before the mirror.
        let b = t.w * mesh.normals[0].cross(t.truncate());
        assert!((b - Vec3::Y).length() < 1e-6, "{b}");
    }

    #[test]
    fn append_zero_fills_attributes_only_one_side_has() {
        let plain = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            triangles: vec![[0, 1, 2]],
            material_of_triangle: vec![0],
            ..Default::default()
        };
        let textured = TriangleMesh {
            uvs: Some(vec![Vec2::ONE; 3]),
            ..plain.clone()
        };
        let mut all = plain.clone();
        all.append(textured, 1);
        let uvs = all.uvs.as_ref().unwrap();
        assert_eq!(uvs.len(), 6);
        assert_eq!((uvs[0], uvs[5]), (Vec2::ZERO, Vec2::ONE));
        assert!(all.uvs1.is_none() && all.tangents.is_none());
    }
}
