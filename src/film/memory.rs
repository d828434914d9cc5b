//! The memory a render's film needs at its peak, estimated before the render starts and held
//! against the memory this process can have, so that a film the size check accepts is refused at
//! once instead of aborting on a failed allocation after minutes of rendering.
//!
//! The bytes per pixel are measured, not derived: the peak resident size of renders of 1024² and
//! 2048² pixels, differenced (`python3 benches/film_memory.py`; its table is in
//! docs/benchmarks.md). They cover the film's sums, the finished image and its encoded copies.
//! The constants round the measurements up.

/// Peak bytes per pixel of a plain render (sums, image, encoded file).
pub const BYTES_PER_PIXEL: u64 = 44;
/// Added per AOV image other than `samples`.
pub const BYTES_PER_AOV_PIXEL: u64 = 44;
/// Added by the `samples` AOV (little: the sample counts are kept anyway).
pub const BYTES_PER_SAMPLES_AOV_PIXEL: u64 = 8;
/// Added by the adaptive samplers (`adaptive`, `cells`: their per-pixel state).
pub const BYTES_PER_ADAPTIVE_PIXEL: u64 = 40;

/// What a film of `pixels` pixels needs at its peak, with `aovs` AOV images besides `samples`,
/// the `samples` AOV if `samples_aov`, and an adaptive sampler if `adaptive`.
pub fn peak_bytes(pixels: u64, aovs: usize, samples_aov: bool, adaptive: bool) -> u64 {
    let per_pixel = BYTES_PER_PIXEL
        + aovs as u64 * BYTES_PER_AOV_PIXEL
        + u64::from(samples_aov) * BYTES_PER_SAMPLES_AOV_PIXEL
        + u64::from(adaptive) * BYTES_PER_ADAPTIVE_PIXEL;
    pixels.saturating_mul(per_pixel)
}

/// The memory this process can still allocate, and where the bound comes from: the smaller of
/// the system's available memory (`MemAvailable`) and what the address-space limit
/// (`ulimit -v`) leaves beside what the process already maps. `None` where neither can be read.
pub fn available_bytes() -> Option<(u64, &'static str)> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let available = meminfo.as_deref().and_then(|m| kib_field(m, "MemAvailable:"));
    let limit = address_space_left();
    match (available, limit) {
        (Some(a), Some(l)) if l < a => Some((l, "left under the address-space limit")),
        (Some(a), _) => Some((a, "available (MemAvailable)")),
        (None, Some(l)) => Some((l, "left under the address-space limit")),
        (None, None) => None,
    }
}

/// Refuses a film that needs more than [`available_bytes`] (see [`peak_bytes`]); the message
/// names the need and the memory available.
pub fn check_fits(width: u32, height: u32, aovs: usize, samples_aov: bool, adaptive: bool) -> Result<(), String> {
    let need = peak_bytes(width as u64 * height as u64, aovs, samples_aov, adaptive);
    let Some((available, source)) = available_bytes() else {
        return Ok(());
    };
    if need > available {
        return Err(format!(
            "a {width}×{height} film{} needs about {} at its peak, more than the {} {source}: \
             render it in crops (--crop, then `pointshade merge`) or make it smaller",
            match aovs + usize::from(samples_aov) {
                0 => String::new(),
                n => format!(" with {n} AOV(s)"),
            },
            gigabytes(need),
            gigabytes(available)
        ));
    }
    Ok(())
}

/// `bytes` as gigabytes for messages.
fn gigabytes(bytes: u64) -> String {
    format!("{:.2} GB", bytes as f64 / 1e9)
}

/// A `NAME: N kB` field of /proc/meminfo or /proc/self/status, in bytes.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kib * 1024)
}

/// The address-space limit less what the process maps now (`VmSize`); `None` when unlimited.
fn address_space_left() -> Option<u64> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes the limit into `limit`, a valid rlimit.
    if unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } != 0 || limit.rlim_cur == libc::RLIM_INFINITY {
        return None;
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let mapped = kib_field(&status, "VmSize:").unwrap_or(0);
    Some(limit.rlim_cur.saturating_sub(mapped))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_adds_aovs_and_adaptive_state() {
        assert_eq!(peak_bytes(1000, 0, false, false), 44_000);
        assert_eq!(peak_bytes(1000, 3, true, true), 1000 * (44 + 3 * 44 + 8 + 40));
        assert_eq!(peak_bytes(u64::MAX, 1, false, false), u64::MAX, "saturates");
    }

    #[test]
    fn a_film_of_the_largest_accepted_size_with_aovs_does_not_fit_a_small_machine() {
        // 65536 × 4096 with three AOVs: about 47 GB, more than any machine this runs on has
        // free (the test machines have 24 GB).
        let err = check_fits(65536, 4096, 3, false, false).unwrap_err();
        assert!(
            err.contains("a 65536×4096 film with 3 AOV(s) needs about 47.24 GB"),
            "{err}"
        );
        assert!(check_fits(512, 512, 5, true, true).is_ok());
    }

    #[test]
    fn meminfo_fields_read_in_bytes() {
        let text = "MemTotal:       24000000 kB\nMemAvailable:   12345 kB\n";
        assert_eq!(kib_field(text, "MemAvailable:"), Some(12345 * 1024));
        assert_eq!(kib_field(text, "SwapFree:"), None);
    }
}
