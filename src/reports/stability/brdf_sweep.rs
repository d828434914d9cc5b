//! Random and adversarial BRDF evaluations: `--cases` samples of a random material and random
//! directions, each evaluated through `LocalDots::from_unit_vectors` and `Material::eval` in f32
//! and in f64 on the same f32 vectors.
//!
//! A third of the samples are adversarial: ω_i = ω_o, ω_i ≈ −ω_o, the mirror direction with a
//! tiny tilt (the peak of every lobe), grazing directions from both sides, unnormalised, zero and
//! NaN normals; material parameters are drawn from their extremes (α = 0, 1e-8, 1e-4, shininess
//! 0 and 1e6, η and κ from 0 to 1e8, ior = 1 and < 1) a fifth of the time.
//!
//! Every value of every sample must be finite and ≥ 0. The f32-vs-f64 tolerance applies to the
//! well-conditioned samples; the others (within 1e-3 of the horizon, where the one-sided cut
//! makes f_r jump; |ω_i + ω_o| < 1e-2, where the half vector is ill-defined; α < 1e-2 or
//! shininess > 1e4, where the lobe is narrower than f32 directions resolve; a weakly absorbing
//! conductor with η < 1, whose reflectance has an infinite slope at the critical angle) are
//! counted and their worst error reported, without a tolerance.

use rayon::prelude::*;

use super::case::{num, rel_err, Case, Options, Rng, REL_TOL};
use crate::brdf::{FresnelTerm, LocalDots, MaskingShadowing, MicrofacetDistribution};
use crate::material::{BlinnPhong, BrdfModel, CookTorrance, Material};

/// Masking terms: the Cook-Torrance families are the D × G pairs, D-major.
const GS: usize = MaskingShadowing::ALL.len();

/// Families the sweep reports on, one pair of rows each: Lambert, Blinn-Phong and every
/// Cook-Torrance D × G pair (a new term adds its families here by itself).
const FAMILIES: usize = 2 + MicrofacetDistribution::ALL.len() * GS;

/// The D × G pair of Cook-Torrance family `f` (f ≥ 2).
fn terms(f: usize) -> (MicrofacetDistribution, MaskingShadowing) {
    (
        MicrofacetDistribution::ALL[(f - 2) / GS],
        MaskingShadowing::ALL[(f - 2) % GS],
    )
}

fn family_name(f: usize) -> String {
    match f {
        0 => "lambert".into(),
        1 => "blinn-phong".into(),
        _ => {
            let (d, g) = terms(f);
            format!("cook-torrance {}/{}", d.name(), g.name())
        }
    }
}

/// Per-family tallies.
#[derive(Clone, Copy, Default)]
struct Tally {
    evals: [u64; 2],
    nan: u64,
    inf: u64,
    neg: u64,
    worst: [f64; 2],
    worst_input: [u64; 2],
}

impl Tally {
    fn merge(mut self, o: &Tally) -> Tally {
        for k in 0..2 {
            self.evals[k] += o.evals[k];
            if o.worst[k] > self.worst[k] {
                self.worst[k] = o.worst[k];
                self.worst_input[k] = o.worst_input[k];
            }
        }
        self.nan += o.nan;
        self.inf += o.inf;
        self.neg += o.neg;
        self
    }
}

fn pick<T: Copy>(rng: &mut Rng, items: &[T]) -> T {
    items[rng.below(items.len())]
}

