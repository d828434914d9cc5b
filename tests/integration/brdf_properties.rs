//! Property tests of the BRDF module (proptest): random and adversarial inputs, over 1e6
//! evaluations in all. Every model: finite and non-negative for any input, reciprocal
//! (f(ω_i, ω_o) = f(ω_o, ω_i)); Lambert's white furnace returns k_d·albedo; the normalised
//! Cook-Torrance lobes (Smith masking, F ≤ 1) never reflect more than they receive.

use pointshade::brdf::{FresnelTerm, LocalDots, MaskingShadowing, MicrofacetDistribution};

use pointshade::lanes::Scalar;
use pointshade::material::{BlinnPhong, BrdfModel, CookTorrance, Material};
use proptest::prelude::*;
use std::f64::consts::PI;

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (l > 1e-6).then(|| v.map(|c| c / l))
}

fn direction() -> impl Strategy<Value = [f64; 3]> {
    [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0].prop_filter_map("non-zero", unit)
}

/// Roughness: random, and the extremes the issue lists.
fn alpha() -> impl Strategy<Value = f32> {
    prop_oneof![3 => 1e-4f32..1.0, 1 => prop::sample::select(vec![0.0f32, 1e-8, 1e-4, 1.0])]
}

fn cook_torrance() -> impl Strategy<Value = Material> {
    (
        alpha(),
        prop::sample::select(MicrofacetDistribution::ALL.to_vec()),
        prop::sample::select(MaskingShadowing::ALL.to_vec()),
        prop::sample::select(FresnelTerm::ALL.to_vec()),
        any::<bool>(),
        prop_oneof![0.01f32..10.0, Just(1.0f32)],
        prop::array::uniform3(prop_oneof![0.0f32..5.0, Just(0.0), Just(1e8)]),
        prop::array::uniform3(prop_oneof![0.0f32..5.0, Just(0.0), Just(1e8)]),
    )
        .prop_map(|(alpha, d, g, f, metallic, ior, eta, k)| Material {
            kd: 0.0,
            model: BrdfModel::CookTorrance(CookTorrance {
                alpha,
                d,
                g,
                f,
                metallic,
                specular_color: [0.9, 0.6, 1.0],
                ior,
                eta,
                k,
            }),
            ..Material::lambert("ct", [0.5; 3])
        })
}

fn any_material() -> impl Strategy<Value = Material> {
    prop_oneof![
        (0.0f32..1.0, 0.0f32..1.0).prop_map(|(kd, a)| Material {
            kd,
            ..Material::lambert("l", [a, 0.5, 1.0])
        }),
        (0.0f32..2.0, prop_oneof![0.0f32..1e6, Just(0.0), Just(1.0), Just(1e6)]).prop_map(|(ks, s)| Material {
            model: BrdfModel::BlinnPhong(BlinnPhong {
                ks,
                shininess: s,
                color: [1.0, 0.5, 0.25],
            }),
            ..Material::lambert("bp", [0.5; 3])
        }),
        cook_torrance(),
    ]
}

fn eval<R: Scalar>(m: &Material, n: [f64; 3], wi: [f64; 3], wo: [f64; 3]) -> Option<[f64; 3]> {
    let c = |v: [f64; 3]| v.map(|x| R::lit(x as f32 as f64));
    LocalDots::from_unit_vectors(c(n), c(wi), c(wo)).map(|d| m.eval(&d).map(|v| v.as_f64()))
}

