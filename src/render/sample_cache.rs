//! The samples one tile's passes traced, kept by film position, so that a time budget's finer
//! thresholds trace only positions the coarser ones did not ([`SampleCache`]).

use std::collections::hash_map::{Entry, HashMap};
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;

use super::tile::{PixelSums, SampleJob};

/// The samples one tile's passes traced, by film position: a sample is a pure function of its
/// position, so a finer pass reuses what a coarser one traced at the same cell centre or Sobol
/// point (the cells and rounds of a finer threshold revisit most of them).
pub struct SampleCache<'a> {
    /// Film position's bits → index into the sample arrays.
    index: HashMap<u64, u32, BuildHasherDefault<PositionHasher>>,
    radiance: Vec<Vec3>,
    surface: Vec<u32>,
    aovs: Vec<Vec<Vec3>>,
    /// How many more samples all tiles together may keep.
    room: &'a AtomicUsize,
    misses: Vec<SampleJob>,
    places: Vec<u32>,
    fresh: PixelSums,
}

/// The hasher of the cache's keys, a film position's two `f32` bit patterns, far cheaper than
/// the standard SipHash: a 64×64 → 128-bit multiply by the golden ratio's constant, folded
/// (high half XOR low half), so that every key bit reaches the low bits the table indexes with
/// (sub-pixel positions such as y + 5/64 have mostly zero low mantissa bits).
#[derive(Default)]
struct PositionHasher(u64);

impl PositionHasher {
    fn mix(&mut self, v: u64) {
        let product = u128::from(self.0 ^ v) * 0x9e37_79b9_7f4a_7c15;
        self.0 = (product as u64) ^ ((product >> 64) as u64);
    }
}

impl Hasher for PositionHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.mix(u64::from(b));
        }
    }

    fn write_u64(&mut self, v: u64) {
        self.mix(v);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

impl<'a> SampleCache<'a> {
    pub(super) fn new(room: &'a AtomicUsize) -> Self {
        Self {
            index: HashMap::default(),
            radiance: Vec::new(),
            surface: Vec::new(),
            aovs: Vec::new(),
            room,
            misses: Vec::new(),
            places: Vec::new(),
            fresh: PixelSums::new(0, 0),
        }
    }

    /// Adds each job's sample to its slot of `sums`, as `trace` would, tracing (with `trace`)
    /// only positions not kept yet, and keeping those while there is room. Slots add their
    /// samples in job order, so the sums have the bits `trace` alone gives.
    pub fn trace(
        &mut self,
        jobs: &[SampleJob],
        sums: &mut PixelSums,
        trace: &mut dyn FnMut(&[SampleJob], &mut PixelSums),
    ) {
        let naovs = sums.aovs.len();
        self.aovs.resize_with(naovs, Vec::new);
        self.fresh.aovs.resize_with(naovs, Vec::new);
        let key = |job: &SampleJob| u64::from(job.film.x.to_bits()) << 32 | u64::from(job.film.y.to_bits());
        let keep = self
            .room
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |r| r.checked_sub(jobs.len()))
            .is_ok();
        // Positions not kept yet are traced into `fresh` (slot = their place in `misses`);
        // with room, they are kept under the next indices (a position listed twice, once).
        // `places` says where each job's sample will be: kept (index) or fresh (!slot).
        self.misses.clear();
        self.places.clear();
        let base = self.radiance.len();
        for job in jobs {
            let fresh = !(self.misses.len() as u32);
            let place = match self.index.entry(key(job)) {
                Entry::Occupied(e) => *e.get(),
                Entry::Vacant(e) if keep => *e.insert((base + self.misses.len()) as u32),
                Entry::Vacant(_) => fresh,
            };
            self.places.push(place);
            if place == fresh || place as usize == base + self.misses.len() {
                let slot = self.misses.len() as u32;
                self.misses.push(SampleJob { slot, film: job.film });
            }
        }
        self.fresh.reset(self.misses.len());
        trace(&self.misses, &mut self.fresh);
        if keep {
            self.radiance.extend_from_slice(&self.fresh.radiance);
            self.surface.extend_from_slice(&self.fresh.surface);
            for (kept, fresh) in self.aovs.iter_mut().zip(&self.fresh.aovs) {
                kept.extend_from_slice(fresh);
            }
            // Give back the room of the positions that were already kept.
            self.room.fetch_add(jobs.len() - self.misses.len(), Ordering::Relaxed);
        }
        // Every slot adds its samples in job order, kept or fresh.
        for (job, &place) in jobs.iter().zip(&self.places) {
            if (place as usize) < self.radiance.len() {
                add(job, place as usize, &self.radiance, &self.surface, &self.aovs, sums);
            } else {
                let f = &self.fresh;
                add(job, !place as usize, &f.radiance, &f.surface, &f.aovs, sums);
            }
        }
    }
}