/// A random material of family `f`, and whether its lobe is well-conditioned in f32.
fn material(rng: &mut Rng, f: usize) -> (Material, bool) {
    let extreme = rng.uniform() < 0.2;
    let mut m = Material::lambert(
        "sweep",
        [rng.uniform() as f32, rng.uniform() as f32, rng.uniform() as f32],
    );
    m.kd = rng.uniform() as f32;
    let color = [rng.uniform() as f32, rng.uniform() as f32, rng.uniform() as f32];
    let mut ok = true;
    match f {
        0 => {}
        1 => {
            let shininess = if extreme {
                pick(rng, &[0.0, 1.0, 1e6])
            } else {
                rng.log_uniform(1e-2, 1e6)
            };
            ok = shininess <= 1e4;
            m.model = BrdfModel::BlinnPhong(BlinnPhong {
                ks: rng.uniform() as f32,
                shininess: shininess as f32,
                color,
            });
        }
        _ => {
            let alpha = if extreme {
                pick(rng, &[0.0, 1e-8, 1e-4, 1e-3, 1.0])
            } else {
                rng.log_uniform(1e-4, 1.0)
            };
            let index = |rng: &mut Rng| {
                if extreme {
                    pick(rng, &[0.0, 1e-8, 1.0, 1e8])
                } else {
                    rng.log_uniform(1e-3, 1e3)
                }
            };
            let (eta, k) = (
                [index(rng), index(rng), index(rng)],
                [index(rng), index(rng), index(rng)],
            );
            let f_term = pick(rng, FresnelTerm::ALL);
            let weak_tir = (0..3).any(|c| eta[c] < 1.0 && k[c] < 0.1);
            ok = alpha >= 1e-2 && !(f_term == FresnelTerm::Conductor && weak_tir);
            m.model = BrdfModel::CookTorrance(CookTorrance {
                alpha: alpha as f32,
                d: terms(f).0,
                g: terms(f).1,
                f: f_term,
                metallic: rng.uniform() < 0.5,
                specular_color: color,
                ior: if extreme {
                    pick(rng, &[1.0, 0.5, 1e-3, 1e3])
                } else {
                    rng.log_uniform(0.1, 10.0)
                } as f32,
                eta: eta.map(|v| v as f32),
                k: k.map(|v| v as f32),
            });
        }
    }
    (m, ok)
}

fn add(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|v| v / l)
}

/// Random (n, ω_i, ω_o), rounded to f32, and whether the configuration is well-conditioned.
fn directions(rng: &mut Rng) -> ([f32; 3], [f32; 3], [f32; 3], bool) {
    let n = rng.direction();
    let mut wo = rng.direction();
    if dot(n, wo) < 0.0 && rng.uniform() < 0.8 {
        wo = wo.map(|v| -v);
    }
    let mut wi = rng.direction();
    if dot(n, wi) < 0.0 && rng.uniform() < 0.8 {
        wi = wi.map(|v| -v);
    }
    let mut n_out = n;
    if rng.uniform() < 1.0 / 3.0 {
        match rng.below(6) {
            0 => wi = wo,
            1 => wi = normalize(add(wo.map(|v| -v), rng.direction(), rng.log_uniform(1e-8, 1e-2))),
            2 => {
                // Mirror of ω_o about n, tilted a little: the peak of every lobe.
                let mirror = add(wo.map(|v| -v), n, 2.0 * dot(n, wo));
                wi = normalize(add(mirror, rng.direction(), rng.log_uniform(1e-8, 1e-1)));
            }
            3 => {
                // Grazing, from above or below: n·ω_i = ±ε.
                let e = rng.log_uniform(1e-9, 1e-3) * if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
                let t = normalize(add(rng.direction(), n, -dot(rng.direction(), n)));
                let t = normalize(add(t, n, -dot(t, n)));
                wi = add(t.map(|v| v * (1.0 - e * e).sqrt()), n, e);
            }
            4 => n_out = n.map(|v| v * rng.log_uniform(1e-3, 1e3)),
            _ => n_out = pick(rng, &[[0.0; 3], [f64::NAN, 0.0, 1.0], [0.0, 0.0, 1e-30]]),
        }
    }
    let (n32, wi32, wo32) = (n_out.map(|v| v as f32), wi.map(|v| v as f32), wo.map(|v| v as f32));
    // Conditioning, judged on the vectors both precisions see.
    let (nn, i, o) = (n32.map(f64::from), wi32.map(f64::from), wo32.map(f64::from));
    let n_len = dot(nn, nn).sqrt();
    let well = n_len > 1e-3
        && (dot(nn, i) / n_len).abs() >= 1e-3
        && (dot(nn, o) / n_len).abs() >= 1e-3
        && dot(add(i, o, 1.0), add(i, o, 1.0)).sqrt() >= 1e-2;
    (n32, wi32, wo32, well)
}

