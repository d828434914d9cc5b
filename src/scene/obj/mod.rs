//! Wavefront OBJ/MTL loading (via tobj) into a [`TriangleMesh`] and [`Material`]s.
//!
//! Polygons are fan-triangulated and vertices are unique (position, uv, normal) tuples, as in
//! Mitsuba's OBJ loader, so a mesh renders the same in both. MTL materials map to the BRDF models
//! (`mtl.rs`): `Pr`/`Pm` (the PBR extension) → Cook-Torrance; `Ks` with `Ns` → Blinn-Phong;
//! otherwise `Kd` → Lambert; their texture statements texture the parameters. A missing MTL file is a warning, not
//! an error (many OBJ files name one they lack), and so is every MTL statement left unused.
//!
//! Plain files (positions and triangles only, like the scanned meshes) are parsed on all cores by
//! `plain.rs`, which returns exactly what tobj would; everything else goes to tobj.

mod mtl;
mod plain;
pub mod write;

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};

use crate::error::{InputError, InputResult};
use crate::material::Material;
use crate::scene::mesh::{local_origin, DerivedNormals, TriangleMesh};
use crate::scene::textures::PendingImage;

/// The geometry and materials of one OBJ file, in the file's own coordinates.
#[derive(Debug)]
pub struct ObjContents {
    /// All triangles; `material_of_triangle` indexes `materials`, or is `u32::MAX` for faces with
    /// no material (the caller substitutes its default). Positions are relative to `origin`.
    pub mesh: TriangleMesh,
    /// Where the mesh's coordinates start, in the file's coordinates (f64): zero, or for a mesh
    /// far from the origin (map coordinates) the centre of its bounds (`scene::mesh::local_origin`).
    pub origin: DVec3,
    /// The MTL materials, converted.
    pub materials: Vec<Material>,
    /// The images the materials' textures name, not decoded: the caller decodes
    /// those a rendered material uses (`scene::textures::decode_used_images`).
    pub images: Vec<PendingImage>,
    /// Warnings about the file's materials, only worth showing when the caller renders them:
    /// why its material library could not be loaded, if it names one that failed, and one per
    /// MTL statement that pointshade does not use, naming the statement and the materials.
    pub material_warnings: Vec<String>,
    /// Warnings about its geometry: faces that repeat a vertex (drawn as nothing).
    pub warnings: Vec<String>,
}

/// Material index meaning "no material assigned in the file".
pub const NO_MATERIAL: u32 = u32::MAX;

/// Loads `path`, with angle-weighted normals for the models that have none. Errors name the file
/// and the problem; nothing is partially returned.
pub fn load_obj(path: &Path) -> InputResult<ObjContents> {
    let (mut contents, derived) = load_obj_underived(path)?;
    contents.mesh.derive_normals(&derived);
    Ok(contents)
}

/// [`load_obj`], but the models without normals keep zero normals, and the parts they make are
/// returned: a caller that transforms the mesh derives them afterwards
/// ([`TriangleMesh::derive_normals`]), from the transformed positions, as Mitsuba does.
pub fn load_obj_underived(path: &Path) -> InputResult<(ObjContents, Vec<DerivedNormals>)> {
    let bytes = crate::input_files::read(path).map_err(|e| InputError::new(path, e))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let refused = std::cell::RefCell::new(None);
    let parsed = parse_with_tobj_semantics(&bytes, &dir, &refused);
    // A material library outside the folder reads are confined to is an error, not the
    // warning an unreadable library is: the confinement is a promise about every file.
    if let Some((mtl, problem)) = refused.into_inner() {
        return Err(InputError::new(path, format!("mtllib '{}': {problem}", mtl.display())));
    }
    let (models, materials) = parsed.map_err(|e| InputError::new(path, format!("malformed OBJ: {e}")))?;
    contents_of_models(path, &bytes, &dir, &models, materials)
}

