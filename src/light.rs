//! Punctual lights: point, directional and spot.
//!
//! A light seen from a surface point gives a direction towards it, a distance (for shadow rays)
//! and the irradiance it delivers on a surface facing it, E. The shader adds f·E·cos θ_i.
//! - point: E = I/d² with I = color × intensity in W/sr (Mitsuba's `point`);
//! - directional: E = color × intensity, `direction` is where the light travels (Mitsuba's
//!   `directional`);
//! - spot: a point light times a cone profile ([`SpotProfile`]): KHR_lights_punctual's
//!   `saturate(cos θ·s + o)²`, s = 1/max(0.001, cos θ_inner − cos θ_outer), o = −cos θ_outer·s,
//!   or Mitsuba 3's `spot`, linear in the angle from the inner cone to the outer one.
//!
//! `Falloff::None` drops the 1/d² (L_i = color × intensity at any distance, as the normal-map
//! `tp` preset's lights are);
//! `Falloff::InverseSquareWithin` is KHR_lights_punctual's range window.

use glam::Vec3;

#[cfg(doc)]
use crate::lanes::F32x8;
use crate::lanes::{dot3 as dot, map3, normalize_or_zero, Mask, Real};

/// How a positional light's irradiance falls with distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Falloff {
    /// Physical: E = I/d².
    InverseSquare,
    /// None: E = I at any distance.
    None,
    /// KHR_lights_punctual's `range`: E = I·clamp(1 − (d/range)⁴, 0, 1)/d², the inverse square
    /// smoothly windowed to reach 0 at d = range (`range` > 0, finite).
    InverseSquareWithin { range: f32 },
}

/// Where a light is and how it emits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Isotropic point light.
    Point { position: Vec3 },
    /// Light from infinitely far away travelling along `direction` (unit).
    Directional { direction: Vec3 },
    /// Point light restricted to a cone around `direction` (unit, where it points).
    Spot {
        position: Vec3,
        direction: Vec3,
        cos_inner: f32,
        cos_outer: f32,
        profile: SpotProfile,
    },
}

/// How a spot light's intensity falls from its inner cone (θ_inner, full intensity) to its
/// outer one (θ_outer, none), θ the angle between its direction and the point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpotProfile {
    /// KHR_lights_punctual's: saturate((cos θ − cos θ_outer)/(cos θ_inner − cos θ_outer))²,
    /// smooth in cos θ (glTF 2.0 KHR_lights_punctual, "Inner and Outer Cone Angles").
    #[default]
    Gltf,
    /// Mitsuba 3's `spot` emitter: 1 within the inner cone (its `beam_width`), then
    /// (θ_outer − θ)/(θ_outer − θ_inner), linear in the angle, to 0 at the outer cone (its
    /// `cutoff_angle`) and beyond (Mitsuba 3 documentation, "Spot light source").
    Mitsuba,
}

/// A light source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Geometry and emission pattern.
    pub kind: LightKind,
    /// color × intensity: radiant intensity (W/sr) for point and spot, irradiance for directional.
    pub power: Vec3,
    /// Distance falloff of positional lights.
    pub falloff: Falloff,
}

/// A light as seen from a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point towards the light.
    pub wi: Vec3,
    /// Distance to the light (infinity for directional lights).
    pub distance: f32,
    /// Irradiance on a surface facing the light.
    pub irradiance: Vec3,
}

/// [`LightSample`]s of several points at once, in any [`Real`] (one f32 or [`F32x8`] lanes).
#[derive(Clone, Copy, Debug)]
pub struct LightSamples<R: Real> {
    /// Unit direction towards the light.
    pub wi: [R; 3],
    /// Distance to the light.
    pub distance: R,
    /// Irradiance on a surface facing the light.
    pub irradiance: [R; 3],
    /// Where the light sends something; elsewhere the other fields are 0 (directions and
    /// irradiance) and must not be used.
    pub lit: R::Mask,
}

