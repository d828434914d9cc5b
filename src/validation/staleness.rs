//! Whether a committed Mitsuba reference is stale: a fresh Mitsuba render of the same export
//! differs from it by more than another host's float rounding.
//!
//! Dr.Jit compiles Mitsuba's kernels for the host CPU (16 lanes on AVX-512, 8 on AVX2, none
//! in `scalar_rgb`) and Embree picks its traversal kernels the same way, so one
//! export renders with slightly different rounding on different machines. Most pixels move by a
//! few ulps; a few sit on a knife edge (a shadow ray grazing an occluder, a texture lookup on a
//! texel boundary) and move by up to a few percent, or jump. A changed scene — a light moved by
//! a centimetre, a roughness or an exponent changed by one step — moves a large share of the lit
//! pixels by more than 1e-3. So the check bounds two shares instead of asking for 99.99% within
//! 1e-4: the pixels beyond 1e-3 ([`MAX_BEYOND_1E3`]) and the pixels beyond 1e-2
//! ([`MAX_BEYOND_1E2`]), whatever the largest error of those few. The bounds and the
//! measurements behind them are in docs/reference-drift.md (`validation/reference-drift.sh`).

use crate::film::compare::compare;
use crate::film::Image;

/// Largest share of pixels beyond 1e-3 relative error that host rounding explains: above the
/// share by which AVX-512, AVX2 and scalar renders of any validation scene differ, far below
/// the share the smallest deliberate change moves (docs/reference-drift.md).
pub const MAX_BEYOND_1E3: f64 = 0.005;

/// Largest share of pixels beyond 1e-2 relative error that host rounding explains: pixels that
/// jump (a shadow edge on the other side). Above what host rounding gives, far below what a
/// light moved by a centimetre moves that far (docs/reference-drift.md).
pub const MAX_BEYOND_1E2: f64 = 0.001;

/// How a fresh reference differs from the committed one.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceDrift {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels whose relative error ([`compare`]'s definition) is beyond 1e-3.
    pub beyond_1e3: usize,
    /// Pixels beyond 1e-2.
    pub beyond_1e2: usize,
    /// The largest relative error (infinite when a pixel is not finite in either image).
    pub largest: f32,
}

impl ReferenceDrift {
    /// Measures `fresh` against `committed` (same size).
    pub fn measure(fresh: &Image, committed: &Image) -> Self {
        let c = compare(fresh, committed, 1e-3, 0);
        let count = |t: f32| c.relative_errors.iter().filter(|&&e| !(e <= t)).count();
        Self {
            pixels: c.pixels,
            beyond_1e3: count(1e-3),
            beyond_1e2: count(1e-2),
            largest: c.relative_errors.iter().copied().fold(0.0, f32::max),
        }
    }

    fn share(&self, n: usize) -> f64 {
        n as f64 / self.pixels.max(1) as f64
    }

    /// Whether the difference is more than host rounding explains.
    pub fn is_stale(&self) -> bool {
        !self.largest.is_finite()
            || self.share(self.beyond_1e3) > MAX_BEYOND_1E3
            || self.share(self.beyond_1e2) > MAX_BEYOND_1E2
    }

    /// One line: the two shares and the largest error.
    pub fn summary(&self) -> String {
        format!(
            "{:.3}% of the pixels beyond 1e-3 (host rounding: ≤ {}%), {:.3}% beyond 1e-2 (≤ {}%), largest {:.1e}",
            100.0 * self.share(self.beyond_1e3),
            100.0 * MAX_BEYOND_1E3,
            100.0 * self.share(self.beyond_1e2),
            100.0 * MAX_BEYOND_1E2,
            self.largest
        )
    }
}

/// The verdict on a committed reference.
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceCheck {
    /// The fresh render is the committed one, bit for bit.
    Identical,
    /// They differ by no more than another host's rounding.
    HostRounding(ReferenceDrift),
    /// They differ by more: the scene or the exporter changed. The reason, one line.
    Stale(String),
}

/// Checks a fresh Mitsuba render against the committed reference of the same scene.
pub fn check_reference(fresh: &Image, committed: &Image) -> ReferenceCheck {
    if (fresh.width, fresh.height) != (committed.width, committed.height) {
        return ReferenceCheck::Stale(format!(
            "the fresh render is {}×{}, the committed one {}×{}",
            fresh.width, fresh.height, committed.width, committed.height
        ));
    }
    if fresh
        .pixels
        .iter()
        .zip(&committed.pixels)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits))
    {
        return ReferenceCheck::Identical;
    }
    let drift = ReferenceDrift::measure(fresh, committed);
    if drift.is_stale() {
        ReferenceCheck::Stale(drift.summary())
    } else {
        ReferenceCheck::HostRounding(drift)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use ReferenceCheck::Stale;

    fn image(width: u32, height: u32, f: impl Fn(u32) -> Vec3) -> Image {
        Image {
            width,
            height,
            pixels: (0..width * height).map(f).collect(),
        }
    }

    fn ramp(i: u32) -> Vec3 {
        Vec3::new(0.1 + (i % 97) as f32 * 0.01, 0.2, 0.05 + (i % 13) as f32 * 0.02)
    }

    #[test]
    fn the_same_image_is_identical() {
        let a = image(64, 64, ramp);
        assert_eq!(check_reference(&a, &a.clone()), ReferenceCheck::Identical);
    }

    #[test]
    fn ulps_everywhere_and_a_few_knife_edge_pixels_are_host_rounding() {
        let committed = image(100, 100, ramp);
        // Every pixel a few ulps off, 0.3% of them off by 5e-3 and 0.05% off by 50%.
        let fresh = image(100, 100, |i| {
            let v = ramp(i);
            match (i % 2000, i % 1000) {
                (0, _) => v * 1.5,
                (_, 1..=3) => v * 1.005,
                _ => v * (1.0 + 3.0 * f32::EPSILON),
            }
        });
        match check_reference(&fresh, &committed) {
            ReferenceCheck::HostRounding(d) => {
                assert_eq!((d.beyond_1e3, d.beyond_1e2), (35, 5));
                assert!((d.largest - 0.5).abs() < 1e-5, "{}", d.largest);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_change_of_a_share_of_the_pixels_is_stale() {
        let committed = image(100, 100, ramp);
        // 0.6% of the pixels 0.2% brighter: more than the rounding bound beyond 1e-3.
        let brighter = image(100, 100, |i| if i % 1000 < 6 { ramp(i) * 1.002 } else { ramp(i) });
        assert!(matches!(
            check_reference(&brighter, &committed),
            ReferenceCheck::Stale(_)
        ));
        // 0.3% of the pixels jump: more than the bound beyond 1e-2.
        let jumps = image(100, 100, |i| if i % 1000 < 3 { ramp(i) * 2.0 } else { ramp(i) });
        assert!(matches!(check_reference(&jumps, &committed), ReferenceCheck::Stale(_)));
    }

    #[test]
    fn another_size_or_a_nan_is_stale() {
        let committed = image(10, 10, ramp);
        let Stale(reason) = check_reference(&image(10, 11, ramp), &committed) else {
            panic!("another size is stale")
        };
        assert!(reason.contains("10×11"), "{reason}");
        let nan = image(10, 10, |i| if i == 7 { Vec3::NAN } else { ramp(i) });
        assert!(matches!(check_reference(&nan, &committed), ReferenceCheck::Stale(_)));
    }
}
