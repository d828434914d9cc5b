//! The plain parser must give tobj's models, bit for bit, or decline.

use super::*;

/// tobj's answer for `text`, with the options `load_obj` uses for files without attributes.
fn tobj_model(text: &str) -> Result<tobj::Model, tobj::LoadError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        ..Default::default()
    };
    let (mut models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Err(tobj::LoadError::OpenFileFailed))?;
    assert_eq!(models.len(), 1, "test inputs have one model");
    Ok(models.remove(0))
}

/// Asserts that the plain parser accepts `text` and agrees with tobj on every field it fills.
fn assert_agrees(text: &str) {
    let plain = parse(text.as_bytes()).unwrap_or_else(|| panic!("declined a plain file:\n{text}"));
    let expected = tobj_model(text).unwrap();
    assert_same_model(&plain.model, &expected, text);
}

fn assert_same_model(got: &tobj::Model, expected: &tobj::Model, what: &str) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(got.name, expected.name, "{what}");
    assert_eq!(got.mesh.indices, expected.mesh.indices, "{what}");
    assert_eq!(bits(&got.mesh.positions), bits(&expected.mesh.positions), "{what}");
    let m = &expected.mesh;
    assert!(m.normals.is_empty() && m.texcoords.is_empty() && m.vertex_color.is_empty());
    assert!(m.face_arities.is_empty() && m.material_id.is_none(), "{what}");
}

#[test]
fn plain_files_parse_to_tobjs_models() {
    // Forward references, an unused vertex, quads and a pentagon (fans), comments, `s` lines,
    // unknown keywords, CRLF, tabs, vertical tabs and form feeds, leading zeros, exponents,
    // inf and NaN (refused later by `load_obj`, as after tobj), no final newline.
    assert_agrees("f 3 1 2\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    assert_agrees(
        "# header\r\n####\r\nv 1e-3 -2.5E2 .5\r\nv\t1 2 3\r\nvx 0 1 2\r\n\
         v 4 5 6\nv 7 8 9\u{b}\nv 1 1 1\u{c}\n v 2 2 2 \ns off\nvp 0.1 0.2\n\
         f 1 2 3 4\nf 02 3 4\n\tf 4 5 6 2 1 \r\ng1 x\nf 6 6 6",
    );
    assert_agrees("v inf 0 0\nv 0 NaN 0\nv 0 0 -infinity\nf 1 2 3\n");
}

#[test]
fn anything_tobj_treats_otherwise_is_declined() {
    let declined = [
        ("texture coordinates", "v 0 0 0\nvt 0 0\nf 1 1 1\n"),
        ("normals", "v 0 0 0\nvn 0 0 1\nf 1 1 1\n"),
        ("a group", "v 0 0 0\ng body\nf 1 1 1\n"),
        ("an object", "v 0 0 0\no body\nf 1 1 1\n"),
        ("usemtl", "v 0 0 0\nusemtl red\nf 1 1 1\n"),
        ("a polyline", "v 0 0 0\nl 1 1\n"),
        ("a point", "v 0 0 0\nf 1\n"),
        ("a line as a face", "v 0 0 0\nf 1 1\n"),
        ("a relative index", "v 0 0 0\nf -1 -1 -1\n"),
        ("an index with a sign", "v 0 0 0\nf +1 1 1\n"),
        ("index 0", "v 0 0 0\nf 0 1 1\n"),
        ("an index past the vertices", "v 0 0 0\nf 1 1 2\n"),
        ("an index past u32", "v 0 0 0\nf 1 1 4294967297\n"),
        ("slashes", "v 0 0 0\nf 1// 1// 1//\n"),
        ("a w", "v 0 0 0 1\nf 1 1 1\n"),
        ("a colour", "v 0 0 0 1 0 0\nf 1 1 1\n"),
        ("two coordinates", "v 0 0\nf 1 1 1\n"),
        ("a bad number", "v 0 0 1.0e\nf 1 1 1\n"),
        ("no faces", "v 0 0 0\n"),
        ("non-ASCII text", "# café\nv 0 0 0\nf 1 1 1\n"),
        ("a Unicode space", "v 0\u{a0}0 0\nf 1 1 1\n"),
    ];
    for (what, text) in declined {
        assert!(parse(text.as_bytes()).is_none(), "{what} was not declined");
    }
}

