//! Per-pixel comparison of two linear images: error metrics, worst pixels and a heat map.
//!
//! The relative error of a pixel is max over channels of |ours − ref| / max(|ref|, floor), with
//! floor = 1e-4 · (largest finite |ref| in the image), so black pixels of the reference are
//! judged against a small absolute tolerance instead of dividing by zero. Non-finite values in
//! either image are counted and reported; such pixels never count as within tolerance and are
//! left out of the averages (so one NaN cannot hide the rest of the comparison).

use std::fmt::Write as _;

use glam::Vec3;

use crate::film::Image;

/// Relative floor: a reference value counts as at least this share of the image's maximum.
pub const RELATIVE_FLOOR: f32 = 1e-4;
/// ε of the relative MSE, mean((o − r)² / (r² + ε)).
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// One pixel where the images differ most.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelDifference {
    /// Column.
    pub x: u32,
    /// Row (0 = top).
    pub y: u32,
    /// Our value.
    pub ours: Vec3,
    /// The reference value.
    pub reference: Vec3,
    /// Relative error (see the module documentation); infinite for non-finite pixels.
    pub relative_error: f32,
}

/// Metrics of a comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Number of pixels.
    pub pixels: usize,
    /// Root mean squared error over finite channels.
    pub rmse: f64,
    /// Mean of (o − r)² / (r² + ε) over finite channels, ε = [`REL_MSE_EPSILON`].
    pub rel_mse: f64,
    /// Mean relative error over finite pixels.
    pub mean_relative_error: f64,
    /// Share of all pixels whose relative error is ≤ `tolerance`.
    pub within_tolerance: f64,
    /// The tolerance used.
    pub tolerance: f32,
    /// Share of pixels within tolerance when renders with the texture coordinates one ulp up
    /// and down count too (`validation::rounding`); `None` when not measured (no texture is
    /// sampled, or the caller did not ask).
    pub within_rounding_band: Option<f64>,
    /// Pixels with a NaN or infinite channel in our image.
    pub non_finite_ours: usize,
    /// Pixels with a NaN or infinite channel in the reference.
    pub non_finite_reference: usize,
    /// The worst pixels, worst first.
    pub worst: Vec<PixelDifference>,
    /// Per-pixel relative errors (for the heat map), infinite for non-finite pixels.
    pub relative_errors: Vec<f32>,
}

/// Which of the two images a [`compare_checked`] refusal is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The image under test.
    Ours,
    /// The reference.
    Reference,
}

/// [`compare`], after checking that the images can be compared: the same size, and — unless
/// `count_non_finite`, which counts such pixels as mismatches — no NaN or infinite pixel, since
/// a metric that leaves them out would call an image of NaN a match. The error says which image
/// is at fault and why, on one line.
pub fn compare_checked(
    ours: &Image,
    reference: &Image,
    tolerance: f32,
    worst: usize,
    count_non_finite: bool,
) -> Result<Comparison, (Side, String)> {
    if (ours.width, ours.height) != (reference.width, reference.height) {
        return Err((
            Side::Reference,
            format!(
                "size {}×{} differs from {}×{} of the image compared with it",
                reference.width, reference.height, ours.width, ours.height
            ),
        ));
    }
    if !count_non_finite {
        for (side, image) in [(Side::Ours, ours), (Side::Reference, reference)] {
            if let Some((x, y, value)) = image.first_non_finite() {
                let count = image.pixels.iter().filter(|p| !p.is_finite()).count();
                return Err((
                    side,
                    format!(
                        "{count} pixel(s) are not finite, the first at ({x}, {y}): {value}; \
                         count them as mismatches with --count-non-finite (Python: count_non_finite=True)"
                    ),
                ));
            }
        }
    }
    Ok(compare(ours, reference, tolerance, worst))
}