/// Directional albedo ∫ f cos θ_i dω_i of a Cook-Torrance lobe, integrated over half vectors
/// (dω_i = 4 |ω_o·ω_h| dω_h) with θ_h = atan(a·tan(πu/2)), which crowds samples into a lobe of
/// width ~a, and the midpoint rule in u and φ. Returns the albedo and the evaluation count.
fn directional_albedo(m: &Material, cos_o: f64, a: f64) -> (f64, u64) {
    let (nu, nphi) = (400, 96);
    let wo = [(1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o];
    let (mut sum, mut evals) = (0.0, 0);
    for i in 0..nu {
        let u = (i as f64 + 0.5) / nu as f64;
        let t = (PI / 2.0 * u).tan();
        let theta = (a * t).atan();
        let dtheta = a * PI / 2.0 * (1.0 + t * t) / (1.0 + a * a * t * t) / nu as f64;
        for j in 0..nphi {
            let phi = 2.0 * PI * (j as f64 + 0.5) / nphi as f64;
            let h = [theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()];
            let oh = wo[0] * h[0] + wo[2] * h[2];
            let wi = [0, 1, 2].map(|k| 2.0 * oh * h[k] - wo[k]);
            if wi[2] <= 0.0 || oh <= 0.0 {
                continue;
            }
            if let Some(f) = eval::<f64>(m, [0.0, 0.0, 1.0], wi, wo) {
                evals += 1;
                sum += f[1] * wi[2] * 4.0 * oh * theta.sin() * dtheta * 2.0 * PI / nphi as f64;
            }
        }
    }
    (sum, evals)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 20_000, failure_persistence: None, ..ProptestConfig::default() })]

    /// 20k materials × 12 direction sets × 2 precisions × 2 orders ≈ 1e6 evaluations.
    #[test]
    fn finite_non_negative_and_reciprocal(
        m in any_material(),
        dirs in prop::collection::vec((direction(), direction(), direction(), 0u8..5), 12),
    ) {
        for (n, wi, wo, mode) in dirs {
            // Adversarial modes: ω_i = ω_o, ω_i = −ω_o, grazing ω_i, an unnormalised normal.
            let (n, wi) = match mode {
                0 => (n, wo),
                1 => (n, wo.map(|v| -v)),
                2 => {
                    let d = wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2];
                    let t = unit([wi[0] - d * n[0], wi[1] - d * n[1], wi[2] - d * n[2]]).unwrap_or(wi);
                    (n, unit([t[0] + 1e-7 * n[0], t[1] + 1e-7 * n[1], t[2] + 1e-7 * n[2]]).unwrap_or(wi))
                }
                3 => (n.map(|v| v * 37.0), wi),
                _ => (n, wi),
            };
            for v in [eval::<f32>(&m, n, wi, wo), eval::<f64>(&m, n, wi, wo)].into_iter().flatten() {
                prop_assert!(v.iter().all(|c| c.is_finite() && *c >= 0.0), "{:?} at {:?}", v, (n, wi, wo));
            }
            // Reciprocity: every model is symmetric in ω_i, ω_o, and LocalDots computes
            // ω_i·ω_h = |ω_i + ω_o|/2, symmetric by construction.
            if let (Some(a), Some(b)) = (eval::<f64>(&m, n, wi, wo), eval::<f64>(&m, n, wo, wi)) {
                for c in 0..3 {
                    prop_assert!((a[c] - b[c]).abs() <= 1e-12 * a[c].max(b[c]), "{} vs {}", a[c], b[c]);
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn lambert_white_furnace_returns_kd_times_albedo(kd in 0.0f32..1.0, albedo in 0.0f32..1.0, n in direction()) {
        // ∫ f cos θ dω over the hemisphere, midpoint rule in (cos θ, φ) around n.
        let m = Material { kd, ..Material::lambert("l", [albedo; 3]) };
        let t = unit(if n[0].abs() < 0.9 { [0.0, -n[2], n[1]] } else { [-n[2], 0.0, n[0]] }).unwrap();
        let b = [n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]];
        let (nc, nphi) = (64, 64);
        let mut sum = 0.0;
        for i in 0..nc {
            let c = (i as f64 + 0.5) / nc as f64;
            let s = (1.0 - c * c).sqrt();
            for j in 0..nphi {
                let phi = 2.0 * PI * (j as f64 + 0.5) / nphi as f64;
                let wi = [0, 1, 2].map(|k| s * phi.cos() * t[k] + s * phi.sin() * b[k] + c * n[k]);
                let f = eval::<f64>(&m, n, wi, n).unwrap();
                sum += f[0] * c / nc as f64 * 2.0 * PI / nphi as f64;
            }
        }
        let expect = kd as f64 * albedo as f64;
        prop_assert!((sum - expect).abs() <= 1e-6 * expect.max(1e-9), "{} vs {}", sum, expect);
    }

    /// 48 materials × 3 view angles × ~38k evaluations ≈ 5e6 evaluations.
    #[test]
    fn normalised_cook_torrance_albedo_is_at_most_one(
        alpha in 0.02f32..1.0,
        d in prop::sample::select(MicrofacetDistribution::ALL.to_vec()),
        g in prop::sample::select(vec![MaskingShadowing::SmithGgx, MaskingShadowing::SmithGgxCorrelated]),
        f in prop::sample::select(vec![FresnelTerm::Schlick, FresnelTerm::Conductor, FresnelTerm::Constant]),
    ) {
        let m = Material {
            kd: 0.0,
            model: BrdfModel::CookTorrance(CookTorrance {
                alpha, d, g, f,
                metallic: true,
                specular_color: [1.0; 3],
                eta: [0.2; 3],
                k: [3.9; 3],
                ..CookTorrance::default()
            }),
            ..Material::lambert("ct", [0.0; 3])
        };
        for cos_o in [1.0, 0.5, 0.1] {
            let (albedo, evals) = directional_albedo(&m, cos_o, alpha as f64);
            prop_assert!(evals > 10_000);
            // Quadrature error is well below 1%; Smith masking makes the exact value < 1.
            prop_assert!(albedo <= 1.01, "albedo {} at cos_o {} for {:?}", albedo, cos_o, m.model);
            prop_assert!(albedo > 0.0);
        }
    }
}
