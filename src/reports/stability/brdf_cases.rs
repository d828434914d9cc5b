//! Fixed BRDF cases: every term and model at its singular and extreme inputs (α → 0, grazing
//! angles, ω_i = −ω_o, huge exponents and indices), each in
//! f32 and f64 through the same generic function, with the value the singular ones must take.
//!
//! Documented values (tested here and next to each term):
//! - α = 0 and α = 1e-8 are raised to `MIN_ALPHA` = 1e-4: the GGX peak is 1/(π·1e-8) ≈ 3.2e7;
//! - D = 0 where n·ω_h ≤ 0 (χ⁺); V = 0 (and G = 0) where n·ω_i ≤ 0 or n·ω_o ≤ 0, so grazing
//!   directions from below give 0 and from above a finite value bounded by ~1/α²;
//! - ω_i = −ω_o, zero and NaN normals: no shading frame, the light contributes 0;
//! - an unnormalised normal gives the value of its direction;
//! - Blinn-Phong: 0⁰ = 1 (shininess 0 is the constant k_s);
//! - ior = 1: F0 = 0; ior < 1: F0 of 1/ior (Schlick is symmetric);
//! - conductor η, κ beyond 1e8 are clamped (F = 1 to 4e-8 there); A = 0 (a lossless medium at
//!   its critical angle) gives 1.
//!
//! The singular rows are the narrow lobes evaluated from f32 *vectors*: the half vector's
//! direction is only known to ~1e-7 rad in f32, so D relative to a lobe of width α is known to
//! about 2e-8/α (2.2e-4 at α = 1e-4; α ≥ 1e-3 stays within 1e-5) — an ill-conditioned input, not a formulation defect (given sin²θ_h, the term itself
//! is exact to 1e-7, see the term-level rows). Their rows check the bound 1e-6/α instead.
//! Blinn-Phong with s = 1e6 from vectors stays within 2e-6 thanks to the ln_1p form.

use super::case::{num, rel_err, Case, REL_TOL};
use crate::brdf::{
    blinn_phong, fresnel_conductor, fresnel_schlick, fresnel_schlick_sg, lambert, schlick_f0_dielectric, LocalDots,
    MaskingShadowing, MicrofacetDistribution,
};
use crate::lanes::Scalar;
use crate::material::{BlinnPhong, BrdfModel, CookTorrance, Material};

/// What one case evaluates; every input is rounded to f32 first, so both precisions see the
/// same numbers.
#[derive(Clone, Debug)]
enum Eval {
    /// D(n·ω_h, sin²θ_h, α).
    D(MicrofacetDistribution, f64, f64, f64),
    /// G(n·ω_i, n·ω_o, α).
    G(MaskingShadowing, f64, f64, f64),
    /// V = G / (4 n·ω_i n·ω_o).
    V(MaskingShadowing, f64, f64, f64),
    /// Schlick F(F0, ω_i·ω_h).
    Schlick(f64, f64),
    /// Schlick with Karis' exponent.
    SchlickSg(f64, f64),
    /// Schlick's F0 of a dielectric of this ior.
    F0(f64),
    /// Conductor F(ω_i·ω_h, η, κ).
    Conductor(f64, f64, f64),
    /// Blinn-Phong (n·ω_h, sin²θ_h, shininess), k_s = 1.
    BlinnPhong(f64, f64, f64),
    /// Lambert (k_d, albedo).
    Lambert(f64, f64),
    /// A material's f_r (green channel) from vectors n, ω_i, ω_o; 0 without a frame.
    Material(Box<Material>, [f64; 3], [f64; 3], [f64; 3]),
    /// A material's f_r from vectors, but through the four cosines only (sin²θ_h recovered from
    /// the rounded n·ω_h): the formulation LocalDots replaced.
    MaterialFromCosines(Box<Material>, [f64; 3], [f64; 3], [f64; 3]),
}

fn r<R: Scalar>(v: f64) -> R {
    R::lit(v as f32 as f64)
}