/// A mesh given as arrays rather than a file (the Python module's `Scene.add_mesh`): what an OBJ
/// file with the same `v`, `vt`, `vn` and `f` lines holds, so it loads exactly as that file would.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshArrays {
    /// x, y, z of each vertex.
    pub positions: Vec<f64>,
    /// Three vertex indices (0-based) per triangle.
    pub indices: Vec<u32>,
    /// x, y, z of each vertex's normal; empty: derived, as for an OBJ without `vn`.
    pub normals: Vec<f64>,
    /// u, v of each vertex, v pointing up as in OBJ; empty: none.
    pub uvs: Vec<f64>,
}

/// Loads `arrays` (named `name` in messages) as [`load_obj_underived`] loads the OBJ file that
/// holds them: same checks, same vertex order, same derived normals.
pub fn load_mesh_arrays(name: &Path, arrays: &MeshArrays) -> InputResult<(ObjContents, Vec<DerivedNormals>)> {
    let count = arrays.positions.len() / 3;
    let err = |problem: String| InputError::new(name, problem);
    if !arrays.positions.len().is_multiple_of(3) || !arrays.indices.len().is_multiple_of(3) {
        return Err(err("positions and faces come in threes".into()));
    }
    if !arrays.normals.is_empty() && arrays.normals.len() != arrays.positions.len() {
        return Err(err(format!(
            "{} normals for {count} vertices",
            arrays.normals.len() / 3
        )));
    }
    if !arrays.uvs.is_empty() && arrays.uvs.len() != 2 * count {
        return Err(err(format!(
            "{} texture coordinates for {count} vertices",
            arrays.uvs.len() / 2
        )));
    }
    if let Some(bad) = arrays.uvs.iter().position(|v| !v.is_finite()) {
        return Err(err(format!("texture coordinate {} is not finite", bad / 2 + 1)));
    }
    if let Some(bad) = arrays.indices.iter().find(|&&i| i as usize >= count) {
        return Err(err(format!("face index {bad} out of range ({count} vertices)")));
    }
    // Vertices in order of first use, unused ones dropped: the order tobj gives the OBJ file.
    const UNSEEN: u32 = u32::MAX;
    let mut new_index = vec![UNSEEN; count];
    let mut order = Vec::with_capacity(count);
    let indices = arrays
        .indices
        .iter()
        .map(|&i| {
            let slot = &mut new_index[i as usize];
            if *slot == UNSEEN {
                *slot = order.len() as u32;
                order.push(i as usize);
            }
            *slot
        })
        .collect();
    let gather = |values: &[f64], width: usize| -> Vec<f64> {
        match values.is_empty() {
            true => Vec::new(),
            false => order
                .iter()
                .flat_map(|&i| values[width * i..width * (i + 1)].iter().copied())
                .collect(),
        }
    };
    let mesh = tobj::Mesh {
        positions: gather(&arrays.positions, 3),
        normals: gather(&arrays.normals, 3),
        texcoords: gather(&arrays.uvs, 2),
        indices,
        ..Default::default()
    };
    let models = [tobj::Model::new(mesh, "arrays".into())];
    contents_of_models(name, &[], Path::new("."), &models, Ok(Vec::new()))
}

