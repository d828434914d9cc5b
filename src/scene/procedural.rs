//! Procedural meshes: the shapes in `meshes/`, generated here and written as OBJ
//! ([`crate::scene::obj::write`]) by `cargo run --bin gen-meshes`.
//!
//! Every shape is counter-clockwise seen from outside (or from inside the room, for the Cornell
//! box walls), so one-sided materials show their front. Analytic shapes carry analytic normals.

use std::f32::consts::{PI, TAU};
use std::fmt::Write as _;

use crate::scene::obj::write::ObjMesh;
use crate::scene::obj::MeshArrays;
use crate::scene::TriangleMesh;
use glam::{Vec2, Vec3};

/// An indexed triangle mesh with optional per-vertex normals and texture coordinates, and
/// optional named groups (one material each) as runs of consecutive triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProceduralMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, if the shape has them.
    pub normals: Option<Vec<Vec3>>,
    /// Texture coordinates (v up, as OBJ stores them), if the shape has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Counter-clockwise triangles.
    pub triangles: Vec<[u32; 3]>,
    /// (material name, first triangle) for each group, in triangle order; empty = no groups.
    pub groups: Vec<(String, usize)>,
}

/// A material of an MTL file written beside a procedural OBJ: name and Kd.
pub type MtlEntry = (&'static str, [f32; 3]);

impl ProceduralMesh {
    /// This mesh as the arrays a scene file's object may name instead of a file (what the
    /// explorer bakes its default normal image from): the same f32 values, as f64.
    pub fn to_arrays(&self) -> MeshArrays {
        fn flat<const N: usize>(rows: &[impl Copy + Into<[f32; N]>]) -> Vec<f64> {
            rows.iter().flat_map(|&r| r.into()).map(f64::from).collect()
        }
        MeshArrays {
            positions: flat(&self.positions),
            indices: self.triangles.iter().flatten().copied().collect(),
            normals: self.normals.as_deref().map(flat).unwrap_or_default(),
            uvs: self.uvs.as_deref().map(flat).unwrap_or_default(),
        }
    }

    /// This mesh as a scene mesh, every triangle with material 0; a mesh without normals gets
    /// the angle-weighted vertex normals of its positions, as a loaded OBJ without `vn` does.
    pub fn into_triangle_mesh(self) -> TriangleMesh {
        let normals = self
            .normals
            .unwrap_or_else(|| crate::scene::mesh::angle_weighted_normals(&self.positions, &self.triangles));
        TriangleMesh {
            material_of_triangle: vec![0; self.triangles.len()],
            positions: self.positions,
            normals,
            triangles: self.triangles,
            ..Default::default()
        }
    }

    /// Wavefront OBJ text ([`ObjMesh`]): f32 values in their shortest round-trip form, so
    /// reading the file back gives exactly these values. `mtllib` names the MTL file of the groups.
    pub fn to_obj(&self, header: &str, mtllib: Option<&str>) -> String {
        let normals: Option<Vec<[f32; 3]>> = self.normals.as_ref().map(|n| n.iter().map(|v| v.to_array()).collect());
        let uvs: Option<Vec<[f32; 2]>> = self.uvs.as_ref().map(|t| t.iter().map(|v| v.to_array()).collect());
        let positions: Vec<[f32; 3]> = self.positions.iter().map(|p| p.to_array()).collect();
        ObjMesh {
            header,
            mtllib,
            positions: &positions,
            normals: normals.as_deref(),
            uvs: uvs.as_deref(),
            triangles: &self.triangles,
            groups: &self.groups,
        }
        .to_obj()
    }

    /// The triangles of one group as a mesh of their own (vertices compacted, no groups).
    pub fn group(&self, name: &str) -> ProceduralMesh {
        let mut out = ProceduralMesh::default();
        let mut remap = vec![u32::MAX; self.positions.len()];
        for (k, t) in self.triangles.iter().enumerate() {
            let group = self
                .groups
                .iter()
                .rev()
                .find(|(_, first)| *first <= k)
                .map(|(g, _)| g.as_str());
            if group != Some(name) {
                continue;
            }
            out.triangles.push(t.map(|i| {
                if remap[i as usize] == u32::MAX {
                    remap[i as usize] = out.positions.len() as u32;
                    out.positions.push(self.positions[i as usize]);
                }
                remap[i as usize]
            }));
        }
        out
    }

    /// Drops the normals (for testing angle-weighted normals on meshes without them).
    pub fn without_normals(mut self) -> Self {
        self.normals = None;
        self
    }
}

/// MTL text for `entries` (Lambert materials: Kd only).
pub fn to_mtl(header: &str, entries: &[MtlEntry]) -> String {
    let mut s = String::new();
    for line in header.lines() {
        let _ = writeln!(s, "# {line}");
    }
    for (name, kd) in entries {
        let _ = writeln!(s, "newmtl {name}\nKd {} {} {}\n", kd[0], kd[1], kd[2]);
    }
    s
}

/// Unit icosphere: a regular icosahedron with each triangle split into 4, `subdivisions` times,
/// vertices pushed to the sphere; 20·4^n triangles. Normals are the unit positions.
pub fn icosphere(subdivisions: u32) -> ProceduralMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    ProceduralMesh {
        normals: Some(positions.clone()),
        positions,
        triangles,
        ..Default::default()
    }
}

