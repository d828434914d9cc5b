//! The validation report: an HTML page (images side by side, metrics, times, expected
//! differences) and a Markdown summary table for the README.

use std::fmt::Write as _;
use std::path::Path;

use crate::film::compare::Comparison;
use crate::validation::run::{
    meets_thresholds, SceneValidation, REQUIRED_MEAN_RELATIVE_ERROR, REQUIRED_WITHIN, TOLERANCE,
};

/// The leading `#` comment of a scene file, without a "Validation:" prefix.
pub fn scene_description(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .map(|l| l.trim_start_matches('#').trim())
        .collect();
    lines.join(" ").trim_start_matches("Validation:").trim().to_string()
}

fn status(s: &SceneValidation) -> &'static str {
    match (s.is_exact(), s.passes()) {
        (false, _) => "expected difference",
        (true, true) => "agrees",
        (true, false) => "FAILS",
    }
}

fn percent(share: f64) -> String {
    format!("{:.3}%", 100.0 * share)
}

/// The like-for-like share within tolerance, and with the rounding band where it was measured.
pub fn within(c: &Comparison) -> String {
    match c.within_rounding_band {
        Some(band) => format!(
            "{} ({} with the ±1 ulp uv band)",
            percent(c.within_tolerance),
            percent(band)
        ),
        None => percent(c.within_tolerance),
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The Markdown summary: one row per scene and sample count.
pub fn markdown(results: &[SceneValidation]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| scene | spp | within {TOLERANCE:.0e} | mean rel. error | within {TOLERANCE:.0e}, pointshade's own shadow offset | pointshade s | Mitsuba s | status |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for r in results {
        for run in &r.runs {
            let (compat, own) = (&run.ours[0], &run.ours[1]);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1e} | {} | {:.3} | {:.3} | {} |",
                r.name,
                run.spp,
                within(&compat.comparison),
                compat.comparison.mean_relative_error,
                percent(own.comparison.within_tolerance),
                compat.time.as_secs_f64(),
                (run.mitsuba.load + run.mitsuba.render).as_secs_f64(),
                status(r)
            );
        }
    }
    let checks: Vec<_> = results
        .iter()
        .filter_map(|r| r.plugin_check.as_ref().map(|c| (r, c)))
        .collect();
    if !checks.is_empty() {
        let _ = writeln!(
            s,
            "\nThe BSDF plugin against Mitsuba's own BSDFs (pixel centres, every material through the plugin):\n"
        );
        let _ = writeln!(s, "| scene | within {TOLERANCE:.0e} | mean rel. error |");
        let _ = writeln!(s, "|---|---|---|");
        for (r, c) in checks {
            let _ = writeln!(
                s,
                "| {} | {} | {:.1e} |",
                r.name,
                percent(c.within_tolerance),
                c.mean_relative_error
            );
        }
    }
    s
}

/// The Mitsuba variants the references were rendered with (`validation/render.py` picks
/// llvm_ad_rgb where libLLVM 19 is installed, scalar_rgb elsewhere), comma-separated.
pub fn mitsuba_variants(results: &[SceneValidation]) -> String {
    let mut variants: Vec<&str> = results
        .iter()
        .flat_map(|r| &r.runs)
        .map(|r| r.mitsuba.variant.as_str())
        .collect();
    variants.sort_unstable();
    variants.dedup();
    if variants.is_empty() {
        "none".into()
    } else {
        variants.join(", ")
    }
}