/// The meshes and materials of parsed OBJ `models` (from `path`, whose textures are found in
/// `dir`): positions relative to the local origin, every check, normals left to derive.
fn contents_of_models(
    path: &Path,
    bytes: &[u8],
    dir: &Path,
    models: &[tobj::Model],
    materials: Result<Vec<tobj::Material>, tobj::LoadError>,
) -> InputResult<(ObjContents, Vec<DerivedNormals>)> {
    let mut material_warnings = Vec::new();
    let materials = match materials {
        Ok(m) => m,
        Err(e) => {
            material_warnings.push(format!(
                "{}: its material library (mtllib) could not be loaded ({e}): faces get the default material",
                path.display()
            ));
            Vec::new()
        }
    };

    let origin = local_origin(
        models
            .iter()
            .flat_map(|m| m.mesh.positions.chunks_exact(3).map(DVec3::from_slice)),
    );
    let mut mesh = TriangleMesh::default();
    let mut derived = Vec::new();
    let mut all_have_uvs = true;
    let mut uvs = Vec::new();
    for model in models {
        let m = &model.mesh;
        let count = m.positions.len() / 3;
        let positions: Vec<Vec3> = m
            .positions
            .chunks_exact(3)
            .map(|c| (DVec3::from_slice(c) - origin).as_vec3())
            .collect();
        if let Some(bad) = positions.iter().position(|p| !p.is_finite()) {
            return Err(InputError::new(
                path,
                format!("vertex {} of object '{}' is not finite", bad + 1, model.name),
            ));
        }
        if m.indices.len() % 3 != 0 {
            return Err(InputError::new(
                path,
                format!(
                    "object '{}' has a face that is not a triangle after triangulation",
                    model.name
                ),
            ));
        }
        let triangles: Vec<[u32; 3]> = m.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        if let Some(bad) = m.indices.iter().find(|&&i| i as usize >= count) {
            return Err(InputError::new(
                path,
                format!(
                    "face index {bad} out of range ({count} vertices) in object '{}'",
                    model.name
                ),
            ));
        }
        let normals = if m.normals.len() == m.positions.len() {
            let n: Vec<Vec3> = m
                .normals
                .chunks_exact(3)
                .map(|c| DVec3::from_slice(c).as_vec3().normalize_or_zero())
                .collect();
            if n.iter().any(|v| !v.is_finite()) {
                return Err(InputError::new(
                    path,
                    format!("a normal of object '{}' is not finite", model.name),
                ));
            }
            n
        } else {
            let (vertices, first) = (mesh.positions.len(), mesh.triangles.len());
            let part = DerivedNormals {
                vertices: vertices..vertices + count,
                triangles: first..first + triangles.len(),
            };
            DerivedNormals::push(&mut derived, part);
            vec![Vec3::ZERO; count]
        };
        if m.texcoords.len() / 2 == count && count > 0 {
            // OBJ's v axis points up; images store row 0 at the top.
            uvs.extend(
                m.texcoords
                    .chunks_exact(2)
                    .map(|c| Vec2::new(c[0] as f32, 1.0 - c[1] as f32)),
            );
        } else {
            all_have_uvs = false;
        }
        let material = match m.material_id {
            Some(id) if id < materials.len() => id as u32,
            _ => NO_MATERIAL,
        };
        let part = TriangleMesh {
            material_of_triangle: vec![material; triangles.len()],
            positions,
            normals,
            triangles,
            ..Default::default()
        };
        mesh.append(part, 0);
    }
    if mesh.triangles.is_empty() {
        return Err(InputError::new(path, "no faces: nothing to render"));
    }
    let warnings = repeated_vertex_warning(path, bytes, &mesh.triangles)?
        .into_iter()
        .collect();
    mesh.uvs = (all_have_uvs && uvs.len() == mesh.positions.len()).then_some(uvs);

    let mtl = mtl::convert(&materials, dir, path, mesh.uvs.is_some())?;
    material_warnings.extend(mtl.warnings);
    Ok((
        ObjContents {
            mesh,
            origin,
            materials: mtl.materials,
            images: mtl.images,
            material_warnings,
            warnings,
        },
        derived,
    ))
}

/// A warning when some of `triangles` repeat a vertex (tobj makes `f 1 2` the triangle 1 2 2 and
/// `f 1` the triangle 1 1 1): they have no area and are drawn as nothing. The warning names how
/// many and the first face line that repeats a vertex; an error when no triangle is left.
fn repeated_vertex_warning(path: &Path, bytes: &[u8], triangles: &[[u32; 3]]) -> InputResult<Option<String>> {
    let repeated = triangles
        .iter()
        .filter(|&&[a, b, c]| a == b || b == c || a == c)
        .count();
    if repeated == 0 {
        return Ok(None);
    }
    let first = first_face_repeating_a_vertex(bytes)
        .map(|(line, text)| format!(" (the first such face: line {line}, `{text}`)"))
        .unwrap_or_default();
    if repeated == triangles.len() {
        return Err(InputError::new(
            path,
            format!("every triangle repeats a vertex{first}: nothing to render"),
        ));
    }
    Ok(Some(format!(
        "{}: {repeated} of its {} triangles repeat a vertex{first} and are not drawn",
        path.display(),
        triangles.len()
    )))
}

