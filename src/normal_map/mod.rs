//! The normal-map driver: the pixels of a normal image become surface points
//! ([`crate::normal_map::image`]) and go through the same [`Shader`] and
//! [`Material::eval`](crate::material::Material::eval) as a mesh render's hits. No BVH,
//! no rays. The `tp` preset computes in float64, as the assignment's numpy code does; the
//! `physical` preset in f32, as a mesh render. Rows are shaded in parallel; every pixel is a
//! pure function of its colour and position, so the image does not depend on the thread count.

pub mod bake;
pub mod formats;
pub mod image;
pub mod likeness;
pub mod pixels;
pub mod plan;
pub mod scene_file;

use std::time::{Duration, Instant};

use glam::{DVec3, Vec3};

use crate::accel::shadow::NoOcclusion;
use crate::accel::shadow::SceneExtent;
use crate::error::{InputError, InputResult};
use crate::film::{all_finite, overflow_error, Image};
#[cfg(target_arch = "x86_64")]
use crate::lanes::x86::{F64x4Avx, F64x8Avx512};
use crate::lanes::{LaneArray, LaneInstructions, Lanes, Real, Scalar, LANES};
use crate::normal_map::image::NormalImage;
use crate::normal_map::likeness::NormalLikeness;
use crate::normal_map::pixels::{ImageSurface, MinMaxDecoding, MinMaxScaling, NormalDecoding, PixelPositions};
use crate::normal_map::plan::NormalMapPlan;
use crate::normal_map::scene_file::{NormalMapScene, Preset};
use crate::shading::convention::ShadingConvention;
use crate::shading::shader::{clamped_to_viewer_form, clamped_unit_form, Shader};
use crate::surface::SurfaceLanes;

/// Counters and per-stage times of one normal-map shading.
#[derive(Clone, Debug, Default)]
pub struct NormalMapStats {
    /// Pixels that became surface points (the others are background).
    pub surface_points: u64,
    /// Time summed over threads spent finding the foreground pixels of each row (and counting
    /// its image-check verdicts, [`NormalMapStats::likeness`]).
    pub surface_time: Duration,
    /// Time summed over threads spent decoding the foreground pixels into surface points and
    /// shading them: one loop, a lane group at a time, so the two are not timed apart.
    pub shading_time: Duration,
    /// Wall-clock time of surface points + shading.
    pub wall_time: Duration,
    /// The image check's counts ([`NormalLikeness::of`] the image), counted by each row's worker
    /// while the row is in its cache rather than in a pass of their own.
    pub likeness: NormalLikeness,
    /// Rows holding a pixel that is not finite, counted by the worker that wrote the row while it
    /// is in its cache. The shader saturates L_o at `f32::MAX` (`shading::shader`), so this is 0
    /// today: it is defence in depth, so that a shader change letting an infinity or a NaN
    /// through would be an error [`shade`] reports, never a pixel of the output.
    pub non_finite_rows: u64,
}

/// A normal image shaded: what both front ends make of it.
pub struct ShadedNormalImage {
    /// Linear L_o per pixel (background 0).
    pub radiance: Image,
    /// Counters and times.
    pub stats: NormalMapStats,
    /// What the user should hear about (an image that does not look like a normal image).
    pub warnings: Vec<String>,
    /// What was done, and why (`--explain`).
    pub plan: NormalMapPlan,
}

/// Shades `image` as `scene` says: the normal-map mode's one call, which the CLI
/// (`pointshade normalmap`) and the Python module (`shade_normal_image`) make. `output`
/// describes what the caller makes of L_o, for the plan. An error names the image (a `tp`
/// image whose values are all equal) or, should the shader ever let one through, the pixel that
/// is not finite ([`NormalMapStats::non_finite_rows`]).
pub fn shade(scene: &NormalMapScene, image: &NormalImage, output: &str) -> InputResult<ShadedNormalImage> {
    let mut warnings = Vec::new();
    let surface = image_surface(scene, image).map_err(|e| InputError::new(&image.source, e))?;
    let (radiance, stats) = shade_image(scene, image, &surface);
    if let Some(warning) = stats.likeness.warning() {
        warnings.push(format!("{}: {warning}", image.source.display()));
    }
    if stats.non_finite_rows > 0 {
        let (x, y, p) = radiance
            .first_non_finite()
            .expect("a row holds a pixel that is not finite");
        return Err(InputError::new(&image.source, overflow_error(x, y, p)));
    }
    Ok(ShadedNormalImage {
        radiance,
        stats,
        warnings,
        plan: plan::plan(scene, image, output),
    })
}

