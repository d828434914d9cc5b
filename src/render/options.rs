//! The options a front end sets on a render, declared once.
//!
//! [`RENDER_OPTIONS`] lists each option's name, the values it takes and its help: the CLI makes
//! its flags from it (`--shadow-offset`), the Python module its keywords (`shadow_offset=`), the
//! explorer its controls. [`RenderOptions::set`] is the one place a value given to an option is
//! read and checked, whatever its front end; [`RenderOptions::apply`] then puts the options on a
//! loaded scene, and the render request ([`super::request`]) uses the rest (threads, camera,
//! AOVs).
//!
//! A new option is a row of the table, a field of [`RenderOptions`] that its row's `store`
//! fills, and the code that acts on it (usually [`RenderOptions::apply`]). The CLI and the
//! Python module need nothing more; the Python stub (`__init__.pyi`) lists keywords by hand, and
//! a test holds it to the table.

use crate::error::{InputError, InputResult};
use crate::film::{time_budget_defaults, PixelRect, SamplerKind, MAX_SIDE, MAX_SPP, MAX_TIME_BUDGET};
use crate::plan::Aov;
use crate::scene::framing::{Aim, View};
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};
use crate::scene::Scene;

/// How a front end spells option names, for its error messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spelling {
    /// The command line's `--shadow-offset`.
    Flag,
    /// Python's keyword, the table's name: `shadow_offset`.
    Keyword,
}

impl Spelling {
    /// `name` (a table name) as this front end spells it.
    pub fn of(self, name: &str) -> String {
        match self {
            Spelling::Flag => format!("--{}", name.replace('_', "-")),
            Spelling::Keyword => name.to_string(),
        }
    }
}

/// A closed or open end of a number's range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct End {
    /// The end's value.
    pub value: f64,
    /// Whether the value itself is allowed.
    pub included: bool,
}

/// What an option takes. Front ends read it to convert their values (the CLI's text, Python's
/// objects) and to show the option (the explorer's sliders and menus).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Values {
    /// A whole number in `min..=max`.
    Whole {
        /// The smallest allowed.
        min: u64,
        /// The largest allowed.
        max: u64,
    },
    /// A finite number between two ends.
    Number {
        /// The lower end.
        low: End,
        /// The upper end.
        high: End,
    },
    /// One of these names.
    Name(&'static [&'static str]),
    /// Any of these names, as a list (comma-separated on the command line).
    Names(&'static [&'static str]),
    /// From `min` to `max` finite numbers (comma-separated on the command line), whole ones if
    /// `whole`.
    Numbers {
        /// The fewest numbers.
        min: usize,
        /// The most numbers.
        max: usize,
        /// Whole numbers ≥ 0 only.
        whole: bool,
    },
}

const fn closed(low: f64, high: f64) -> Values {
    Values::Number {
        low: End {
            value: low,
            included: true,
        },
        high: End {
            value: high,
            included: true,
        },
    }
}

const fn open(low: f64, high: f64) -> Values {
    Values::Number {
        low: End {
            value: low,
            included: false,
        },
        high: End {
            value: high,
            included: false,
        },
    }
}

/// A value as a front end gives it: the command line's text, or a Python int, float, str or
/// sequence. [`RenderOptions::set`] reads whichever form the option's [`Values`] allow.
#[derive(Clone, Debug, PartialEq)]
pub enum OptionValue {
    /// Text, read as the command line writes the value (`1,2,3` for a list).
    Text(String),
    /// A whole number.
    Whole(i128),
    /// A number.
    Number(f64),
    /// A sequence of values.
    List(Vec<OptionValue>),
}