/// The first `f` line (1-based number, up to 40 characters of it) that names one vertex twice,
/// or has fewer than three vertices.
fn first_face_repeating_a_vertex(bytes: &[u8]) -> Option<(usize, String)> {
    let text = String::from_utf8_lossy(bytes);
    text.lines().enumerate().find_map(|(k, line)| {
        let mut tokens = line.split_whitespace();
        if tokens.next() != Some("f") {
            return None;
        }
        let vertices: Vec<&str> = tokens.map(|t| t.split('/').next().unwrap_or(t)).collect();
        let repeats = (1..vertices.len()).any(|i| vertices[..i].contains(&vertices[i]));
        (vertices.len() < 3 || repeats).then(|| (k + 1, line.trim().chars().take(40).collect()))
    })
}

/// tobj's models and materials for an OBJ file's `bytes`, whose MTL files are looked up in `dir`.
/// A plain file (positions and faces only) goes to the parallel [`plain`] parser, which gives the
/// same models; any other file, and every error, to tobj itself. A library outside the current
/// confinement is not read, and `refused` says which and why.
fn parse_with_tobj_semantics(
    bytes: &[u8],
    dir: &Path,
    refused: &std::cell::RefCell<Option<(PathBuf, String)>>,
) -> tobj::LoadResult {
    let load_mtl = |mtl: &Path| {
        let path = dir.join(mtl);
        if let Err(problem) = crate::input_files::check_confinement(&path) {
            refused.borrow_mut().get_or_insert((mtl.to_path_buf(), problem));
            return Err(tobj::LoadError::OpenFileFailed);
        }
        load_mtl(&path)
    };
    let options = |single_index| tobj::LoadOptions {
        triangulate: true,
        single_index,
        ..Default::default()
    };
    if let Some(plain) = plain::parse(bytes) {
        // The MTL libraries load as tobj loads them: from the file's `mtllib` lines alone.
        let mtllib_lines = plain.material_lines.join("\n");
        let (_, materials) = tobj::load_obj_buf(&mut mtllib_lines.as_bytes(), &options(false), load_mtl)?;
        return Ok((vec![plain.model], materials));
    }
    // Vertices are unique (position, uv, normal) index tuples, as in Mitsuba. A file with only
    // positions needs no tuple matching: its position indices are the vertex indices, and tobj's
    // per-attribute mode, which is faster, returns exactly those.
    tobj::load_obj_buf(&mut &bytes[..], &options(has_vertex_attributes(bytes)), load_mtl)
}

/// `tobj::load_mtl`, except that a colour line (`Ka`, `Kd`, `Ks`, `Ke`) with fewer than three
/// values is a parse error: tobj 4.0.5 unwraps it and panics. (The error makes the library's
/// materials a warning, as every MTL error does.)
fn load_mtl(path: &Path) -> tobj::MTLLoadResult {
    // tobj's two errors: the file does not open (missing, a FIFO or a device, which are not
    // opened at all), or it does not read (a directory, as tobj finds).
    crate::input_files::check(path).map_err(|_| match path.is_dir() {
        true => tobj::LoadError::ReadError,
        false => tobj::LoadError::OpenFileFailed,
    })?;
    let bytes = crate::input_files::read(path).map_err(|_| tobj::LoadError::ReadError)?;
    let short_colour = String::from_utf8_lossy(&bytes).lines().any(|line| {
        let mut words = line.split_whitespace();
        matches!(words.next(), Some("Ka" | "Kd" | "Ks" | "Ke")) && words.count() < 3
    });
    if short_colour {
        return Err(tobj::LoadError::MaterialParseError);
    }
    tobj::load_mtl_buf(&mut &bytes[..])
}

