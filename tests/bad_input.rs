//! Every class of bad input gives a one-line error naming the file and the problem, exit code 2,
//! no panic, and no output file.

use std::path::{Path, PathBuf};
use std::process::Command;

struct Case {
    dir: PathBuf,
}

impl Case {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("pointshade-bad-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        Case { dir }
    }

    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// Runs `render SCENE -o out.png EXTRA…` and checks the failure contract; returns stderr.
    fn fails(&self, scene: &Path, extra: &[&str], expect_in_message: &[&str]) -> String {
        let out = self.dir.join("out.png");
        let result = Command::new(env!("CARGO_BIN_EXE_pointshade"))
            .arg("render")
            .arg(scene)
            .arg("-o")
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
        assert_eq!(result.status.code(), Some(2), "exit code for {scene:?}: {stderr}");
        let errors: Vec<_> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "exactly one error line: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for e in expect_in_message {
            assert!(errors[0].contains(e), "'{}' should mention '{e}'", errors[0]);
        }
        assert!(!out.exists(), "no output file after an error");
        let leftovers: Vec<_> = std::fs::read_dir(&self.dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty(), "temporary files left behind");
        errors[0].to_string()
    }

    fn scene(&self, body: &str) -> PathBuf {
        self.file("scene.toml", body)
    }
}

impl Drop for Case {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

const CAMERA: &str = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n";

#[test]
fn malformed_obj_files() {
    let c = Case::new("obj");
    let out_of_range = c.file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    c.fails(&out_of_range, &[], &["range.obj"]);
    let garbage = c.file("garbage.obj", "v 0 0 zero\nf 1 2 3\n");
    c.fails(&garbage, &[], &["garbage.obj", "malformed OBJ"]);
    let nan = c.file("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    c.fails(&nan, &[], &["nan.obj", "not finite"]);
    let empty = c.file("empty.obj", "# nothing\n");
    c.fails(&empty, &[], &["empty.obj", "no faces"]);
    let binary = c.dir.join("binary.obj");
    std::fs::write(&binary, [0u8, 159, 146, 150, 255, 0, 1, 2]).unwrap();
    c.fails(&binary, &[], &["binary.obj"]);
}

#[test]
fn toml_syntax_unknown_keys_and_wrong_types_give_line_and_column() {
    let c = Case::new("toml");
    let syntax = c.scene("[film\nwidth = 3\n");
    c.fails(&syntax, &[], &["scene.toml", "line 1"]);
    let unknown = c.scene(&format!("{CAMERA}\n[film]\nwidth = 64\nwidht = 64\n"));
    c.fails(&unknown, &[], &["scene.toml", "line 8", "widht"]);
    let wrong_type = c.scene(&format!("{CAMERA}[film]\nwidth = \"big\"\n"));
    c.fails(&wrong_type, &[], &["scene.toml", "line 6"]);
    let unknown_model = c.scene("[material.m]\nmodel = \"phong\"\n");
    c.fails(&unknown_model, &[], &["line 2", "phong"]);
    let unknown_term = c.scene("[material.m]\nmodel = \"cook-torrance\"\ng = \"smith\"\n");
    c.fails(&unknown_term, &[], &["line 3", "smith"]);
}

#[test]
fn unknown_material_name() {
    let c = Case::new("material");
    let s = c.scene(&format!(
        "{CAMERA}[material.red]\nalbedo = [0.8, 0.1, 0.1]\n[[object]]\nmesh = \"tri.obj\"\nmaterial = \"blue\"\n"
    ));
    c.fails(&s, &[], &["scene.toml", "line 9", "unknown material 'blue'", "red"]);
}

#[test]
fn missing_files() {
    let c = Case::new("missing");
    c.fails(&c.dir.join("nope.toml"), &[], &["nope.toml"]);
    c.fails(&c.dir.join("nope.obj"), &[], &["nope.obj", "not found"]);
    let s = c.scene(&format!("{CAMERA}[[object]]\nmesh = \"absent.obj\"\n"));
    c.fails(&s, &[], &["absent.obj", "not found"]);
}

#[test]
fn nan_and_negative_parameters() {
    let c = Case::new("params");
    let nan_roughness = c.scene(&format!(
        "{CAMERA}[material.m]\nmodel = \"cook-torrance\"\nroughness = nan\n[[object]]\nmesh = \"tri.obj\"\nmaterial = \"m\"\n"
    ));
    c.fails(&nan_roughness, &[], &["scene.toml", "roughness"]);
    let negative_light = c.scene(&format!(
        "{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 1.0]\nintensity = -5.0\n"
    ));
    c.fails(&negative_light, &[], &["scene.toml", "line 5", "intensity"]);
    let nan_position = c.scene(&format!(
        "{CAMERA}[[light]]\ntype = \"point\"\nposition = [0.0, nan, 1.0]\n"
    ));
    c.fails(&nan_position, &[], &["position"]);
    let bad_fov = c.scene("[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 190.0\n");
    c.fails(&bad_fov, &[], &["fov"]);
    let zero_scale = c.scene(&format!(
        "{CAMERA}[[object]]\nmesh = \"tri.obj\"\ntransform = {{ scale = 0.0 }}\n"
    ));
    c.fails(&zero_scale, &[], &["scale"]);
}

#[test]
fn absurd_sizes_and_bad_options() {
    let c = Case::new("sizes");
    let huge = c.scene(&format!("{CAMERA}[film]\nwidth = 1000000\nheight = 1000000\n"));
    c.fails(&huge, &[], &["scene.toml", "too large"]);
    let tri = c.dir.join("tri.obj");
    c.fails(&tri, &["--width", "0"], &["image size"]);
    c.fails(&tri, &["--spp", "10000000"], &["spp"]);
    c.fails(&tri, &["--sampler", "grid", "--spp", "8"], &["square"]);
    c.fails(&tri, &["--sampler", "halton"], &["--sampler", "halton"]);
    c.fails(&tri, &["--aov", "normals"], &["--aov"]);
    let out = c.dir.join("out.png");
    let r = Command::new(env!("CARGO_BIN_EXE_pointshade"))
        .args([
            "render",
            tri.to_str().unwrap(),
            "-o",
            c.dir.join("out.jpg").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(2));
    assert!(!out.exists());
}
