//! What the two refiners (adaptive.rs for the `adaptive` sampler, cells.rs for `cells`) are
//! given by the driver (mod.rs): an active pixel and the refinement settings.

use glam::Vec3;

/// Floor of a pixel's scale in the convergence test, as a share of its neighbourhood's level.
pub(super) const DARK_FLOOR: f32 = 0.05;

/// What refinement needs of the film and the plan: the same for both samplers.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Most samples per pixel.
    pub spp: u32,
    /// The film's adaptive threshold (tolerance relative to a pixel's scale).
    pub threshold: f32,
    /// AOVs per sample.
    pub aovs: usize,
    /// The film's sampling seed.
    pub seed: u64,
    /// Display white (see [`display_white`]), the floor of a pixel's scale.
    pub white: f32,
}

/// An active pixel: where it is, where its sums go, and what its neighbourhood says. The cells
/// read `beside` and `scale` (their tests compare cells with the neighbours' centres and fix the
/// tolerance once); the Sobol rounds read `low` (their contrast test) and rescale as their
/// estimate moves; both read `centre` and `level`.
pub struct ActivePixel {
    /// Film column.
    pub x: u32,
    /// Film row.
    pub y: u32,
    /// Its slot in the tile's sums.
    pub slot: u32,
    /// Its centre sample.
    pub centre: Vec3,
    /// Centre samples of its four neighbours (left, right, above, below), where on the film.
    pub beside: [Option<Vec3>; 4],
    /// Scale of the tolerance: the largest of display white, the centre, and a floor relative to
    /// the neighbourhood's level (see `adaptive`).
    pub scale: f32,
    /// Largest channel of the neighbourhood's centre samples.
    pub level: f32,
    /// Smallest of the neighbourhood's centre samples' largest channels.
    pub low: f32,
    /// The centre values bend at the pixel itself; else it refines only because they bend at a
    /// neighbour (the dilation), and the cells take a first look of 3×3 instead of 4×4.
    pub bends: bool,
}
