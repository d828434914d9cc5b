//! Normal-map speed: pointshade's `tp` shading of normal.png with Cook-Torrance (or the BRDF
//! `--brdf` names), in float64 (the preset) and in f32 lanes, against a
//! straightforward numpy float64 implementation of the same formulas
//! (`benches/normalmap_numpy.py`), measured in the same run, plus the library's whole call
//! (`normal_map::shade`: the image check and level range too, each also timed alone) and the whole `pointshade normalmap` process
//! (decode + shade + encode) timed as a process.
//!
//! `cargo bench --bench normalmap [-- --brdf lambert|blinn-phong|cook-torrance]` prints a table of
//! medians (`--quick`: fewer repeats). The
//! numpy part needs python3 with numpy (`POINTSHADE_PYTHON` names the interpreter; CI gives it
//! the validation's virtual environment, which pins numpy); without them it says SKIPPED loudly
//! and the ratios are not printed. Both implementations' L_o are compared, so the times are for
//! the same result, and the bench fails if the float64 ones differ by more than [`AGREEMENT_F64`]
//! of the peak.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use pointshade::brdf::LocalDots;
use pointshade::film::Image;
use pointshade::lanes::LaneInstructions;
use pointshade::normal_map::image::NormalImage;
use pointshade::normal_map::likeness::NormalLikeness;
use pointshade::normal_map::scene_file::{ModelName, NormalMapScene, Preset};
use pointshade::normal_map::{self, image_surface, shade_image_with, MinMaxPrecision};
use pointshade::shading::convention::{clamped_dots, UnitForm};
use pointshade::surface::SurfacePoint;

/// Median and minimum of a set of times.
#[derive(Clone, Copy)]
struct Times {
    median: f64,
    best: f64,
}

impl Times {
    fn of(mut v: Vec<f64>) -> Times {
        v.sort_by(f64::total_cmp);
        Times {
            median: v[v.len() / 2],
            best: v[0],
        }
    }
}

/// Writes the image's 8-bit RGB as a (H, W, 3) uint8 .npy file for the numpy script.
fn write_npy_u8(path: &Path, image: &NormalImage) {
    let header = format!(
        "{{'descr': '|u1', 'fortran_order': False, 'shape': ({}, {}, 3), }}",
        image.height, image.width
    );
    let mut header = header.into_bytes();
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(b' ');
    }
    header.push(b'\n');
    let mut f = std::fs::File::create(path).expect("temporary .npy");
    f.write_all(b"\x93NUMPY\x01\x00").unwrap();
    f.write_all(&(header.len() as u16).to_le_bytes()).unwrap();
    f.write_all(&header).unwrap();
    let raw: Vec<u8> = (0..image.pixel_count())
        .flat_map(|i| image.pixel(i).0.map(|v| (v * 255.0).round() as u8))
        .collect();
    f.write_all(&raw).unwrap();
}

/// Reads a little-endian float64 .npy written by numpy (version 1 header).
fn read_npy_f64(path: &Path) -> Option<Vec<f64>> {
    let bytes = std::fs::read(path).ok()?;
    let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + header_len]).ok()?;
    if !header.contains("'<f8'") || header.contains("'fortran_order': True") {
        return None;
    }
    Some(
        bytes[10 + header_len..]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect(),
    )
}

struct Numpy {
    times: Times,
    /// Largest difference from pointshade's float64 and f32 images, relative to the peak.
    max_rel_diff: [f64; 2],
    /// Values of the f32 image further than [`AGREEMENT_F32`] of the peak from numpy's.
    f32_outliers: usize,
    version: String,
}

/// Largest difference between numpy's float64 L_o and pointshade's float64 one (stored as f32:
/// one rounding, 6e-8 of a value), relative to the peak, that the bench accepts.
const AGREEMENT_F64: f64 = 1e-7;

/// What the f32 lanes are held to: the share of values further than this from numpy's is
/// printed, not asserted (where a cosine is 0 in exact arithmetic f32 rounding may land on the
/// other side of the Cook-Torrance guard, and the pixel is off by a large step).
const AGREEMENT_F32: f64 = 1e-5;

