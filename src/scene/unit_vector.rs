//! Unit vectors of any finite vector, and unit normals of any finite triangle.
//!
//! `normalize` squares the components: in f32 a vector longer than ~1.8e19 (a triangle whose
//! edges exceed ~4e9, as their cross product squares again) overflows to an infinite length and
//! normalises to zero, and one shorter than ~1e-19 underflows to a zero length. Scaling by a
//! power of two first is exact, so for every vector `normalize` already handled the result has
//! the same bits, and for the others it is the direction instead of zero.

use glam::Vec3;

/// 2^k with `x · 2^k` in [1, 4) for the largest `|x|` of `v` (a normal or subnormal f32; the
/// exponent is clamped so that 2^k itself stays a normal number). Multiplying by it is exact.
pub fn power_of_two_scale(v: Vec3) -> f32 {
    let largest = v.abs().max_element();
    let exponent = ((largest.to_bits() >> 23) & 0xff).min(253);
    // bits of 2^(127 − e): (127 − e + 127) << 23.
    f32::from_bits((254 - exponent) << 23)
}

/// `v` normalised, or zero when `v` is zero or not finite; unlike `Vec3::normalize_or_zero`,
/// whatever its length.
pub fn unit_or_zero(v: Vec3) -> Vec3 {
    normalized_if_normal(v).unwrap_or_else(|| (v * power_of_two_scale(v)).normalize_or_zero())
}

/// `v.normalize_or_zero()`, bit for bit, when the squared length is a normal f32 (then neither
/// it overflowed nor underflowed): the common case, without the scaling's extra work.
#[inline]
fn normalized_if_normal(v: Vec3) -> Option<Vec3> {
    let squared = v.dot(v);
    squared.is_normal().then(|| v * squared.sqrt().recip())
}

/// The unit normal of the triangle `(a, b, c)`, counter-clockwise front: normalize((b − a) ×
/// (c − a)), zero when it has no area in f32. The edges are scaled before the cross product, so
/// neither it nor its squared length overflows or underflows for any finite triangle whose edges
/// are finite.
pub fn triangle_normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (e1, e2) = (b - a, c - a);
    if let Some(n) = normalized_if_normal(e1.cross(e2)) {
        return n;
    }
    let s = power_of_two_scale(e1.abs().max(e2.abs()));
    unit_or_zero((e1 * s).cross(e2 * s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_vectors_keep_the_bits_of_normalize() {
        let mut random = crate::test_random::XorShift32::new(0x2545_f491);
        for _ in 0..10_000 {
            let mut next = || (random.unit() - 0.5) * 1e3;
            let v = Vec3::new(next(), next(), next());
            assert_eq!(unit_or_zero(v), v.normalize_or_zero(), "{v}");
            let [a, b, c] = [v, Vec3::new(next(), next(), next()), Vec3::new(next(), next(), next())];
            assert_eq!(triangle_normal(a, b, c), (b - a).cross(c - a).normalize_or_zero());
        }
    }

    #[test]
    fn huge_and_tiny_vectors_have_a_direction() {
        for s in [1e-38f32, 1e-30, 1e-20, 1e20, 1e30, 3e38] {
            let v = Vec3::new(3.0, 0.0, 4.0) * (s / 5.0);
            let u = unit_or_zero(v);
            assert!((u - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-6, "{s:e}: {u}");
        }
        assert_eq!(unit_or_zero(Vec3::ZERO), Vec3::ZERO);
        assert_eq!(unit_or_zero(Vec3::new(f32::INFINITY, 0.0, 0.0)), Vec3::ZERO);
        assert_eq!(unit_or_zero(Vec3::new(f32::NAN, 1.0, 0.0)), Vec3::ZERO);
    }

    #[test]
    fn triangles_of_any_size_have_their_normal() {
        for s in [1e-25f32, 1e-15, 1.0, 1e10, 1e18, 1e30] {
            let n = triangle_normal(Vec3::ZERO, Vec3::X * s, Vec3::Y * s);
            assert_eq!(n, Vec3::Z, "edges {s:e}");
            let far = Vec3::splat(1e18);
            let n = triangle_normal(far, far + Vec3::Y * 1e12, far + Vec3::X * 1e12);
            assert_eq!(n, Vec3::NEG_Z);
        }
        assert_eq!(
            triangle_normal(Vec3::ZERO, Vec3::X, Vec3::X * 2.0),
            Vec3::ZERO,
            "collinear"
        );
    }
}
