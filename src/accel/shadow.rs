//! Shadow rays and the origin offset that keeps them off their own surface at any scale.
//!
//! The hit point p is reconstructed from barycentrics and is off the true surface by a few ulps of
//! its coordinates. Following Wächter & Binder ("A Fast and Robust Method for Avoiding
//! Self-Intersection", Ray Tracing Gems ch. 6), the origin moves along the geometric normal by a
//! fixed number of ulps per coordinate — a relative offset, right for p at 1e5 as at 1 — or by a
//! small absolute step where that is larger (near the origin, where ulps vanish). That absolute
//! step is measured in scene units (`scene_unit`, about the scene's size / 200) rather than fixed,
//! so it also holds for scenes measured in micrometres or kilometres.

use glam::Vec3;

use crate::scene::shadows::ShadowOffset;

/// A segment from a (offset) surface point towards a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowRay {
    /// Offset origin.
    pub origin: Vec3,
    /// Unit direction towards the light.
    pub direction: Vec3,
    /// Distance beyond which hits do not occlude (just short of the light).
    pub t_max: f32,
}

/// What shadow rays need to know of the scene's size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneExtent {
    /// Length unit of the error-bound offset (about the scene's size / 200, `Bvh::scene_unit`).
    pub unit: f32,
    /// Centre of the scene's bounding sphere (the sphere of its bounding box, as Mitsuba
    /// takes it).
    pub centre: Vec3,
    /// Radius of that sphere. With the `mitsuba` offset a directional light's shadow ray is
    /// aimed, as Mitsuba's `directional` emitter aims it, at p + ω_i·2·max(radius, |p − centre|)
    /// rather than run to infinity along ω_i: from the offset origin the two directions differ
    /// by a few ulps, enough to flip a shadow edge a ray grazes (aimed so, every pixel of the
    /// `directional` validation scene is within 1e-3 of Mitsuba's; docs/performance-log.md).
    pub radius: f32,
}

impl SceneExtent {
    /// A unit scene around the origin (tests, and shading without a BVH).
    pub const UNIT: Self = Self {
        unit: 1.0,
        centre: Vec3::ZERO,
        radius: 1.0,
    };

    /// The extent of a scene whose box is `bounds` (`None`: empty), with offset unit `unit`. The
    /// radius is Mitsuba's: |max − centre|, grown by a factor 1 + RayEpsilon and at least
    /// RayEpsilon (its `directional` emitter's `set_scene`).
    pub fn new(unit: f32, bounds: Option<(Vec3, Vec3)>) -> Self {
        let (centre, radius) = bounds.map_or((Vec3::ZERO, 0.0), |(lo, hi)| {
            let centre = (lo + hi) * 0.5;
            (centre, (hi - centre).length())
        });
        let radius = (radius * (1.0 + MITSUBA_RAY_EPSILON)).max(MITSUBA_RAY_EPSILON);
        Self { unit, centre, radius }
    }
}

/// Answers "is anything between these two points?" (the BVH, or nothing in normal-map mode).
pub trait Occluder {
    /// True if the segment is blocked.
    fn occluded(&self, ray: &ShadowRay) -> bool;

    /// `occluded[k] = self.occluded(&rays[k])` for every k, for a batch of segments that may
    /// share work (the BVH traces nearly parallel ones as packets). The answers must be exactly
    /// the per-ray ones. `occluded` has one entry per ray.
    fn occluded_batch(&self, rays: &[ShadowRay], occluded: &mut [bool]) {
        for (ray, blocked) in rays.iter().zip(occluded) {
            *blocked = self.occluded(ray);
        }
    }
}

/// Nothing ever occludes: used when shadows are off or there is no geometry.
pub struct NoOcclusion;

impl Occluder for NoOcclusion {
    #[inline]
    fn occluded(&self, _ray: &ShadowRay) -> bool {
        false
    }
}

