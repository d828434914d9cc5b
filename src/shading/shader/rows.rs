//! [`brdf_value`] of many rows at once: the (N, 3) arrays of normals and directions a caller
//! holds (the Python module's `eval_brdf` passes numpy's buffers), read in place, evaluated in
//! lanes on every core, each row giving the bits the scalar call gives.
//!
//! The rows are checked in the same pass that evaluates them (a second pass over arrays of
//! 10⁶ rows would cost as much as the evaluation): [`brdf_rows`] reports whether every row was
//! plainly inside the domain, and a caller that must name the first bad row looks for it only
//! when the answer is no.

use std::mem::MaybeUninit;

use rayon::prelude::*;

use super::brdf_value;
use crate::lanes::{dot3, LaneInstructions, Lanes, Mask, Real, Scalar};
use crate::material::Material;

/// A caller's (N, 3) array of float32 or float64 values, row-major, read in place.
#[derive(Clone, Copy, Debug)]
pub enum FloatRows<'a> {
    F32(&'a [f32]),
    F64(&'a [f64]),
}

impl FloatRows<'_> {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        match self {
            FloatRows::F32(v) => v.len() / 3,
            FloatRows::F64(v) => v.len() / 3,
        }
    }

    /// Component `c` of row `i` in precision `T` (rounded once, as `T::lit` rounds).
    #[cfg(test)]
    fn get<T: Scalar>(&self, i: usize, c: usize) -> T {
        match self {
            FloatRows::F32(v) => T::of(v[3 * i + c]),
            FloatRows::F64(v) => T::lit(v[3 * i + c]),
        }
    }

    /// Rows `first..first + N` as lanes of three components, each rounded once to `T`; rows
    /// past `end` repeat the last row (their results are not written). Plain loops, the
    /// format matched once: this is the inner loop's gather.
    #[inline(always)]
    fn lanes<T: Scalar, const N: usize>(&self, first: usize, end: usize) -> [Lanes<T, N>; 3] {
        #[inline(always)]
        fn gather<S: Copy, T: Scalar, const N: usize>(
            v: &[S],
            first: usize,
            end: usize,
            to: impl Fn(S) -> T,
        ) -> [Lanes<T, N>; 3] {
            let mut lanes = [Lanes::splat(T::zero()); 3];
            for l in 0..N {
                let row = &v[3 * (first + l).min(end - 1)..][..3];
                for c in 0..3 {
                    lanes[c].0[l] = to(row[c]);
                }
            }
            lanes
        }
        match self {
            FloatRows::F32(v) => gather(v, first, end, T::of),
            FloatRows::F64(v) => gather(v, first, end, T::lit),
        }
    }
}

/// Rows a worker takes at a time: large enough that scheduling costs nothing, small enough
/// that both cores stay busy to the end.
const CHUNK_ROWS: usize = 8192;

/// What the one-pass check of [`brdf_rows`] accepts: ω_i and ω_o whose squared length is
/// within `unit_tolerance / 2` of 1 (so their length is too), and n with a finite, normal |n|²
/// (so every component of n is finite too).
#[derive(Clone, Copy, Debug)]
pub struct RowDomain {
    /// How far from 1 the caller lets |ω_i| and |ω_o| be; rows within half of it pass.
    pub unit_tolerance: f64,
}

/// f_r of row i of `n`, `wi`, `wo` (one length) at `[3i..3i + 3]` of the returned vector, for
/// f32 or f64 `T`: the bits [`brdf_value`] gives for that row in `T` (up to the sign of a zero).
/// With it, whether every row was inside `domain`. Rows outside it are evaluated too; a caller
/// that rejects such input searches for the offending row only when this says `false` (a row
/// just inside the caller's own limit may fail this stricter check, so `false` is a reason to
/// look, not a verdict).
pub fn brdf_rows<T: RowPrecision>(
    material: &Material,
    [n, wi, wo]: [FloatRows; 3],
    domain: RowDomain,
) -> (Vec<T>, bool) {
    let rows = n.rows();
    assert!(
        wi.rows() == rows && wo.rows() == rows,
        "brdf_rows: arrays of different lengths"
    );
    let instructions = RowInstructions::detect();
    // Filled in place, never zeroed first: a pass over 24 MB that the evaluation's own writes
    // make unnecessary.
    let mut out = Vec::with_capacity(3 * rows);
    let inside = out.spare_capacity_mut()[..3 * rows]
        .par_chunks_mut(3 * CHUNK_ROWS)
        .enumerate()
        .map(|(chunk, out)| {
            let first = chunk * CHUNK_ROWS;
            let job = Job {
                material,
                rows: [n, wi, wo],
                domain,
                first,
                end: first + out.len() / 3,
            };
            T::run(&job, instructions, out)
        })
        .reduce(|| true, |a, b| a && b);
    // SAFETY: the chunks cover the first 3·rows elements, and `Job::eval` writes each element
    // of its chunk.
    unsafe { out.set_len(3 * rows) };
    (out, inside)
}

