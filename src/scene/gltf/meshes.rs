//! Mesh primitives → one world-space [`TriangleMesh`].
//!
//! Every primitive in triangle mode is read, indexed or not; other modes (points, lines, strips,
//! fans) are skipped and counted for one warning. A primitive is read once and transformed for
//! each node that places its mesh (`TriangleMesh::transform`: normals by the inverse transpose,
//! winding and tangent signs flipped by mirroring transforms).
//!
//! - No `NORMAL`: flat normals, as the glTF specification requires — the triangles stop sharing
//!   vertices and each vertex gets its triangle's normal.
//! - `TANGENT` present: used. Absent while the material has a normal texture and the primitive
//!   has that texture's coordinates: generated with MikkTSpace ([`crate::scene::tangents`]), on
//!   unshared vertices too (MikkTSpace can give a shared vertex different tangents per face).

use std::collections::BTreeMap;

use ::gltf::accessor::DataType;
use ::gltf::mesh::{Mode, Semantic};
use glam::{Vec2, Vec3, Vec4};

use crate::error::InputResult;
use crate::material::Material;
use crate::scene::gltf::accessor::{read_indices, read_vectors};
use crate::scene::gltf::document::GltfDocument;
use crate::scene::gltf::nodes::World;
use crate::scene::mesh::{placed_origin, TriangleMesh};
use crate::scene::tangents::generate_tangents;

/// The geometry of a file's rendered scene.
pub struct SceneGeometry {
    /// All triangles in world space; material indices index `materials` of the file, with
    /// `default_material` for primitives without one.
    pub mesh: TriangleMesh,
    /// Whether some primitive has no material (then index `materials.len()` is the glTF default
    /// material, which the caller appends).
    pub uses_default_material: bool,
    /// Warnings (skipped primitive modes).
    pub warnings: Vec<String>,
    /// Facts for `--explain` (generated tangents, flat normals).
    pub notes: Vec<String>,
    /// Where the mesh's coordinates start, in the file's world coordinates (f64): zero, or the
    /// centre of the first placed primitive when the scene lies far from the origin
    /// (`scene::mesh::local_origin`).
    pub origin: glam::DVec3,
}

