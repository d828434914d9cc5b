//! What every group of stability cases shares: the case record and its verdict, the report, the
//! relative error and its tolerance, number formatting and the random generator.

/// Largest f32-vs-f64 relative error a non-singular case may have.
pub const REL_TOL: f64 = 1e-4;

/// What the suite runs.
#[derive(Clone, Debug)]
pub struct Options {
    /// Random BRDF samples (each evaluated in f32 and f64) and rays fired from inside closed
    /// meshes: this many of each.
    pub cases: u64,
    /// Seed of every random choice.
    pub seed: u64,
    /// Directory with the shared test meshes (the dragon); `None` or missing = skipped, loudly.
    pub shared_meshes: Option<std::path::PathBuf>,
}

/// One row of the table.
#[derive(Clone, Debug)]
pub struct Case {
    /// brdf, brdf-sweep, geometry or light.
    pub group: &'static str,
    /// What is checked.
    pub name: String,
    /// The inputs, briefly.
    pub inputs: String,
    /// The f32 result (or, for checks without two precisions, the measured value).
    pub f32_value: String,
    /// The f64 result of the same code (or the reference / requirement).
    pub f64_value: String,
    /// f32-vs-f64 relative error, where two precisions are compared.
    pub rel_err: Option<f64>,
    /// Evaluations (or rays, or pixels) behind the row.
    pub evals: u64,
    /// NaN results.
    pub nan: u64,
    /// Infinite results.
    pub inf: u64,
    /// Negative results.
    pub neg: u64,
    /// Why the relative-error tolerance does not apply, if it does not.
    pub singular: Option<String>,
    /// Why the case failed, if it did.
    pub failure: Option<String>,
}

impl Case {
    /// A case with no values yet.
    pub fn new(group: &'static str, name: impl Into<String>, inputs: impl Into<String>) -> Self {
        Self {
            group,
            name: name.into(),
            inputs: inputs.into(),
            f32_value: String::new(),
            f64_value: String::new(),
            rel_err: None,
            evals: 0,
            nan: 0,
            inf: 0,
            neg: 0,
            singular: None,
            failure: None,
        }
    }

    /// Whether it passed.
    pub fn passed(&self) -> bool {
        self.failure.is_none()
    }

    /// Records a failure (keeps the first one).
    pub fn fail(&mut self, why: impl Into<String>) {
        if self.failure.is_none() {
            self.failure = Some(why.into());
        }
    }

    /// Counts one value into the NaN/Inf/negative columns.
    pub fn count(&mut self, v: f64) {
        self.evals += 1;
        if v.is_nan() {
            self.nan += 1;
        } else if v.is_infinite() {
            self.inf += 1;
        }
        if v < 0.0 {
            self.neg += 1;
        }
    }

    /// Fails the case if any NaN, infinite or negative value was counted.
    pub fn require_clean(&mut self) {
        if self.nan + self.inf + self.neg > 0 {
            let (n, i, g) = (self.nan, self.inf, self.neg);
            self.fail(format!("{n} NaN, {i} Inf, {g} negative"));
        }
    }
}

/// Relative error |a − b| / max(|b|, 2⁻¹²⁶), with NaN or infinite values counting as infinite.
pub fn rel_err(a: f64, b: f64) -> f64 {
    if !a.is_finite() || !b.is_finite() {
        return if a == b { 0.0 } else { f64::INFINITY };
    }
    (a - b).abs() / b.abs().max(f32::MIN_POSITIVE as f64)
}

/// Formats a value compactly for the table.
pub fn num(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else if v.is_nan() || v.is_infinite() {
        format!("{v}")
    } else if (1e-3..1e5).contains(&v.abs()) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.6e}")
    }
}

/// SplitMix64: a small, deterministic generator for the random cases.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed` and `stream` (independent streams for parallel chunks).
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Rng(seed ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03));
        r.next_u64();
        r
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform integer in [0, n).
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }

    /// Log-uniform in [lo, hi].
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + self.uniform() * (hi.ln() - lo.ln())).exp()
    }

    /// Uniform direction on the unit sphere.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = 2.0 * self.uniform() - 1.0;
        let phi = std::f64::consts::TAU * self.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

/// The whole suite's result.
pub struct Report {
    /// Every case, in table order.
    pub cases: Vec<Case>,
    /// Notes printed under the table (skipped parts, measured depths).
    pub notes: Vec<String>,
}

impl Report {
    /// Number of failed cases.
    pub fn failures(&self) -> usize {
        self.cases.iter().filter(|c| !c.passed()).count()
    }
}