impl Light {
    /// Checks a light made in code as a scene file's are checked when read: power finite and
    /// ≥ 0, a finite position, a unit direction, ordered spot cones (cos θ_inner > cos θ_outer
    /// ≥ 0), a finite range > 0. Positions beyond what the scene's f32 coordinates resolve are
    /// the scene's business (`scene::extent::check_lights`).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.power.is_finite() && self.power.min_element() >= 0.0) {
            return Err(format!(
                "power (color × intensity) must be finite and ≥ 0, got {}",
                self.power
            ));
        }
        let unit = |d: Vec3| {
            if d.is_finite() && (d.length() - 1.0).abs() <= 1e-4 {
                Ok(())
            } else {
                Err(format!("direction must be a unit vector, got {d}"))
            }
        };
        let finite = |p: Vec3| {
            if p.is_finite() {
                Ok(())
            } else {
                Err(format!("position must be finite, got {p}"))
            }
        };
        match self.kind {
            LightKind::Point { position } => finite(position)?,
            LightKind::Directional { direction } => unit(direction)?,
            LightKind::Spot {
                position,
                direction,
                cos_inner,
                cos_outer,
                ..
            } => {
                finite(position)?;
                unit(direction)?;
                if !(cos_outer >= 0.0 && cos_outer < cos_inner && cos_inner <= 1.0) {
                    return Err(format!(
                        "spot cones must satisfy 1 ≥ cos(inner) > cos(outer) ≥ 0, got {cos_inner} and {cos_outer}"
                    ));
                }
            }
        }
        if let Falloff::InverseSquareWithin { range } = self.falloff {
            if !(range > 0.0 && range.is_finite()) {
                return Err(format!("range must be finite and > 0, got {range}"));
            }
        }
        Ok(())
    }

    /// Where a point or spot light is; `None` for a directional light.
    pub fn position(&self) -> Option<Vec3> {
        match self.kind {
            LightKind::Point { position } | LightKind::Spot { position, .. } => Some(position),
            LightKind::Directional { .. } => None,
        }
    }

    /// The light seen from `p`, or `None` when it sends nothing there: outside a spot's cone, or
    /// at the light's own position (d = 0, where the direction is undefined; such a point is
    /// documented to receive no light rather than an infinite amount).
    #[inline(always)]
    pub fn sample(&self, p: Vec3) -> Option<LightSample> {
        let s = self.sample_points::<f32>(p.to_array());
        s.lit.then(|| LightSample {
            wi: Vec3::from(s.wi),
            distance: s.distance,
            irradiance: Vec3::from(s.irradiance),
        })
    }

    /// [`Light::sample`] at the points `p`, in any [`Real`]: the one implementation of every
    /// light, used by the scalar shader (f32) and by the eight-lane one ([`F32x8`]).
    #[inline(always)]
    pub fn sample_points<R: Real>(&self, p: [R; 3]) -> LightSamples<R> {
        let lane = |v: Vec3| map3(v.to_array(), R::of);
        match self.kind {
            LightKind::Directional { direction } => LightSamples {
                wi: lane(-direction),
                distance: R::of(f32::INFINITY),
                irradiance: lane(self.power),
                lit: R::Mask::splat(true),
            },
            LightKind::Point { position } => self.positional(p, lane(position), R::one()),
            LightKind::Spot {
                position,
                direction,
                cos_inner,
                cos_outer,
                profile,
            } => {
                let position = lane(position);
                let v = [p[0] - position[0], p[1] - position[1], p[2] - position[2]];
                let to_point = normalize_or_zero(v);
                let cos = dot(to_point, lane(direction));
                let factor = match profile {
                    SpotProfile::Gltf => {
                        let scale = R::of(1.0 / (cos_inner - cos_outer).max(0.001));
                        let cone = (cos * scale - R::of(cos_outer) * scale).clamped(R::zero(), R::one());
                        cone * cone
                    }
                    SpotProfile::Mitsuba => mitsuba_cone(cos, cos_inner, cos_outer),
                };
                let mut s = self.positional(p, position, factor);
                s.lit = s.lit & factor.gt(R::zero());
                s
            }
        }
    }

    /// [`Light::sample_points`] of a point light whose offset from the points is known:
    /// `from_light` = p − x_s and `distance` = √(`from_light` · `from_light`), summed in that
    /// order — the length a caller that also divides `from_light` by it has taken, so that the
    /// root is taken once. The same irradiance, distance and lit lanes as `sample_points`
    /// (x_s − p is −(p − x_s) exactly, and their dot products are equal). Only for a point light.
    #[inline(always)]
    pub fn sample_point_light_from<R: Real>(&self, from_light: [R; 3], distance: R) -> LightSamples<R> {
        debug_assert!(matches!(self.kind, LightKind::Point { .. }));
        self.positional_at(map3(from_light, |c| -c), distance, R::one())
    }

    #[inline(always)]
    fn positional<R: Real>(&self, p: [R; 3], position: [R; 3], factor: R) -> LightSamples<R> {
        let offset = [position[0] - p[0], position[1] - p[1], position[2] - p[2]];
        self.positional_at(offset, dot(offset, offset).sqrt(), factor)
    }

    /// A positional light's samples given `offset` = x_s − p and its length `distance`.
    #[inline(always)]
    fn positional_at<R: Real>(&self, offset: [R; 3], distance: R, factor: R) -> LightSamples<R> {
        // d = 0: no direction; d underflowing in d² would give an infinite irradiance.
        let d2 = distance * distance;
        let mut lit = d2.gt(R::zero()) & d2.is_finite();
        let safe_d2 = R::select(lit, d2, R::one());
        let falloff = match self.falloff {
            Falloff::InverseSquare => R::one() / safe_d2,
            Falloff::None => R::one(),
            Falloff::InverseSquareWithin { range } => {
                let r = distance / R::of(range);
                let r2 = r * r;
                let window = (R::one() - r2 * r2).clamped(R::zero(), R::one());
                lit = lit & window.gt(R::zero());
                window / safe_d2
            }
        };
        // Saturate instead of overflowing: huge intensities at tiny distances stay finite, so no
        // inf·0 = NaN can arise downstream.
        let max = R::of(f32::MAX);
        let scale = factor * falloff.at_most(max);
        let irradiance = map3(self.power.to_array(), |c| {
            R::select(lit, (R::of(c) * scale).at_most(max), R::zero())
        });
        let inv_distance = R::select(lit, distance, R::one()).recip();
        LightSamples {
            wi: map3(offset, |c| R::select(lit, c * inv_distance, R::zero())),
            distance,
            irradiance,
            lit,
        }
    }
}

