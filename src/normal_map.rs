//! The normal-map driver: the pixels of a normal image become surface points
//! ([`crate::surface::normal_image`]) and go through the same [`Shader`] and
//! [`Material::eval`](crate::shading::material::Material::eval) as a mesh render's hits. No BVH,
//! no rays. Rows are shaded in parallel; every pixel is a pure function of its colour and
//! position, so the image does not depend on the thread count.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::Vec3;
use rayon::prelude::*;

use crate::film::Image;
use crate::plan::RenderPlan;
use crate::scene::normal_map::{NormalMapScene, Preset};
use crate::shading::brdf::LANES;
use crate::shading::convention::ShadingConvention;
use crate::shading::shader::Shader;
use crate::shading::shadow::NoOcclusion;
use crate::surface::normal_image::{ImageSurface, NormalDecoding, NormalImage, PixelPositions, TpScaling};
use crate::surface::SurfacePoint;

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
        scene_unit: 1.0,
        shadow_offset: Default::default(),
        convention,
        textures: None,
        emission: false,
    }
}

/// Shades every pixel of `image` (linear L_o; background pixels 0) following `plan`.
pub fn shade_image(
    scene: &NormalMapScene,
    plan: &RenderPlan,
    image: &NormalImage,
    surface: &ImageSurface,
) -> (Image, NormalMapStats) {
    let start = Instant::now();
    let shader = shader(scene, plan.convention);
    let (surface_ns, shading_ns, points) = (AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0));
    let mut out = Image::new(image.width, image.height);
    out.pixels
        .par_chunks_mut(image.width as usize)
        .enumerate()
        .for_each_init(
            || Vec::with_capacity(image.width as usize),
            |row_points: &mut Vec<(u32, SurfacePoint)>, (row, pixels)| {
                row_points.clear();
                let t0 = Instant::now();
                surface.row_points(image, row as u32, row_points);
                let t1 = Instant::now();
                shade_row(&shader, row_points, pixels);
                let t2 = Instant::now();
                surface_ns.fetch_add((t1 - t0).as_nanos() as u64, Ordering::Relaxed);
                shading_ns.fetch_add((t2 - t1).as_nanos() as u64, Ordering::Relaxed);
                points.fetch_add(row_points.len() as u64, Ordering::Relaxed);
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

/// Shades `points` into `pixels` (indexed by column), eight points at a time through the
/// shader's lanes; the last group is padded with copies of its last point, whose results are
/// dropped.
fn shade_row(shader: &Shader<NoOcclusion>, points: &[(u32, SurfacePoint)], pixels: &mut [Vec3]) {
    for group in points.chunks(LANES) {
        let lanes = std::array::from_fn(|i| group[i.min(group.len() - 1)].1);
        let shaded = shader.shade_lanes(&lanes, &mut 0);
        for ((col, _), value) in group.iter().zip(shaded) {
            pixels[*col as usize] = value;
        }
    }
}

/// One pixel of the `tp` preset, decoded and shaded by exactly the code `pointshade normalmap
/// --preset tp` runs for every pixel: L_o (before the output's min-max normalisation) of the
/// pixel at (`row`, `col`) with colour `rgb` (each channel in [0, 1]) in an image whose global
/// RGB range is `scaling`, under `scene`'s lights, viewer and material (build `scene` with
/// [`NormalMapScene::from_preset`] and [`Preset::Tp`], then change what you need).
///
/// The documented values of the degenerate inputs (README.md, "Normal-map mode"): background
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