#[test]
fn mtllib_lines_are_kept_whole_and_in_order() {
    let text = "mtllib a b.mtl\r\nv 0 0 0\n  mtllib c.mtl\nf 1 1 1\nmtllib\n";
    let plain = parse(text.as_bytes()).unwrap();
    assert_eq!(plain.material_lines, ["mtllib a b.mtl\r", "  mtllib c.mtl", "mtllib"]);
}

/// A small deterministic generator (xorshift64*) for the random files below.
struct Xorshift(u64);
impl Xorshift {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % n
    }
    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

/// Random files of plain and non-plain lines: whenever the parser accepts one, tobj must read it
/// without error and give the same model. Large files cross block boundaries.
#[test]
fn random_files_are_declined_or_parsed_as_tobj_parses_them() {
    let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15);
    let numbers = ["0", "1", "-2.5", "1e3", "0.125", ".5", "7.", "nan", "1e", "x"];
    let spaces = [" ", " ", " ", "\t", "  ", "\r", "\u{b}"];
    let (mut accepted, mut declined) = (0, 0);
    for round in 0..400 {
        // Half of the files hold only lines a plain file may hold, the other half a few others.
        let others = if round % 2 == 0 { 0 } else { 1 + rng.below(8) };
        let lines = if round % 50 == 0 { 20_000 } else { 1 + rng.below(40) };
        let mut text = String::new();
        let mut vertices = 0;
        for _ in 0..lines {
            let sp = rng.pick(&spaces);
            match rng.below(100) {
                0..=39 => {
                    vertices += 1;
                    let count = if rng.below(50) == 0 { 4 } else { 3 };
                    text += "v";
                    for _ in 0..count {
                        text += sp;
                        text += if rng.below(60) == 0 {
                            rng.pick(&numbers)
                        } else {
                            rng.pick(&numbers[..7])
                        };
                    }
                }
                40..=84 => {
                    text += "f";
                    let count = if rng.below(40) == 0 { 2 } else { 3 + rng.below(3) };
                    for _ in 0..count {
                        let limit = vertices + 1 + usize::from(rng.below(30) == 0);
                        text += sp;
                        text += &(1 + rng.below(limit)).to_string();
                    }
                }
                85..=99 if rng.below(100) >= others => {
                    text += rng.pick(&["# comment", "s 1", "", "   ", "#v 1 2 3", "vertex 1"])
                }
                _ => text += rng.pick(&["vt 0 0", "g part", "usemtl red", "f -1 -2 -3", "l 1 2"]),
            }
            text += rng.pick(&["\n", "\n", "\r\n"]);
        }
        match parse(text.as_bytes()) {
            Some(plain) => {
                accepted += 1;
                let expected =
                    tobj_model(&text).unwrap_or_else(|e| panic!("tobj refused an accepted file ({e}):\n{text}"));
                assert_same_model(&plain.model, &expected, &format!("round {round}"));
            }
            None => declined += 1,
        }
    }
    // Both outcomes must occur, or the test checks nothing.
    assert!(
        accepted > 50 && declined > 50,
        "accepted {accepted}, declined {declined}"
    );
}

/// The scanned meshes of ../shared/data: the plain ones parse to tobj's models; the others
/// (texture coordinates, normals) are declined.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn shared_meshes_parse_to_tobjs_models() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/meshes");
    let plain_files = [
        "stanford-dragon.obj",
        "stanford-bunny.obj",
        "armadillo.obj",
        "teapot.obj",
    ];
    for name in plain_files.iter().chain(&["suzanne.obj", "spot.obj"]) {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        match parse(text.as_bytes()) {
            Some(plain) => {
                assert!(plain_files.contains(name), "{name} has attributes but was accepted");
                assert_same_model(&plain.model, &tobj_model(&text).unwrap(), name);
            }
            None => assert!(!plain_files.contains(name), "{name} was declined"),
        }
    }
}