/// A value once read: what an option's `store` receives.
enum Read {
    Whole(u64),
    Number(f64),
    Name(&'static str),
    Names(Vec<&'static str>),
    Numbers(Vec<f64>),
}

/// One render option.
pub struct RenderOption {
    /// The name: Python's keyword and the explorer's; `--name-with-dashes` on the command line.
    pub name: &'static str,
    /// Another command-line name it answers to (the older `--aov`).
    pub alias: Option<&'static str>,
    /// What it takes.
    pub values: Values,
    /// How help texts show the value (`x0,y0,x1,y1`).
    pub placeholder: &'static str,
    /// What it does, in a sentence or three.
    pub help: &'static str,
    /// Puts a value that passed `values`' checks into the options.
    store: fn(&mut RenderOptions, Read) -> Result<(), String>,
}

/// The options of a render; `None` (or empty) keeps the scene's setting or the default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: Option<u32>,
    /// Image height in pixels.
    pub height: Option<u32>,
    /// Samples per pixel (with a time budget: the most it may reach).
    pub spp: Option<u32>,
    /// The sampler.
    pub sampler: Option<SamplerKind>,
    /// Relative tolerance of the adaptive samplers.
    pub adaptive_threshold: Option<f32>,
    /// Seconds the BVH build and the render may take.
    pub time_budget: Option<f32>,
    /// Seed of the random sequences.
    pub seed: Option<u64>,
    /// The part of the frame to render.
    pub crop: Option<PixelRect>,
    /// Exposure in stops for 8-bit output.
    pub exposure: Option<f32>,
    /// How shadow rays leave the surface.
    pub shadow_offset: Option<ShadowOffset>,
    /// Where shadow rays start on smooth-shaded meshes.
    pub shadow_terminator: Option<ShadowTerminator>,
    /// A camera aimed anew.
    pub aim: Aim,
    /// Extra images beside the colour.
    pub aovs: Vec<Aov>,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Which camera of a glTF file to render through.
    pub camera: Option<usize>,
}

/// Every render option, in the order help texts list them.
pub static RENDER_OPTIONS: &[RenderOption] = &[
    RenderOption {
        name: "width",
        alias: None,
        values: Values::Whole {
            min: 1,
            max: MAX_SIDE as u64,
        },
        placeholder: "PIXELS",
        help: "Image width in pixels.",
        store: |o, v| {
            o.width = Some(whole(v) as u32);
            Ok(())
        },
    },
    RenderOption {
        name: "height",
        alias: None,
        values: Values::Whole {
            min: 1,
            max: MAX_SIDE as u64,
        },
        placeholder: "PIXELS",
        help: "Image height in pixels.",
        store: |o, v| {
            o.height = Some(whole(v) as u32);
            Ok(())
        },
    },
    RenderOption {
        name: "spp",
        alias: None,
        values: Values::Whole {
            min: 1,
            max: MAX_SPP as u64,
        },
        placeholder: "N",
        help: "Samples per pixel (the grid sampler takes square numbers; the adaptive ones, and \
               a time budget, at most this many).",
        store: |o, v| {
            o.spp = Some(whole(v) as u32);
            Ok(())
        },
    },
    RenderOption {
        name: "sampler",
        alias: None,
        values: Values::Name(SamplerKind::NAMES),
        placeholder: "grid|sobol|independent|adaptive|cells",
        help: "Where a pixel's samples fall: grid (spp = N², sub-pixel centres), sobol (the \
               default), independent, adaptive (Sobol rounds where a pixel needs them, spp at \
               most) or cells (sub-pixel cells subdivided where a pixel needs them, spp at most).",
        store: |o, v| {
            o.sampler = Some(SamplerKind::parse(name(v))?);
            Ok(())
        },
    },
    RenderOption {
        name: "adaptive_threshold",
        alias: None,
        values: open(0.0, 1.0),
        placeholder: "TOLERANCE",
        help: "The adaptive samplers' relative tolerance per pixel (default 0.01; smaller takes \
               more samples).",
        store: |o, v| {
            o.adaptive_threshold = Some(number(v) as f32);
            Ok(())
        },
    },
    RenderOption {
        name: "time_budget",
        alias: None,
        values: Values::Number {
            low: End {
                value: 0.0,
                included: false,
            },
            high: End {
                value: MAX_TIME_BUDGET as f64,
                included: true,
            },
        },
        placeholder: "SECONDS",
        help: "Seconds the BVH build and the render may take. sobol and independent add samples \
               in passes (doubling, then smaller: sobol to totals of 2^k or 1.5·2^k only) while \
               they fit, up to spp if given (else 65536); adaptive and cells refine at \
               thresholds halving from 0.04 down to adaptive_threshold if given (else 1/1024), \
               within spp (else 1024). The scene's spp and threshold are then ignored. The image \
               is bit for bit the render at the count or threshold reached.",
        store: |o, v| {
            o.time_budget = Some(number(v) as f32);
            Ok(())
        },
    },
    RenderOption {
        name: "seed",
        alias: None,
        values: Values::Whole { min: 0, max: u64::MAX },
        placeholder: "N",
        help: "Seed of the samplers' random sequences (default: the scene's, else 0).",
        store: |o, v| {
            o.seed = Some(whole(v));
            Ok(())
        },
    },
    RenderOption {
        name: "crop",
        alias: None,
        values: Values::Numbers {
            min: 4,
            max: 4,
            whole: true,
        },
        placeholder: "x0,y0,x1,y1",
        help: "Render only pixels [x0, x1) × [y0, y1) of the frame (the images have the crop's \
               size; on the command line an EXR crop that `pointshade merge` reassembles \
               bit-identically).",
        store: |o, v| {
            let n = numbers(v);
            let c = |i: usize| u32::try_from(n[i] as u64).map_err(|_| format!("{} is beyond the largest image", n[i]));
            o.crop = Some(PixelRect {
                x0: c(0)?,
                y0: c(1)?,
                x1: c(2)?,
                y1: c(3)?,
            });
            Ok(())
        },
    },
    RenderOption {
        name: "exposure",
        alias: None,
        values: closed(-64.0, 64.0),
        placeholder: "STOPS",
        help: "Exposure in stops of 8-bit (PNG) output.",
        store: |o, v| {
            o.exposure = Some(number(v) as f32);
            Ok(())
        },
    },
    RenderOption {
        name: "shadow_offset",
        alias: None,
        values: Values::Name(ShadowOffset::NAMES),
        placeholder: "error-bound|mitsuba",
        help: "Shadow-ray origin offset: error-bound (the default, correct at any scale) or \
               mitsuba (Mitsuba 3's fixed epsilon, for pixel-exact validation).",
        store: |o, v| {
            o.shadow_offset = Some(ShadowOffset::parse(name(v))?);
            Ok(())
        },
    },
    RenderOption {
        name: "shadow_terminator",
        alias: None,
        values: Values::Name(ShadowTerminator::NAMES),
        placeholder: "smooth|flat",
        help: "Where shadow rays start on smooth-shaded meshes: smooth (the default: from the \
               surface the vertex normals describe, so coarse meshes show no faceted shadow \
               terminator) or flat (from the triangle itself). The mitsuba offset always starts \
               on the triangle.",
        store: |o, v| {
            o.shadow_terminator = Some(ShadowTerminator::parse(name(v))?);
            Ok(())
        },
    },
    RenderOption {
        name: "view",
        alias: None,
        values: Values::Numbers {
            min: 2,
            max: 3,
            whole: false,
        },
        placeholder: "azimuth,elevation[,distance]",
        help: "Aim the automatic framing: degrees around the vertical from the front (+Z; 90 \
               looks from +X), degrees above the horizontal, and the distance as a multiple of \
               the one that fits the bounding box (default 1). Replaces the scene's camera; \
               automatic lights follow it. The default framing is about 24.2,17.7.",
        store: |o, v| {
            let n = numbers(v);
            let distance = n.get(2).copied().unwrap_or(1.0);
            o.aim.view = Some(View::new(n[0] as f32, n[1] as f32, distance as f32)?);
            Ok(())
        },
    },
    RenderOption {
        name: "look_from",
        alias: None,
        values: Values::Numbers {
            min: 3,
            max: 3,
            whole: false,
        },
        placeholder: "x,y,z",
        help: "Put the camera at this point (world coordinates, as a scene file writes them).",
        store: |o, v| {
            o.aim.look_from = Some(point(v));
            Ok(())
        },
    },
    RenderOption {
        name: "look_at",
        alias: None,
        values: Values::Numbers {
            min: 3,
            max: 3,
            whole: false,
        },
        placeholder: "x,y,z",
        help: "Aim the camera at this point (world coordinates).",
        store: |o, v| {
            o.aim.look_at = Some(point(v));
            Ok(())
        },
    },
    RenderOption {
        name: "fov",
        alias: None,
        values: open(0.0, 180.0),
        placeholder: "DEGREES",
        help: "Vertical field of view of the (perspective) camera, in degrees.",
        store: |o, v| {
            o.aim.fov = Some(number(v) as f32);
            Ok(())
        },
    },
    RenderOption {
        name: "aovs",
        alias: Some("aov"),
        values: Values::Names(Aov::NAMES),
        placeholder: "normal,position,depth,albedo,samples",
        help: "Extra images beside the colour (linear; on the command line EXRs named after the \
               output): shading normal, world position, distance from the camera, albedo·kd, and \
               the samples each pixel took.",
        store: |o, v| {
            let Read::Names(names) = v else {
                unreachable!("a Names option")
            };
            o.aovs = Aov::parse_list(&names.join(","))?;
            Ok(())
        },
    },
    RenderOption {
        name: "threads",
        alias: None,
        values: Values::Whole {
            min: 1,
            max: u32::MAX as u64,
        },
        placeholder: "N",
        help: "Worker threads (default: all cores; at most 8 per logical CPU).",
        store: |o, v| {
            let n = whole(v) as usize;
            super::workers::check_thread_count(n)?;
            o.threads = Some(n);
            Ok(())
        },
    },
    RenderOption {
        name: "camera",
        alias: None,
        values: Values::Whole {
            min: 0,
            max: u32::MAX as u64,
        },
        placeholder: "N",
        help: "Render a glTF file through its camera N (0-based) instead of the first one.",
        store: |o, v| {
            o.camera = Some(whole(v) as usize);
            Ok(())
        },
    },
];

fn whole(v: Read) -> u64 {
    match v {
        Read::Whole(n) => n,
        _ => unreachable!("a Whole option"),
    }
}

fn number(v: Read) -> f64 {
    match v {
        Read::Number(x) => x,
        _ => unreachable!("a Number option"),
    }
}

fn name(v: Read) -> &'static str {
    match v {
        Read::Name(n) => n,
        _ => unreachable!("a Name option"),
    }
}