/// The spot profile of Mitsuba 3 at cos θ = `cos`: 1 where cos θ ≥ cos θ_inner, 0 where
/// cos θ ≤ cos θ_outer, else (θ_outer − θ)/(θ_outer − θ_inner). Lights are loaded with ordered
/// cones (θ_inner < θ_outer), so the quotient divides by a positive angle; cos θ is clamped to
/// [−1, 1] before its arccos, against rounding.
#[inline(always)]
fn mitsuba_cone<R: Real>(cos: R, cos_inner: f32, cos_outer: f32) -> R {
    let (inner, outer) = (cos_inner.acos(), cos_outer.acos());
    let theta = cos.clamped(-R::one(), R::one()).acos();
    let ramp = (R::of(outer) - theta) / R::of((outer - inner).max(f32::MIN_POSITIVE));
    let inside = R::select(cos.ge(R::of(cos_inner)), R::one(), ramp.clamped(R::zero(), R::one()));
    R::select(cos.gt(R::of(cos_outer)), inside, R::zero())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(falloff: Falloff) -> Light {
        Light {
            kind: LightKind::Point {
                position: Vec3::new(0.0, 2.0, 0.0),
            },
            power: Vec3::splat(8.0),
            falloff,
        }
    }

    #[test]
    fn point_light_irradiance_falls_with_the_inverse_square() {
        let s = point(Falloff::InverseSquare).sample(Vec3::ZERO).unwrap();
        assert_eq!(s.wi, Vec3::Y);
        assert_eq!(s.distance, 2.0);
        assert_eq!(s.irradiance, Vec3::splat(2.0)); // 8 / 2²
        let none = point(Falloff::None).sample(Vec3::ZERO).unwrap();
        assert_eq!(none.irradiance, Vec3::splat(8.0));
    }

    #[test]
    fn range_window_follows_khr_lights_punctual() {
        let mut l = point(Falloff::InverseSquareWithin { range: 4.0 });
        // d = 2: window 1 − (2/4)⁴ = 15/16, E = 8·(15/16)/4.
        let e = l.sample(Vec3::ZERO).unwrap().irradiance.x;
        assert!((e - 8.0 * 15.0 / 16.0 / 4.0).abs() < 1e-6, "{e}");
        // At and beyond the range: nothing.
        l.falloff = Falloff::InverseSquareWithin { range: 2.0 };
        assert!(l.sample(Vec3::ZERO).is_none());
        assert!(l.sample(Vec3::new(0.0, -5.0, 0.0)).is_none());
    }

    #[test]
    fn a_point_light_sampled_from_a_known_offset_is_sampled_as_from_the_point() {
        // float64, as the tp rows use it; the light at the point and at an underflowing distance
        // included, where it sends nothing.
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 800.0 - 100.0
        };
        for falloff in [
            Falloff::None,
            Falloff::InverseSquare,
            Falloff::InverseSquareWithin { range: 300.0 },
        ] {
            let light = point(falloff);
            let x_s = [0.0, 2.0, 0.0];
            let mut points: Vec<[f64; 3]> = (0..2000).map(|_| [next(), next(), next()]).collect();
            points.extend([x_s, [1e-170, 2.0, 0.0]]);
            for p in points {
                let from_light = [p[0] - x_s[0], p[1] - x_s[1], p[2] - x_s[2]];
                let distance = dot(from_light, from_light).sqrt();
                let (a, b) = (
                    light.sample_points(p),
                    light.sample_point_light_from(from_light, distance),
                );
                assert_eq!(a.distance.to_bits(), b.distance.to_bits(), "{p:?}");
                assert_eq!(a.irradiance.map(f64::to_bits), b.irradiance.map(f64::to_bits), "{p:?}");
                assert_eq!(a.lit, b.lit, "{p:?}");
            }
        }
    }

    #[test]
    fn light_at_the_shaded_point_sends_nothing() {
        assert!(point(Falloff::InverseSquare).sample(Vec3::new(0.0, 2.0, 0.0)).is_none());
    }

    #[test]
    fn huge_intensity_at_a_tiny_distance_saturates_instead_of_overflowing() {
        let mut l = point(Falloff::InverseSquare);
        l.power = Vec3::splat(1e30);
        let s = l.sample(Vec3::new(0.0, 2.0 - 1e-6, 0.0)).unwrap();
        assert!(s.irradiance.is_finite() && s.irradiance.x > 1e30);
    }

    #[test]
    fn directional_light_comes_from_against_its_direction() {
        let l = Light {
            kind: LightKind::Directional { direction: Vec3::NEG_Y },
            power: Vec3::ONE,
            falloff: Falloff::InverseSquare,
        };
        let s = l.sample(Vec3::new(5.0, -3.0, 1.0)).unwrap();
        assert_eq!((s.wi, s.irradiance), (Vec3::Y, Vec3::ONE));
        assert!(s.distance.is_infinite());
    }

    /// A unit spot at the origin facing −y, its inner cone 10° and its outer 20° wide.
    fn spot_between_10_and_20_degrees(profile: SpotProfile) -> Light {
        Light {
            kind: LightKind::Spot {
                position: Vec3::ZERO,
                direction: Vec3::NEG_Y,
                cos_inner: 10f32.to_radians().cos(),
                cos_outer: 20f32.to_radians().cos(),
                profile,
            },
            power: Vec3::ONE,
            falloff: Falloff::None,
        }
    }

    /// The irradiance of `light` at the point one unit below it and `deg` degrees off its axis.
    fn irradiance_at_angle(light: &Light, deg: f32) -> Option<f32> {
        light
            .sample(Vec3::new(deg.to_radians().tan(), -1.0, 0.0))
            .map(|s| s.irradiance.x)
    }

    #[test]
    fn spot_cone_is_full_inside_inner_zero_outside_outer_and_quadratic_between() {
        let (inner, outer) = (10f32.to_radians(), 20f32.to_radians());
        let l = spot_between_10_and_20_degrees(SpotProfile::Gltf);
        let at = |deg: f32| irradiance_at_angle(&l, deg);
        assert_eq!(at(5.0), Some(1.0));
        assert_eq!(at(25.0), None);
        let mid = 15f32.to_radians().cos();
        let expected = ((mid - outer.cos()) / (inner.cos() - outer.cos())).powi(2);
        assert!((at(15.0).unwrap() - expected).abs() < 1e-5);
    }

    #[test]
    fn mitsuba_profile_is_linear_in_the_angle_between_the_cones() {
        let (inner, outer) = (10f32.to_radians(), 20f32.to_radians());
        let l = spot_between_10_and_20_degrees(SpotProfile::Mitsuba);
        let at = |deg: f32| irradiance_at_angle(&l, deg);
        assert_eq!(at(5.0), Some(1.0));
        assert_eq!(at(20.5), None);
        for (deg, expected) in [(12.5, 0.75), (15.0, 0.5), (17.5, 0.25)] {
            assert!((at(deg).unwrap() - expected).abs() < 1e-4, "{deg}°: {:?}", at(deg));
        }
        // Lanes and scalars agree, and rounding past ±1 gives no NaN.
        let lanes = mitsuba_cone(crate::lanes::F32x8::splat(1.0 + 1e-7), inner.cos(), outer.cos());
        assert_eq!(lanes.0, [1.0; 8]);
        assert_eq!(mitsuba_cone(-1.0f32 - 1e-7, inner.cos(), outer.cos()), 0.0);
    }
}