/// How `scene` turns the pixels of `image` into surface points. For the `tp` preset this reads
/// the image's global min and max; an image whose RGB values are all equal is an error (the
/// scaling would divide by zero).
pub fn image_surface(scene: &NormalMapScene, image: &NormalImage) -> Result<ImageSurface, String> {
    let decoding = match scene.preset {
        Preset::Tp => NormalDecoding::MinMax(MinMaxScaling::of(image)?),
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

/// Shades every pixel of `image` (linear L_o; background pixels 0).
///
/// A row's foreground pixels become [`SurfaceLanes`] straight from the image — eight in f32
/// lanes for the `physical` preset, four in float64 lanes for `tp` (the assignment's numpy code
/// is float64) — and go through the shader's lane path. The decoding and the BRDF are the same
/// functions [`ImageSurface::point`], [`shade_min_max_pixel`] and [`Shader::shade`] run for one pixel.
pub fn shade_image(scene: &NormalMapScene, image: &NormalImage, surface: &ImageSurface) -> (Image, NormalMapStats) {
    shade_image_with(
        scene,
        image,
        surface,
        LaneInstructions::detect(),
        MinMaxPrecision::Float64,
    )
}

/// [`shade_image`] with the lane path compiled for `instructions` (at most what this CPU runs:
/// [`LaneInstructions::detect`] says which; a better choice falls back to the best available)
/// and the `tp` preset in `precision`. Every choice of instructions gives the same image, bit
/// for bit: the benchmark compares their speed, a test their results.
pub fn shade_image_with(
    scene: &NormalMapScene,
    image: &NormalImage,
    surface: &ImageSurface,
    instructions: LaneInstructions,
    precision: MinMaxPrecision,
) -> (Image, NormalMapStats) {
    let instructions = instructions.min(LaneInstructions::detect());
    let rows = Rows { scene, image, surface };
    let to_viewer = clamped_to_viewer_form(&scene.material);
    match (surface.decoding, precision) {
        (NormalDecoding::MinMax(s), MinMaxPrecision::Float64) => {
            match (instructions, &MinMaxDecoding::new(s, to_viewer)) {
                (LaneInstructions::Portable, s) => {
                    rows.shade::<MinMaxLanes<Lanes<f64, 4>>>(s, |job, buffers, pixels| job.run(buffers, pixels))
                }
                // SAFETY (both): `instructions` is at most what `detect` found on this CPU.
                #[cfg(target_arch = "x86_64")]
                (LaneInstructions::Avx2, s) => rows
                    .shade::<MinMaxLanes<F64x4Avx>>(s, |job, buffers, pixels| unsafe { job.run_avx2(buffers, pixels) }),
                #[cfg(target_arch = "x86_64")]
                (LaneInstructions::Avx512, s) => rows
                    .shade::<MinMaxLanes<F64x8Avx512>>(s, |job, buffers, pixels| unsafe {
                        job.run_avx512(buffers, pixels)
                    }),
            }
        }
        (NormalDecoding::MinMax(s), MinMaxPrecision::Float32) => {
            rows.shade_f32::<MinMaxLanes<Lanes<f32, LANES>>>(&MinMaxDecoding::new(s, to_viewer), instructions)
        }
        (NormalDecoding::Signed, _) => rows.shade_f32::<PhysicalLanes>(&(), instructions),
    }
}

/// The precision the `tp` preset shades in: float64, as the assignment's numpy code (what
/// `pointshade normalmap` runs), or f32 lanes — twice as many per instruction, but where a
/// cosine is 0 in exact arithmetic f32 rounding can land on the other side of the Cook-Torrance
/// guard than numpy's (`cargo bench --bench normalmap` compares both). The `physical` preset is
/// always f32.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MinMaxPrecision {
    /// Float64 lanes (the default): four, or eight with AVX-512.
    Float64,
    /// Eight f32 lanes.
    Float32,
}

/// What every row of one shading reads.
#[derive(Clone, Copy)]
struct Rows<'a> {
    scene: &'a NormalMapScene,
    image: &'a NormalImage<'a>,
    surface: &'a ImageSurface,
}

