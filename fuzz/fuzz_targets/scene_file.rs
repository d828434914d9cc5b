//! TOML mesh scene files: parsed, validated and loaded as `pointshade render s.toml` does (with
//! `tri.obj`, a textured `quad.obj` and their MTL beside it to refer to), then rendered tiny.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::sync::Once;

static MESHES: Once = Once::new();

fuzz_target!(|data: &[u8]| {
    MESHES.call_once(|| {
        pointshade_fuzz::put("tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        pointshade_fuzz::put(
            "quad.obj",
            b"mtllib quad.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\nusemtl q\nf 1/1/1 2/2/1 3/3/1 4/4/1\n",
        );
        pointshade_fuzz::put("quad.mtl", b"newmtl q\nKd 0.8 0.5 0.2\nKs 0.2 0.2 0.2\nNs 40\n");
    });
    let path = pointshade_fuzz::put("s.toml", data);
    if let Ok(scene) = pointshade::scene::load(&path) {
        pointshade_fuzz::tiny_render(scene);
    }
});