/// Runs the numpy script on `npy` with `POINTSHADE_PYTHON` (default `python3`); `None` (after a
/// loud SKIPPED) when python or numpy are absent.
fn run_numpy(npy: &Path, out: &Path, brdf: ModelName, repeats: usize, ours: [&Image; 2]) -> Option<Numpy> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/normalmap_numpy.py");
    let python = std::env::var_os("POINTSHADE_PYTHON").unwrap_or_else(|| "python3".into());
    let result = Command::new(&python)
        .arg(&script)
        .arg(npy)
        .args(["--brdf", brdf.name(), "--repeats", &repeats.to_string(), "--save"])
        .arg(out)
        .output();
    let output = match result {
        Ok(o) if o.status.success() => o,
        Ok(o) => {
            eprintln!(
                "\n*** SKIPPED: the numpy comparison: {} failed (is numpy installed? `pip install numpy`):\n{}",
                script.display(),
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
            );
            return None;
        }
        Err(e) => {
            eprintln!(
                "\n*** SKIPPED: the numpy comparison: cannot run {}: {e}",
                python.to_string_lossy()
            );
            return None;
        }
    };
    let stdout = String::from_utf8_lossy(&output.stdout);
    let field = |key: &str| stdout.lines().find_map(|l| l.strip_prefix(key)).map(str::to_string);
    let times = Times {
        median: field("numpy_shade_seconds_median=")?.parse().ok()?,
        best: field("numpy_shade_seconds_min=")?.parse().ok()?,
    };
    let version = field("numpy_version=").unwrap_or_default();
    let theirs = read_npy_f64(out)?;
    let peak = theirs.iter().cloned().fold(0.0, f64::max);
    let differences = |ours: &Image| -> Vec<f64> {
        ours.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .zip(&theirs)
            .map(|(a, b)| (a as f64 - b).abs() / peak)
            .collect()
    };
    let max_rel_diff = ours.map(|ours| differences(ours).into_iter().fold(0.0, f64::max));
    let f32_outliers = differences(ours[1]).into_iter().filter(|&d| d > AGREEMENT_F32).count();
    Some(Numpy {
        times,
        max_rel_diff,
        f32_outliers,
        version,
    })
}

/// The surface points of every foreground pixel, one `ImageSurface::point` each.
fn surface_points(scene: &NormalMapScene, image: &NormalImage) -> Vec<SurfacePoint> {
    let surface = image_surface(scene, image).expect("normal.png has a range");
    let mut points = Vec::new();
    let mut columns = Vec::new();
    for row in 0..image.height {
        columns.clear();
        surface.foreground_columns(image, row, &mut columns);
        points.extend(columns.iter().filter_map(|&col| {
            let (rgb, alpha) = image.pixel((row * image.width + col) as usize);
            surface.point(col, row, rgb, alpha)
        }));
    }
    points
}

