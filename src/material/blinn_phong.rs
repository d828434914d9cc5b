//! The Blinn-Phong lobe's parameters (evaluated by [`crate::brdf::blinn_phong`]).

/// Blinn-Phong specular lobe: f_s = ks · color · (n·ω_h)^shininess.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlinnPhong {
    /// Specular weight k_s.
    pub ks: f32,
    /// Exponent s.
    pub shininess: f32,
    /// Specular tint (white by default).
    pub color: [f32; 3],
}
