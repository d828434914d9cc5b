//! Sets `cfg(shared_data)` when the shared test data (`../shared/data`, see README "Test data")
//! is beside the repository. Tests that need it carry
//! `#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]`, so that without the data
//! `cargo test` counts them as ignored, with the reason, instead of passing them unrun.
//! Likewise `cfg(system_font)` when the convergence plot will find a font to draw text with,
//! and `cfg(cpu_avx2)`, `cfg(cpu_avx512)` when this machine runs those instructions (the tests
//! of the lane code compiled for them; the build itself stays portable and picks at run time).

use std::path::Path;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(shared_data)");
    println!("cargo::rustc-check-cfg=cfg(system_font)");
    println!("cargo::rustc-check-cfg=cfg(cpu_avx2)");
    println!("cargo::rustc-check-cfg=cfg(cpu_avx512)");
    println!("cargo::rerun-if-changed=build.rs");
    system_font();
    cpu_features();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if data.is_dir() {
        println!("cargo::rustc-cfg=shared_data");
        // Rerun when the data goes away (a missing path always reruns the script).
        println!("cargo::rerun-if-changed={}", data.display());
    } else {
        // A missing rerun-if-changed path would rebuild the crate on every build, so the data's
        // arrival is not watched: `touch build.rs` after adding it.
        println!(
            "cargo::warning=../shared/data is missing: the tests that need it are ignored \
             (touch build.rs after adding it)"
        );
    }
}

/// `cfg(cpu_avx2)` and `cfg(cpu_avx512)` (AVX-512F with AVX2) from this CPU, for a build whose
/// tests run here (the target is this machine's architecture).
fn cpu_features() {
    #[cfg(target_arch = "x86_64")]
    if std::env::var("CARGO_CFG_TARGET_ARCH").as_deref() == Ok("x86_64") {
        let avx2 = std::arch::is_x86_feature_detected!("avx2");
        if avx2 {
            println!("cargo::rustc-cfg=cpu_avx2");
        }
        if avx2 && std::arch::is_x86_feature_detected!("avx512f") {
            println!("cargo::rustc-cfg=cpu_avx512");
        }
    }
}

/// `cfg(system_font)` when `POINTSHADE_FONT` or one of the plot's font paths can be read.
fn system_font() {
    let list = "src/reports/convergence/fonts.txt";
    println!("cargo::rerun-if-changed={list}");
    println!("cargo::rerun-if-env-changed=POINTSHADE_FONT");
    let candidates = std::fs::read_to_string(list).unwrap_or_default();
    let from_env = std::env::var("POINTSHADE_FONT").ok();
    if from_env
        .iter()
        .map(String::as_str)
        .chain(candidates.lines())
        .any(|p| std::fs::metadata(p).is_ok_and(|m| m.is_file()))
    {
        println!("cargo::rustc-cfg=system_font");
    }
}
