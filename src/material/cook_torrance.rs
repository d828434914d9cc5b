//! The Cook-Torrance microfacet lobe: its parameters and f_s = D·F·G / (4 (n·ω_i)(n·ω_o)).

use crate::brdf::{
    fresnel_conductor_rgb, fresnel_schlick, fresnel_schlick_sg, schlick_f0_dielectric, FresnelTerm, LocalDots,
    MaskingShadowing, MicrofacetDistribution,
};
use crate::lanes::{map3, Mask, Real};

/// Cook-Torrance microfacet lobe: f_s = D·F·G / (4 (n·ω_i)(n·ω_o)), terms chosen by name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CookTorrance {
    /// Roughness α, used directly (no roughness² remapping).
    pub alpha: f32,
    /// Normal distribution D.
    pub d: MicrofacetDistribution,
    /// Masking-shadowing G.
    pub g: MaskingShadowing,
    /// Fresnel F.
    pub f: FresnelTerm,
    /// Conductor: Schlick's F0 is the specular colour; dielectric: F0 from `ior`.
    pub metallic: bool,
    /// F0 of metals (Schlick), tint of the conductor Fresnel, and F of `constant`.
    pub specular_color: [f32; 3],
    /// Index of refraction of a dielectric (Schlick's F0 when not metallic).
    pub ior: f32,
    /// Real part of the complex index, per channel (conductor Fresnel).
    pub eta: [f32; 3],
    /// Imaginary part (extinction) of the complex index, per channel (conductor Fresnel).
    pub k: [f32; 3],
}

impl CookTorrance {
    /// The scene files' Cook-Torrance (docs/scene-format.md, "Materials"): Mitsuba 3's
    /// `roughconductor` terms (GGX, separable Smith) at its default roughness α = 0.1, with an
    /// untinted specular colour over a dielectric of index 1.5 (Schlick's F0 = 0.04). η and κ are
    /// Mitsuba's "none" (F ≡ 1) until a scene makes the material a conductor.
    pub const DEFAULT: CookTorrance = CookTorrance {
        alpha: 0.1,
        d: MicrofacetDistribution::Ggx,
        g: MaskingShadowing::SmithGgx,
        f: FresnelTerm::Schlick,
        metallic: false,
        specular_color: [1.0; 3],
        ior: 1.5,
        eta: [0.0; 3],
        k: [1.0; 3],
    };
}

impl Default for CookTorrance {
    /// [`CookTorrance::DEFAULT`].
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl CookTorrance {
    /// Schlick's F0 per channel: the specular colour for metals, ((ior − 1)/(ior + 1))² otherwise.
    #[inline(always)]
    pub fn f0<R: Real>(&self) -> [R; 3] {
        if self.metallic {
            map3(self.specular_color, R::of)
        } else {
            [schlick_f0_dielectric(R::of(self.ior)); 3]
        }
    }

    /// F(ω_i·ω_h) per channel.
    #[inline(always)]
    pub fn fresnel<R: Real>(&self, i_dot_h: R) -> [R; 3] {
        // Each channel written out, not through a closure: a closure is inlined only when the
        // compiler deems it small, and in the float64 register lanes (`lanes::x86`) one left
        // as a call would run its lane operations as calls too.
        let f0 = self.f0::<R>();
        match self.f {
            FresnelTerm::Schlick => [
                fresnel_schlick(f0[0], i_dot_h),
                fresnel_schlick(f0[1], i_dot_h),
                fresnel_schlick(f0[2], i_dot_h),
            ],
            FresnelTerm::SchlickSg => [
                fresnel_schlick_sg(f0[0], i_dot_h),
                fresnel_schlick_sg(f0[1], i_dot_h),
                fresnel_schlick_sg(f0[2], i_dot_h),
            ],
            FresnelTerm::Conductor => {
                let f = fresnel_conductor_rgb(i_dot_h, self.eta, self.k);
                map3([0, 1, 2], |c| f[c] * R::of(self.specular_color[c]))
            }
            FresnelTerm::Constant => map3(self.specular_color, R::of),
        }
    }

    /// f_s = D·F·V with V = G/(4 (n·ω_i)(n·ω_o)) (see `MaskingShadowing::visibility`); 0 when
    /// n·ω_i ≤ 0 or n·ω_o ≤ 0, where G is 0 (a denominator guarded against 0 gives 0 there too).
    #[inline(always)]
    pub fn eval<R: Real>(&self, dots: &LocalDots<R>) -> [R; 3] {
        let alpha = R::of(self.alpha);
        let v = self.g.visibility(dots.n_dot_i, dots.n_dot_o, alpha);
        let unlit = v.eq(R::zero());
        if unlit.all() {
            return [R::zero(); 3];
        }
        // D and F are finite, so where V = 0 the product is 0 as well.
        let dv = self.d.eval(dots.n_dot_h, dots.sin2_h, alpha) * v;
        map3(self.fresnel(dots.i_dot_h), |f| R::select(unlit, R::zero(), f * dv))
    }
}