impl Rows<'_> {
    /// [`Rows::shade`] for f32 lane groups, whose code the AVX2 form serves on AVX-512
    /// machines too.
    fn shade_f32<G: LaneGroup>(
        self,
        decoding: &G::Decoding,
        instructions: LaneInstructions,
    ) -> (Image, NormalMapStats) {
        match instructions {
            LaneInstructions::Portable => self.shade::<G>(decoding, |job, buffers, pixels| job.run(buffers, pixels)),
            // SAFETY: `instructions` is at most what `detect` found on this CPU, and AVX-512F
            // implies AVX2.
            #[cfg(target_arch = "x86_64")]
            LaneInstructions::Avx2 | LaneInstructions::Avx512 => self
                .shade::<G>(decoding, |job, buffers, pixels| unsafe {
                    job.run_avx2(buffers, pixels)
                }),
        }
    }

    /// Every row, in parallel, as lane groups `G` run by `run` (one of [`LaneRow`]'s forms).
    fn shade<G: LaneGroup>(
        self,
        decoding: &G::Decoding,
        run: impl Fn(&LaneRow<G>, &mut RowBuffers, &mut [Vec3]) -> RowShaded + Sync,
    ) -> (Image, NormalMapStats) {
        let start = Instant::now();
        let shader = shader(self.scene, self.scene.preset.convention());
        debug_assert!(shader.has_lanes());
        let (out, counts) = Image::par_from_rows(
            self.image.width,
            self.image.height,
            RowBuffers::default,
            |buffers, row, pixels| {
                let t0 = Instant::now();
                let job = LaneRow {
                    shader: &shader,
                    surface: self.surface,
                    decoding,
                    image: self.image,
                    row,
                };
                let shaded = run(&job, buffers, pixels);
                let (t1, t2) = (shaded.surface_end, Instant::now());
                RowCounts {
                    surface_ns: (t1 - t0).as_nanos() as u64,
                    shading_ns: (t2 - t1).as_nanos() as u64,
                    points: buffers.columns.len() as u64,
                    likeness: shaded.likeness,
                    non_finite_rows: u64::from(!shaded.finite),
                }
            },
        );
        let stats = NormalMapStats {
            surface_points: counts.points,
            surface_time: Duration::from_nanos(counts.surface_ns),
            shading_time: Duration::from_nanos(counts.shading_ns),
            wall_time: start.elapsed(),
            likeness: counts.likeness,
            non_finite_rows: counts.non_finite_rows,
        };
        (out, stats)
    }
}

/// What the rows of one shading counted, summed over rows ([`NormalMapStats`]' sources).
#[derive(Clone, Copy, Default)]
struct RowCounts {
    surface_ns: u64,
    shading_ns: u64,
    points: u64,
    likeness: NormalLikeness,
    non_finite_rows: u64,
}

impl std::ops::Add for RowCounts {
    type Output = RowCounts;
    fn add(self, b: RowCounts) -> RowCounts {
        RowCounts {
            surface_ns: self.surface_ns + b.surface_ns,
            shading_ns: self.shading_ns + b.shading_ns,
            points: self.points + b.points,
            likeness: self.likeness + b.likeness,
            non_finite_rows: self.non_finite_rows + b.non_finite_rows,
        }
    }
}

/// Pixels of one row shaded together: how they are read from the image and shaded.
trait LaneGroup: Copy + Send {
    /// Pixels per group.
    const WIDTH: usize;
    /// What decoding needs besides the [`ImageSurface`].
    type Decoding: Sync;
    /// The group of the foreground pixels at `cols` (`WIDTH` of them) of row `row`.
    fn read(surface: &ImageSurface, decoding: &Self::Decoding, image: &NormalImage, row: u32, cols: &[u32]) -> Self;
    /// L_o of lane `i`, for every lane, into `out`.
    fn shade(&self, shader: &Shader<NoOcclusion>, out: impl FnMut(usize, Vec3));
}

