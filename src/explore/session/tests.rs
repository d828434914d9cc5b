use super::*;

fn state(explorer: &Explorer) -> State {
    explorer.initial_state().clone()
}

/// The default session is the assignment's setting on a baked image: tp, Cook-Torrance; its
/// render is what `normalmap` gives for its saved file (read back through the same reader).
#[test]
fn the_default_session_is_the_tp_preset_on_a_baked_image() {
    let mut e = Explorer::open(None).unwrap();
    assert_eq!(e.mode(), Mode::NormalImage);
    assert_eq!((e.size()), (512, 384));
    let s = state(&e);
    assert_eq!(s.preset.as_deref(), Some("tp"));
    assert_eq!(s.materials[NORMAL_MAP_MATERIAL]["model"], "cook-torrance");
    let png = e.render(&s, None, None).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    let saved = e.save(&s).unwrap();
    assert!(saved.contains(&format!("image = \"{BAKED_IMAGE}\"")), "{saved}");
}

#[test]
fn an_edit_changes_the_image_and_a_bad_value_names_the_key() {
    let mut e = Explorer::open(None).unwrap();
    let mut s = state(&e);
    let before = e.render(&s, None, None).unwrap();
    s.materials.get_mut(NORMAL_MAP_MATERIAL).unwrap()["roughness"] = 0.2.into();
    let after = e.render(&s, None, None).unwrap();
    assert_ne!(before, after);
    s.materials.get_mut(NORMAL_MAP_MATERIAL).unwrap()["roughness"] = 2.0.into();
    let err = e.render(&s, None, None).unwrap_err();
    assert!(err.contains("roughness must be in [0, 1]"), "{err}");
    s.materials.get_mut(NORMAL_MAP_MATERIAL).unwrap()["roughness"] = 0.2.into();
    s.materials
        .get_mut(NORMAL_MAP_MATERIAL)
        .unwrap()
        .insert("texture".into(), "/etc/passwd".into());
    let err = e.render(&s, None, None).unwrap_err();
    assert!(err.contains("unknown field `texture`"), "{err}");
}

#[test]
fn a_pixel_reports_what_shaded_it() {
    let mut e = Explorer::open(None).unwrap();
    let s = state(&e);
    let (w, h) = e.size();
    let centre = e.pixel(&s, w / 2, h / 2 - 20).unwrap();
    assert_eq!(centre["hit"], true, "{centre}");
    assert_eq!(centre["material"], NORMAL_MAP_MATERIAL);
    let n: Vec<f64> = serde_json::from_value(centre["n"].clone()).unwrap();
    assert!((n.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-5);
    assert!(e.pixel(&s, w, 0).unwrap_err().contains("outside"));
}

#[test]
fn a_scene_file_opens_edits_and_saves() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cook-torrance.toml");
    let mut e = Explorer::open(Some(&path)).unwrap();
    assert_eq!(e.mode(), Mode::Scene);
    let mut s = state(&e);
    assert!(s.preset.is_none() && !s.materials.is_empty() && !s.lights.is_empty());
    let before = e.render(&s, None, None).unwrap();
    s.lights[0]["intensity"] = 0.5.into();
    let after = e.render(&s, None, None).unwrap();
    assert_ne!(before, after);
    let saved = e.save(&s).unwrap();
    assert!(saved.contains("[[light]]") && saved.contains("[film]"), "{saved}");
    // A state that would not load is not saved.
    let mut bad = s.clone();
    bad.lights[0]["intensity"] = (-1.0).into();
    let err = e.save(&bad).unwrap_err();
    assert!(err.contains("light 1: light intensity must be finite and ≥ 0"), "{err}");
    s.preset = Some("tp".into());
    assert!(e
        .render(&s, None, None)
        .unwrap_err()
        .contains("preset applies to a normal image"));
}

/// A scene's coarse pass is `render` of its file at that sample count, and its last pass the
/// film's; a normal image has no passes.
#[test]
fn a_scene_renders_in_passes_and_a_normal_image_in_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
    let mut e = Explorer::open(Some(&path)).unwrap();
    assert_eq!(e.spp(), Some(4));
    let s = state(&e);
    let coarse = e.render(&s, Some(1), None).unwrap();
    let full = e.render(&s, None, None).unwrap();
    assert_ne!(coarse, full);
    assert_eq!(e.render(&s, Some(4), None).unwrap(), full);
    let mut scene = crate::scene::load(&path).unwrap();
    scene.film.spp = 1;
    let plan = crate::plan::RenderPlan::new(&scene, &[]);
    let whole = crate::render::render_scene(&scene, &plan, &crate::render::progress::Silent).unwrap();
    assert_eq!(coarse, encode(&whole.image, Format::Png, scene.film.exposure).unwrap());
    assert!(e
        .render(&s, Some(9), None)
        .unwrap_err()
        .contains("at most the film's 4"));

    let mut image = Explorer::open(None).unwrap();
    assert_eq!(image.spp(), None);
    let s = state(&image);
    assert!(image
        .render(&s, Some(1), None)
        .unwrap_err()
        .starts_with("spp: a normal image"));
}

/// A bare mesh saves as a scene file of one object, which renders to the image shown (its
/// automatic lights written out, its materials, from an MTL file or the neutral default, as
/// sections).
#[test]
fn a_bare_mesh_saves_as_a_scene_file_of_one_object() {
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    for mesh in ["cornell-box.obj", "icosphere.obj"] {
        let mut e = Explorer::open(Some(&meshes.join(mesh))).unwrap();
        let mut s = state(&e);
        assert!(!s.lights.is_empty(), "{mesh}: the automatic lights are the state's");
        s.lights[0]["intensity"] = 0.75.into();
        let shown = e.render(&s, None, None).unwrap();
        let saved = e.save(&s).unwrap();
        assert!(saved.contains(&format!("mesh = \"{mesh}\"")), "{saved}");
        let scene =
            crate::scene::file::load_scene_text(&meshes.join("saved.toml"), saved, &meshes, &Default::default())
                .unwrap();
        let plan = crate::plan::RenderPlan::new(&scene, &[]);
        let whole = crate::render::render_scene(&scene, &plan, &crate::render::progress::Silent).unwrap();
        assert_eq!(
            shown,
            encode(&whole.image, Format::Png, scene.film.exposure).unwrap(),
            "{mesh}"
        );
    }
}

/// A glTF file that brings its own camera opens through it; a scene file of one object would
/// frame the mesh itself, so saving is refused rather than writing a file of another view.
#[test]
fn a_gltf_file_with_its_own_camera_is_not_saved_as_another_view() {
    let dir = std::env::temp_dir().join(format!("pointshade-explore-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One triangle, (0,0,0) (1,0,0) (0,1,0), and a camera 3 units in front of it.
    let gltf = r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 3.0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.0}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36,
                     "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}"#;
    let path = dir.join("triangle.gltf");
    std::fs::write(&path, gltf).unwrap();
    let mut e = Explorer::open(Some(&path)).unwrap();
    let s = state(&e);
    assert!(e.render(&s, None, None).unwrap().starts_with(b"\x89PNG"));
    let err = e.save(&s).unwrap_err();
    assert!(
        err.contains("its own camera cannot be written into a scene file"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