fn numbers(v: Read) -> Vec<f64> {
    match v {
        Read::Numbers(n) => n,
        _ => unreachable!("a Numbers option"),
    }
}

fn point(v: Read) -> glam::DVec3 {
    let n = numbers(v);
    glam::DVec3::new(n[0], n[1], n[2])
}

/// The option called `name`, if there is one.
pub fn render_option(name: &str) -> Option<&'static RenderOption> {
    RENDER_OPTIONS.iter().find(|o| o.name == name)
}

impl RenderOptions {
    /// Sets option `name` to `value`, checked against what the option takes. The error names
    /// the option as `spelling` writes it and says what it takes.
    pub fn set(&mut self, name: &str, value: &OptionValue, spelling: Spelling) -> InputResult<()> {
        let option =
            render_option(name).ok_or_else(|| InputError::new(spelling.of(name), "is not an option of a render"))?;
        option
            .read(value)
            .and_then(|read| (option.store)(self, read))
            .map_err(|problem| InputError::new(spelling.of(name), problem))
    }

    /// Puts the options that change the scene on it, then validates the film. An error names
    /// the option as `spelling` writes it; a film that does not validate names the scene.
    pub fn apply(&self, scene: &mut Scene, spelling: Spelling) -> InputResult<()> {
        let err = |key: &str, problem: String| InputError::new(spelling.of(key), problem);
        self.aim.apply(scene).map_err(|e| err(aim_key(&self.aim), e))?;
        let f = &mut scene.film;
        f.width = self.width.unwrap_or(f.width);
        f.height = self.height.unwrap_or(f.height);
        f.exposure = self.exposure.unwrap_or(f.exposure);
        f.seed = self.seed.unwrap_or(f.seed);
        f.sampler = self.sampler.unwrap_or(f.sampler);
        if let Some(budget) = self.time_budget {
            f.time_budget = Some(budget);
            (f.spp, f.adaptive_threshold) = time_budget_defaults(f.sampler);
        }
        f.spp = self.spp.unwrap_or(f.spp);
        f.adaptive_threshold = self.adaptive_threshold.unwrap_or(f.adaptive_threshold);
        f.crop = self.crop.or(f.crop);
        scene.shadow_offset = self.shadow_offset.unwrap_or(scene.shadow_offset);
        scene.shadow_terminator = self.shadow_terminator.unwrap_or(scene.shadow_terminator);
        scene.film.validate().map_err(|e| InputError::new(&scene.source, e))
    }
}