/// Whether an OBJ file has texture coordinates or normals (`vt` or `vn` lines, maybe indented).
/// Finds the keywords with memchr's vectorised substring search and only then checks that one
/// starts its line, instead of walking every line, which is a noticeable share of tobj's load
/// on a large file (docs/performance-log.md). Each hit looks back only to the
/// previous one, so the work stays linear however many hits a line holds.
fn has_vertex_attributes(bytes: &[u8]) -> bool {
    [b"vt", b"vn"].iter().any(|keyword| {
        let mut looked_at = 0;
        memchr::memmem::find_iter(bytes, keyword).any(|at| {
            let from = std::mem::replace(&mut looked_at, at);
            let line_start = match memchr::memrchr(b'\n', &bytes[from..at]) {
                Some(i) => from + i + 1,
                None if from == 0 => 0,
                // No newline since the previous hit: this one follows that keyword on its line.
                None => return false,
            };
            bytes[line_start..at].iter().all(u8::is_ascii_whitespace)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::BrdfModel;

    #[test]
    fn a_mesh_in_map_coordinates_keeps_its_precision_relative_to_its_centre() {
        // A 2 m triangle at a UTM position: 6.5e5 E, 6.86e6 N (f32 step there: 0.5 m).
        let text = "v 650000.25 10.0 6860000.75\nv 650002.25 10.0 6860000.75\nv 650000.25 12.0 6860000.75\nf 1 2 3\n";
        let dir = std::env::temp_dir().join(format!("pointshade-far-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("far.obj");
        std::fs::write(&path, text).unwrap();
        let c = load_obj(&path).unwrap();
        assert_eq!(c.origin, DVec3::new(650001.25, 11.0, 6860000.75));
        // Exact relative to the centre; in f32 world coordinates the corners would snap to 0.5 m.
        assert_eq!(
            c.mesh.positions,
            [
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0)
            ]
        );
        assert_eq!(c.mesh.normals[0], Vec3::Z);
        std::fs::remove_dir_all(&dir).unwrap();
        // Near the origin (centre within 8 sizes of it), coordinates stay as read.
        let near = [DVec3::new(5.0, 0.0, 0.0), DVec3::new(7.0, 1.0, 1.0)];
        assert_eq!(local_origin(near.into_iter()), DVec3::ZERO);
        assert_eq!(local_origin(std::iter::empty()), DVec3::ZERO);
    }

    #[test]
    fn vertex_attributes_are_found_only_as_line_keywords() {
        let has = |text: &str| has_vertex_attributes(text.as_bytes());
        assert!(has("vn 0 0 1\nv 0 0 0\n"), "at the start of the file");
        assert!(has("v 0 0 0\r\n  \tvt 0.5 0.5\r\n"), "indented, after a CRLF line");
        assert!(
            has("# converted\nv 1 2 3\nvn 0 1 0"),
            "on the last line, without a newline"
        );
        assert!(!has("v 0 0 0\nf 1 1 1\n"), "positions and faces only");
        assert!(
            !has("# made with vtk, vn-free\nv 0 0 0\ng vn\nf 1 1 1\n"),
            "in a comment or a name"
        );
        assert!(!has(""));
        assert!(has("x vn\nvn 0 0 1"), "after a line where the keyword is not first");
        // Many hits on one line: each looks back only to the previous one. Looking back to the
        // line's start each time would scan about 10^12 bytes here: quadratic in the line.
        let long_line = format!("g {}\nv 0 0 0\n", "vn".repeat(1 << 20));
        assert!(!has(&long_line));
        assert!(has(&(long_line + " vt 0 0\n")));
    }

    fn load(name: &str, obj: &str, mtl: &str) -> ObjContents {
        let dir = std::env::temp_dir().join(format!("pointshade-obj-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("m.mtl"), mtl).unwrap();
        std::fs::write(dir.join("m.obj"), obj).unwrap();
        let c = load_obj(&dir.join("m.obj")).unwrap();
        std::fs::remove_dir_all(dir).unwrap();
        c
    }

    #[test]
    fn mtl_keys_choose_the_brdf_model() {
        let mtl = "newmtl matte\nKd 0.5 0.25 0.125\n\
                   newmtl shiny\nKd 0.1 0.2 0.3\nKs 0.5 0.5 0.5\nNs 40\n\
                   newmtl metal\nKd 0.9 0.6 0.3\nPr 0.5\nPm 1\n";
        let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\n";
        let c = load("mtl", obj, mtl);
        let by_name = |n: &str| c.materials.iter().find(|m| m.name == n).unwrap();
        assert_eq!(by_name("matte").model, BrdfModel::Lambert);
        assert_eq!(by_name("matte").albedo, [0.5, 0.25, 0.125]);
        match by_name("shiny").model {
            BrdfModel::BlinnPhong(bp) => assert_eq!((bp.shininess, bp.color), (40.0, [0.5; 3])),
            other => panic!("{other:?}"),
        }
        match by_name("metal").model {
            BrdfModel::CookTorrance(ct) => {
                assert_eq!(ct.alpha, 0.25, "α = Pr²");
                assert!(ct.metallic);
                assert_eq!(ct.specular_color, [0.9, 0.6, 0.3]);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(by_name("metal").kd, 0.0);
        // The face uses "shiny".
        let shiny = c.materials.iter().position(|m| m.name == "shiny").unwrap() as u32;
        assert_eq!(c.mesh.material_of_triangle, vec![shiny]);
        assert!(!c.material_warnings.iter().any(|w| w.contains("could not be loaded")));
    }

    #[test]
    fn a_colour_line_with_fewer_than_three_values_is_a_warning_not_a_panic() {
        // tobj 4.0.5 unwraps the short list (found by mutating MTL files).
        for (k, line) in ["Kd 0.5 0.5", "Ka 0.1", "Ks", "  Ke 1 1  "].iter().enumerate() {
            let mtl = format!("newmtl m\nKd 0.5 0.5 0.5\n{line}\n");
            // Both parsers: a plain file (positions and faces) and one with normals.
            for obj in [
                "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
                "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nusemtl m\nf 1//1 2//1 3//1\n",
            ] {
                let c = load(&format!("short-colour-{k}"), obj, &mtl);
                let warning = c.material_warnings.first().expect("a warning");
                assert!(warning.contains("material parse error"), "{warning}");
                assert_eq!(c.mesh.material_of_triangle, vec![NO_MATERIAL]);
            }
        }
        // Three values or more (tobj reads the first three) still load.
        let c = load(
            "long-colour",
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
            "newmtl m\nKd 0.5 0.25 0.125 9\n",
        );
        assert_eq!(c.materials[0].albedo, [0.5, 0.25, 0.125]);
    }

    #[test]
    fn plain_files_load_their_material_libraries_as_tobj_does() {
        let dir = std::env::temp_dir().join(format!("pointshade-obj-plain-mtl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("a.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
        std::fs::write(dir.join("b c.mtl"), "newmtl blue\nKd 0 0 1\nnewmtl red\nKd 1 1 0\n").unwrap();
        let geometry = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        for libraries in [
            "",
            "mtllib a.mtl\n",
            "mtllib a.mtl\r\nmtllib b c.mtl\n",
            "mtllib none.mtl\n",
            "mtllib\n",
        ] {
            let text = format!("{libraries}{geometry}");
            assert!(
                plain::parse(text.as_bytes()).is_some(),
                "{text:?} takes the plain parser"
            );
            let (models, got) = parse_with_tobj_semantics(text.as_bytes(), &dir, &Default::default()).unwrap();
            let options = tobj::LoadOptions {
                triangulate: true,
                ..Default::default()
            };
            let (expected_models, expected) =
                tobj::load_obj_buf(&mut text.as_bytes(), &options, |m| tobj::load_mtl(dir.join(m))).unwrap();
            assert_eq!(models.len(), expected_models.len());
            let names = |r: &Result<Vec<tobj::Material>, tobj::LoadError>| {
                r.as_ref()
                    .map(|v| v.iter().map(|m| (m.name.clone(), m.diffuse)).collect::<Vec<_>>())
                    .map_err(|e| e.to_string())
            };
            assert_eq!(names(&got), names(&expected), "{libraries:?}");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn missing_normals_become_angle_weighted_and_quads_are_fan_triangulated() {
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
        let c = load("quad", obj, "");
        assert_eq!(c.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert!(c.mesh.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        assert_eq!(c.mesh.material_of_triangle, vec![NO_MATERIAL; 2]);
    }
}