/// Compares `ours` with `reference` (same size; checked by the caller). `worst` pixels are kept.
/// Non-finite pixels are counted and never within tolerance ([`compare_checked`] refuses them).
pub fn compare(ours: &Image, reference: &Image, tolerance: f32, worst: usize) -> Comparison {
    assert_eq!(
        (ours.width, ours.height),
        (reference.width, reference.height),
        "sizes checked by the caller"
    );
    let finite = |v: &Vec3| v.is_finite();
    let max_ref = reference
        .pixels
        .iter()
        .filter(|v| finite(v))
        .map(|v| v.abs().max_element())
        .fold(0.0f32, f32::max);
    // A black reference has no scale: judge it against an absolute floor of 1e-4 · 1e-4.
    let floor = (RELATIVE_FLOOR * max_ref).max(f32::MIN_POSITIVE);
    let (mut sq, mut rel_sq, mut rel_sum) = (0.0f64, 0.0f64, 0.0f64);
    let (mut finite_pixels, mut within) = (0usize, 0usize);
    let (mut bad_ours, mut bad_ref) = (0, 0);
    let mut relative_errors = Vec::with_capacity(ours.pixels.len());
    for (o, r) in ours.pixels.iter().zip(&reference.pixels) {
        bad_ours += usize::from(!finite(o));
        bad_ref += usize::from(!finite(r));
        if !(finite(o) && finite(r)) {
            relative_errors.push(f32::INFINITY);
            continue;
        }
        let mut rel = 0.0f32;
        for c in 0..3 {
            let d = (o[c] - r[c]) as f64;
            sq += d * d;
            rel_sq += d * d / ((r[c] as f64).powi(2) + REL_MSE_EPSILON);
            rel = rel.max((o[c] - r[c]).abs() / r[c].abs().max(floor));
        }
        finite_pixels += 1;
        rel_sum += rel as f64;
        within += usize::from(rel <= tolerance);
        relative_errors.push(rel);
    }
    let channels = (3 * finite_pixels).max(1) as f64;
    let mut order: Vec<usize> = (0..relative_errors.len()).collect();
    order.sort_by(|&a, &b| relative_errors[b].total_cmp(&relative_errors[a]).then(a.cmp(&b)));
    let worst = order
        .into_iter()
        .take(worst)
        .filter(|&i| relative_errors[i] > 0.0)
        .map(|i| PixelDifference {
            x: i as u32 % ours.width,
            y: i as u32 / ours.width,
            ours: ours.pixels[i],
            reference: reference.pixels[i],
            relative_error: relative_errors[i],
        })
        .collect();
    Comparison {
        pixels: ours.pixels.len(),
        rmse: (sq / channels).sqrt(),
        rel_mse: rel_sq / channels,
        mean_relative_error: rel_sum / finite_pixels.max(1) as f64,
        within_tolerance: within as f64 / ours.pixels.len().max(1) as f64,
        tolerance,
        within_rounding_band: None,
        non_finite_ours: bad_ours,
        non_finite_reference: bad_ref,
        worst,
        relative_errors,
    }
}

/// The pixels whose group image has one value, and their part of the error.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorGroup {
    /// The value (first channel of the group image), e.g. a sample count.
    pub value: f32,
    /// Pixels in the group (finite in both images).
    pub pixels: usize,
    /// RMSE over the group's channels.
    pub rmse: f64,
    /// The group's share of the image's summed squared error (0 when there is no error).
    pub share: f64,
}

/// Most distinct values `error_by_group` accepts: it is meant for labels such as sample counts,
/// not for continuous images.
pub const MAX_GROUPS: usize = 64;

