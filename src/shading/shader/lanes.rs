//! The shader on [`F32x8`] lanes: eight points of one material shaded by the very functions the
//! scalar path runs, lane by lane, giving what it gives.
//!
//! Two users. The normal-map mode fills [`SurfaceLanes`] straight from the image (no shadow
//! rays). The mesh renderer's batches — the samples of a pixel or of a 4×4 pixel block — are cut
//! into groups of one material ([`Shader::shade_batch_lanes`]); each light's shadow rays from every
//! group still go to the occluder together, as one packet, and the lanes they find blocked add
//! nothing.

use std::borrow::Borrow;

use glam::Vec3;

use super::{clamped_term, clamped_to_viewer_form, clamped_unit_form, reflected_radiance, Shader, BATCH};
use crate::accel::shadow::{Occluder, ShadowRay};
use crate::brdf::LocalDots;
use crate::lanes::{dot3, map3, F32x8, LaneInstructions, LaneMask, Mask, Mask8, Real, LANES};
use crate::light::{Light, LightKind, LightSamples};
use crate::material::Material;
use crate::shading::convention::{unit_of_length, ShadingConvention};
use crate::surface::{SurfaceLanes, SurfacePoint};

/// Most groups of one material a batch of [`BATCH`] points is cut into: two of eight, and one more
/// per change of material (a pixel on a silhouette). A batch that needs more is shaded point by
/// point.
const GROUPS: usize = 4;

/// Up to eight points of one material, normals turned to the viewer's side as
/// [`Shader::shade`] turns them.
struct FacingLanes<'m> {
    material: &'m Material,
    position: [F32x8; 3],
    /// Geometric normal (the shadow ray's offset side).
    ng: [F32x8; 3],
    /// Height above the point its shadow rays start at (`SurfacePoint::shadow_lift`), 0 where
    /// a two-sided material turned the normals round: lifting along the turned normal would
    /// move the origin through the surface (see `front_lift`).
    lift: F32x8,
    ns: [F32x8; 3],
    wo: [F32x8; 3],
    cos_o: F32x8,
    /// Lanes holding a point whose shading normal faces the viewer (cos θ_o > 0, not NaN).
    visible: Mask8,
}

/// One light at the lanes of a [`FacingLanes`]: its sample, cos θ_i, the BRDF's dot products,
/// and the lanes it reaches (in front of the shading normal, with a shading frame).
struct LitLanes {
    ls: LightSamples<F32x8>,
    cos_i: F32x8,
    dots: LocalDots<F32x8>,
    lit: Mask8,
}

impl<'m> FacingLanes<'m> {
    /// The lanes of `present` points with shadow-ray lifts `lift`: a two-sided material turns
    /// both normals towards the viewer where the shading normal faces away from it, and drops
    /// the lift there.
    #[inline(always)]
    fn new(material: &'m Material, points: &SurfaceLanes, ng: [F32x8; 3], lift: F32x8, present: Mask8) -> Self {
        let wo = points.to_viewer;
        let (mut ns, mut ng, mut lift) = (points.shading_normal, ng, lift);
        if material.two_sided {
            let flip = dot3(ns, wo).lt(F32x8::splat(0.0));
            ns = map3(ns, |c| F32x8::select(flip, -c, c));
            ng = map3(ng, |c| F32x8::select(flip, -c, c));
            lift = F32x8::select(flip, F32x8::splat(0.0), lift);
        }
        let cos_o = dot3(ns, wo);
        FacingLanes {
            material,
            position: points.position,
            ng,
            lift,
            ns,
            wo,
            cos_o,
            visible: present & cos_o.gt(F32x8::splat(0.0)),
        }
    }

    /// `light` at these points (the scalar shader's `lit`, lane by lane).
    #[inline(always)]
    fn lit(&self, light: &Light) -> LitLanes {
        let ls = light.sample_points(self.position);
        let cos_i = dot3(self.ns, ls.wi);
        let mut lit = self.visible & ls.lit & cos_i.gt(F32x8::splat(0.0));
        let dots = if self.material.has_specular() {
            let (dots, frame) = LocalDots::from_unit_vectors_masked(self.ns, ls.wi, self.wo);
            lit = lit & frame;
            dots
        } else {
            // Lambert reads no dot product: skip the half vector.
            LocalDots::from_cosines(cos_i, self.cos_o, F32x8::splat(0.0), F32x8::splat(0.0))
        };
        LitLanes { ls, cos_i, dots, lit }
    }

