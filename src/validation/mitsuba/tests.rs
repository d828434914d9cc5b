use super::*;
use crate::material::Material;
use crate::scene;
use crate::texture::TextureImage;

fn load(toml: &str) -> Scene {
    let dir = std::env::temp_dir().join(format!("pointshade-mitsuba-{}-{}", std::process::id(), toml.len()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    // Two triangles of two materials (from its own library) in one OBJ.
    std::fs::write(
        dir.join("two.mtl"),
        "newmtl red\nKd 0.8 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.8\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("two.obj"),
        "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl red\nf 1 2 3\nusemtl blue\nf 2 4 3\n",
    )
    .unwrap();
    std::fs::write(dir.join("s.toml"), toml).unwrap();
    let s = scene::load(&dir.join("s.toml")).unwrap();
    std::fs::remove_dir_all(dir).unwrap();
    s
}

const CAMERA: &str = "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\nnear_clip = 0.5\n";

#[test]
fn exact_scene_has_no_differences_and_uses_native_bsdfs() {
    let s = load(&format!(
            "{CAMERA}[film]\nwidth = 32\nheight = 16\nsampler = \"grid\"\n\
             [[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 2.0]\nintensity = 5.0\n\
             [[light]]\ntype = \"directional\"\ndirection = [0.0, 0.0, -1.0]\n\
             [material.a]\nalbedo = [0.5, 0.5, 0.5]\ntwo_sided = false\n\
             [material.b]\nmodel = \"cook-torrance\"\nkd = 0.0\nroughness = 0.3\ng = \"smith-ggx\"\nfresnel = \"conductor\"\neta = [0.2, 0.9, 1.1]\nk = [3.9, 2.4, 2.1]\n\
             [[object]]\nmesh = \"tri.obj\"\nmaterial = \"a\"\n\
             [[object]]\nmesh = \"tri.obj\"\nmaterial = \"b\"\ntransform = {{ translate = [1.0, 2.0, 3.0] }}\n"
        ));
    let e = export(&s, 4, BsdfChoice::NativeWhereExact, "s");
    assert!(e.differences.is_empty(), "{:?}", e.differences);
    assert_eq!(e.per_light.len(), 2);
    assert!(e.per_light[0].contains("type=\"point\"") && !e.per_light[0].contains("directional"));
    let x = &e.scene;
    assert!(
        x.contains("<bsdf id=\"mat0\" type=\"diffuse\"><rgb name=\"reflectance\" value=\"0.5, 0.5, 0.5\"/></bsdf>"),
        "{x}"
    );
    assert!(x.contains("<bsdf id=\"mat1\" type=\"twosided\"><bsdf type=\"roughconductor\">"));
    assert!(x.contains("<float name=\"fov\" value=\"40\"/>") && x.contains("value=\"y\""));
    assert!(x.contains("<float name=\"near_clip\" value=\"0.5\"/>"));
    assert!(x.contains("<integer name=\"sample_count\" value=\"4\"/>") && x.contains("jitter"));
    assert!(
        x.contains("<matrix value=\"1 0 0 1 0 1 0 2 0 0 1 3 0 0 0 1\"/>"),
        "row-major translation"
    );
    assert!(x.contains("<emitter type=\"point\"><point name=\"position\" x=\"0\" y=\"1\" z=\"2\"/><rgb name=\"intensity\" value=\"5, 5, 5\"/>"));
}

#[test]
fn models_without_native_bsdf_use_the_plugin_and_inexact_features_are_listed() {
    let s = load(&format!(
            "{CAMERA}[[light]]\ntype = \"spot\"\nposition = [0.0, 2.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\nfalloff = \"none\"\n\
             [material.bp]\nmodel = \"blinn-phong\"\nks = 0.5\nshininess = 20.0\n\
             [[object]]\nmesh = \"tri.obj\"\nmaterial = \"bp\"\n"
        ));
    let e = export(&s, 1, BsdfChoice::NativeWhereExact, "s");
    assert!(e
        .scene
        .contains("type=\"pointshade\"><string name=\"model\" value=\"blinn-phong\"/>"));
    assert!(e.material_notes[0].contains("plugin"));
    assert_eq!(
        e.differences,
        ["sobol sampler (exported as Mitsuba's independent sampler)"]
    );
    // A spot without the inverse square: the light plugin, with its falloff and cone.
    assert!(e.scene.contains("<emitter type=\"pointshade_light\">"), "{}", e.scene);
    assert!(e.scene.contains("<string name=\"falloff\" value=\"none\"/>"));
    assert!(e.scene.contains("<string name=\"profile\" value=\"gltf\"/>"));
    assert!(e.scene.contains("emitters of type \"pointshade_light\""));
}

#[test]
fn spot_lights_are_mitsubas_spot_only_with_its_profile() {
    let spot = |extra: &str| {
        load(&format!(
            "{CAMERA}[[light]]\ntype = \"spot\"\nposition = [0.0, 2.0, 0.0]\ndirection = [0.0, -1.0, 0.0]\n\
             inner_cone = 15.0\nouter_cone = 30.0\n{extra}[[object]]\nmesh = \"tri.obj\"\n"
        ))
    };
    let native = export(&spot("falloff = \"mitsuba\"\n"), 1, BsdfChoice::NativeWhereExact, "s");
    assert!(native.scene.contains("<emitter type=\"spot\">"), "{}", native.scene);
    assert!(native.scene.contains("<float name=\"cutoff_angle\" value=\"30"));
    assert!(native.scene.contains("<float name=\"beam_width\" value=\"15"));
    let gltf = export(&spot(""), 1, BsdfChoice::NativeWhereExact, "s");
    assert!(
        gltf.scene.contains("<emitter type=\"pointshade_light\">"),
        "{}",
        gltf.scene
    );
    assert!(!gltf.scene.contains("type=\"spot\""));
}

#[test]
fn orthographic_scale_spans_the_same_film() {
    let s = load(
        "[camera]\ntype = \"orthographic\"\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nscale = 2.0\n\
             [film]\nwidth = 200\nheight = 100\n[[object]]\nmesh = \"tri.obj\"\n",
    );
    let e = export(&s, 1, BsdfChoice::PluginEverywhere, "s");
    assert!(e.scene.contains("<scale x=\"4\" y=\"4\" z=\"1\"/>"), "{}", e.scene);
    assert!(e.scene.contains("type=\"pointshade\""));
}

#[test]
fn an_obj_of_two_materials_is_exported_as_a_ply_per_material() {
    let s = load(&format!(
        "{CAMERA}[film]\nsampler = \"grid\"\n[[object]]\nmesh = \"two.obj\"\n[[object]]\nmesh = \"tri.obj\"\n"
    ));
    let e = export(&s, 1, BsdfChoice::NativeWhereExact, "scene");
    assert!(e.differences.is_empty(), "{:?}", e.differences);
    let names: Vec<&str> = e.meshes.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names.len(), 2, "{names:?}");
    for (name, bytes) in &e.meshes {
        assert!(
            name.starts_with("scene.object0.mat") && name.ends_with(".ply"),
            "{name}"
        );
        assert!(bytes.starts_with(b"ply\n") && bytes.windows(15).any(|w| w == b"element face 1\n"));
        assert!(
            e.scene
                .contains(&format!("<string name=\"filename\" value=\"{name}\"/>")),
            "{}",
            e.scene
        );
    }
    // The one-material OBJ is referenced as it is.
    assert!(e.scene.contains("tri.obj") && !names.iter().any(|n| n.contains("object1")));
}

#[test]
fn emission_is_a_pass_of_its_own_and_normal_mapped_materials_keep_their_sides_in_the_plugin() {
    use crate::material::{MaterialTextures, NormalTexture};
    use crate::texture::TextureRef;
    let mut s = load(&format!(
            "{CAMERA}[film]\nsampler = \"grid\"\n[[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 2.0]\n[[object]]\nmesh = \"tri.obj\"\n"
        ));
    let texture = TextureRef::gltf_default(0);
    let mut m = Material::gltf_pbr("glow", [1.0; 3], 0.0, 0.5);
    if let BrdfModel::GltfPbr(p) = &mut m.model {
        p.emissive = [1.0, 0.5, 0.25];
        m.textures = MaterialTextures {
            normal: Some(NormalTexture { texture, scale: 1.0 }),
            emissive: Some(texture),
            ..MaterialTextures::default()
        };
    }
    s.materials = vec![m];
    s.textures = vec![TextureImage {
        label: "1x1".into(),
        width: 1,
        height: 1,
        texels: vec![[128, 128, 255, 255]],
    }];
    let e = export(&s, 1, BsdfChoice::NativeWhereExact, "s");
    assert_eq!(
        e.differences,
        ["material 'glow': emits from both sides (two-sided), Mitsuba's area emitter from the front only"]
    );
    let passes: Vec<String> = e.passes().into_iter().map(|(suffix, _)| suffix).collect();
    assert_eq!(passes, ["light0", "emission"]);
    let emission = e.emission.as_deref().unwrap();
    assert!(emission.contains("<bsdf id=\"mat0\" type=\"diffuse\"><rgb name=\"reflectance\" value=\"0, 0, 0\"/>"));
    assert!(emission.contains("type=\"pointshade_emission\"><rgb name=\"factor\" value=\"1, 0.5, 0.25\"/>"));
    assert!(!emission.contains("type=\"point\""), "no lights in the emission pass");
    let lit = &e.per_light[0];
    assert!(!lit.contains("<emitter type=\"area\"") && lit.contains("<integer name=\"normal_width\" value=\"1\"/>"));
    assert!(
        lit.contains("<bsdf id=\"mat0\" type=\"pointshade\">")
            && lit.contains("<boolean name=\"two_sided\" value=\"true\"/>"),
        "the plugin turns the mapped normal itself, unwrapped: {lit}"
    );
    // The textured OBJ goes out as a PLY with texture coordinates and tangents, and the image
    // as its texels.
    let names: Vec<&str> = e.meshes.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["s.image0.rgba", "s.object0.mat0.ply"]);
    assert!(e.meshes[1].1.windows(9).any(|w| w == b"uv0_x\npro"));
}
