//! What a render option is: its name, the values it takes and where a value goes, and the
//! options a render is given.

use crate::film::{PixelRect, SamplerKind};
use crate::plan::Aov;
use crate::scene::framing::Aim;
use crate::scene::matching::Match;
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};

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
pub(super) enum Read {
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
    pub(super) store: fn(&mut RenderOptions, Read) -> Result<(), String>,
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
    /// Another renderer whose samples and shadow rays to take.
    pub matching: Option<Match>,
    /// A camera aimed anew.
    pub aim: Aim,
    /// Extra images beside the colour.
    pub aovs: Vec<Aov>,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Which camera of a glTF file to render through.
    pub camera: Option<usize>,
}
