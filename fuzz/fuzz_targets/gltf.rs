//! glTF: a `.glb` when the input starts with the binary magic, else `.gltf` JSON; after a line
//! `#--bin` (JSON only) the `b.bin` buffer and texture file it may refer to. Loaded as
//! `pointshade render` loads it, then rendered tiny.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = if data.starts_with(b"glTF") {
        pointshade_fuzz::put("m.glb", data)
    } else {
        let (json, bin) = pointshade_fuzz::split(data, b"\n#--bin\n");
        pointshade_fuzz::put("b.bin", bin);
        pointshade_fuzz::put("m.gltf", json)
    };
    if let Ok(scene) = pointshade::scene::load(&path) {
        pointshade_fuzz::tiny_render(scene);
    }
});