/// Adds sample `i` of the arrays to `job`'s slot of `sums`, as `Context::trace` adds a sample.
fn add(job: &SampleJob, i: usize, radiance: &[Vec3], surface: &[u32], aovs: &[Vec<Vec3>], sums: &mut PixelSums) {
    let slot = job.slot as usize;
    sums.radiance[slot] += radiance[i];
    // A sample that hit nothing leaves the slot's surface as it was.
    if surface[i] != 0 {
        sums.surface[slot] = surface[i];
    }
    for (sum, values) in sums.aovs.iter_mut().zip(aovs) {
        sum[slot] += values[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An analytic trace: adds f(position) to each job's slot (hits where x < 3, surface 2),
    /// and counts the samples it traced.
    fn analytic(traced: &mut usize) -> impl FnMut(&[SampleJob], &mut PixelSums) + '_ {
        move |jobs, sums| {
            for job in jobs {
                *traced += 1;
                let v = (job.film.x * 0.37 + job.film.y * 0.11).sin().abs();
                if job.film.x < 3.0 {
                    sums.radiance[job.slot as usize] += Vec3::new(v, 0.1 * v, 1.0 / 3.0 + v);
                    sums.aovs[0][job.slot as usize] += Vec3::splat(v * v);
                    sums.surface[job.slot as usize] = 2;
                }
            }
        }
    }

    #[test]
    fn the_cache_adds_the_bits_tracing_adds_and_traces_each_position_once() {
        let job = |slot, x, y| SampleJob {
            slot,
            film: glam::Vec2::new(x, y),
        };
        // Three calls over two slots, with a position repeated within a call and across calls.
        let calls = [
            vec![
                job(0, 0.5, 0.5),
                job(0, 1.25, 0.75),
                job(1, 3.5, 0.5),
                job(0, 1.25, 0.75),
            ],
            vec![
                job(1, 3.5, 0.5),
                job(1, 2.5, 0.25),
                job(0, 0.5, 0.5),
                job(0, 0.125, 0.875),
            ],
            vec![job(0, 0.125, 0.875), job(1, 2.5, 0.25), job(1, 4.5, 0.5)],
        ];
        let bits = |s: &PixelSums| {
            let v =
                [&s.radiance, &s.aovs[0]].map(|b| b.iter().map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>());
            (v, s.surface.clone())
        };
        let mut traced = 0;
        let mut plain = PixelSums::new(2, 1);
        calls.iter().for_each(|c| analytic(&mut traced)(c, &mut plain));
        assert_eq!(traced, 11);
        // Six positions. With room for every sample each is traced once; with room for none
        // nothing is kept and all eleven jobs are traced.
        for (room, traced_by_cache) in [(usize::MAX, 6), (0, 11)] {
            let room = AtomicUsize::new(room);
            let mut cache = SampleCache::new(&room);
            let (mut sums, mut traced) = (PixelSums::new(2, 1), 0);
            for c in &calls {
                cache.trace(c, &mut sums, &mut analytic(&mut traced));
            }
            assert_eq!(bits(&sums), bits(&plain));
            assert_eq!(traced, traced_by_cache);
        }
    }
}