    /// Adds f_r · E · cos θ_i of the lanes `lit` reaches to `radiance`.
    #[inline(always)]
    fn add_reflected(&self, lit: &LitLanes, radiance: &mut [F32x8; 3]) {
        if !lit.lit.any() {
            return;
        }
        let term = reflected_radiance(self.material.eval(&lit.dots), lit.ls.irradiance, lit.cos_i);
        for c in 0..3 {
            radiance[c] = radiance[c] + F32x8::select(lit.lit, term[c], F32x8::splat(0.0));
        }
    }
}

/// Lane `i` of three lanes, as a vector.
#[inline(always)]
fn lane(v: &[F32x8; 3], i: usize) -> Vec3 {
    Vec3::new(v[0].0[i], v[1].0[i], v[2].0[i])
}

impl<O: Occluder> Shader<'_, O> {
    /// Whether [`Shader::shade_lanes`] serves this shader: always under the clamped
    /// convention; under the physical one when there is nothing the lanes do not carry — no
    /// shadow rays, no textures, no emission (the normal-map mode).
    pub fn has_lanes(&self) -> bool {
        match self.convention {
            ShadingConvention::Clamped => true,
            ShadingConvention::Physical => self.occluder.is_none() && self.textures.is_none() && !self.emission,
        }
    }

    /// [`Shader::shade`] of eight points of one material on [`F32x8`] lanes, per channel, under
    /// either convention — the same functions in eight lanes, giving what the scalar path gives.
    /// Only for a shader that [`Shader::has_lanes`].
    #[inline(always)]
    pub fn shade_lanes(&self, points: &SurfaceLanes) -> [F32x8; 3] {
        debug_assert!(self.has_lanes());
        match self.convention {
            ShadingConvention::Clamped => self.shade_clamped_lanes(points),
            ShadingConvention::Physical => self.physical_lanes(points),
        }
    }

    /// The physical convention of [`Shader::shade`] without shadow rays, textures or emission,
    /// on lanes: a two-sided material turns the normal towards the viewer, and a light adds
    /// f·E·cos θ_i where n·ω_o > 0, n·ω_i > 0 and a shading frame exists (elsewhere the lane
    /// adds 0, which the scalar path skips).
    #[inline(always)]
    fn physical_lanes(&self, points: &SurfaceLanes) -> [F32x8; 3] {
        let material = &self.materials[points.material as usize];
        // No shadow rays here: the geometric normal and the lift are not read.
        let facing = FacingLanes::new(
            material,
            points,
            points.shading_normal,
            F32x8::splat(0.0),
            Mask8::splat(true),
        );
        let mut radiance = [F32x8::splat(0.0); 3];
        if !facing.visible.any() {
            return radiance;
        }
        for light in self.lights {
            facing.add_reflected(&facing.lit(light), &mut radiance);
        }
        map3(radiance, |c| c.at_most(F32x8::splat(f32::MAX)))
    }

    /// The clamped convention's L_o (see [`ShadingConvention::Clamped`]) of points of one
    /// material in the lanes of `R`, per channel, in any precision: eight in [`F32x8`], four `tp`
    /// pixels in float64 lanes (the preset computes as numpy does), one point in a scalar. The
    /// result ignores sides. Only for a shader whose convention is the clamped one.
    #[inline(always)]
    pub fn shade_clamped_lanes<R: Real>(&self, points: &SurfaceLanes<R>) -> [R; 3] {
        debug_assert_eq!(self.convention, ShadingConvention::Clamped);
        let material = &self.materials[points.material as usize];
        let x = points.position;
        let (form, half_vector) = (clamped_unit_form(material), clamped_to_viewer_form(material));
        let mut radiance = [R::zero(); 3];
        for light in self.lights {
            // Where the light sends nothing (a light at the point), its irradiance is 0 and its
            // direction the zero vector: the term is 0 and finite.
            // ω_i = (x − x_s)/‖x − x_s‖ in the material's `clamped_unit_form`; a directional
            // light's direction of travel. A point light's sample needs the same length, so it
            // is taken once.
            let (ls, wi_from_light) = match light.position() {
                Some(x_s) => {
                    let x_s = map3(x_s.to_array(), R::of);
                    let from_light = [x[0] - x_s[0], x[1] - x_s[1], x[2] - x_s[2]];
                    let distance = dot3(from_light, from_light).sqrt();
                    let ls = match light.kind {
                        LightKind::Point { .. } => light.sample_point_light_from(from_light, distance),
                        _ => light.sample_points(x),
                    };
                    (ls, unit_of_length(from_light, distance, form).0)
                }
                None => {
                    let ls = light.sample_points(x);
                    (ls, map3(ls.wi, |c| -c))
                }
            };
            let term = clamped_term(
                material,
                half_vector,
                points.shading_normal,
                wi_from_light,
                points.to_viewer,
                ls.irradiance,
            );
            for c in 0..3 {
                radiance[c] = radiance[c] + term[c];
            }
        }
        map3(radiance, |c| c.at_most(R::lit(f32::MAX as f64)))
    }

    /// [`Shader::shade`] of a batch of at most [`BATCH`] points under the physical convention,
    /// on lanes, into `out`: the points are ordered by material and cut into groups of at most
    /// eight of one material; for each light, every group's shadow rays go to the occluder in
    /// one call (one packet for the BVH), then each group adds the light where it was not
    /// blocked. The same values as `shade` (the lanes run its functions), the same shadow rays.
    ///
    /// Returns false, having written nothing, where the lanes do not carry what the points
    /// need — emission, a material whose BRDF varies with textures — or the batch mixes more
    /// materials than [`GROUPS`] groups hold; the caller then shades it point by point.
    ///
    /// Compiled for AVX2 as well, picked at run time ([`LaneInstructions::detect`], a cached
    /// flag): one 256-bit instruction per lane operation instead of two. No FMA, so both give
    /// the same bits.
    pub(super) fn shade_batch_lanes<P: Borrow<SurfacePoint>>(
        &self,
        points: &[P],
        out: &mut [Vec3],
        shadow_rays: &mut u64,
    ) -> bool {
        match LaneInstructions::detect() {
            LaneInstructions::Portable => self.batch_lanes(points, out, shadow_rays),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `detect` found AVX2 on this CPU.
            LaneInstructions::Avx2 | LaneInstructions::Avx512 => unsafe {
                self.batch_lanes_avx2(points, out, shadow_rays)
            },
        }
    }

    /// [`Self::batch_lanes`] compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn batch_lanes_avx2<P: Borrow<SurfacePoint>>(&self, points: &[P], out: &mut [Vec3], shadow_rays: &mut u64) -> bool {
        self.batch_lanes(points, out, shadow_rays)
    }

    /// [`Self::shade_batch_lanes`] for the instructions the caller compiles it with.
    #[inline(always)]
    pub(super) fn batch_lanes<P: Borrow<SurfacePoint>>(
        &self,
        points: &[P],
        out: &mut [Vec3],
        shadow_rays: &mut u64,
    ) -> bool {
        let n = points.len();
        debug_assert!(n <= BATCH && out.len() == n && self.convention == ShadingConvention::Physical);
        if self.emission {
            return false;
        }
        let point = |i: u8| points[i as usize].borrow();
        // The points by material (a stable sort: ties keep the batch order), cut into groups.
        let mut order = [0u8; BATCH];
        for (i, o) in order.iter_mut().enumerate() {
            *o = i as u8;
        }
        order[..n].sort_by_key(|&i| point(i).material);
        let mut ranges = [(0, 0); GROUPS];
        let (mut groups, mut start) = (0, 0);
        while start < n {
            let material = point(order[start]).material;
            let run = order[start..n]
                .iter()
                .take(LANES)
                .take_while(|&&i| point(i).material == material)
                .count();
            if groups == GROUPS || self.textured_brdf(&self.materials[material as usize]) {
                return false;
            }
            ranges[groups] = (start, start + run);
            (groups, start) = (groups + 1, start + run);
        }
        let ranges = &ranges[..groups];
        // Lanes past a group's points repeat its last point and are masked out. (Loops, not
        // `array::from_fn`, which the compiler left as calls copying the groups around.)
        let mut facing: [Option<FacingLanes>; GROUPS] = [const { None }; GROUPS];
        for (&(start, end), facing) in ranges.iter().zip(&mut facing) {
            // Each lane's point as a row of its four vectors and its lift, then the rows as lanes.
            let mut rows = [[0.0f32; 13]; LANES];
            for (i, row) in rows.iter_mut().enumerate() {
                let p = point(order[(start + i).min(end - 1)]);
                let vectors = [p.position, p.shading_normal, p.to_viewer, p.geometric_normal];
                for (v, chunk) in vectors.iter().zip(row.chunks_exact_mut(3)) {
                    chunk.copy_from_slice(&v.to_array());
                }
                row[12] = p.shadow_lift;
            }
            let lanes = |v: usize| map3([0, 1, 2], |c| F32x8::from_fn(|i| rows[i][3 * v + c]));
            let material = point(order[start]).material;
            let surface = SurfaceLanes {
                position: lanes(0),
                shading_normal: lanes(1),
                to_viewer: lanes(2),
                material,
            };
            let present = LaneMask::from_fn(|i| start + i < end);
            *facing = Some(FacingLanes::new(
                &self.materials[material as usize],
                &surface,
                lanes(3),
                F32x8::from_fn(|i| rows[i][12]),
                present,
            ));
        }
        let mut radiance = [[F32x8::splat(0.0); 3]; GROUPS];
        for light in self.lights {
            let mut lit: [Option<LitLanes>; GROUPS] = [const { None }; GROUPS];
            for (lit, facing) in lit.iter_mut().zip(&facing) {
                *lit = facing.as_ref().map(|f| f.lit(light));
            }
            if let Some(occluder) = self.occluder {
                self.block(occluder, &facing, &mut lit, shadow_rays);
            }
            for ((facing, lit), radiance) in facing.iter().zip(&lit).zip(&mut radiance) {
                if let (Some(facing), Some(lit)) = (facing, lit) {
                    facing.add_reflected(lit, radiance);
                }
            }
        }
        for (&(start, end), radiance) in ranges.iter().zip(&radiance) {
            for (i, &k) in order[start..end].iter().enumerate() {
                out[k as usize] = lane(radiance, i).min(Vec3::splat(f32::MAX));
            }
        }
        true
    }

    /// Traces the shadow rays of every lit lane of every group in one call to `occluder`, and
    /// clears the lanes found blocked.
    #[inline(always)]
    fn block(
        &self,
        occluder: &O,
        facing: &[Option<FacingLanes>; GROUPS],
        lit: &mut [Option<LitLanes>; GROUPS],
        shadow_rays: &mut u64,
    ) {
        // Only rays[..n] are read; the rest are placeholders. A batch has at most BATCH points.
        let mut rays = [ShadowRay {
            origin: Vec3::ZERO,
            direction: Vec3::Z,
            t_max: 0.0,
        }; BATCH];
        let mut from = [(0, 0); BATCH];
        let mut n = 0;
        for (g, (facing, lit)) in facing.iter().zip(&*lit).enumerate() {
            let (Some(facing), Some(lit)) = (facing, lit) else {
                continue;
            };
            for i in (0..LANES).filter(|&i| lit.lit.test(i)) {
                let (wi, distance) = (lane(&lit.ls.wi, i), lit.ls.distance.0[i]);
                let (p, ng, lift) = (lane(&facing.position, i), lane(&facing.ng, i), facing.lift.0[i]);
                rays[n] = ShadowRay::new(self.shadow_offset, p, lift, ng, wi, distance, &self.extent);
                from[n] = (g, i);
                n += 1;
            }
        }
        let mut blocked = [false; BATCH];
        occluder.occluded_batch(&rays[..n], &mut blocked[..n]);
        *shadow_rays += n as u64;
        for (&(g, i), _) in from[..n].iter().zip(blocked).filter(|(_, blocked)| *blocked) {
            if let Some(lit) = &mut lit[g] {
                lit.lit.0[i] = 0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::lane;
    use crate::surface::SurfaceLanes;
    use glam::Vec3;

    use super::super::tests::{
        assert_shaded_as_one_by_one, batch_materials, lights, materials, physical, points, HalfOccluder,
    };
    use super::super::{Shader, BATCH};
    use crate::accel::shadow::{NoOcclusion, SceneExtent};
    use crate::lanes::{map3, F32x8, LANES};
    use crate::material::Material;
    use crate::shading::convention::ShadingConvention;
    use crate::surface::SurfacePoint;
    use crate::texture::TextureRef;

    /// `points` (of one material) in lanes.
    fn surface_lanes(points: &[SurfacePoint; LANES]) -> SurfaceLanes {
        assert!(points.iter().all(|p| p.material == points[0].material), "one material");
        let lanes = |v: fn(&SurfacePoint) -> Vec3| map3([0, 1, 2], |c| F32x8::from_fn(|i| v(&points[i])[c]));
        SurfaceLanes {
            position: lanes(|p| p.position),
            shading_normal: lanes(|p| p.shading_normal),
            to_viewer: lanes(|p| p.to_viewer),
            material: points[0].material,
        }
    }

    #[test]
    fn eight_lanes_shade_exactly_as_one_point_at_a_time() {
        let lights = lights();
        let points = points();
        let conventions = [ShadingConvention::Clamped, ShadingConvention::Physical];
        let sided = materials().into_iter().flat_map(|m| {
            let mut other = m.clone();
            other.two_sided = !m.two_sided;
            [m, other]
        });
        for (material, convention) in sided.flat_map(|m| conventions.map(|c| (m.clone(), c))) {
            let shader = Shader::<NoOcclusion> {
                materials: std::slice::from_ref(&material),
                lights: &lights,
                occluder: None,
                extent: SceneExtent::UNIT,
                convention,
                textures: None,
                emission: false,
                shadow_offset: Default::default(),
            };
            assert!(shader.has_lanes());
            for start in 0..points.len() - LANES {
                let group: [SurfacePoint; LANES] = std::array::from_fn(|i| points[start + i]);
                let surface = surface_lanes(&group);
                let radiance = shader.shade_lanes(&surface);
                for (i, p) in group.iter().enumerate() {
                    let lane = lane(&radiance, i);
                    let one = shader.shade(p, &mut 0);
                    // Equal as numbers (the sign of a zero may differ) and never NaN.
                    assert!(
                        lane == one && lane.is_finite(),
                        "{} {convention:?} two-sided {}: {lane} vs {one} at {p:?}",
                        material.name,
                        material.two_sided
                    );
                }
            }
        }
    }

    #[test]
    fn batches_go_on_lanes_where_they_can_and_point_by_point_where_not() {
        let (lights, materials) = (lights(), batch_materials());
        let occluder = HalfOccluder(Default::default());
        let batch = |materials: u32| -> Vec<SurfacePoint> {
            let points = points();
            (0..BATCH)
                .map(|i| SurfacePoint {
                    material: i as u32 % materials,
                    ..points[i]
                })
                .collect()
        };
        let shader = physical(&materials, &lights, &occluder);
        // Up to four groups of one material: lanes, both compilations (`shade_batch_lanes`
        // picks AVX2 where the CPU has it; `batch_lanes` is the portable code).
        for m in [1, 3, 4] {
            let (mut got, mut portable) = (vec![Vec3::NAN; BATCH], vec![Vec3::NAN; BATCH]);
            assert!(shader.shade_batch_lanes(&batch(m), &mut got, &mut 0), "{m} materials");
            assert!(shader.batch_lanes(&batch(m), &mut portable, &mut 0));
            assert_shaded_as_one_by_one(&shader, &batch(m), &got);
            assert_shaded_as_one_by_one(&shader, &batch(m), &portable);
        }
        // Without shadows (the plan left them out): lanes too, the same values.
        let unshadowed = Shader {
            occluder: None,
            ..physical(&materials, &lights, &occluder)
        };
        occluder.0.store(0, std::sync::atomic::Ordering::Relaxed);
        for m in [1, 4] {
            let mut got = vec![Vec3::NAN; BATCH];
            unshadowed.shade_batch(&batch(m), &mut got, &mut 0);
            assert_shaded_as_one_by_one(&unshadowed, &batch(m), &got);
        }
        assert_eq!(
            occluder.0.load(std::sync::atomic::Ordering::Relaxed),
            0,
            "no shadow ray traced"
        );
        // Five groups, emission, or BRDF textures: refused, nothing written.
        let untouched = |shader: &Shader<HalfOccluder>, batch: &[SurfacePoint]| {
            let mut out = vec![Vec3::NAN; batch.len()];
            !shader.shade_batch_lanes(batch, &mut out, &mut 0) && out.iter().all(|v| v.is_nan())
        };
        assert!(untouched(&shader, &batch(5)), "five materials");
        assert!(untouched(
            &Shader {
                emission: true,
                ..physical(&materials, &lights, &occluder)
            },
            &batch(1)
        ));
        let mut pbr = Material::gltf_pbr("textured", [0.8, 0.5, 0.2], 0.6, 0.4);
        pbr.textures.base_color = Some(TextureRef::gltf_default(0));
        let pbr = [pbr];
        let textured = Shader {
            textures: Some(&[]),
            ..physical(&pbr, &lights, &occluder)
        };
        assert!(
            untouched(&textured, &batch(1)),
            "a material whose BRDF varies with a texture"
        );
    }
}
