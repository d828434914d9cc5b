//! The committed meshes in `meshes/` are exactly what the generator writes (`cargo run --bin
//! gen-meshes`), and every one of them loads.

use std::path::Path;

use pointshade::scene::obj::load_obj;
use pointshade::scene::procedural::catalogue;

#[test]
fn committed_meshes_equal_the_generator_output_and_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    for (name, contents) in catalogue() {
        let path = dir.join(name);
        let committed = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            committed == contents,
            "meshes/{name} is stale: run `cargo run --bin gen-meshes`"
        );
        if name.ends_with(".obj") {
            let obj = load_obj(&path).unwrap();
            assert!(obj.mesh.triangle_count() > 0);
            let library = obj.material_warnings.iter().find(|w| w.contains("could not be loaded"));
            assert!(library.is_none(), "{name}: {library:?}");
        }
    }
}

/// A scene object whose mesh has no normals gets angle-weighted normals of its *world*
/// positions, as Mitsuba derives them: under a non-uniform scale they differ from the
/// object-space normals transformed as normals. Objects with normals keep theirs, transformed.
#[test]
fn missing_normals_are_derived_after_the_objects_transform() {
    use pointshade::scene::mesh::angle_weighted_normals;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = crate::support::Scratch::new("derived-normals");
    let meshes = root.join("meshes");
    let scene = dir.path("scaled.toml");
    let transform = "transform = { scale = [1.6, 0.7, 1.0], rotate = [0.0, 30.0, 0.0] }";
    let object = |mesh: &str| format!("[[object]]\nmesh = \"{}\"\n{transform}\n", meshes.join(mesh).display());
    let text = format!(
        "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n{}{}",
        object("icosphere-no-normals.obj"),
        object("icosphere.obj")
    );
    std::fs::write(&scene, text).unwrap();
    let loaded = pointshade::scene::load(&scene).unwrap();
    drop(dir);
    let (mesh, m) = (loaded.mesh, loaded.objects[0].transform);
    assert!(m.x_axis.length() > 1.5, "the scale is applied: {m}");

    let bare = load_obj(&meshes.join("icosphere-no-normals.obj")).unwrap().mesh;
    let (n, t) = (bare.positions.len(), bare.triangles.len());
    let world = angle_weighted_normals(&mesh.positions[..n], &mesh.triangles[..t]);
    assert_eq!(mesh.normals[..n], world[..], "derived from the world positions");
    // Deriving them before the transform gives other normals under this scale.
    let mut early = bare.clone();
    early.transform(m);
    let off = early
        .normals
        .iter()
        .zip(&world)
        .map(|(a, b)| a.angle_between(*b))
        .fold(0.0f32, f32::max);
    // (0.037 rad at most on this icosphere; rounding alone would be about 1e-6.)
    assert!(off > 0.01, "the scale matters: {off} rad at most");
    // The icosphere with normals keeps its own, transformed as normals.
    let with = load_obj(&meshes.join("icosphere.obj")).unwrap().mesh;
    let mut transformed = with.clone();
    transformed.transform(m);
    assert_eq!(mesh.normals[n..], transformed.normals[..]);
}