/// The setting an aiming error is reported under: the last of them that was given.
fn aim_key(aim: &Aim) -> &'static str {
    if aim.fov.is_some() {
        "fov"
    } else if aim.look_at.is_some() {
        "look_at"
    } else if aim.look_from.is_some() {
        "look_from"
    } else {
        "view"
    }
}

impl RenderOption {
    /// `value` read as this option takes it, or what is wrong with it.
    fn read(&self, value: &OptionValue) -> Result<Read, String> {
        match self.values {
            Values::Whole { min, max } => {
                let expected = || format!("must be a whole number from {min} to {max}, got {}", shown(value));
                let n = match value {
                    OptionValue::Whole(n) => *n,
                    OptionValue::Text(t) => t.trim().parse::<i128>().map_err(|_| expected())?,
                    _ => return Err(expected()),
                };
                match u64::try_from(n) {
                    Ok(n) if (min..=max).contains(&n) => Ok(Read::Whole(n)),
                    _ => Err(expected()),
                }
            }
            Values::Number { low, high } => {
                let x = match value {
                    OptionValue::Number(x) => Some(*x),
                    OptionValue::Whole(n) => Some(*n as f64),
                    OptionValue::Text(t) => t.trim().parse::<f64>().ok(),
                    OptionValue::List(_) => None,
                };
                match x {
                    Some(x) if within(x, low, high) => Ok(Read::Number(x)),
                    _ => Err(format!(
                        "must be a number in {}, got {}",
                        interval(low, high),
                        shown(value)
                    )),
                }
            }
            Values::Name(names) => match value {
                OptionValue::Text(t) => names
                    .iter()
                    .find(|n| **n == t.trim())
                    .map(|n| Read::Name(n))
                    .ok_or_else(|| format!("expected {}, got {}", alternatives(names), shown(value))),
                _ => Err(format!("expected {}, got {}", alternatives(names), shown(value))),
            },
            Values::Names(names) => {
                let items: Vec<String> = match value {
                    OptionValue::Text(t) => t
                        .split(',')
                        .map(|s| s.trim().to_string())
                        .filter(|s| !s.is_empty())
                        .collect(),
                    OptionValue::List(items) => items
                        .iter()
                        .map(|i| match i {
                            OptionValue::Text(t) => Ok(t.trim().to_string()),
                            other => Err(format!("expected names ({}), got {}", names.join(", "), shown(other))),
                        })
                        .collect::<Result<_, _>>()?,
                    other => return Err(format!("expected names ({}), got {}", names.join(", "), shown(other))),
                };
                let mut read = Vec::new();
                for item in items {
                    let n = names
                        .iter()
                        .find(|n| **n == item)
                        .ok_or_else(|| format!("unknown name '{item}' (expected {})", alternatives(names)))?;
                    if !read.contains(n) {
                        read.push(*n);
                    }
                }
                Ok(Read::Names(read))
            }
            Values::Numbers { min, max, whole } => {
                let count = match min == max {
                    true => format!("{min}"),
                    false => format!("{min} to {max}"),
                };
                let kind = match whole {
                    true => "whole numbers ≥ 0",
                    false => "finite numbers",
                };
                let expected = || format!("expected {} ({count} {kind}), got {}", self.placeholder, shown(value));
                let items: Vec<Option<f64>> = match value {
                    OptionValue::Text(t) => t.split(',').map(|s| s.trim().parse::<f64>().ok()).collect(),
                    OptionValue::List(items) => items
                        .iter()
                        .map(|i| match i {
                            OptionValue::Whole(n) => Some(*n as f64),
                            OptionValue::Number(x) if !whole => Some(*x),
                            _ => None,
                        })
                        .collect(),
                    _ => return Err(expected()),
                };
                let good = |x: &f64| x.is_finite() && (!whole || (*x >= 0.0 && x.fract() == 0.0));
                let items: Vec<f64> = items
                    .into_iter()
                    .map(|x| x.filter(good))
                    .collect::<Option<_>>()
                    .ok_or_else(expected)?;
                match (min..=max).contains(&items.len()) {
                    true => Ok(Read::Numbers(items)),
                    false => Err(expected()),
                }
            }
        }
    }
}

fn within(x: f64, low: End, high: End) -> bool {
    let above = if low.included { x >= low.value } else { x > low.value };
    let below = if high.included { x <= high.value } else { x < high.value };
    above && below && x.is_finite()
}

/// `[a, b)` and the like.
fn interval(low: End, high: End) -> String {
    format!(
        "{}{}, {}{}",
        if low.included { '[' } else { '(' },
        low.value,
        high.value,
        if high.included { ']' } else { ')' }
    )
}

/// `a, b or c`.
fn alternatives(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// A value as a message quotes it.
fn shown(value: &OptionValue) -> String {
    match value {
        OptionValue::Text(t) => format!("'{t}'"),
        OptionValue::Whole(n) => n.to_string(),
        OptionValue::Number(x) => x.to_string(),
        OptionValue::List(items) => format!("[{}]", items.iter().map(shown).collect::<Vec<_>>().join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
