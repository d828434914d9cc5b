//! Writes the procedural meshes of `meshes/` (see `pointshade::scene::procedural::catalogue`).
//!
//! `cargo run --bin gen-meshes` regenerates them in place; a test checks they are up to date.

use std::path::Path;

fn main() -> std::io::Result<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    std::fs::create_dir_all(&dir)?;
    for (name, contents) in pointshade::scene::procedural::catalogue() {
        std::fs::write(dir.join(name), contents)?;
        println!("wrote meshes/{name}");
    }
    Ok(())
}
