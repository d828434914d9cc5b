//! OBJ + MTL: the input is an OBJ file, then (after a line `#--mtl`) the `m.mtl` it may name,
//! loaded as `pointshade render m.obj` loads them, then rendered tiny.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = pointshade_fuzz::split(data, b"\n#--mtl\n");
    pointshade_fuzz::put("m.mtl", mtl);
    let path = pointshade_fuzz::put("m.obj", obj);
    if let Ok(scene) = pointshade::scene::load(&path) {
        pointshade_fuzz::tiny_render(scene);
    }
});
