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
            assert!(obj.material_warning.is_none(), "{name}: {:?}", obj.material_warning);
        }
    }
}
