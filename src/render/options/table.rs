//! The table of render options: one row per option, its values, its help and where its value
//! goes. A new option starts here.

use super::option::{End, Read, RenderOption, Values};
use crate::film::{PixelRect, SamplerKind, MAX_SIDE, MAX_SPP, MAX_TIME_BUDGET};
use crate::plan::Aov;
use crate::scene::framing::View;
use crate::scene::matching::Match;
use crate::scene::shadows::{ShadowOffset, ShadowTerminator};

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

/// Three numbers: a point in world coordinates.
const POINT: Values = Values::Numbers {
    min: 3,
    max: 3,
    whole: false,
};

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
        name: "match",
        alias: None,
        values: Values::Name(Match::NAMES),
        placeholder: "mitsuba",
        help: "Render like another renderer, for pixel-by-pixel comparison: mitsuba sets \
               sampler = grid (spp = N², one sample at each pixel centre at spp = 1, as the \
               Mitsuba export samples) and shadow_offset = mitsuba. A different sampler or \
               shadow offset given with it is an error.",
        store: |o, v| {
            o.matching = Some(Match::parse(name(v))?);
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
        values: POINT,
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
        values: POINT,
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
            crate::render::workers::check_thread_count(n)?;
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