fn eval<R: crate::lanes::Scalar>(m: &Material, n: [f32; 3], wi: [f32; 3], wo: [f32; 3]) -> [f64; 3] {
    let cast = |v: [f32; 3]| v.map(R::of);
    match LocalDots::from_unit_vectors(cast(n), cast(wi), cast(wo)) {
        Some(d) => m.eval(&d).map(|v| v.as_f64()),
        None => [0.0; 3],
    }
}

/// One chunk of samples, with its own random stream.
fn chunk(seed: u64, index: u64, samples: u64) -> Vec<Tally> {
    let mut rng = Rng::new(seed, index);
    let mut tallies = vec![Tally::default(); FAMILIES];
    for s in 0..samples {
        let f = rng.below(FAMILIES);
        let (m, lobe_ok) = material(&mut rng, f);
        let (n, wi, wo, dirs_ok) = directions(&mut rng);
        let (v32, v64) = (eval::<f32>(&m, n, wi, wo), eval::<f64>(&m, n, wi, wo));
        let t = &mut tallies[f];
        let class = if lobe_ok && dirs_ok { 0 } else { 1 };
        t.evals[class] += 1;
        let mut worst = 0.0f64;
        for (a, b) in v32.iter().zip(&v64) {
            for v in [*a, *b] {
                t.nan += v.is_nan() as u64;
                t.inf += v.is_infinite() as u64;
                t.neg += (v < 0.0) as u64;
            }
            worst = worst.max(rel_err(*a, *b));
        }
        if worst > t.worst[class] {
            t.worst[class] = worst;
            t.worst_input[class] = index << 32 | s;
        }
    }
    tallies
}

/// The sweep's rows: per family, the well-conditioned samples (tolerance applies) and the rest.
pub fn run(options: &Options) -> Vec<Case> {
    const CHUNK: u64 = 1 << 16;
    let chunks = options.cases.div_ceil(CHUNK);
    let totals = (0..chunks)
        .into_par_iter()
        .map(|k| chunk(options.seed, k, CHUNK.min(options.cases - k * CHUNK)))
        .reduce(
            || vec![Tally::default(); FAMILIES],
            |a, b| a.iter().zip(&b).map(|(x, y)| x.merge(y)).collect(),
        );
    let mut out = Vec::new();
    for (f, t) in totals.iter().enumerate() {
        for class in 0..2 {
            let what = if class == 0 {
                "random, well-conditioned"
            } else {
                "adversarial / ill-conditioned"
            };
            let mut c = Case::new(
                "brdf-sweep",
                format!("{} {what}", family_name(f)),
                "random materials and directions",
            );
            c.evals = 2 * t.evals[class];
            // NaN/Inf/negative tallies are per family; report them on the first row.
            if class == 0 {
                (c.nan, c.inf, c.neg) = (t.nan, t.inf, t.neg);
            }
            c.rel_err = Some(t.worst[class]);
            c.f32_value = format!("{} samples", t.evals[class]);
            c.f64_value = format!("worst at #{:x}", t.worst_input[class]);
            c.require_clean();
            if class == 0 {
                if t.worst[class] > REL_TOL {
                    c.fail(format!("relative error {} > {REL_TOL:.0e}", num(t.worst[class])));
                }
            } else {
                c.singular = Some(
                    "ill-conditioned samples (horizon, ω_i ≈ −ω_o, α < 1e-2, shininess > 1e4, η < 1 with κ < 0.1): finite and ≥ 0 required, error reported".into(),
                );
            }
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_sweep_is_clean_and_within_tolerance() {
        let options = Options {
            cases: 40_000,
            seed: 7,
            shared_meshes: None,
        };
        let rows = run(&options);
        assert_eq!(rows.len(), 2 * FAMILIES);
        let evals: u64 = rows.iter().map(|c| c.evals).sum();
        assert_eq!(evals, 2 * 40_000);
        for c in &rows {
            assert!(c.passed(), "{}: {:?}", c.name, c.failure);
        }
    }

    #[test]
    fn the_sweep_is_deterministic_for_a_seed() {
        let a = chunk(3, 1, 2000);
        let b = chunk(3, 1, 2000);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!((x.evals, x.worst, x.worst_input), (y.evals, y.worst, y.worst_input));
        }
    }
}