/// The squared error of `ours` against `reference` split by the value of `groups`' first channel
/// at each pixel (all three the same size; checked by the caller), groups in increasing value.
/// Pixels non-finite in either image are left out, as in [`compare`]'s RMSE. Errs when `groups`
/// has more than [`MAX_GROUPS`] distinct finite values or a non-finite one.
pub fn error_by_group(ours: &Image, reference: &Image, groups: &Image) -> Result<Vec<ErrorGroup>, String> {
    let mut labelled: Vec<(f32, f64)> = Vec::new();
    for ((o, r), g) in ours.pixels.iter().zip(&reference.pixels).zip(&groups.pixels) {
        if !g.x.is_finite() {
            return Err(format!("has a non-finite value ({})", g.x));
        }
        if o.is_finite() && r.is_finite() {
            labelled.push((g.x, (*o - *r).as_dvec3().length_squared()));
        }
    }
    labelled.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = labelled.iter().map(|(_, sq)| sq).sum();
    let groups: Vec<ErrorGroup> = labelled
        .chunk_by(|a, b| a.0 == b.0)
        .map(|group| {
            let sq: f64 = group.iter().map(|(_, sq)| sq).sum();
            ErrorGroup {
                value: group[0].0,
                pixels: group.len(),
                rmse: (sq / (3 * group.len()) as f64).sqrt(),
                share: if total > 0.0 { sq / total } else { 0.0 },
            }
        })
        .collect();
    if groups.len() > MAX_GROUPS {
        return Err(format!(
            "has {} distinct values; groups are for a few labels, such as a samples AOV (at most {MAX_GROUPS})",
            groups.len()
        ));
    }
    Ok(groups)
}

/// `labels` with each value replaced by the largest of `edges` at or below it (values below the
/// first edge stay as they are): a few groups for labels with many values, such as the adaptive
/// sampler's sample counts. `edges` increase strictly (the caller checks).
pub fn bin_labels(labels: &Image, edges: &[f32]) -> Image {
    let bin = |v: f32| match edges.partition_point(|&e| e <= v) {
        0 => v,
        i => edges[i - 1],
    };
    Image {
        width: labels.width,
        height: labels.height,
        pixels: labels.pixels.iter().map(|p| Vec3::splat(bin(p.x))).collect(),
    }
}

/// `groups` as a table, one line per group.
pub fn group_table(groups: &[ErrorGroup]) -> String {
    let mut s = String::from("squared error by group:\n        value     pixels         RMSE  share\n");
    for g in groups {
        let _ = writeln!(
            s,
            "  {:>11} {:>10} {:>12.4e} {:>5.1}%",
            g.value,
            g.pixels,
            g.rmse,
            100.0 * g.share
        );
    }
    s
}

impl Comparison {
    /// The metrics as a few lines of text (what `pointshade compare` prints).
    pub fn summary(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "pixels                {}", self.pixels);
        let _ = writeln!(s, "RMSE                  {:.6e}", self.rmse);
        let _ = writeln!(s, "relative MSE          {:.6e}", self.rel_mse);
        let _ = writeln!(s, "mean relative error   {:.6e}", self.mean_relative_error);
        let _ = writeln!(
            s,
            "within {:.0e}           {:.4}%",
            self.tolerance,
            100.0 * self.within_tolerance
        );
        if self.non_finite_ours + self.non_finite_reference > 0 {
            let _ = writeln!(
                s,
                "non-finite pixels     {} in ours, {} in the reference",
                self.non_finite_ours, self.non_finite_reference
            );
        }
        if !self.worst.is_empty() {
            let _ = writeln!(s, "worst pixels (x, y): relative error, ours vs reference");
            for w in &self.worst {
                let _ = writeln!(
                    s,
                    "  ({:>4}, {:>4}): {:.3e}  [{:.6e} {:.6e} {:.6e}] vs [{:.6e} {:.6e} {:.6e}]",
                    w.x,
                    w.y,
                    w.relative_error,
                    w.ours.x,
                    w.ours.y,
                    w.ours.z,
                    w.reference.x,
                    w.reference.y,
                    w.reference.z
                );
            }
        }
        s
    }

    /// A heat map of the relative errors, coloured by [`heat_colour`].
    pub fn heat_map(&self, width: u32, height: u32) -> Image {
        let pixels = self.relative_errors.iter().map(|&e| heat_colour(e)).collect();
        Image { width, height, pixels }
    }
}

