use super::*;
use crate::shading::shader::tests::materials;

/// Rows of every kind the shader meets: directions on both sides of n, a normal of length
/// 0.5–2, grazing directions, ω_i = −ω_o, and (row 5) n = 0.
fn rows(count: usize) -> [Vec<f64>; 3] {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut unit = move || loop {
        let v = [next(), next(), next()];
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.1 && l < 1.0 {
            break v.map(|c| c / l);
        }
    };
    let [mut n, mut wi, mut wo] = [vec![], vec![], vec![]];
    for i in 0..count {
        let (a, b, c) = (unit(), unit(), unit());
        let scale = 1.25 + 0.75 * (i as f64 * 0.37).sin();
        n.extend(a.map(|x| x * scale));
        wi.extend(b);
        match i % 7 {
            3 => wo.extend(b.map(|x| -x)),
            4 => wo.extend([b[1], -b[0], 0.0].map(|x| x / (b[0] * b[0] + b[1] * b[1]).sqrt())),
            _ => wo.extend(c),
        }
    }
    n[15..18].fill(0.0);
    [n, wi, wo]
}

fn every_material() -> Vec<Material> {
    materials()
        .into_iter()
        .flat_map(|m| {
            let mut two = m.clone();
            two.two_sided = !m.two_sided;
            [m, two]
        })
        .collect()
}

/// f_r of each row by the scalar call.
fn scalar<T: Scalar>(m: &Material, r: &[FloatRows; 3], i: usize) -> [T; 3] {
    let v = |a: &FloatRows| [0, 1, 2].map(|c| a.get::<T>(i, c));
    brdf_value(m, v(&r[0]), v(&r[1]), v(&r[2]))
}

fn assert_rows_are_scalar<T: RowPrecision>(r: [FloatRows; 3], instructions: RowInstructions) {
    let count = r[0].rows();
    for m in every_material() {
        let mut out = vec![MaybeUninit::new(T::zero()); 3 * count];
        let job = Job {
            material: &m,
            rows: r,
            domain: RowDomain { unit_tolerance: 1e-4 },
            first: 0,
            end: count,
        };
        T::run(&job, instructions, &mut out);
        for i in 0..count {
            let want = scalar::<T>(&m, &r, i);
            for c in 0..3 {
                // SAFETY: initialised above.
                let (got, want) = (unsafe { out[3 * i + c].assume_init() }, want[c]);
                // Bit for bit, but for the sign of a zero (== holds for ±0 and for no other
                // pair of different bits but NaNs, which must both be NaN).
                let both_nan = got.as_f64().is_nan() && want.as_f64().is_nan();
                assert!(
                    got == want || both_nan,
                    "{} row {i} channel {c}: {got} from lanes, {want} from brdf_value",
                    m.name
                );
            }
        }
    }
}

#[test]
fn lanes_give_the_scalar_calls_bits_in_both_precisions_and_every_instruction_set() {
    // 203 rows: a tail shorter than a group of lanes.
    let [n, wi, wo] = rows(203);
    let narrow: Vec<Vec<f32>> = [&n, &wi, &wo]
        .iter()
        .map(|v| v.iter().map(|&x| x as f32).collect())
        .collect();
    let wide = [FloatRows::F64(&n), FloatRows::F64(&wi), FloatRows::F64(&wo)];
    let mixed = [
        FloatRows::F32(&narrow[0]),
        FloatRows::F64(&wi),
        FloatRows::F32(&narrow[2]),
    ];
    // Every level this CPU runs, each against the scalar calls.
    #[cfg(target_arch = "x86_64")]
    let levels = [
        RowInstructions::Portable,
        RowInstructions::Avx2,
        RowInstructions::Avx512,
    ];
    #[cfg(not(target_arch = "x86_64"))]
    let levels = [RowInstructions::Portable];
    for instructions in levels.into_iter().filter(|&l| l <= RowInstructions::detect()) {
        for r in [wide, mixed] {
            assert_rows_are_scalar::<f32>(r, instructions);
            assert_rows_are_scalar::<f64>(r, instructions);
        }
    }
}

#[test]
fn brdf_rows_covers_every_row_across_chunks() {
    let count = 2 * CHUNK_ROWS + 5;
    let [n, wi, wo] = rows(count);
    let r = [FloatRows::F64(&n), FloatRows::F64(&wi), FloatRows::F64(&wo)];
    let m = &materials()[5];
    let (out, _) = brdf_rows::<f64>(m, r, RowDomain { unit_tolerance: 1e-4 });
    assert_eq!(out.len(), 3 * count);
    for i in (0..count).step_by(97).chain([count - 1, CHUNK_ROWS, CHUNK_ROWS - 1]) {
        assert_eq!(out[3 * i..3 * i + 3], scalar::<f64>(m, &r, i), "row {i}");
    }
}

#[test]
fn the_domain_check_fails_on_each_kind_of_bad_row_and_passes_good_ones() {
    let m = &materials()[1];
    let check = |n: [f64; 3], wi: [f64; 3], tolerance: f64| {
        // 20 good rows, the one under test at 13.
        let (mut nn, mut wii, wo) = (
            [0.0, 0.0, 1.0].repeat(20),
            [0.6, 0.0, 0.8].repeat(20),
            [0.0, 0.0, 1.0].repeat(20),
        );
        nn[39..42].copy_from_slice(&n);
        wii[39..42].copy_from_slice(&wi);
        let rows = [FloatRows::F64(&nn), FloatRows::F64(&wii), FloatRows::F64(&wo)];
        brdf_rows::<f32>(
            m,
            rows,
            RowDomain {
                unit_tolerance: tolerance,
            },
        )
        .1
    };
    let good = [0.0, 0.6, 0.8];
    assert!(check([0.0, 0.0, 3.0], good, 1e-4), "a long normal is fine");
    assert!(
        check([0.0, 0.0, 1.0], [0.0, 0.6, 0.80001], 1e-4),
        "within half the tolerance"
    );
    assert!(!check([0.0, 0.0, 1.0], [0.0, 0.6, 0.9], 1e-4), "|ω_i| = 1.08");
    assert!(
        check([0.0, 0.0, 1.0], [0.0, 0.6, 0.9], 0.4),
        "|ω_i|² = 1.17 with a loose tolerance"
    );
    assert!(!check([0.0, 0.0, 0.0], good, 1e-4), "n = 0");
    assert!(!check([0.0, f64::NAN, 1.0], good, 1e-4), "NaN in n");
    assert!(!check([0.0, 0.0, 1.0], [0.0, f64::INFINITY, 0.8], 1e-4), "∞ in ω_i");
}
