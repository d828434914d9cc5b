//! The BRDF module: every reflectance term pointshade knows, as small pure functions.
//!
//! Each term is a function of a few dot products and material parameters, generic over [`Real`](crate::lanes::Real)
//! (f32 and f64), with its formula in the comment above it. The renderer calls them in f32; the
//! stability checks call the very same functions in f64 and compare. [`Material`] composes them
//! into a full BRDF; nothing else in pointshade evaluates a BRDF.
//!
//! Conventions: ω_i points towards the light, ω_o towards the viewer, n is the shading normal and
//! ω_h = (ω_i + ω_o)/‖ω_i + ω_o‖ the half vector. [`LocalDots`] carries n·ω_i, n·ω_o, n·ω_h and
//! ω_i·ω_h. Every term returns a finite, non-negative value for any finite input; the singular
//! cases (grazing angles, α → 0, ω_i = −ω_o) have a documented value, tested next to the term.
//!
//! [`Material`]: crate::material::Material

mod dots;
mod fresnel;
mod lobes;
mod masking;
mod microfacet;

pub use dots::LocalDots;
pub use fresnel::{
    fresnel_conductor, fresnel_conductor_rgb, fresnel_schlick, fresnel_schlick_sg, schlick_f0_dielectric, FresnelTerm,
    MAX_CONDUCTOR_INDEX,
};
pub use lobes::{blinn_phong, lambert, MAX_WHOLE_EXPONENT};
pub use masking::{
    schlick_k_beckmann, schlick_k_karis, v_schlick, v_smith_ggx, v_smith_ggx_correlated, MaskingShadowing,
};
pub use microfacet::{beckmann_d, ggx_d, MicrofacetDistribution, MIN_ALPHA};

/// A term name that is not one of the known ones, with the list of valid names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownTerm {
    /// What kind of term (D, G, F).
    pub kind: &'static str,
    /// The name given.
    pub name: String,
    /// Valid names.
    pub expected: &'static [&'static str],
}

impl std::fmt::Display for UnknownTerm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "unknown {} term '{}' (expected {})",
            self.kind,
            self.name,
            self.expected.join(", ")
        )
    }
}

/// Implements `FromStr` and `name()` for a term enum from a list of (variant, name) pairs.
macro_rules! named_terms {
    ($ty:ident, $kind:literal, $($variant:ident => $name:literal),+ $(,)?) => {
        impl $ty {
            /// Every variant, in documentation order.
            pub const ALL: &'static [$ty] = &[$($ty::$variant),+];
            const NAMES: &'static [&'static str] = &[$($name),+];

            /// The name used in scene files.
            pub fn name(self) -> &'static str {
                match self { $($ty::$variant => $name),+ }
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::brdf::UnknownTerm;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                match s {
                    $($name => Ok($ty::$variant),)+
                    _ => Err($crate::brdf::UnknownTerm { kind: $kind, name: s.to_string(), expected: Self::NAMES }),
                }
            }
        }
    };
}
pub(crate) use named_terms;