fn value<R: Scalar>(e: &Eval) -> R {
    match e {
        Eval::D(d, c, s2, a) => d.eval(r(*c), r(*s2), r(*a)),
        Eval::G(g, ci, co, a) => g.g(r(*ci), r(*co), r(*a)),
        Eval::V(g, ci, co, a) => g.visibility(r(*ci), r(*co), r(*a)),
        Eval::Schlick(f0, c) => fresnel_schlick(r(*f0), r(*c)),
        Eval::SchlickSg(f0, c) => fresnel_schlick_sg(r(*f0), r(*c)),
        Eval::F0(ior) => schlick_f0_dielectric(r(*ior)),
        Eval::Conductor(c, eta, k) => fresnel_conductor(r(*c), r(*eta), r(*k)),
        Eval::BlinnPhong(c, s2, s) => blinn_phong(R::one(), r(*c), r(*s2), *s as f32),
        Eval::Lambert(kd, albedo) => lambert(r(*kd), r(*albedo)),
        Eval::Material(m, n, wi, wo) => {
            match LocalDots::from_unit_vectors(n.map(r::<R>), wi.map(r::<R>), wo.map(r::<R>)) {
                Some(d) => m.eval(&d)[1],
                None => R::zero(),
            }
        }
        Eval::MaterialFromCosines(m, n, wi, wo) => {
            match LocalDots::from_unit_vectors(n.map(r::<R>), wi.map(r::<R>), wo.map(r::<R>)) {
                Some(d) => m.eval(&LocalDots::from_cosines(d.n_dot_i, d.n_dot_o, d.n_dot_h, d.i_dot_h))[1],
                None => R::zero(),
            }
        }
    }
}

/// How a case is judged besides "finite and non-negative in both precisions".
enum Expect {
    /// f32 within `REL_TOL` of f64.
    Match,
    /// f32 within `REL_TOL` of f64, and f64 equal to this documented value (to 1e-6).
    Value(f64),
    /// Singular: f32 within `bound` of f64 (relative), for the stated reason.
    Singular(f64, String),
}

fn case(name: &str, inputs: &str, eval: Eval, expect: Expect) -> Case {
    let mut c = Case::new("brdf", name, inputs);
    let (v32, v64) = (value::<f32>(&eval) as f64, value::<f64>(&eval));
    c.count(v32);
    c.count(v64);
    c.f32_value = num(v32);
    c.f64_value = num(v64);
    let rel = rel_err(v32, v64);
    c.rel_err = Some(rel);
    c.require_clean();
    match expect {
        Expect::Match => {
            if rel > REL_TOL {
                c.fail(format!("relative error {rel:.1e} > {REL_TOL:.0e}"));
            }
        }
        Expect::Value(want) => {
            if rel > REL_TOL {
                c.fail(format!("relative error {rel:.1e} > {REL_TOL:.0e}"));
            }
            if (v64 - want).abs() > 1e-6 * want.abs().max(1e-30) {
                c.fail(format!("value {} is not the documented {}", num(v64), num(want)));
            }
            c.f64_value = format!("{} (= {})", num(v64), num(want));
        }
        Expect::Singular(bound, reason) => {
            if rel > bound {
                c.fail(format!("relative error {rel:.1e} > its bound {bound:.0e}"));
            }
            c.singular = Some(reason);
        }
    }
    c
}

/// A pure Cook-Torrance material (k_d = 0) with the given terms.
fn ct(d: MicrofacetDistribution, g: MaskingShadowing, alpha: f32) -> Box<Material> {
    Box::new(Material {
        kd: 0.0,
        model: BrdfModel::CookTorrance(CookTorrance {
            alpha,
            d,
            g,
            ..CookTorrance::default()
        }),
        ..Material::lambert("ct", [0.5; 3])
    })
}

fn bp(shininess: f32) -> Box<Material> {
    Box::new(Material {
        kd: 0.0,
        model: BrdfModel::BlinnPhong(BlinnPhong {
            ks: 1.0,
            shininess,
            color: [1.0; 3],
        }),
        ..Material::lambert("bp", [0.5; 3])
    })
}

/// A mirror pair at 0.7 rad around +Z and a normal tilted by θ_h (the half vector is +Z, at
/// angle θ_h from the normal), all turned by a fixed generic rotation so that no component is
/// exactly 0 or 1 (axis-aligned vectors would make the f32 arithmetic exact).
fn tilted(theta_h: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let t = 0.7f64;
    let turn = |v: [f64; 3]| {
        // Rodrigues: 1.1 rad about the unit axis (0.36, 0.48, 0.8).
        let (k, a) = ([0.36, 0.48, 0.8], 1.1f64);
        let kv = [
            k[1] * v[2] - k[2] * v[1],
            k[2] * v[0] - k[0] * v[2],
            k[0] * v[1] - k[1] * v[0],
        ];
        let kd = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
        [0, 1, 2].map(|i| v[i] * a.cos() + kv[i] * a.sin() + k[i] * kd * (1.0 - a.cos()))
    };
    (
        turn([theta_h.sin(), 0.0, theta_h.cos()]),
        turn([t.sin(), 0.0, t.cos()]),
        turn([-t.sin(), 0.0, t.cos()]),
    )
}

