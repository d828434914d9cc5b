//! `--confine DIR` (issue 42, class 9): with it, no file outside DIR is read, whichever way a
//! scene names it (`../`, an absolute path, a link, a percent-encoded or `file:` glTF URI, an
//! `mtllib`); without it, such files are read as before. Warnings never quote a file that is not
//! what it was named as.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::json;

use support::gltf_builder::{square, write_png, GltfBuilder};
use support::Scratch;

/// `render INPUT -o DIR/out.png` at 8×6, with `--confine inside` when given: the output and
/// whether the image was written.
fn render(input: &Path, confine: Option<&Path>) -> (Output, bool) {
    let out = input.parent().unwrap().join("out.png");
    let _ = std::fs::remove_file(&out);
    let mut args = vec![Path::new("render"), input, Path::new("-o"), &out];
    args.extend(["--width", "8", "--height", "6"].map(Path::new));
    if let Some(dir) = confine {
        args.extend([Path::new("--confine"), dir]);
    }
    let output = support::pointshade(&args);
    (output, out.exists())
}

fn succeeds(input: &Path, confine: Option<&Path>) -> String {
    let (out, written) = render(input, confine);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success() && written, "{}: {stderr}", input.display());
    stderr
}

/// The one error line of a refused render, which wrote nothing.
fn refused(input: &Path, confine: &Path) -> String {
    let (out, _) = render(input, Some(confine));
    let image = input.parent().unwrap().join("out.png");
    support::assert_input_error(&out, &["the folder reads are confined to"], &[&image])
}

const TRIANGLE: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

/// `root/inside` (the confinement) and `root/outside` with a triangle OBJ in each; `root` is
/// removed when the first value is dropped.
fn folders(name: &str) -> (Scratch, PathBuf, PathBuf) {
    let root = Scratch::new(name);
    let (inside, outside) = (root.path("inside"), root.path("outside"));
    for d in [&inside, &outside] {
        std::fs::create_dir_all(d).unwrap();
        std::fs::write(d.join("tri.obj"), TRIANGLE).unwrap();
    }
    (root, inside, outside)
}

fn scene_naming(inside: &Path, name: &str, mesh: &str) -> PathBuf {
    let path = inside.join(format!("{name}.toml"));
    std::fs::write(&path, format!("[[object]]\nmesh = \"{mesh}\"\n")).unwrap();
    path
}

#[test]
fn scene_files_reach_no_mesh_outside_the_folder() {
    let (_root, inside, outside) = folders("confine-scene");
    std::os::unix::fs::symlink(outside.join("tri.obj"), inside.join("link.obj")).unwrap();
    let own = scene_naming(&inside, "own", "tri.obj");
    succeeds(&own, Some(&inside));
    let outside_mesh = outside.join("tri.obj");
    for (name, mesh, named) in [
        ("up", "../outside/tri.obj".to_string(), "outside/tri.obj"),
        ("absolute", outside_mesh.display().to_string(), "outside/tri.obj"),
        ("link", "link.obj".to_string(), "link.obj"),
        ("missing", "../outside/none.obj".to_string(), "none.obj"),
    ] {
        let scene = scene_naming(&inside, name, &mesh);
        let e = refused(&scene, &inside);
        assert!(e.contains(named), "{e}");
        if name != "missing" {
            succeeds(&scene, None);
        }
    }
    // The input itself, given on the command line, is a read like the others.
    let e = refused(&outside_mesh, &inside);
    assert!(e.contains("outside/tri.obj"), "{e}");
    // A confinement that is not a folder is an error about the option.
    let (out, _) = render(&own, Some(&inside.join("nowhere")));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr.contains("--confine") && stderr.contains("folder not found"),
        "{stderr}"
    );
}

#[test]
fn material_libraries_outside_are_errors_and_foreign_files_are_never_quoted() {
    let (_root, inside, outside) = folders("confine-mtl");
    // A file that is not an MTL, like /etc/passwd.
    let passwd = "root:x:0:0:root:/root:/bin/bash\nsecret_user:x:1000:1000:Some Name:/home/s:/bin/sh\n";
    std::fs::write(outside.join("passwd"), passwd).unwrap();
    let obj = inside.join("m.obj");
    std::fs::write(&obj, format!("mtllib ../outside/passwd\n{TRIANGLE}")).unwrap();
    let e = refused(&obj, &inside);
    assert!(e.contains("mtllib '../outside/passwd'"), "{e}");
    // Unconfined, it is read; as an MTL holding a material the faces use, its lines are
    // counted in a warning, never quoted.
    std::fs::write(outside.join("fake.mtl"), format!("newmtl m\n{passwd}")).unwrap();
    std::fs::write(&obj, format!("mtllib ../outside/fake.mtl\nusemtl m\n{TRIANGLE}")).unwrap();
    let stderr = succeeds(&obj, None);
    assert!(
        stderr.contains("lines of its material library that are not MTL statements"),
        "{stderr}"
    );
    for secret in ["root:x", "secret_user", "/bin/bash", "Some Name"] {
        assert!(!stderr.contains(secret), "quoted '{secret}': {stderr}");
    }
}

#[test]
fn gltf_uris_outside_are_refused_however_they_are_spelled() {
    let (_root, inside, outside) = folders("confine-gltf");
    write_png(&outside.join("a.png"), 1, 1, &[[200, 100, 50, 255]]);
    write_png(&inside.join("a.png"), 1, 1, &[[200, 100, 50, 255]]);
    let outside_png = outside.join("a.png").display().to_string();
    for (name, uri) in [
        ("own", "a.png".to_string()),
        ("up", "../outside/a.png".to_string()),
        ("encoded", "%2e%2e/outside/a.png".to_string()),
        ("file", format!("file://{outside_png}")),
    ] {
        let mut b = GltfBuilder::default();
        let mesh = square(&mut b, true, Some(0));
        let rest = json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [mesh],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
            "images": [{"uri": uri}],
            "textures": [{"source": 0}],
        });
        let path = b.write_gltf(&inside, name, rest);
        if name == "own" {
            succeeds(&path, Some(&inside));
        } else {
            let e = refused(&path, &inside);
            assert!(e.contains(&format!("{name}.gltf")) && e.contains("a.png"), "{e}");
            succeeds(&path, None);
        }
    }
}

#[test]
fn normal_images_outside_are_refused() {
    let (_root, inside, outside) = folders("confine-normals");
    write_png(&outside.join("n.png"), 2, 2, &[[128, 128, 255, 255]; 4]);
    let out = inside.join("shaded.png");
    let args = |confine: bool| {
        let mut a: Vec<&Path> = vec![Path::new("normalmap"), Path::new("../outside/n.png")];
        a.extend(["--brdf", "lambert", "-o"].map(Path::new));
        a.push(&out);
        if confine {
            a.extend([Path::new("--confine"), Path::new(".")]);
        }
        a
    };
    let refused = support::command()
        .args(args(true))
        .current_dir(&inside)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("n.png") && stderr.contains("confined to"), "{stderr}");
    assert!(!out.exists());
    let allowed = support::command()
        .args(args(false))
        .current_dir(&inside)
        .output()
        .unwrap();
    assert!(allowed.status.success(), "{}", String::from_utf8_lossy(&allowed.stderr));
    assert!(out.exists());
}
