//! The normal-map driver: the pixels of a normal image become surface points
//! ([`crate::surface::normal_image`]) and go through the same [`Shader`] and
//! [`Material::eval`](crate::shading::material::Material::eval) as a mesh render's hits. No BVH,
//! no rays. Rows are shaded in parallel; every pixel is a pure function of its colour and
//! position, so the image does not depend on the thread count.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::Vec3;

use crate::film::Image;
use crate::plan::RenderPlan;
use crate::scene::normal_map::{NormalMapScene, Preset};
use crate::shading::brdf::{LaneInstructions, LANES};
use crate::shading::convention::ShadingConvention;
use crate::shading::shader::Shader;
use crate::shading::shadow::NoOcclusion;
use crate::shading::shadow::SceneExtent;
use crate::surface::normal_image::{ImageSurface, NormalDecoding, NormalImage, PixelPositions, TpScaling};
use crate::surface::SurfaceLanes;

/// Counters and per-stage times of one normal-map shading.
#[derive(Clone, Debug, Default)]
pub struct NormalMapStats {
    /// Pixels that became surface points (the others are background).
    pub surface_points: u64,
    /// Time summed over threads spent turning pixels into surface points.
    pub surface_time: Duration,
    /// Time summed over threads spent in the shader.
    pub shading_time: Duration,
    /// Wall-clock time of surface points + shading.
    pub wall_time: Duration,
}

/// How `scene` turns the pixels of `image` into surface points. For the `tp` preset this reads
/// the image's global min and max; an image whose RGB values are all equal is an error (the
/// scaling would divide by zero).
pub fn image_surface(scene: &NormalMapScene, image: &NormalImage) -> Result<ImageSurface, String> {
    let decoding = match scene.preset {
        Preset::Tp => NormalDecoding::MinMax(TpScaling::of(image)?),
        Preset::Physical => NormalDecoding::Signed,
    };
    Ok(ImageSurface {
        decoding,
        positions: scene.preset.positions(),
        viewer: scene.viewer,
        width: image.width,
        height: image.height,
        material: 0,
    })
}

/// The shader of a normal-map scene: its material and lights, no occluder.
pub fn shader<'a>(scene: &'a NormalMapScene, convention: ShadingConvention) -> Shader<'a, NoOcclusion> {
    Shader {
        materials: std::slice::from_ref(&scene.material),
        lights: &scene.lights,
        occluder: None,
        extent: SceneExtent::UNIT,
        shadow_offset: Default::default(),
        convention,
        textures: None,
        emission: false,
    }
}

/// Shades every pixel of `image` (linear L_o; background pixels 0) following `plan`.
///
/// A row's foreground pixels become [`SurfaceLanes`] eight at a time, straight from the image,
/// and go through [`Shader::shade_surface_lanes`], for both presets (a normal-map shader has no
/// shadow rays, textures or emission, so it always has lanes). The decoding and the BRDF are the
/// same functions [`ImageSurface::point`] and [`Shader::shade`] run for one pixel.
pub fn shade_image(
    scene: &NormalMapScene,
    plan: &RenderPlan,
    image: &NormalImage,
    surface: &ImageSurface,
) -> (Image, NormalMapStats) {
    shade_image_with(scene, plan, image, surface, LaneInstructions::detect())
}

/// [`shade_image`] with the lane path compiled for `instructions` (which must be available on
/// this CPU: [`LaneInstructions::detect`] says which are; others fall back to the portable code).
/// Every choice gives the same image, bit for bit: the benchmark compares their speed, a test
/// their results.
pub fn shade_image_with(
    scene: &NormalMapScene,
    plan: &RenderPlan,
    image: &NormalImage,
    surface: &ImageSurface,
    instructions: LaneInstructions,
) -> (Image, NormalMapStats) {
    let instructions = instructions.min(LaneInstructions::detect());
    let start = Instant::now();
    let shader = shader(scene, plan.convention);
    debug_assert!(shader.has_lanes());
    let (surface_ns, shading_ns, points) = (AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0));
    let out = Image::par_from_rows(
        image.width,
        image.height,
        RowBuffers::default,
        |buffers, row, pixels| {
            let t0 = Instant::now();
            let job = LaneRow {
                shader: &shader,
                surface,
                image,
                row,
            };
            let t1 = match instructions {
                LaneInstructions::Portable => job.run(buffers, pixels),
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `instructions` is at most what `detect` found on this CPU.
                LaneInstructions::Avx2 => unsafe { job.run_avx2(buffers, pixels) },
            };
            let t2 = Instant::now();
            surface_ns.fetch_add((t1 - t0).as_nanos() as u64, Ordering::Relaxed);
            shading_ns.fetch_add((t2 - t1).as_nanos() as u64, Ordering::Relaxed);
            points.fetch_add(buffers.columns.len() as u64, Ordering::Relaxed);
        },
    );
    let stats = NormalMapStats {
        surface_points: points.into_inner(),
        surface_time: Duration::from_nanos(surface_ns.into_inner()),
        shading_time: Duration::from_nanos(shading_ns.into_inner()),
        wall_time: start.elapsed(),
    };
    (out, stats)
}