/// One worker's rows `first..end` of [`brdf_rows`].
pub struct Job<'a> {
    material: &'a Material,
    rows: [FloatRows<'a>; 3],
    domain: RowDomain,
    first: usize,
    end: usize,
}

impl Job<'_> {
    /// The rows in groups of `N` lanes of `T`, results to `out` (this job's rows only, every
    /// element written).
    #[inline(always)]
    fn eval<T: Scalar, const N: usize>(&self, out: &mut [MaybeUninit<T>]) -> bool
    where
        Lanes<T, N>: Real,
    {
        let half = Lanes::<T, N>::splat(T::lit(self.domain.unit_tolerance / 2.0));
        let mut inside = true;
        let mut row = self.first;
        while row < self.end {
            let [n, wi, wo] = &self.rows;
            let (n, wi, wo) = (
                n.lanes::<T, N>(row, self.end),
                wi.lanes::<T, N>(row, self.end),
                wo.lanes::<T, N>(row, self.end),
            );
            // |ω|² − 1 = (|ω| − 1)(|ω| + 1): within tolerance/2 of 0 puts |ω| within
            // tolerance/2 of 1, without a square root.
            let unit = |v: [Lanes<T, N>; 3]| half.ge((dot3(v, v) - Lanes::splat(T::one())).abs());
            let n2 = dot3(n, n);
            let ok = unit(wi) & unit(wo) & n2.ge(Lanes::<T, N>::min_positive_value()) & n2.is_finite();
            let f = brdf_value(self.material, n, wi, wo);
            // Lanes past the end repeat the last row, so they change nothing here.
            inside &= ok.all();
            for l in 0..N.min(self.end - row) {
                let o = &mut out[3 * (row - self.first + l)..][..3];
                for c in 0..3 {
                    o[c].write(f[c].0[l]);
                }
            }
            row += N;
        }
        inside
    }
}

/// Which instructions [`brdf_rows`] runs, best last: the same bits from each (Rust never fuses
/// a multiply and an add unless asked), only fewer instructions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum RowInstructions {
    /// The target's baseline.
    Portable,
    /// AVX2: eight f32 or four f64 lanes in a 256-bit register.
    #[cfg(target_arch = "x86_64")]
    Avx2,
    /// AVX-512F: f64 rows eight to a 512-bit register (f32 rows stay on the AVX2 code).
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl RowInstructions {
    /// The best this CPU runs, detected at run time (the binary stays portable).
    pub fn detect() -> RowInstructions {
        match LaneInstructions::detect() {
            LaneInstructions::Portable => RowInstructions::Portable,
            #[cfg(target_arch = "x86_64")]
            LaneInstructions::Avx2 => RowInstructions::Avx2,
            #[cfg(target_arch = "x86_64")]
            LaneInstructions::Avx512 => RowInstructions::Avx512,
        }
    }
}

/// f32 or f64, with the lanes each evaluates rows in, per [`RowInstructions`].
pub trait RowPrecision: Scalar {
    #[doc(hidden)]
    fn run(job: &Job, instructions: RowInstructions, out: &mut [MaybeUninit<Self>]) -> bool;
}

macro_rules! row_precision {
    ($t:ty, $lanes:literal, $avx2:ident, $avx512:ident) => {
        impl RowPrecision for $t {
            fn run(job: &Job, instructions: RowInstructions, out: &mut [MaybeUninit<$t>]) -> bool {
                match instructions {
                    RowInstructions::Portable => job.eval::<$t, $lanes>(out),
                    // SAFETY: `RowInstructions::detect` found AVX2 on this CPU.
                    #[cfg(target_arch = "x86_64")]
                    RowInstructions::Avx2 => unsafe { $avx2(job, out) },
                    // SAFETY: `RowInstructions::detect` found AVX-512F (and so AVX2) on this CPU.
                    #[cfg(target_arch = "x86_64")]
                    RowInstructions::Avx512 => unsafe { $avx512(job, out) },
                }
            }
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        unsafe fn $avx2(job: &Job, out: &mut [MaybeUninit<$t>]) -> bool {
            job.eval::<$t, $lanes>(out)
        }
    };
}

// f32 rows take the AVX2 code on AVX-512 machines too: compiled for AVX-512F, eight lanes or
// sixteen, they measured slower (docs/performance-log.md).
row_precision!(f32, 8, rows_f32_avx2, rows_f32_avx2);
row_precision!(f64, 4, rows_f64_avx2, rows_f64_avx512);

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,avx512f")]
unsafe fn rows_f64_avx512(job: &Job, out: &mut [MaybeUninit<f64>]) -> bool {
    job.eval::<f64, 8>(out)
}

#[cfg(test)]
mod tests;