const PI: f64 = std::f64::consts::PI;

/// Every fixed case, in table order.
pub fn run() -> Vec<Case> {
    use MaskingShadowing as G;
    use MicrofacetDistribution as D;
    let mut out = Vec::new();

    // D: roughness extremes at the peak and in the tail; half vectors at and below the horizon.
    for d in D::ALL {
        for alpha in [0.0, 1e-8, 1e-4, 1.0] {
            let peak = 1.0 / (PI * (alpha as f32 as f64).max(1e-4).powi(2));
            let name = format!("D {} peak", d.name());
            out.push(case(
                &name,
                &format!("α={alpha:e}, θh=0"),
                Eval::D(*d, 1.0, 0.0, alpha),
                Expect::Value(peak),
            ));
            let t = 0.3f64;
            let name = format!("D {} tail", d.name());
            let inputs = format!("α={alpha:e}, θh=0.3");
            out.push(case(
                &name,
                &inputs,
                Eval::D(*d, t.cos(), t.sin().powi(2), alpha),
                Expect::Match,
            ));
        }
        let narrow = 1e-4f64;
        let name = format!("D {} narrow, given sin²θh", d.name());
        let eval = Eval::D(*d, narrow.cos(), narrow.sin().powi(2), narrow);
        out.push(case(&name, "α=1e-4, θh=α", eval, Expect::Match));
        let name = format!("D {} half vector on horizon", d.name());
        out.push(case(
            &name,
            "n·h=0, α=0.5",
            Eval::D(*d, 0.0, 1.0, 0.5),
            Expect::Value(0.0),
        ));
        let name = format!("D {} half vector below", d.name());
        out.push(case(
            &name,
            "n·h=-0.5, α=0.5",
            Eval::D(*d, -0.5, 0.75, 0.5),
            Expect::Value(0.0),
        ));
    }

    // G and V: grazing from above and below, exactly 0, roughness extremes.
    for g in G::ALL {
        let n = g.name();
        out.push(case(
            &format!("V {n} grazing 0+"),
            "n·ωi=1e-30, n·ωo=0.7, α=0.5",
            Eval::V(*g, 1e-30, 0.7, 0.5),
            Expect::Match,
        ));
        out.push(case(
            &format!("V {n} grazing 0-"),
            "n·ωi=-1e-30, n·ωo=0.7",
            Eval::V(*g, -1e-30, 0.7, 0.5),
            Expect::Value(0.0),
        ));
        out.push(case(
            &format!("G {n} grazing 0"),
            "n·ωi=0, n·ωo=0.7",
            Eval::G(*g, 0.0, 0.7, 0.5),
            Expect::Value(0.0),
        ));
        out.push(case(
            &format!("V {n} both grazing, α=0"),
            "n·ωi=n·ωo=1e-30, α=0",
            Eval::V(*g, 1e-30, 1e-30, 0.0),
            Expect::Match,
        ));
        out.push(case(
            &format!("V {n} normal incidence"),
            "n·ωi=n·ωo=1, α=1",
            Eval::V(*g, 1.0, 1.0, 1.0),
            Expect::Match,
        ));
        out.push(case(
            &format!("G {n} α=1e-8"),
            "n·ωi=0.3, n·ωo=0.9",
            Eval::G(*g, 0.3, 0.9, 1e-8),
            Expect::Match,
        ));
    }

    // F: Schlick at the ends of its range, ior = 1 and ior < 1, conductor extremes.
    out.push(case("F0 ior=1", "ior=1", Eval::F0(1.0), Expect::Value(0.0)));
    out.push(case(
        "F0 ior<1",
        "ior=0.5 (= ior 2)",
        Eval::F0(0.5),
        Expect::Value(1.0 / 9.0),
    ));
    out.push(case(
        "F schlick ior=1",
        "F0=0, ωi·ωh=0.5",
        Eval::Schlick(0.0, 0.5),
        Expect::Value(0.5f64.powi(5)),
    ));
    out.push(case(
        "F schlick grazing",
        "F0=0.04, ωi·ωh=0",
        Eval::Schlick(0.04, 0.0),
        Expect::Value(1.0),
    ));
    out.push(case(
        "F schlick below",
        "F0=0.04, ωi·ωh=-0.3",
        Eval::Schlick(0.04, -0.3),
        Expect::Value(1.0),
    ));
    out.push(case(
        "F schlick-sg grazing",
        "F0=0.04, ωi·ωh=0",
        Eval::SchlickSg(0.04, 0.0),
        Expect::Value(1.0),
    ));
    out.push(case(
        "F schlick-sg normal",
        "F0=0.04, ωi·ωh=1",
        Eval::SchlickSg(0.04, 1.0),
        Expect::Match,
    ));
    let conductor = [
        ("F conductor η=κ=0", "c=1", 1.0, 0.0, 0.0, Some(1.0)),
        ("F conductor index match", "η=1, κ=0, c=0.7", 0.7, 1.0, 0.0, Some(0.0)),
        (
            "F conductor critical angle",
            "η=1, κ=0, c=0 (A=0)",
            0.0,
            1.0,
            0.0,
            Some(1.0),
        ),
        ("F conductor near match", "η=1.001, κ=0, c=1", 1.0, 1.001, 0.0, None),
        (
            "F conductor weak absorber",
            "η=0.5, κ=1e-3, c=0.3",
            0.3,
            0.5,
            1e-3,
            None,
        ),
        ("F conductor tiny η, κ", "η=κ=1e-8, c=0.5", 0.5, 1e-8, 1e-8, None),
        ("F conductor huge η, κ", "η=κ=1e8, c=0.5", 0.5, 1e8, 1e8, None),
        ("F conductor η beyond clamp", "η=1e30, κ=0, c=0.5", 0.5, 1e30, 0.0, None),
        (
            "F conductor copper grazing",
            "η=0.2, κ=3.9, c=1e-30",
            1e-30,
            0.2,
            3.9,
            None,
        ),
    ];
    for (name, inputs, c, eta, k, want) in conductor {
        let expect = want.map_or(Expect::Match, Expect::Value);
        out.push(case(name, inputs, Eval::Conductor(c, eta, k), expect));
    }

    // Blinn-Phong: shininess 0, 1, 1e6; 0⁰; a huge exponent near and far from its peak.
    let s2 = |t: f64| t.sin().powi(2);
    out.push(case(
        "Blinn-Phong s=0",
        "n·h=0 (0⁰=1)",
        Eval::BlinnPhong(0.0, 1.0, 0.0),
        Expect::Value(1.0),
    ));
    out.push(case(
        "Blinn-Phong s=1",
        "θh=0.5",
        Eval::BlinnPhong(0.5f64.cos(), s2(0.5), 1.0),
        Expect::Match,
    ));
    out.push(case(
        "Blinn-Phong s=1e6 peak",
        "θh=0",
        Eval::BlinnPhong(1.0, 0.0, 1e6),
        Expect::Value(1.0),
    ));
    out.push(case(
        "Blinn-Phong s=1e6, given sin²θh",
        "θh=1e-3",
        Eval::BlinnPhong(1e-3f64.cos(), s2(1e-3), 1e6),
        Expect::Match,
    ));
    out.push(case(
        "Blinn-Phong s=1e6 tail",
        "θh=0.1 (underflow)",
        Eval::BlinnPhong(0.1f64.cos(), s2(0.1), 1e6),
        Expect::Value(0.0),
    ));
    out.push(case(
        "Lambert",
        "kd=1, albedo=0.7",
        Eval::Lambert(1.0, 0.7),
        Expect::Value(0.7 / PI),
    ));

    // Whole materials from f32 vectors: the configurations the shader can meet.
    let gg = || ct(D::Ggx, G::SmithGgxCorrelated, 0.5);
    let up = [0.0, 0.0, 1.0];
    let wi = [0.6, 0.0, 0.8];
    let wo = [0.0, 0.6, 0.8];
    let unit_value = value::<f64>(&Eval::Material(gg(), up, wi, wo));
    out.push(case(
        "CT ωi = -ωo",
        "grazing pair, no half vector",
        Eval::Material(gg(), up, [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        Expect::Value(0.0),
    ));
    out.push(case(
        "CT ωi = ωo = n",
        "α=0.5",
        Eval::Material(gg(), up, up, up),
        Expect::Match,
    ));
    let graze = [(1.0f64 - 1e-14).sqrt(), 0.0, 1e-7];
    out.push(case(
        "CT ωi = ωo grazing",
        "n·ω=1e-7, α=0.5",
        Eval::Material(gg(), up, graze, graze),
        Expect::Match,
    ));
    out.push(case(
        "CT unnormalised normal",
        "|n|=3",
        Eval::Material(gg(), [0.0, 0.0, 3.0], wi, wo),
        Expect::Value(unit_value),
    ));
    out.push(case(
        "CT unnormalised normal",
        "|n|=1e-3",
        Eval::Material(gg(), [0.0, 0.0, 1e-3], wi, wo),
        Expect::Value(unit_value),
    ));
    out.push(case(
        "CT zero normal",
        "n=0",
        Eval::Material(gg(), [0.0; 3], wi, wo),
        Expect::Value(0.0),
    ));
    out.push(case(
        "CT NaN normal",
        "n=(NaN,0,1)",
        Eval::Material(gg(), [f64::NAN, 0.0, 1.0], wi, wo),
        Expect::Value(0.0),
    ));
    for d in D::ALL {
        for alpha in [1e-2f64, 1e-3, 1e-4] {
            let (n, wi, wo) = tilted(alpha);
            let name = format!("CT {} narrow lobe from vectors", d.name());
            let inputs = format!("α={alpha:e}, θh=α");
            let m = ct(*d, G::SmithGgx, alpha as f32);
            let expect = if alpha >= 1e-3 {
                Expect::Match
            } else {
                Expect::Singular(
                    1e-6 / alpha,
                    "narrow lobe from f32 vectors: ω_h's direction is known to ~1e-7 rad, so D is known to about 2e-8/α (measured 2.2e-4 at α = 1e-4; bound checked: 1e-6/α)".into(),
                )
            };
            out.push(case(&name, &inputs, Eval::Material(m, n, wi, wo), expect));
        }
    }
    let (n, wi, wo) = tilted(1e-3);
    out.push(case(
        "Blinn-Phong s=1e6 from vectors",
        "θh=1e-3",
        Eval::Material(bp(1e6), n, wi, wo),
        Expect::Match,
    ));
    // A formulation that loses the narrow lobe, kept for comparison: sin²θ_h recovered from the
    // f32 cosine n·ω_h alone. The renderer does not use it (LocalDots carries sin²θ_h).
    let (n, wi, wo) = tilted(1e-2);
    let mut cos_only = case(
        "CT ggx narrow, sin²θh from n·h (old)",
        "α=1e-2, θh=α",
        Eval::MaterialFromCosines(ct(D::Ggx, G::SmithGgx, 1e-2), n, wi, wo),
        Expect::Singular(f64::INFINITY, String::new()),
    );
    cos_only.singular = Some(
        "for comparison only, not used by the renderer: 1 − (n·ω_h)² from the rounded f32 cosine cancels (this is why LocalDots carries sin²θ_h)".into(),
    );
    out.push(cos_only);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_fixed_case_passes_and_covers_every_term() {
        let cases = run();
        for c in &cases {
            assert!(c.passed(), "{} ({}): {:?}", c.name, c.inputs, c.failure);
        }
        for d in MicrofacetDistribution::ALL {
            assert!(cases.iter().any(|c| c.name.starts_with(&format!("D {}", d.name()))));
        }
        for g in MaskingShadowing::ALL {
            assert!(cases.iter().any(|c| c.name.contains(&format!(" {} ", g.name()))));
        }
        for f in ["F schlick", "F schlick-sg", "F conductor", "Blinn-Phong", "Lambert"] {
            assert!(cases.iter().any(|c| c.name.starts_with(f)), "{f}");
        }
    }

    #[test]
    fn the_old_cosine_only_formulation_really_loses_precision() {
        // The comparison row must show a real loss, or the fix it documents would be moot.
        let row = run().into_iter().find(|c| c.name.ends_with("(old)")).unwrap();
        assert!(row.rel_err.unwrap() > REL_TOL, "{:?}", row.rel_err);
    }

    #[test]
    fn a_case_outside_tolerance_fails() {
        // The cosine-only formulation at α = 1e-2, judged as a regular case, must fail.
        let (n, wi, wo) = tilted(1e-2);
        let m = ct(MicrofacetDistribution::Ggx, MaskingShadowing::SmithGgx, 1e-2);
        let c = case("x", "y", Eval::MaterialFromCosines(m, n, wi, wo), Expect::Match);
        assert!(!c.passed(), "rel {:?}", c.rel_err);
    }
}