/// Ulps each coordinate moves by (times the normal's component). p = b0·p0 + b1·p1 + b2·p2 is
/// computed in f32 straight from world-space vertices, so it is off the triangle's plane by at
/// most about 4 ulps of its coordinates (the γ₄ bound of that sum, b0 = 1 − b1 − b2 included);
/// 8 leaves a factor of two. Wächter & Binder use 256 for points that went through instance
/// transforms, but 256 ulps at 1e5 is 2 units, which moves shadow edges visibly.
const ULP_STEP: f32 = 8.0;
/// Smallest move, in scene units: covers the rounding of vertex coordinates when p itself is
/// near zero (where ulps of p vanish but the error from the vertices does not).
const FLOAT_STEP: f32 = 1.0 / 4096.0;

/// Moves `p` off its surface along `n` (unit geometric normal, pointing to the side the ray
/// leaves towards): per coordinate, the larger of `ULP_STEP`·n ulps and `FLOAT_STEP`·n scene
/// units. `scene_unit` is the length the float step is measured in.
#[inline]
pub fn offset_origin(p: Vec3, n: Vec3, scene_unit: f32) -> Vec3 {
    let mut out = p;
    for k in 0..3 {
        let ulps = (ULP_STEP * n[k]) as i32;
        let bits = p[k].to_bits() as i32;
        let by_ulps = f32::from_bits(if p[k] < 0.0 {
            bits.wrapping_sub(ulps)
        } else {
            bits.wrapping_add(ulps)
        } as u32);
        let by_length = p[k] + FLOAT_STEP * scene_unit * n[k];
        out[k] = if by_ulps.is_finite() && (by_ulps - p[k]).abs() > (by_length - p[k]).abs() {
            by_ulps
        } else {
            by_length
        };
    }
    out
}

/// Mitsuba's `math::RayEpsilon` = 2⁻²⁴·1500 (mitsuba3.md §3.5).
const MITSUBA_RAY_EPSILON: f32 = 1500.0 / 16_777_216.0;
/// Mitsuba's `math::ShadowEpsilon` = 10·RayEpsilon.
const MITSUBA_SHADOW_EPSILON: f32 = 10.0 * MITSUBA_RAY_EPSILON;

impl ShadowRay {
    /// The shadow ray from `p` (geometric normal `ng`) towards a light in direction `wi` at
    /// `distance` (infinite for directional lights), with the origin offset `offset` asks for.
    /// The error-bound offset starts `lift` above `p` along `ng` (the point's
    /// [`shadow_lift`](crate::surface::SurfacePoint::shadow_lift), 0 on flat meshes) and aims
    /// at the light from there, so the segment still ends at the light: kept parallel to `wi`,
    /// it would end a lift's height beside the light, through a ceiling the light hangs under
    /// (`tests/integration/shadow_terminator.rs`). `mitsuba` always starts at `p`. Always inlined: left to
    /// the compiler, it became a call per shadow ray once it took the lift, a cost even in
    /// renders that lift nothing.
    #[inline(always)]
    pub fn new(
        offset: ShadowOffset,
        p: Vec3,
        lift: f32,
        ng: Vec3,
        wi: Vec3,
        distance: f32,
        scene: &SceneExtent,
    ) -> Self {
        match offset {
            ShadowOffset::ErrorBound => Self::from_lifted(p, lift, ng, wi, distance, scene.unit),
            ShadowOffset::Mitsuba => Self::mitsuba(p, ng, wi, distance, scene),
        }
    }

    /// Mitsuba's `spawn_ray_to`: origin p + mag·n toward the light's side, direction re-aimed at
    /// the light from the moved origin, t_max = |target − origin|·(1 − ShadowEpsilon). A
    /// directional light's target is where Mitsuba puts it (see [`SceneExtent::radius`]).
    #[inline]
    fn mitsuba(p: Vec3, ng: Vec3, wi: Vec3, distance: f32, scene: &SceneExtent) -> Self {
        let n = if ng.dot(wi) >= 0.0 { ng } else { -ng };
        let magnitude = (1.0 + p.abs().max_element()) * MITSUBA_RAY_EPSILON;
        let origin = p + n * magnitude;
        let distance = if distance.is_finite() {
            distance
        } else {
            2.0 * scene.radius.max((p - scene.centre).length())
        };
        let to_light = p + wi * distance - origin;
        let length = to_light.length();
        // length > 0: the light is not at the shaded point (the light rejects d = 0, and a
        // directional light's target lies a scene's diameter away) and the offset is orders
        // of magnitude smaller than any distance it sends light over.
        Self {
            origin,
            direction: to_light / length,
            t_max: length * (1.0 - MITSUBA_SHADOW_EPSILON),
        }
    }