/// The heat-map colour of a relative error (linear RGB in [0, 1]), interpolated in log10 of the
/// error between stops: black ≤ 1e-6, blue 1e-4, green 1e-3 (the default tolerance), yellow
/// 1e-2, red ≥ 1e-1; white where an input is non-finite.
pub fn heat_colour(error: f32) -> Vec3 {
    if !error.is_finite() {
        return Vec3::ONE;
    }
    const STOPS: [(f32, Vec3); 5] = [
        (-6.0, Vec3::ZERO),
        (-4.0, Vec3::new(0.0, 0.0, 0.9)),
        (-3.0, Vec3::new(0.0, 0.75, 0.0)),
        (-2.0, Vec3::new(0.95, 0.9, 0.0)),
        (-1.0, Vec3::new(1.0, 0.0, 0.0)),
    ];
    let e = error.max(1e-30).log10();
    if e <= STOPS[0].0 {
        return STOPS[0].1;
    }
    for pair in STOPS.windows(2) {
        let ((e0, c0), (e1, c1)) = (pair[0], pair[1]);
        if e <= e1 {
            return c0.lerp(c1, (e - e0) / (e1 - e0));
        }
    }
    STOPS[STOPS.len() - 1].1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[f32]) -> Image {
        Image {
            width: values.len() as u32,
            height: 1,
            pixels: values.iter().map(|&v| Vec3::splat(v)).collect(),
        }
    }

    #[test]
    fn error_by_group_splits_the_squared_error_and_its_groups_add_up_to_the_rmse() {
        let reference = image(&[1.0, 1.0, 2.0, 0.0, 0.5, f32::NAN]);
        let ours = image(&[1.1, 1.0, 2.2, 0.0, 0.8, 0.5]);
        // Sample counts: pixels 0 and 3 took 1, pixels 1, 2 and 5 took 16, pixel 4 took 64.
        let counts = image(&[1.0, 16.0, 16.0, 1.0, 64.0, 16.0]);
        let groups = error_by_group(&ours, &reference, &counts).unwrap();
        let summary: Vec<(f32, usize)> = groups.iter().map(|g| (g.value, g.pixels)).collect();
        // The NaN reference pixel is left out, as in the RMSE.
        assert_eq!(summary, [(1.0, 2), (16.0, 2), (64.0, 1)]);
        // Squared errors per pixel (three channels): 0.03, 0, 0.12, 0, 0.27 → total 0.42.
        let shares: Vec<f64> = groups.iter().map(|g| g.share).collect();
        for (got, want) in shares.iter().zip([0.03 / 0.42, 0.12 / 0.42, 0.27 / 0.42]) {
            assert!((got - want).abs() < 1e-6, "{shares:?}");
        }
        assert!(
            (groups[2].rmse - 0.3).abs() < 1e-6,
            "one pixel off by 0.3: {:?}",
            groups[2]
        );
        let c = compare(&ours, &reference, 1e-3, 0);
        let pooled = groups.iter().map(|g| g.rmse.powi(2) * g.pixels as f64).sum::<f64>() / 5.0;
        assert!((pooled.sqrt() - c.rmse).abs() < 1e-9, "{} vs {}", pooled.sqrt(), c.rmse);
    }

    #[test]
    fn error_by_group_refuses_continuous_and_non_finite_labels() {
        let a = image(&[0.5; 100]);
        let ramp: Vec<f32> = (0..100).map(|i| i as f32).collect();
        let err = error_by_group(&a, &a, &image(&ramp)).unwrap_err();
        assert!(err.contains("100 distinct values"), "{err}");
        let mut labels = [1.0; 100];
        labels[7] = f32::INFINITY;
        assert!(error_by_group(&a, &a, &image(&labels)).is_err());
        // No error at all: every share is 0, not NaN.
        let groups = error_by_group(&a, &a, &image(&[1.0; 100])).unwrap();
        assert_eq!(groups[0].share, 0.0);
    }

    #[test]
    fn binned_labels_take_the_largest_edge_at_or_below_them() {
        let counts = image(&[1.0, 16.0, 20.0, 63.0, 64.0, 300.0, 0.5]);
        let binned = bin_labels(&counts, &[1.0, 16.0, 17.0, 64.0]);
        let values: Vec<f32> = binned.pixels.iter().map(|p| p.x).collect();
        assert_eq!(values, [1.0, 16.0, 17.0, 17.0, 64.0, 64.0, 0.5]);
    }

    #[test]
    fn identical_images_have_zero_error() {
        let a = image(&[0.0, 0.5, 1.0, 2.0]);
        let c = compare(&a, &a, 1e-3, 5);
        assert_eq!(
            (c.rmse, c.rel_mse, c.mean_relative_error, c.within_tolerance),
            (0.0, 0.0, 0.0, 1.0)
        );
        assert!(c.worst.is_empty());
    }

    #[test]
    fn known_errors_give_known_metrics() {
        let reference = image(&[1.0, 1.0, 2.0, 0.0]);
        let ours = image(&[1.0, 1.1, 2.0, 0.0]);
        let c = compare(&ours, &reference, 1e-3, 2);
        // One channel-triple off by 0.1 out of 4 pixels: RMSE = √(3·0.01 / 12).
        assert!((c.rmse - (0.03f64 / 12.0).sqrt()).abs() < 1e-7);
        assert!((c.rel_mse - 0.03 / (1.0 + 1e-2) / 12.0).abs() < 1e-7);
        assert!((c.mean_relative_error - 0.1 / 4.0).abs() < 1e-6);
        assert_eq!(c.within_tolerance, 0.75);
        assert_eq!((c.worst.len(), c.worst[0].x, c.worst[0].y), (1, 1, 0));
        assert!((c.worst[0].relative_error - 0.1).abs() < 1e-6);
    }

    #[test]
    fn black_reference_pixels_use_the_relative_floor() {
        // Max ref = 10 → floor = 1e-3: a 5e-7 error on black is 5e-4 relative (within 1e-3),
        // a 5e-6 error is 5e-3 (not within).
        let reference = image(&[10.0, 0.0, 0.0]);
        let ours = image(&[10.0, 5e-7, 5e-6]);
        let c = compare(&ours, &reference, 1e-3, 3);
        assert!((c.within_tolerance - 2.0 / 3.0).abs() < 1e-9);
    }

    #[test]
    fn non_finite_pixels_are_reported_not_fatal() {
        let reference = image(&[1.0, f32::INFINITY, 1.0, 1.0]);
        let ours = image(&[f32::NAN, 1.0, 1.0, 1.0005]);
        let c = compare(&ours, &reference, 1e-3, 4);
        assert_eq!((c.non_finite_ours, c.non_finite_reference), (1, 1));
        assert_eq!(
            c.within_tolerance, 0.5,
            "two finite pixels within, two non-finite ones not"
        );
        assert!(c.rmse.is_finite() && c.mean_relative_error.is_finite());
        assert!(c.worst[0].relative_error.is_infinite());
        assert!(c
            .summary()
            .contains("non-finite pixels     1 in ours, 1 in the reference"));
        assert_eq!(c.heat_map(4, 1).pixels[0], Vec3::ONE);
    }

    #[test]
    fn heat_colours_rise_with_the_error() {
        assert_eq!(heat_colour(0.0), Vec3::ZERO);
        assert_eq!(heat_colour(1.0), Vec3::new(1.0, 0.0, 0.0));
        assert!((heat_colour(1e-3) - Vec3::new(0.0, 0.75, 0.0)).length() < 1e-5);
        assert!(heat_colour(1e-4).z > 0.85 && heat_colour(5e-3).x > 0.5);
        assert_eq!(heat_colour(f32::NAN), Vec3::ONE);
    }
}