/// Unit UV sphere with `segments` around the axis (+Y up) and `rings` from pole to pole, with
/// normals and texture coordinates (u around, v from the south pole up).
pub fn uv_sphere(segments: u32, rings: u32) -> ProceduralMesh {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = PI * (1.0 - v); // from the south pole (θ = π) up
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let phi = TAU * u;
            positions.push(Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos()));
            uvs.push(Vec2::new(u, v));
        }
    }
    let row = segments + 1;
    let mut triangles = Vec::new();
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (r * row + s, r * row + s + 1, (r + 1) * row + s + 1, (r + 1) * row + s);
            // Skip the zero-area triangles at the poles.
            if r != 0 {
                triangles.push([a, b, c]);
            }
            if r != rings - 1 {
                triangles.push([a, c, d]);
            }
        }
    }
    ProceduralMesh {
        normals: Some(positions.clone()),
        positions,
        uvs: Some(uvs),
        triangles,
        groups: Vec::new(),
    }
}

/// A square in the y = 0 plane facing +Y, from −half to +half in x and z, split into
/// `cells`×`cells` quads, with normals and texture coordinates.
pub fn plane(half: f32, cells: u32) -> ProceduralMesh {
    let n = cells + 1;
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (u, v) = (i as f32 / cells as f32, j as f32 / cells as f32);
            positions.push(Vec3::new(-half + 2.0 * half * u, 0.0, half - 2.0 * half * v));
            uvs.push(Vec2::new(u, v));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..cells {
        for i in 0..cells {
            let (a, b, c, d) = (j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    ProceduralMesh {
        normals: Some(vec![Vec3::Y; positions.len()]),
        positions,
        uvs: Some(uvs),
        triangles,
        groups: Vec::new(),
    }
}

/// A torus around +Y: tube centre at distance `major` from the axis, tube radius `minor`,
/// `around` segments along the ring and `tube` around the tube; 2·around·tube triangles.
pub fn torus(major: f32, minor: f32, around: u32, tube: u32) -> ProceduralMesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for i in 0..around {
        let phi = TAU * i as f32 / around as f32;
        let radial = Vec3::new(phi.cos(), 0.0, -phi.sin());
        for j in 0..tube {
            let theta = TAU * j as f32 / tube as f32;
            let n = radial * theta.cos() + Vec3::Y * theta.sin();
            positions.push(radial * major + n * minor);
            normals.push(n);
        }
    }
    let mut triangles = Vec::new();
    for i in 0..around {
        for j in 0..tube {
            let (i1, j1) = ((i + 1) % around, (j + 1) % tube);
            let (a, b, c, d) = (i * tube + j, i1 * tube + j, i1 * tube + j1, i * tube + j1);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    ProceduralMesh {
        positions,
        normals: Some(normals),
        triangles,
        ..Default::default()
    }
}

/// Materials of the Cornell box, as RGB approximations of its measured reflectances.
pub const CORNELL_MATERIALS: [MtlEntry; 3] = [
    ("white", [0.725, 0.71, 0.68]),
    ("red", [0.63, 0.065, 0.05]),
    ("green", [0.14, 0.45, 0.091]),
];

/// The Cornell box from its published measurements (Cornell Program of Computer Graphics,
/// millimetres, +Y up, camera at (278, 273, −800) looking +Z): floor, ceiling, back wall, red
/// (left, x ≈ 550) and green (right, x = 0) walls, a short and a tall block. The ceiling light is
/// not geometry: pointshade's lights are punctual. Walls face into the room, blocks outwards.
pub fn cornell_box() -> ProceduralMesh {
    type Quad = [[f32; 3]; 4];
    let walls: [(&str, Quad); 5] = [
        (
            "white",
            [
                [552.8, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 559.2],
                [549.6, 0.0, 559.2],
            ],
        ),
        (
            "white",
            [
                [556.0, 548.8, 0.0],
                [556.0, 548.8, 559.2],
                [0.0, 548.8, 559.2],
                [0.0, 548.8, 0.0],
            ],
        ),
        (
            "white",
            [
                [549.6, 0.0, 559.2],
                [0.0, 0.0, 559.2],
                [0.0, 548.8, 559.2],
                [556.0, 548.8, 559.2],
            ],
        ),
        (
            "green",
            [
                [0.0, 0.0, 559.2],
                [0.0, 0.0, 0.0],
                [0.0, 548.8, 0.0],
                [0.0, 548.8, 559.2],
            ],
        ),
        (
            "red",
            [
                [552.8, 0.0, 0.0],
                [549.6, 0.0, 559.2],
                [556.0, 548.8, 559.2],
                [556.0, 548.8, 0.0],
            ],
        ),
    ];
    // Each block: its top outline (counter-clockwise or not; orientation is fixed below) and height.
    let blocks: [([[f32; 2]; 4], f32); 2] = [
        ([[130.0, 65.0], [82.0, 225.0], [240.0, 272.0], [290.0, 114.0]], 165.0),
        ([[423.0, 247.0], [265.0, 296.0], [314.0, 456.0], [472.0, 406.0]], 330.0),
    ];
    let mut mesh = ProceduralMesh::default();
    let room_centre = Vec3::new(278.0, 274.4, 279.6);
    let add_quad = |mesh: &mut ProceduralMesh, group: &str, q: [Vec3; 4], facing: Vec3| {
        if mesh.groups.last().map(|(g, _)| g.as_str()) != Some(group) {
            mesh.groups.push((group.to_string(), mesh.triangles.len()));
        }
        let normal = (q[1] - q[0]).cross(q[2] - q[0]);
        let q = if normal.dot(facing) < 0.0 {
            [q[0], q[3], q[2], q[1]]
        } else {
            q
        };
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(q);
        mesh.triangles.push([base, base + 1, base + 2]);
        mesh.triangles.push([base, base + 2, base + 3]);
    };
    for (group, quad) in walls {
        let q = quad.map(Vec3::from);
        let centre = (q[0] + q[1] + q[2] + q[3]) * 0.25;
        add_quad(&mut mesh, group, q, room_centre - centre);
    }
    for (outline, height) in blocks {
        let top = outline.map(|[x, z]| Vec3::new(x, height, z));
        let bottom = outline.map(|[x, z]| Vec3::new(x, 0.0, z));
        let centre = (top[0] + top[1] + top[2] + top[3]) * 0.25 - Vec3::Y * height * 0.5;
        add_quad(&mut mesh, "white", top, Vec3::Y);
        for k in 0..4 {
            let k1 = (k + 1) % 4;
            let side = [bottom[k], bottom[k1], top[k1], top[k]];
            let mid = (side[0] + side[2]) * 0.5;
            add_quad(&mut mesh, "white", side, mid - centre);
        }
    }
    mesh
}

/// Every file of `meshes/`: (file name, contents). `gen-meshes` writes them; a test checks the
/// committed files still equal this output.
pub fn catalogue() -> Vec<(&'static str, String)> {
    let note = "generated by pointshade's gen-meshes (src/scene/procedural.rs); do not edit";
    vec![
        (
            "icosphere.obj",
            icosphere(4).to_obj(&format!("unit icosphere, 4 subdivisions\n{note}"), None),
        ),
        (
            "icosphere-no-normals.obj",
            icosphere(2)
                .without_normals()
                .to_obj(&format!("unit icosphere, 2 subdivisions, no normals\n{note}"), None),
        ),
        (
            "uv-sphere.obj",
            uv_sphere(64, 32).to_obj(&format!("unit UV sphere, 64 segments, 32 rings\n{note}"), None),
        ),
        (
            "uv-sphere-coarse.obj",
            uv_sphere(12, 8).to_obj(
                &format!("unit UV sphere, 12 segments, 8 rings: coarse facets for the shadow terminator\n{note}"),
                None,
            ),
        ),
        (
            "plane.obj",
            plane(10.0, 1).to_obj(&format!("20×20 square in y = 0 facing +Y\n{note}"), None),
        ),
        (
            "torus.obj",
            torus(1.0, 0.35, 96, 48).to_obj(&format!("torus around +Y, radii 1 and 0.35\n{note}"), None),
        ),
        (
            "cornell-box.obj",
            cornell_box().to_obj(
                &format!("Cornell box, published dimensions in mm\n{note}"),
                Some("cornell-box.mtl"),
            ),
        ),
        (
            "cornell-box.mtl",
            to_mtl(&format!("Cornell box materials\n{note}"), &CORNELL_MATERIALS),
        ),
        // One file per material, for Mitsuba (its OBJ loader gives a file one BSDF).
        (
            "cornell-box-white.obj",
            cornell_box()
                .group("white")
                .to_obj(&format!("Cornell box, white parts\n{note}"), None),
        ),
        (
            "cornell-box-red.obj",
            cornell_box()
                .group("red")
                .to_obj(&format!("Cornell box, red wall\n{note}"), None),
        ),
        (
            "cornell-box-green.obj",
            cornell_box()
                .group("green")
                .to_obj(&format!("Cornell box, green wall\n{note}"), None),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's geometric normal points away from `inside` (for closed convex shapes).
    fn outward(m: &ProceduralMesh, inside: Vec3) -> bool {
        m.triangles.iter().all(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            (b - a).cross(c - a).dot((a + b + c) / 3.0 - inside) > 0.0
        })
    }

    #[test]
    fn icosphere_counts_and_orientation() {
        let m = icosphere(3);
        assert_eq!(m.triangles.len(), 20 * 64);
        assert_eq!(m.positions.len(), 10 * 64 + 2);
        assert!(m.positions.iter().all(|p| (p.length() - 1.0).abs() < 1e-6));
        assert!(outward(&m, Vec3::ZERO));
    }

    #[test]
    fn uv_sphere_and_torus_face_outwards() {
        let s = uv_sphere(16, 8);
        assert!(outward(&s, Vec3::ZERO));
        assert_eq!(s.triangles.len(), 2 * 16 * 8 - 2 * 16);
        let t = torus(1.0, 0.3, 24, 12);
        assert_eq!(t.triangles.len(), 2 * 24 * 12);
        // Outward from the tube's centre line: the normal at each vertex is position − ring point.
        for (p, n) in t.positions.iter().zip(t.normals.as_ref().unwrap()) {
            let ring = Vec3::new(p.x, 0.0, p.z).normalize();
            assert!(((*p - ring) / 0.3 - *n).length() < 1e-5);
        }
        let tri = t.triangles[5].map(|i| t.positions[i as usize]);
        let ng = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        assert!(ng.dot(t.normals.as_ref().unwrap()[t.triangles[5][0] as usize]) > 0.0);
    }

    #[test]
    fn plane_faces_up() {
        let p = plane(2.0, 3);
        assert_eq!(p.triangles.len(), 18);
        assert!(p.triangles.iter().all(|t| {
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            (b - a).cross(c - a).y > 0.0
        }));
    }

    #[test]
    fn cornell_box_walls_face_the_camera_side_and_blocks_face_out() {
        let m = cornell_box();
        assert_eq!(m.triangles.len(), 2 * (5 + 10));
        let group_of = |t: usize| m.groups.iter().rev().find(|(_, first)| *first <= t).unwrap().0.as_str();
        assert_eq!(group_of(6), "green");
        assert_eq!(group_of(8), "red");
        // Floor faces up, back wall faces −Z (towards the camera), green wall (x = 0) faces +X.
        let ng = |t: usize| {
            let [a, b, c] = m.triangles[t].map(|i| m.positions[i as usize]);
            (b - a).cross(c - a).normalize()
        };
        assert!(ng(0).y > 0.99 && ng(2).y < -0.99 && ng(4).z < -0.99 && ng(6).x > 0.99 && ng(8).x < -0.99);
        // Short block top faces up.
        assert!(ng(10).y > 0.99);
    }

    #[test]
    fn obj_text_round_trips_through_the_loader_format() {
        let m = icosphere(0);
        let text = m.to_obj("test", None);
        assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 20);
        assert!(text.contains("f 1//1 12//12 6//6"));
        let c = cornell_box().to_obj("cb", Some("cb.mtl"));
        let white = cornell_box().group("white");
        assert_eq!(
            (white.triangles.len(), white.positions.len()),
            (26, 52),
            "floor, ceiling, back wall, two blocks"
        );
        assert!(c.contains("mtllib cb.mtl") && c.contains("usemtl red"));
    }
}