/// The BRDF's share of the shading: `Material::eval` alone on the LocalDots of every shaded
/// pixel (formed beforehand, as the shader forms them), one thread.
fn time_material_eval(scene: &NormalMapScene, image: &NormalImage, repeats: usize) -> Times {
    let dots: Vec<LocalDots<f32>> = surface_points(scene, image)
        .iter()
        .filter_map(|sp| {
            let ls = scene.lights[0].sample(sp.position)?;
            let n = sp.shading_normal.to_array();
            let a = clamped_dots(
                n,
                (-ls.wi).to_array(),
                sp.to_viewer.to_array(),
                Some(UnitForm::Quotients),
            );
            a.half_vector.then_some(a.dots)
        })
        .collect();
    let mut out = vec![[0.0f32; 3]; dots.len()];
    Times::of(
        (0..repeats)
            .map(|_| {
                let t = Instant::now();
                for (o, d) in out.iter_mut().zip(&dots) {
                    *o = scene.material.eval(d);
                }
                std::hint::black_box(&mut out);
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let brdf: ModelName = match args.iter().position(|a| a == "--brdf") {
        Some(i) => args.get(i + 1).map_or("", String::as_str).parse().unwrap_or_else(|e| {
            eprintln!("error: --brdf: {e}");
            std::process::exit(2)
        }),
        None => ModelName::CookTorrance,
    };
    let repeats = if quick { 5 } else { 51 };
    let process_repeats = if quick { 3 } else { 11 };
    let numpy_repeats = if quick { 3 } else { 7 };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/normalmaps/normal.png");
    if !path.is_file() {
        eprintln!(
            "*** SKIPPED: {} is missing; the normal-map benchmark needs the shared test data",
            path.display()
        );
        return;
    }
    let image = NormalImage::load(&path).expect("normal.png decodes");
    let scene = NormalMapScene::from_preset(&path, Preset::Tp, brdf);
    // What numpy's shade() does too: the tp scaling's global min and max, then every pixel.
    let shade_with = |instructions: LaneInstructions, precision: MinMaxPrecision| {
        let surface = image_surface(&scene, &image).expect("normal.png has a range");
        shade_image_with(&scene, &image, &surface, instructions, precision)
    };
    let best = LaneInstructions::detect();

    // Median and best of `repeats` calls of `call` (which black-boxes its result) on a pool of
    // `threads`.
    let time_calls = |threads: usize, call: &(dyn Fn() + Sync)| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            // Warm-up for a second: short runs on a cold core measure the clock ramping up, not
            // the code (about 1.5x slower here); numpy's runs are long enough not to need it.
            let warm = Instant::now();
            while warm.elapsed().as_secs_f64() < 1.0 {
                call();
            }
            let times: Vec<f64> = (0..repeats)
                .map(|_| {
                    let t = Instant::now();
                    call();
                    t.elapsed().as_secs_f64()
                })
                .collect();
            Times::of(times)
        })
    };
    let time_shading = |threads: usize, instructions: LaneInstructions, precision: MinMaxPrecision| {
        time_calls(threads, &|| {
            std::hint::black_box(shade_with(instructions, precision));
        })
    };
    let all = rayon::current_num_threads();
    let (f64_, f32_) = (MinMaxPrecision::Float64, MinMaxPrecision::Float32);
    let one_thread = [f64_, f32_].map(|p| time_shading(1, best, p));
    let all_threads = [f64_, f32_].map(|p| time_shading(all, best, p));
    // The narrower instruction sets this CPU also runs, for the machines that have only those.
    let narrower: Vec<(LaneInstructions, Times)> = [
        #[cfg(target_arch = "x86_64")]
        LaneInstructions::Avx2,
        LaneInstructions::Portable,
    ]
    .into_iter()
    .filter(|&set| set < best)
    .map(|set| (set, time_shading(all, set, f64_)))
    .collect();
    // The library's whole call, as both front ends make it: the tp level range, then the
    // shading above, whose rows also count the image check (NormalLikeness) and test finiteness.
    let whole_call = time_calls(all, &|| {
        std::hint::black_box(normal_map::shade(&scene, &image, "bench").expect("normal.png shades"));
    });
    // Its range pass, and the image check as a pass of its own (as it was before the rows
    // counted it), alone.
    let image_check = time_calls(all, &|| {
        std::hint::black_box(NormalLikeness::of(&image));
    });
    let level_range = time_calls(all, &|| {
        std::hint::black_box(image.level_range());
    });
    let (ours, stats) = shade_with(best, f64_);
    let (ours_f32, _) = shade_with(best, f32_);
    let eval_only = time_material_eval(&scene, &image, repeats);

    let tmp = std::env::temp_dir().join(format!("pointshade-bench-nm-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let out_png: PathBuf = tmp.join("out.png");
    let process: Vec<f64> = (0..process_repeats + 1)
        .map(|_| {
            let t = Instant::now();
            let status = Command::new(env!("CARGO_BIN_EXE_pointshade"))
                .arg("normalmap")
                .arg(&path)
                .args(["--preset", "tp", "--brdf", brdf.name(), "--quiet", "-o"])
                .arg(&out_png)
                .status()
                .expect("pointshade runs");
            assert!(status.success());
            t.elapsed().as_secs_f64()
        })
        .skip(1) // the first run warms the file cache
        .collect();
    let process = Times::of(process);

    let npy = tmp.join("normal-rgb.npy");
    write_npy_u8(&npy, &image);
    let numpy = run_numpy(&npy, &tmp.join("numpy-lo.npy"), brdf, numpy_repeats, [&ours, &ours_f32]);
    let _ = std::fs::remove_dir_all(&tmp);

    println!(
        "normal.png {}x{} ({} shaded points), tp preset, {}; medians of {repeats} runs \
         ({process_repeats} processes, {numpy_repeats} numpy runs)",
        image.width,
        image.height,
        stats.surface_points,
        brdf.name()
    );
    println!(
        "{:<58} {:>10} {:>14} {:>10} {:>12}",
        "what", "median ms", "numpy / this", "best ms", "best ratio"
    );
    let row = |what: &str, t: Times| {
        let ratio = |ours: f64, theirs: f64| format!("{:.1}x", theirs / ours);
        let (median_ratio, best_ratio) = numpy.as_ref().map_or(("-".into(), "-".into()), |n| {
            (ratio(t.median, n.times.median), ratio(t.best, n.times.best))
        });
        println!(
            "{what:<58} {:>10.3} {median_ratio:>14} {:>10.3} {best_ratio:>12}",
            t.median * 1e3,
            t.best * 1e3
        );
    };
    if let Some(n) = &numpy {
        row(
            &format!("numpy {} float64 shading (benches/normalmap_numpy.py)", n.version),
            n.times,
        );
    }
    row(
        "pointshade shading, float64 lanes (the preset), 1 thread",
        one_thread[0],
    );
    row("pointshade shading, f32 lanes, 1 thread", one_thread[1]);
    row(
        "  Material::eval alone (the BRDF, f32), one point at a time, 1 thread",
        eval_only,
    );
    row(
        &format!("pointshade shading, float64, {all} threads ({best:?} lanes, detected)"),
        all_threads[0],
    );
    row(&format!("pointshade shading, f32, {all} threads"), all_threads[1]);
    for (set, times) in narrower {
        row(&format!("  float64 with {set:?} lanes, {all} threads"), times);
    }
    row(
        &format!("normal_map::shade (range + shading with the image check), {all} threads"),
        whole_call,
    );
    row(
        "  the image check as a pass of its own (NormalLikeness::of)",
        image_check,
    );
    row("  its tp level range (NormalImage::level_range) alone", level_range);
    row("pointshade normalmap process (decode + shade + encode)", process);
    match &numpy {
        Some(n) => {
            let [d64, d32] = n.max_rel_diff;
            println!(
                "numpy and pointshade L_o agree to {d64:.1e} of the peak in float64 (stored as f32); \
                 in f32 lanes to {d32:.1e}, with {} values beyond {AGREEMENT_F32:.0e}",
                n.f32_outliers
            );
            if !(d64 <= AGREEMENT_F64) {
                eprintln!(
                    "error: numpy and pointshade's float64 L_o differ by {d64:.1e} of the peak, more than \
                     {AGREEMENT_F64:.0e}"
                );
                std::process::exit(1);
            }
            let verdict = |ok: bool| if ok { "met" } else { "NOT MET" };
            let (numpy, shading) = (n.times.median, all_threads[0].median);
            println!(
                "targets (medians): float64 shading ≥ 150x faster than numpy: {} ({:.0}x); \
                 whole process faster than numpy's shading: {} ({:.1}x)",
                verdict(numpy / shading >= 150.0),
                numpy / shading,
                verdict(process.median < numpy),
                numpy / process.median
            );
        }
        None => println!("*** SKIPPED: numpy comparison (see above): ratios not measured"),
    }
}