/// The HTML page; image paths are relative to the page's folder.
pub fn html(results: &[SceneValidation]) -> String {
    let mut s = String::new();
    let passed = results.iter().filter(|r| r.is_exact() && r.passes()).count();
    let exact = results.iter().filter(|r| r.is_exact()).count();
    let variant = mitsuba_variants(results);
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>pointshade vs Mitsuba 3</title>\n<style>\n\
         body {{ font-family: sans-serif; margin: 1.5em; color: #222; }}\n\
         table {{ border-collapse: collapse; margin: 0.8em 0; }}\n\
         td, th {{ border: 1px solid #bbb; padding: 3px 8px; text-align: right; }}\n\
         th {{ background: #eee; }} td:first-child {{ text-align: left; }}\n\
         .agrees {{ color: #080; font-weight: bold; }} .FAILS {{ color: #c00; font-weight: bold; }}\n\
         .expected {{ color: #a60; font-weight: bold; }}\n\
         figure {{ display: inline-block; margin: 0 8px 8px 0; text-align: center; }}\n\
         figure img {{ width: 192px; image-rendering: pixelated; border: 1px solid #999; }}\n\
         figcaption {{ font-size: 80%; }} .scene {{ margin-top: 2em; border-top: 2px solid #ccc; }}\n\
         .legend span {{ display: inline-block; width: 1.2em; height: 0.9em; vertical-align: middle; }}\n\
         </style></head><body>\n\
         <h1>pointshade vs Mitsuba 3</h1>\n\
         <p>{passed} of {exact} scenes with an exact Mitsuba equivalent agree (≥ {} of pixels within {TOLERANCE:.0e} \
         relative, mean relative error ≤ {REQUIRED_MEAN_RELATIVE_ERROR:.0e}; where textures are sampled, a pixel also \
         agrees when pointshade's render with the texture coordinates one ulp up or down agrees: the ±1 ulp uv band, \
         see <code>validation::rounding</code>). Mitsuba variant: {variant}. \
         Relative error = |ours − ref| / max(|ref|, 1e-4 · max ref). pointshade is compared with Mitsuba's \
         fixed-epsilon shadow offset (like for like) and, for information, with its own error-bound offset \
         (and smooth shadow origins on smooth-shaded meshes).</p>\n\
         <p class=\"legend\">Heat maps: <span style=\"background:#000\"></span> ≤ 1e-6 \
         <span style=\"background:#00e\"></span> 1e-4 <span style=\"background:#0b0\"></span> 1e-3 \
         <span style=\"background:#ee0\"></span> 1e-2 <span style=\"background:#f00\"></span> ≥ 0.1 \
         <span style=\"background:#fff;border:1px solid #999\"></span> NaN/Inf</p>\n",
        percent(REQUIRED_WITHIN)
    );
    s.push_str("<table><tr><th>scene</th><th>spp</th><th>within (Mitsuba offset)</th><th>mean rel. error</th><th>RMSE</th><th>within (own offset)</th><th>pointshade s</th><th>Mitsuba s</th><th>status</th></tr>\n");
    for r in results {
        for run in &r.runs {
            let (c, own) = (&run.ours[0].comparison, &run.ours[1].comparison);
            let class = if r.is_exact() { status(r) } else { "expected" };
            let _ = writeln!(
                s,
                "<tr><td><a href=\"#{0}\">{0}</a></td><td>{1}</td><td>{2}</td><td>{3:.2e}</td><td>{4:.2e}</td><td>{5}</td><td>{6:.3}</td><td>{7:.3}</td><td class=\"{8}\">{9}</td></tr>",
                r.name,
                run.spp,
                within(c),
                c.mean_relative_error,
                c.rmse,
                percent(own.within_tolerance),
                run.ours[0].time.as_secs_f64(),
                (run.mitsuba.load + run.mitsuba.render).as_secs_f64(),
                class,
                if r.is_exact() && !meets_thresholds(c) { "FAILS" } else { status(r) }
            );
        }
    }
    s.push_str("</table>\n");
    for r in results {
        let _ = writeln!(s, "<div class=\"scene\" id=\"{0}\"><h2>{0}</h2>", r.name);
        let _ = writeln!(
            s,
            "<p>{} <br><small>{}</small></p>",
            escape(&scene_description(&r.source)),
            escape(&r.source.display().to_string())
        );
        if r.is_exact() {
            s.push_str("<p>Every feature has an exact Mitsuba equivalent: the images must agree.</p>\n");
        } else {
            s.push_str("<p class=\"expected\">No Mitsuba equivalent, differences expected:</p><ul>\n");
            for d in &r.differences {
                let _ = writeln!(s, "<li>{}</li>", escape(d));
            }
            s.push_str("</ul>\n");
        }
        s.push_str("<p>Materials: ");
        s.push_str(
            &r.material_notes
                .iter()
                .map(|n| escape(n))
                .collect::<Vec<_>>()
                .join("; "),
        );
        s.push_str("</p>\n");
        if let Some(c) = &r.plugin_check {
            let _ = writeln!(
                s,
                "<p>Plugin check: Mitsuba with pointshade's BSDF plugin for every material against Mitsuba's own BSDFs: {} within {TOLERANCE:.0e}, mean relative error {:.2e}.</p>",
                percent(c.within_tolerance),
                c.mean_relative_error
            );
        }
        for run in &r.runs {
            let captions = [
                "pointshade",
                "Mitsuba",
                "heat map (Mitsuba offset)",
                "heat map (own offset)",
            ];
            let _ = writeln!(s, "<h3>{} spp</h3><div>", run.spp);
            for (img, cap) in run.images.iter().zip(captions) {
                let _ = writeln!(
                    s,
                    "<figure><img src=\"{img}\" alt=\"{cap}\"><figcaption>{cap}</figcaption></figure>"
                );
            }
            s.push_str("</div>\n");
            let c = &run.ours[0].comparison;
            if !c.worst.is_empty() {
                let _ = writeln!(
                    s,
                    "<details><summary>worst pixels</summary><pre>{}</pre></details>",
                    escape(&c.summary())
                );
            }
        }
        s.push_str("</div>\n");
    }
    s.push_str("</body></html>\n");
    s
}