/// One thread's surface points of the row it is shading, reused from row to row.
#[derive(Default)]
struct RowBuffers {
    /// The columns of the foreground pixels…
    columns: Vec<u32>,
    /// …and their surface points, eight per entry; the last entry is padded with copies of the
    /// row's last foreground pixel.
    lanes: Vec<SurfaceLanes>,
}

/// One row of the lane path: what it shades and with what.
struct LaneRow<'a> {
    shader: &'a Shader<'a, NoOcclusion>,
    surface: &'a ImageSurface,
    image: &'a NormalImage,
    row: u32,
}

impl LaneRow<'_> {
    /// The row's foreground pixels' [`SurfaceLanes`] into `buffers`, then shaded into `pixels`.
    /// Returns the time at which the surface stage ended.
    #[inline(always)]
    fn run(&self, buffers: &mut RowBuffers, pixels: &mut [Vec3]) -> Instant {
        buffers.surface_lanes(self.surface, self.image, self.row);
        let t1 = Instant::now();
        shade_lanes_row(self.shader, buffers, pixels);
        t1
    }

    /// [`LaneRow::run`] compiled with AVX2 (256-bit registers: an
    /// [`F32x8`](crate::shading::brdf::F32x8) operation is one instruction instead of two). No
    /// FMA: fused products round differently, and every path must give the same bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn run_avx2(&self, buffers: &mut RowBuffers, pixels: &mut [Vec3]) -> Instant {
        self.run(buffers, pixels)
    }
}

impl RowBuffers {
    /// The surface lanes of row `row`'s foreground pixels.
    #[inline(always)]
    fn surface_lanes(&mut self, surface: &ImageSurface, image: &NormalImage, row: u32) {
        self.columns.clear();
        self.lanes.clear();
        surface.foreground_columns(image, row, &mut self.columns);
        for group in self.columns.chunks(LANES) {
            let cols = std::array::from_fn(|i| group[i.min(group.len() - 1)]);
            self.lanes.push(surface.lanes(image, row, cols));
        }
    }
}

/// Shades the lanes of `buffers` into `pixels` (indexed by column); the padding lanes' results
/// are dropped.
#[inline(always)]
fn shade_lanes_row(shader: &Shader<NoOcclusion>, buffers: &RowBuffers, pixels: &mut [Vec3]) {
    for (group, lanes) in buffers.columns.chunks(LANES).zip(&buffers.lanes) {
        let radiance = shader.shade_surface_lanes(lanes);
        let pixel = |i: usize| Vec3::new(radiance[0].0[i], radiance[1].0[i], radiance[2].0[i]);
        let first = group[0] as usize;
        match pixels.get_mut(first..first + LANES) {
            // Eight neighbours (inside an object, most groups): one run of stores.
            Some(run) if group.len() == LANES && group[LANES - 1] as usize == first + LANES - 1 => {
                for (i, out) in run.iter_mut().enumerate() {
                    *out = pixel(i);
                }
            }
            _ => {
                for (i, &col) in group.iter().enumerate() {
                    pixels[col as usize] = pixel(i);
                }
            }
        }
    }
}

/// One pixel of the `tp` preset, decoded and shaded by the same functions `pointshade normalmap
/// --preset tp` runs eight pixels at a time (equal for every pixel: `tests/integration/normalmap.rs`): L_o (before the output's min-max normalisation) of the
/// pixel at (`row`, `col`) with colour `rgb` (each channel in [0, 1]) in an image whose global
/// RGB range is `scaling`, under `scene`'s lights, viewer and material (build `scene` with
/// [`NormalMapScene::from_preset`] and [`Preset::Tp`], then change what you need).
///
/// The documented values of the degenerate inputs (docs/normal-maps.md, "Normal-map mode"): background
/// (max(rgb) ≤ 4/255) and n = 0 give 0; n·ω_i = 0 or n·ω_o = 0 (the Cook-Torrance denominator 0)
/// gives the diffuse part alone, or 0 when n·ω_i = 0; ω_i + ω_o = 0 gives the diffuse part alone;
/// a light at the point adds nothing; a viewer at the point sees n·ω_o = 0. Never NaN.
/// For the stability report (issue 6).
pub fn shade_tp_pixel(scene: &NormalMapScene, scaling: TpScaling, rgb: [f32; 3], row: u32, col: u32) -> Vec3 {
    let surface = ImageSurface {
        decoding: NormalDecoding::MinMax(scaling),
        positions: PixelPositions::RowColumn,
        viewer: scene.viewer,
        width: col.saturating_add(1),
        height: row.saturating_add(1),
        material: 0,
    };
    match surface.point(col, row, rgb, 1.0) {
        Some(sp) => shader(scene, ShadingConvention::Assignment).shade(&sp, &mut 0),
        None => Vec3::ZERO,
    }
}