/// Eight `physical` pixels in f32 lanes.
#[derive(Clone, Copy)]
struct PhysicalLanes(SurfaceLanes);

impl LaneGroup for PhysicalLanes {
    const WIDTH: usize = LANES;
    type Decoding = ();
    #[inline(always)]
    fn read(surface: &ImageSurface, _: &(), image: &NormalImage, row: u32, cols: &[u32]) -> Self {
        PhysicalLanes(surface.lanes(image, row, std::array::from_fn(|i| cols[i])))
    }
    #[inline(always)]
    fn shade(&self, shader: &Shader<NoOcclusion>, mut out: impl FnMut(usize, Vec3)) {
        let radiance = shader.shade_lanes(&self.0);
        for i in 0..LANES {
            out(i, Vec3::new(radiance[0].0[i], radiance[1].0[i], radiance[2].0[i]));
        }
    }
}

/// `tp` pixels in the lanes of `V`: float64 ones for the preset, f32 ones to compare.
#[derive(Clone, Copy)]
struct MinMaxLanes<V: LaneArray>(SurfaceLanes<V>);

impl<V: LaneArray + Send> LaneGroup for MinMaxLanes<V> {
    const WIDTH: usize = V::WIDTH;
    type Decoding = MinMaxDecoding<V::Scalar>;
    #[inline(always)]
    fn read(surface: &ImageSurface, decoding: &Self::Decoding, image: &NormalImage, row: u32, cols: &[u32]) -> Self {
        MinMaxLanes(surface.tp_lanes(decoding, image, row, cols))
    }
    #[inline(always)]
    fn shade(&self, shader: &Shader<NoOcclusion>, mut out: impl FnMut(usize, Vec3)) {
        let radiance = shader.shade_clamped_lanes(&self.0);
        let mut channels = [[V::Scalar::zero(); MAX_GROUP]; 3];
        for (c, lanes) in radiance.into_iter().enumerate() {
            lanes.write_to(&mut channels[c]);
        }
        let channel = |c: usize, i: usize| channels[c][i].as_f64() as f32;
        for i in 0..V::WIDTH {
            out(i, Vec3::new(channel(0, i), channel(1, i), channel(2, i)));
        }
    }
}

/// The widest lane group.
const MAX_GROUP: usize = 8;

/// One thread's foreground columns of the row it is shading, reused from row to row.
#[derive(Default)]
struct RowBuffers {
    columns: Vec<u32>,
}

/// One row of the lane path: what it shades and with what.
struct LaneRow<'a, G: LaneGroup> {
    shader: &'a Shader<'a, NoOcclusion>,
    surface: &'a ImageSurface,
    decoding: &'a G::Decoding,
    image: &'a NormalImage<'a>,
    row: u32,
}

/// What a row's run reports.
struct RowShaded {
    /// When its surface stage ended.
    surface_end: Instant,
    /// Whether every pixel of the row is finite (tested in the run, in its wider instructions).
    finite: bool,
    /// The row's image-check counts (also in the run's instructions).
    likeness: NormalLikeness,
}

