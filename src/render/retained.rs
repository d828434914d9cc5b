//! A render's surface points and shadow verdicts, kept so that the same view can be shaded again
//! after its materials or lights change, tracing only what changed ([`super::preview`]).
//!
//! Shading is a pure function of a surface point, the materials, the lights and the verdicts of
//! the shadow rays it asks for, and a verdict is a pure function of its ray (for one tree). So a
//! frame keeps each tile's surface points and, for each camera-ray packet, the shadow rays its
//! shading asked for with their verdicts. Shading the frame again asks for the same rays wherever
//! a point's side and the light did not change: those verdicts are reused (the rays compared bit
//! for bit), every other ray is traced. The image is the one a whole render of the edited scene
//! gives, byte for byte (tests in `preview.rs`).

use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use super::tile::{assemble, par_tiles, tile_jobs, Context, PixelSums, SurfaceSample};
use super::tiles;
use crate::accel::packet::PACKET;
use crate::accel::shadow::{Occluder, ShadowRay};
use crate::accel::Bvh;
use crate::film::sampler::Sequence;
use crate::film::PixelRect;

/// The surface points and shadow verdicts of a render of a region at a fixed sample count.
pub(super) struct RetainedFrame {
    /// The region rendered, cut into [`tiles`].
    region: PixelRect,
    /// One entry per tile of the region, in the order of [`tiles`].
    tiles: Vec<RetainedTile>,
}

/// One tile's samples in the order they were traced, and what their shading asked of the tree.
#[derive(Default)]
struct RetainedTile {
    /// Every sample that hit a surface, packets numbered through the tile.
    samples: Vec<SurfaceSample>,
    /// The shadow rays the last shading asked for and their verdicts, packet after packet.
    verdicts: Vec<Verdict>,
    /// Where each packet's verdicts end in `verdicts`.
    packet_ends: Vec<u32>,
}

/// A shadow ray and whether it was blocked.
#[derive(Clone, Copy)]
struct Verdict {
    ray: ShadowRay,
    blocked: bool,
}

/// Shadow rays asked for and traced by a shading pass.
#[derive(Default)]
pub(super) struct RayCounts {
    /// Asked for by the shader.
    pub asked: AtomicU64,
    /// Of those, traced (the others reused a kept verdict).
    pub traced: AtomicU64,
    /// Nanoseconds spent tracing them, summed over threads.
    pub trace_ns: AtomicU64,
}

impl RetainedFrame {
    /// The most bytes a frame of `samples` samples under `lights` lights keeps: a surface point
    /// per sample and a verdict per sample and light, twice over for the vectors' growth.
    pub(super) fn bytes_at_most(samples: u64, lights: usize) -> u64 {
        let sample = std::mem::size_of::<SurfaceSample>() as u64;
        let verdict = std::mem::size_of::<Verdict>() as u64 + 4; // + its share of `packet_ends`
        samples.saturating_mul(2 * (sample + lights as u64 * verdict))
    }

    /// Traces every tile of `region` at the film's sample count from `sequence`, keeping the
    /// surface points, then shades them ([`Self::shade`]). Returns the frame and the shaded sums.
    pub(super) fn trace(ctx: &Context, sequence: Sequence, region: PixelRect, counts: &RayCounts) -> (Self, PixelSums) {
        let spp = ctx.scene.film.spp;
        let rects = tiles(region);
        let tiles: Vec<RetainedTile> = par_tiles(&rects)
            .map(|t| {
                let start = Instant::now();
                let mut tile = RetainedTile::default();
                let mut scratch = Vec::new();
                tile_jobs(ctx, sequence, *t, 0, spp, &mut |jobs| {
                    ctx.surface_samples(jobs, &mut scratch);
                    let first = SurfaceSample::packets(&tile.samples);
                    (tile.samples).extend(scratch.drain(..).map(|s| s.packet_moved(first)));
                });
                ctx.counters
                    .surface_ns
                    .fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
                tile
            })
            .collect();
        let mut frame = Self { region, tiles };
        let sums = frame.shade(ctx, counts);
        (frame, sums)
    }

    /// Shades the kept surface points under `ctx`'s materials and lights: a shadow ray asked for
    /// again reuses its verdict, any other is traced by `ctx`'s tree. The verdicts kept are then
    /// this shading's. `ctx` must be of the scene the frame was traced in, with the same camera,
    /// film, geometry, cut-outs and normal textures (the preview sees to it).
    pub(super) fn shade(&mut self, ctx: &Context, counts: &RayCounts) -> PixelSums {
        let region = self.region;
        let rects = tiles(region);
        let naovs = ctx.sampled_aovs;
        let parts: Vec<PixelSums> = par_tiles(&rects)
            .zip(self.tiles.par_iter_mut())
            .map(|(t, tile)| {
                let start = Instant::now();
                let mut sums = PixelSums::new((t.width() * t.height()) as usize, naovs);
                if !ctx.stopped() {
                    tile.shade(ctx, &mut sums, counts);
                }
                ctx.counters
                    .shading_ns
                    .fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
                sums
            })
            .collect();
        assemble(region, &rects, parts, naovs)
    }
}