    /// The shadow ray from surface point `p` (geometric normal `ng`) towards a light in direction
    /// `wi` at `distance` (infinite for directional lights).
    #[inline]
    pub fn towards_light(p: Vec3, ng: Vec3, wi: Vec3, distance: f32, scene_unit: f32) -> Self {
        Self::from_lifted(p, 0.0, ng, wi, distance, scene_unit)
    }

    /// The error-bound ray of [`ShadowRay::new`]: from `p + lift·ng`, moved off the surface by
    /// [`offset_origin`], towards the light at `p + wi·distance` (or along `wi`, if infinite).
    #[inline(always)]
    fn from_lifted(p: Vec3, lift: f32, ng: Vec3, wi: Vec3, distance: f32, scene_unit: f32) -> Self {
        let n = if ng.dot(wi) >= 0.0 { ng } else { -ng };
        // p + 0·ng is p: no branch for flat meshes.
        let origin = offset_origin(p + lift * ng, n, scene_unit);
        if !distance.is_finite() {
            // A directional light: every parallel ray reaches it.
            return Self {
                origin,
                direction: wi,
                t_max: f32::INFINITY,
            };
        }
        // Measure from the moved origin, aim at the light itself, and stop just short of it.
        // length > 0: lights reject d = 0, and the origin moves by a small fraction of a
        // triangle (the lift) plus ulps, so it lands on the light only if the light sits
        // within that of the surface; then the ray is degenerate, t_max is 0 and nothing
        // occludes it (the direction falls back to `wi`, never NaN).
        let to_light = p + wi * distance - origin;
        let length = to_light.length();
        let direction = if length > 0.0 { to_light / length } else { wi };
        Self {
            origin,
            direction,
            t_max: length * (1.0 - 1e-5),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_requested_side_at_every_magnitude() {
        for &c in &[0.0f32, 1e-7, 0.01, 1.0, 1e5, -1e5, 3e7] {
            let p = Vec3::new(c, c, c);
            let up = offset_origin(p, Vec3::Y, 1.0);
            assert!(up.y > p.y, "at {c}: {up}");
            assert_eq!((up.x, up.z), (p.x, p.z));
            let down = offset_origin(p, Vec3::NEG_Y, 1.0);
            assert!(down.y < p.y, "at {c}: {down}");
        }
    }

    #[test]
    fn offset_is_relative_far_from_the_origin_and_scaled_near_it() {
        let far = offset_origin(Vec3::splat(1e5), Vec3::Y, 1.0).y - 1e5;
        assert!(far > 0.0 && far < 1.0, "{far}");
        let tiny = offset_origin(Vec3::ZERO, Vec3::Y, 1e-6).y;
        assert!(tiny > 0.0 && tiny < 1e-9, "{tiny}");
    }

    #[test]
    fn mitsuba_offset_is_fixed_epsilon_along_the_geometric_normal() {
        let p = Vec3::new(1e5, 0.0, 0.0);
        let r = ShadowRay::new(
            ShadowOffset::Mitsuba,
            p,
            0.0,
            Vec3::NEG_Y,
            Vec3::Y,
            10.0,
            &SceneExtent::UNIT,
        );
        // (1 + 1e5)·8.9407e-5 ≈ 8.94 units: far larger than an ulp, as in Mitsuba.
        assert!((r.origin.y - 8.9407).abs() < 1e-3, "{}", r.origin);
        assert!((r.t_max - (10.0 - 8.9407) * (1.0 - 8.9407e-4)).abs() < 1e-3);
    }

    #[test]
    fn shadow_ray_leaves_on_the_light_side_and_stops_before_the_light() {
        let r = ShadowRay::towards_light(Vec3::ZERO, Vec3::NEG_Y, Vec3::Y, 2.0, 1.0);
        assert!(r.origin.y > 0.0);
        assert!(r.t_max < 2.0 && r.t_max > 1.99);
    }
}