impl<G: LaneGroup> LaneRow<'_, G> {
    /// The row's foreground columns into `buffers`, then their pixels read and shaded into
    /// `pixels` a lane group at a time (the decoding's loads and the shading's divisions of
    /// neighbouring groups overlap in the core; a row of groups stored first would not stay in
    /// L1).
    #[inline(always)]
    fn run(&self, buffers: &mut RowBuffers, pixels: &mut [Vec3]) -> RowShaded {
        debug_assert!(G::WIDTH <= MAX_GROUP);
        buffers.columns.clear();
        let likeness = NormalLikeness::of_row(self.image, self.row);
        self.surface
            .foreground_columns(self.image, self.row, &mut buffers.columns);
        let surface_end = Instant::now();
        let mut padded = [0u32; MAX_GROUP];
        for group in buffers.columns.chunks(G::WIDTH) {
            // Full groups are read where the columns are (copied, the lanes' wide load of them
            // would wait for the copy's narrow stores to land); the last one is padded.
            let cols = match group.len() == G::WIDTH {
                true => group,
                false => {
                    for (i, col) in padded.iter_mut().take(G::WIDTH).enumerate() {
                        *col = group[i.min(group.len() - 1)];
                    }
                    &padded[..G::WIDTH]
                }
            };
            let lanes = G::read(self.surface, self.decoding, self.image, self.row, cols);
            shade_group(self.shader, group, &lanes, pixels);
        }
        RowShaded {
            surface_end,
            finite: all_finite(pixels),
            likeness,
        }
    }

    /// [`LaneRow::run`] compiled with AVX2 (256-bit registers: an
    /// [`F32x8`](crate::lanes::F32x8) or four-float64 operation is one instruction instead of
    /// two). No FMA: fused products round differently, and every path must give the same bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn run_avx2(&self, buffers: &mut RowBuffers, pixels: &mut [Vec3]) -> RowShaded {
        self.run(buffers, pixels)
    }

    /// [`LaneRow::run`] compiled with AVX-512F, for the eight-float64 lane groups. No FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f")]
    fn run_avx512(&self, buffers: &mut RowBuffers, pixels: &mut [Vec3]) -> RowShaded {
        self.run(buffers, pixels)
    }
}

/// Shades the pixels at columns `group` (the lanes of `lanes`; padding lanes' results are
/// dropped) into `pixels` (indexed by column).
#[inline(always)]
fn shade_group<G: LaneGroup>(shader: &Shader<NoOcclusion>, group: &[u32], lanes: &G, pixels: &mut [Vec3]) {
    let first = group[0] as usize;
    match pixels.get_mut(first..first + G::WIDTH) {
        // Neighbours (inside an object, most groups): one run of stores.
        Some(run) if group.len() == G::WIDTH && group[G::WIDTH - 1] as usize == first + G::WIDTH - 1 => {
            lanes.shade(shader, |i, v| run[i] = v);
        }
        _ => lanes.shade(shader, |i, v| {
            if let Some(&col) = group.get(i) {
                pixels[col as usize] = v;
            }
        }),
    }
}

/// One pixel of the `tp` preset, decoded and shaded by the same functions `pointshade normalmap
/// --preset tp` runs four pixels at a time, in float64 (equal for every pixel:
/// `tests/integration/normalmap.rs`): L_o (before the output's min-max normalisation) of the
/// pixel at (`row`, `col`) with values `v` in `scaling`'s units (an image's integer levels for
/// [`MinMaxScaling::of`], [0, 1] for [`MinMaxScaling::new`]), under `scene`'s lights, viewer and
/// material (build `scene` with [`NormalMapScene::from_preset`] and [`Preset::Tp`], then change
/// what you need).
///
/// The documented values of the degenerate inputs (docs/normal-maps.md, "Normal-map mode"):
/// background (max(v) ≤ 4/255 of full scale) and n = 0 give 0; n·ω_i = 0 or n·ω_o = 0 (the
/// Cook-Torrance denominator 0) gives the diffuse part alone, or 0 when n·ω_i = 0; ω_i + ω_o = 0
/// gives the diffuse part alone; a light at the point adds nothing; a viewer at the point sees
/// n·ω_o = 0. Never NaN. For the stability report.
pub fn shade_min_max_pixel(scene: &NormalMapScene, scaling: MinMaxScaling, v: [f64; 3], row: u32, col: u32) -> DVec3 {
    if scaling.is_background(v) {
        return DVec3::ZERO;
    }
    let surface = ImageSurface {
        decoding: NormalDecoding::MinMax(scaling),
        positions: PixelPositions::RowColumn,
        viewer: scene.viewer,
        width: col.saturating_add(1),
        height: row.saturating_add(1),
        material: 0,
    };
    let point = surface.tp_point(&scaling, v, col as f64, row as f64, clamped_unit_form(&scene.material));
    DVec3::from(shader(scene, ShadingConvention::Clamped).shade_clamped_lanes(&point))
}