/// Builds the world-space mesh of the mesh instances `(mesh index, world matrix)`.
pub fn build_geometry(
    d: &GltfDocument,
    instances: &[(usize, World)],
    materials: &[Material],
) -> InputResult<SceneGeometry> {
    let meshes: Vec<_> = d.doc.meshes().collect();
    let default_material = materials.len() as u32;
    let mut out = SceneGeometry {
        mesh: TriangleMesh::default(),
        uses_default_material: false,
        warnings: Vec::new(),
        notes: Vec::new(),
        origin: glam::DVec3::ZERO,
    };
    let mut origin = None;
    let mut skipped: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut local: BTreeMap<(usize, usize), TriangleMesh> = BTreeMap::new();
    let (mut flat, mut generated) = (0usize, 0usize);
    for &(mesh_index, world) in instances {
        for primitive in meshes[mesh_index].primitives() {
            if primitive.mode() != Mode::Triangles {
                *skipped.entry(mode_name(primitive.mode())).or_default() += 1;
                continue;
            }
            let key = (mesh_index, primitive.index());
            if let std::collections::btree_map::Entry::Vacant(slot) = local.entry(key) {
                let material = match primitive.material().index() {
                    Some(m) => m as u32,
                    None => {
                        out.uses_default_material = true;
                        default_material
                    }
                };
                let normal_set = materials
                    .get(material as usize)
                    .and_then(|m| m.textures.normal)
                    .map(|n| n.texture.tex_coord);
                let what = format!("mesh {mesh_index} primitive {}", primitive.index());
                let (part, facts) = read_primitive(d, &primitive, &what, material, normal_set)?;
                flat += facts.flat_normals as usize;
                generated += facts.generated_tangents as usize;
                slot.insert(part);
            }
            let mut part = local[&key].clone();
            let origin = *origin.get_or_insert_with(|| placed_origin(&part, |p| world.f64.transform_point3(p)));
            part.transform(world.relative_to(origin));
            out.mesh.append(part, 0);
        }
    }
    if !skipped.is_empty() {
        let list: Vec<String> = skipped.iter().map(|(m, n)| format!("{n} {m}")).collect();
        out.warnings.push(format!(
            "{}: skipped primitives that are not triangles: {}",
            d.path.display(),
            list.join(", ")
        ));
    }
    if flat > 0 {
        out.notes
            .push(format!("{flat} primitive(s) without normals: flat normals"));
    }
    if generated > 0 {
        out.notes.push(format!(
            "{generated} primitive(s) with a normal texture but no tangents: MikkTSpace tangents generated"
        ));
    }
    out.origin = origin.unwrap_or(glam::DVec3::ZERO);
    Ok(out)
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

/// What reading a primitive had to make up.
struct PrimitiveFacts {
    flat_normals: bool,
    generated_tangents: bool,
}

/// One primitive in its mesh's own coordinates, every triangle with material `material`.
/// `normal_set` is the coordinate set of the material's normal texture, if it has one.
fn read_primitive(
    d: &GltfDocument,
    primitive: &::gltf::Primitive,
    what: &str,
    material: u32,
    normal_set: Option<u8>,
) -> InputResult<(TriangleMesh, PrimitiveFacts)> {
    let uv_types = [DataType::F32, DataType::U8, DataType::U16];
    let attribute = |semantic: Semantic| primitive.get(&semantic);
    let position_accessor = attribute(Semantic::Positions).ok_or_else(|| d.error(format!("{what} has no POSITION")))?;
    let positions: Vec<Vec3> =
        read_vectors::<3>(d, &position_accessor, &format!("POSITION of {what}"), &[DataType::F32])?
            .into_iter()
            .map(Vec3::from)
            .collect();
    if let Some(bad) = positions.iter().position(|p| !p.is_finite()) {
        return Err(d.error(format!("{what}: position {bad} is not finite")));
    }
    let n = positions.len();
    let read_same_count = |semantic: Semantic, name: &str| -> InputResult<Option<Vec<[f32; 4]>>> {
        let Some(accessor) = attribute(semantic.clone()) else {
            return Ok(None);
        };
        let label = format!("{name} of {what}");
        let values: Vec<[f32; 4]> = match semantic {
            Semantic::Normals => read_vectors::<3>(d, &accessor, &label, &[DataType::F32])?
                .into_iter()
                .map(|v| [v[0], v[1], v[2], 0.0])
                .collect(),
            Semantic::Tangents => read_vectors::<4>(d, &accessor, &label, &[DataType::F32])?,
            _ => read_vectors::<2>(d, &accessor, &label, &uv_types)?
                .into_iter()
                .map(|v| [v[0], v[1], 0.0, 0.0])
                .collect(),
        };
        if values.len() != n {
            return Err(d.error(format!("{label} has {} elements for {n} positions", values.len())));
        }
        if values.iter().flatten().any(|v| !v.is_finite()) {
            return Err(d.error(format!("{label} has a value that is not finite")));
        }
        Ok(Some(values))
    };
    let normals = read_same_count(Semantic::Normals, "NORMAL")?;
    let tangents = read_same_count(Semantic::Tangents, "TANGENT")?;
    let uvs0 = read_same_count(Semantic::TexCoords(0), "TEXCOORD_0")?;
    let uvs1 = read_same_count(Semantic::TexCoords(1), "TEXCOORD_1")?;

    let indices = match primitive.indices() {
        Some(accessor) => read_indices(d, &accessor, &format!("indices of {what}"))?,
        None => (0..n as u32).collect(),
    };
    if indices.len() % 3 != 0 {
        return Err(d.error(format!(
            "{what}: {} indices is not a whole number of triangles",
            indices.len()
        )));
    }
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(d.error(format!("{what}: index {bad} is out of range ({n} vertices)")));
    }
    let triangles: Vec<[u32; 3]> = indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();

    let to_vec2 = |v: Vec<[f32; 4]>| v.into_iter().map(|a| Vec2::new(a[0], a[1])).collect::<Vec<_>>();
    let mut mesh = TriangleMesh {
        material_of_triangle: vec![material; triangles.len()],
        normals: normals
            .map(|v| {
                v.into_iter()
                    .map(|a| Vec3::new(a[0], a[1], a[2]).normalize_or_zero())
                    .collect()
            })
            .unwrap_or_default(),
        positions,
        uvs: uvs0.map(to_vec2),
        uvs1: uvs1.map(to_vec2),
        tangents: tangents.map(|v| v.into_iter().map(unit_tangent).collect()),
        triangles,
    };
    let flat_normals = mesh.normals.is_empty();
    let normal_uvs_present = match normal_set {
        Some(0) => mesh.uvs.is_some(),
        Some(_) => mesh.uvs1.is_some(),
        None => false,
    };
    let generated_tangents = mesh.tangents.is_none() && normal_uvs_present;
    if flat_normals || generated_tangents {
        mesh = unshare_vertices(mesh);
    }
    if flat_normals {
        mesh.normals = vec![Vec3::ZERO; mesh.positions.len()];
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let face = crate::scene::unit_vector::triangle_normal(a, b, c);
            for &i in t {
                mesh.normals[i as usize] = face;
            }
        }
    }
    if generated_tangents {
        let uvs = if normal_set == Some(0) { &mesh.uvs } else { &mesh.uvs1 };
        let uvs = uvs.as_ref().expect("checked above");
        mesh.tangents = Some(generate_tangents(&mesh.positions, &mesh.normals, uvs, &mesh.triangles));
    }
    Ok((
        mesh,
        PrimitiveFacts {
            flat_normals,
            generated_tangents,
        },
    ))
}

/// A file's tangent as pointshade stores it: unit xyz and w = ±1, or zero when xyz is zero.
fn unit_tangent(t: [f32; 4]) -> Vec4 {
    let xyz = Vec3::new(t[0], t[1], t[2]).normalize_or_zero();
    if xyz == Vec3::ZERO {
        Vec4::ZERO
    } else {
        xyz.extend(if t[3] < 0.0 { -1.0 } else { 1.0 })
    }
}

/// The same triangles with three vertices of their own each (attributes copied per corner).
fn unshare_vertices(mesh: TriangleMesh) -> TriangleMesh {
    fn pick<T: Copy>(corners: &[usize], v: &[T]) -> Vec<T> {
        corners.iter().map(|&i| v[i]).collect()
    }
    let corners: Vec<usize> = mesh.triangles.iter().flatten().map(|&i| i as usize).collect();
    let c = &corners;
    TriangleMesh {
        positions: pick(c, &mesh.positions),
        normals: if mesh.normals.is_empty() {
            Vec::new()
        } else {
            pick(c, &mesh.normals)
        },
        uvs: mesh.uvs.as_deref().map(|v| pick(c, v)),
        uvs1: mesh.uvs1.as_deref().map(|v| pick(c, v)),
        tangents: mesh.tangents.as_deref().map(|v| pick(c, v)),
        triangles: (0..mesh.triangles.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect(),
        material_of_triangle: mesh.material_of_triangle,
    }
}
