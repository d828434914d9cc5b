//! The Stanford dragon, its camera and its light in map coordinates — translated by (1e5, 0,
//! −1e5), (6.5e5, 0, 6.86e6) (a UTM easting and northing) and (1e7, 1e7, 1e7) — against the same
//! scene at the origin. In f32 a coordinate near 1e6 has a step of 0.0625: without the scene's
//! f64 origin (`Scene::origin`) the dragon's vertices snap and its derived normals turn to noise.
//! A case passes when ≥ 99.9% of the pixels are within 1% of the render at the origin.
//!
//! The translated OBJ is written with f64's shortest round-trip digits, so it holds exactly the
//! f64 sums of the dragon's coordinates and the offset; the plane under it is placed by the
//! scene file's `translate`, also read in f64.

use std::path::Path;

use super::case::{num, Case};
use super::scale_cases::{render, share_within};
use crate::scene::{self, Scene};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// The offsets the group renders at.
pub const OFFSETS: [[f64; 3]; 3] = [[1e5, 0.0, -1e5], [6.5e5, 0.0, 6.86e6], [1e7, 1e7, 1e7]];

/// Writes the dragon scene moved by `t` into `dir` (the dragon's OBJ and a scene file) and loads
/// it. `dragon_obj` is the text of the shared `stanford-dragon.obj`.
pub fn translated_dragon(dragon_obj: &str, t: [f64; 3], dir: &Path) -> Result<Scene, String> {
    let add = |v: [f64; 3]| [v[0] + t[0], v[1] + t[1], v[2] + t[2]];
    let mut obj = String::with_capacity(dragon_obj.len() * 2);
    for line in dragon_obj.lines() {
        let mut words = line.split_whitespace();
        if words.next() == Some("v") {
            let mut v = [0.0f64; 3];
            for c in &mut v {
                *c = words
                    .next()
                    .and_then(|w| w.parse().ok())
                    .ok_or("a v line without three numbers")?;
            }
            let [x, y, z] = add(v);
            obj.push_str(&format!("v {x} {y} {z}\n"));
        } else {
            obj.push_str(line);
            obj.push('\n');
        }
    }
    let p = |v: [f64; 3]| {
        let [x, y, z] = add(v);
        format!("[{x}, {y}, {z}]")
    };
    let plane = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/plane.obj");
    let toml = format!(
        "[film]\nwidth = {WIDTH}\nheight = {HEIGHT}\nspp = 1\nsampler = \"grid\"\n\n\
         [camera]\nposition = {}\nlook_at = {}\nfov = 40.0\n\n\
         [[light]]\ntype = \"point\"\nposition = {}\nintensity = 900.0\n\n\
         [material.copper]\nmodel = \"cook-torrance\"\nroughness = 0.25\n\
         eta = [0.200, 0.924, 1.102]\nk = [3.912, 2.452, 2.142]\ntwo_sided = false\n\n\
         [material.ground]\nalbedo = [0.6, 0.6, 0.6]\ntwo_sided = false\n\n\
         [[object]]\nmesh = \"dragon.obj\"\nmaterial = \"copper\"\n\n\
         [[object]]\nmesh = {:?}\nmaterial = \"ground\"\ntransform = {{ scale = 2.0, translate = {} }}\n",
        p([-14.0, 12.0, 22.0]),
        p([0.0, 4.0, 0.0]),
        p([10.0, 25.0, 15.0]),
        plane.display().to_string(),
        p([0.0; 3]),
    );
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::write(dir.join("dragon.obj"), obj).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join("scene.toml");
    std::fs::write(&path, toml).map_err(|e| format!("{}: {e}", path.display()))?;
    scene::load(&path).map_err(|e| e.to_string())
}

/// One row per offset; none (and a SKIPPED note) without the shared dragon.
pub fn run(shared_meshes: Option<&Path>, notes: &mut Vec<String>) -> Vec<Case> {
    let Some(text) = shared_meshes.and_then(|d| std::fs::read_to_string(d.join("stanford-dragon.obj")).ok()) else {
        notes.push("SKIPPED: ../shared/data/meshes/stanford-dragon.obj is missing: no far-from-origin rows".into());
        return Vec::new();
    };
    let dir = std::env::temp_dir().join(format!("pointshade-far-{}", std::process::id()));
    let scene_at = |t: [f64; 3], k: usize| translated_dragon(&text, t, &dir.join(k.to_string()));
    let rows = match scene_at([0.0; 3], 0) {
        Err(e) => {
            notes.push(format!("SKIPPED: the dragon could not be written or loaded: {e}"));
            Vec::new()
        }
        Ok(origin_scene) => {
            let reference = render(&origin_scene);
            OFFSETS
                .iter()
                .enumerate()
                .map(|(k, &t)| {
                    let mut c = Case::new(
                        "geometry",
                        "dragon in map coordinates vs at the origin",
                        format!("offset ({:e}, {:e}, {:e})", t[0], t[1], t[2]),
                    );
                    match scene_at(t, k + 1) {
                        Err(e) => c.fail(e),
                        Ok(scene) => {
                            let image = render(&scene);
                            let (share, bad) = share_within(&reference, &image, 0.01);
                            c.evals = image.pixels.len() as u64;
                            c.nan = image.pixels.iter().filter(|p| p.is_nan()).count() as u64;
                            c.f32_value = format!("{}% within 1%", num(100.0 * share));
                            c.f64_value = "≥ 99.9%".into();
                            if share < 0.999 {
                                c.fail(format!("only {:.2}% of pixels within 1%", 100.0 * share));
                            }
                            if bad > 0 {
                                c.fail(format!("{bad} non-finite or negative pixels"));
                            }
                        }
                    }
                    c
                })
                .collect()
        }
    };
    let _ = std::fs::remove_dir_all(&dir);
    rows
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::light::LightKind;
    use crate::scene::mesh::angle_weighted_normals;

    /// The row can fail: the same far scene as it was rendered before f64 origins — world
    /// coordinates in f32, normals derived from them — is far below the bound.
    #[test]
    #[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
    fn in_f32_world_coordinates_the_far_dragon_fails_the_bound() {
        let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
        let text = std::fs::read_to_string(meshes.join("stanford-dragon.obj")).unwrap();
        let dir = std::env::temp_dir().join(format!("pointshade-far-test-{}", std::process::id()));
        let reference = render(&translated_dragon(&text, [0.0; 3], &dir.join("0")).unwrap());
        let far = translated_dragon(&text, OFFSETS[1], &dir.join("1")).unwrap();
        assert!(far.origin.length() > 6e6, "the scene is rebased: {}", far.origin);
        let world = |p: glam::Vec3| (p.as_dvec3() + far.origin).as_vec3();
        let mut f32_world = far.clone();
        f32_world.origin = DVec3::ZERO;
        for p in &mut f32_world.mesh.positions {
            *p = world(*p);
        }
        f32_world.mesh.normals = angle_weighted_normals(&f32_world.mesh.positions, &f32_world.mesh.triangles);
        f32_world.camera.position = world(far.camera.position);
        f32_world.camera.look_at = world(far.camera.look_at);
        for l in &mut f32_world.lights {
            if let LightKind::Point { position } = &mut l.kind {
                *position = world(*position);
            }
        }
        let (rebased, _) = share_within(&reference, &render(&far), 0.01);
        let (in_f32, _) = share_within(&reference, &render(&f32_world), 0.01);
        eprintln!("within 1% of the render at the origin: {rebased:.4} rebased, {in_f32:.4} in f32 world coordinates");
        assert!(rebased >= 0.999, "{rebased}");
        assert!(in_f32 < 0.99, "{in_f32}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
