//! Tests of the options table and of reading values.

use super::*;
use crate::film::PixelRect;
use crate::plan::Aov;

fn set(name: &str, value: OptionValue) -> InputResult<RenderOptions> {
    let mut o = RenderOptions::default();
    o.set(name, &value, Spelling::Keyword).map(|()| o)
}

fn text(t: &str) -> OptionValue {
    OptionValue::Text(t.into())
}

#[test]
fn names_are_unique_and_spelled_for_each_front_end() {
    for (i, a) in RENDER_OPTIONS.iter().enumerate() {
        assert!(a.name.chars().all(|c| c.is_ascii_lowercase() || c == '_'), "{}", a.name);
        for b in &RENDER_OPTIONS[i + 1..] {
            assert_ne!(a.name, b.name);
        }
    }
    assert_eq!(Spelling::Flag.of("shadow_offset"), "--shadow-offset");
    assert_eq!(Spelling::Keyword.of("shadow_offset"), "shadow_offset");
}

#[test]
fn aov_names_are_the_variants_names() {
    let aovs: Vec<&str> = Aov::ALL.iter().map(|a| a.name()).collect();
    assert_eq!(aovs, Aov::NAMES);
}

#[test]
fn text_and_typed_values_read_alike() {
    assert_eq!(
        set("width", text("320")).unwrap(),
        set("width", OptionValue::Whole(320)).unwrap()
    );
    assert_eq!(
        set("look_at", text("1,2.5,-3")).unwrap(),
        set(
            "look_at",
            OptionValue::List(vec![
                OptionValue::Whole(1),
                OptionValue::Number(2.5),
                OptionValue::Number(-3.0)
            ])
        )
        .unwrap()
    );
    assert_eq!(
        set("aovs", text("depth,normal,depth")).unwrap().aovs,
        vec![Aov::Depth, Aov::Normal]
    );
    assert_eq!(
        set("crop", text("0,1,2,3")).unwrap().crop,
        Some(PixelRect {
            x0: 0,
            y0: 1,
            x1: 2,
            y1: 3
        })
    );
    assert_eq!(set("view", text("30,20")).unwrap().aim.view.unwrap().distance, 1.0);
}

#[test]
fn errors_name_the_option_and_its_real_limits() {
    let e = set("width", OptionValue::Whole(1 << 40)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "width: must be a whole number from 1 to 65536, got 1099511627776"
    );
    let e = RenderOptions::default()
        .set("width", &text("3.5"), Spelling::Flag)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "--width: must be a whole number from 1 to 65536, got '3.5'"
    );
    assert!(
        set("width", OptionValue::Number(3.0)).is_err(),
        "a float is not a whole number"
    );
    let e = set("adaptive_threshold", OptionValue::Number(f64::NAN)).unwrap_err();
    assert_eq!(e.to_string(), "adaptive_threshold: must be a number in (0, 1), got NaN");
    let e = set("sampler", text("halton")).unwrap_err();
    assert_eq!(
        e.problem,
        "expected grid, sobol, independent, adaptive or cells, got 'halton'"
    );
    let e = set("crop", text("0,0,-1,4")).unwrap_err();
    assert!(
        e.problem.starts_with("expected x0,y0,x1,y1 (4 whole numbers ≥ 0)"),
        "{e}"
    );
    assert!(set("look_from", text("1,2")).is_err());
    assert!(set("look_from", text("1,2,inf")).is_err());
    assert!(set("aovs", text("normal,colour"))
        .unwrap_err()
        .problem
        .contains("'colour'"));
    assert!(set("threads", OptionValue::Whole(0)).is_err());
    assert!(set("threads", OptionValue::Whole(1_000_000)).is_err());
    let e = set("elevation", OptionValue::Whole(1)).unwrap_err();
    assert_eq!(e.to_string(), "elevation: is not an option of a render");
    assert!(set("view", text("0,90")).unwrap_err().problem.contains("elevation"));
    assert_eq!(set("view", text("-30,10,2.5")).unwrap().aim.view.unwrap().distance, 2.5);
    for bad in ["", "1", "1,2,3,4", "x,1", "1,nan", "inf,0"] {
        assert!(set("view", text(bad)).is_err(), "{bad}");
    }
}

#[test]
fn every_option_takes_a_value_of_its_kind() {
    for option in RENDER_OPTIONS {
        let value = match option.values {
            Values::Whole { min, .. } => OptionValue::Whole(min.max(1) as i128),
            Values::Number { low, high } => OptionValue::Number(match (low.included, high.included) {
                (true, _) => low.value,
                (false, true) => high.value,
                (false, false) => (low.value + high.value) / 2.0,
            }),
            Values::Name(names) => text(names[0]),
            Values::Names(names) => text(names[0]),
            Values::Numbers { min, .. } => text(&vec!["1"; min].join(",")),
        };
        set(option.name, value).unwrap_or_else(|e| panic!("{}: {e}", option.name));
    }
}