impl RetainedTile {
    /// Shades the tile's samples packet by packet into `sums`, each packet's shadow rays
    /// answered by the verdicts its last shading kept where the ray is the same.
    fn shade(&mut self, ctx: &Context, sums: &mut PixelSums, counts: &RayCounts) {
        let before = std::mem::take(&mut self.verdicts);
        let before_ends = std::mem::take(&mut self.packet_ends);
        let mut kept = Vec::with_capacity(before.len());
        let mut start = 0;
        let (mut asked, mut traced, mut trace_ns) = (0, 0, 0);
        let tree = ctx.bvh();
        for (packet, group) in self.samples.chunk_by(SurfaceSample::same_packet).enumerate() {
            let end = before_ends.get(packet).map_or(start, |&e| e as usize);
            let occluder = KeptVerdicts {
                tree,
                before: &before[start..end],
                next: Cell::new(0),
                now: RefCell::new(kept),
                traced: Cell::new(0),
                trace_ns: Cell::new(0),
            };
            start = end;
            asked += ctx.shade_samples(&ctx.shader_with(tree.map(|_| &occluder)), group, sums);
            (traced, trace_ns) = (traced + occluder.traced.get(), trace_ns + occluder.trace_ns.get());
            kept = occluder.now.into_inner();
            self.packet_ends.push(kept.len() as u32);
        }
        counts.asked.fetch_add(asked, Ordering::Relaxed);
        counts.traced.fetch_add(traced, Ordering::Relaxed);
        counts.trace_ns.fetch_add(trace_ns, Ordering::Relaxed);
        self.verdicts = kept;
    }
}

/// The occluder of one packet's shading: answers a ray from the verdicts the packet's last
/// shading kept when it is among them (bit for bit), else traces it, and keeps every answer.
struct KeptVerdicts<'a> {
    tree: Option<&'a Bvh>,
    /// The packet's verdicts from its last shading, in the order they were asked.
    before: &'a [Verdict],
    /// Where the search for the next ray starts: rays are mostly asked in the same order.
    next: Cell<usize>,
    /// This shading's verdicts, appended to the tile's.
    now: RefCell<Vec<Verdict>>,
    /// Rays traced.
    traced: Cell<u64>,
    /// Nanoseconds spent tracing them.
    trace_ns: Cell<u64>,
}

impl KeptVerdicts<'_> {
    /// The kept verdict of `ray`, if the last shading asked for the same ray.
    fn kept(&self, ray: &ShadowRay) -> Option<bool> {
        let n = self.before.len();
        let from = self.next.get();
        let found = (0..n)
            .map(|k| (from + k) % n)
            .find(|&i| same_ray(&self.before[i].ray, ray))?;
        self.next.set(found + 1);
        Some(self.before[found].blocked)
    }

    fn trace(&self, rays: &[ShadowRay], blocked: &mut [bool]) {
        let start = Instant::now();
        match self.tree {
            Some(tree) => tree.occluded_batch(rays, blocked),
            None => blocked.fill(false),
        }
        self.traced.set(self.traced.get() + rays.len() as u64);
        (self.trace_ns).set(self.trace_ns.get() + start.elapsed().as_nanos() as u64);
    }
}

impl Occluder for KeptVerdicts<'_> {
    fn occluded(&self, ray: &ShadowRay) -> bool {
        let mut blocked = [false];
        self.occluded_batch(std::slice::from_ref(ray), &mut blocked);
        blocked[0]
    }

    fn occluded_batch(&self, rays: &[ShadowRay], occluded: &mut [bool]) {
        for (rays, occluded) in rays.chunks(PACKET).zip(occluded.chunks_mut(PACKET)) {
            // The rays without a kept verdict go to the tree together (as one packet). A call
            // asks for one light's rays from one packet's points: when its first ray is new, the
            // light moved (or was added) and the others are new too, so they are not searched
            // for. Either way the answers are exact: tracing a ray gives its verdict.
            let mut missing = [0; PACKET];
            let mut subset = [rays[0]; PACKET];
            let mut n = 0;
            let mut search = true;
            for (k, ray) in rays.iter().enumerate() {
                let found = if search { self.kept(ray) } else { None };
                match found {
                    Some(blocked) => occluded[k] = blocked,
                    None => {
                        search &= k > 0;
                        (missing[n], subset[n]) = (k, *ray);
                        n += 1;
                    }
                }
            }
            if n == rays.len() {
                self.trace(rays, occluded);
            } else if n > 0 {
                let mut answers = [false; PACKET];
                self.trace(&subset[..n], &mut answers[..n]);
                for (&k, &blocked) in missing[..n].iter().zip(&answers) {
                    occluded[k] = blocked;
                }
            }
            let mut now = self.now.borrow_mut();
            now.extend(
                rays.iter()
                    .zip(occluded.iter())
                    .map(|(&ray, &blocked)| Verdict { ray, blocked }),
            );
        }
    }
}

/// Whether two rays are the same, bit for bit (−0.0 and 0.0 differ: a walk may answer them
/// differently).
fn same_ray(a: &ShadowRay, b: &ShadowRay) -> bool {
    let bits = |r: &ShadowRay| {
        let (o, d) = (r.origin, r.direction);
        [o.x, o.y, o.z, d.x, d.y, d.z, r.t_max].map(f32::to_bits)
    };
    bits(a) == bits(b)
}
