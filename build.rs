//! Sets `cfg(shared_data)` when the shared test data (`../shared/data`, see README "Test data")
//! is beside the repository. Tests that need it carry
//! `#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]`, so that without the data
//! `cargo test` counts them as ignored, with the reason, instead of passing them unrun.

use std::path::Path;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(shared_data)");
    println!("cargo::rerun-if-changed=build.rs");
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
