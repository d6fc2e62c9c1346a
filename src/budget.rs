//! Resource limits checked before big allocations: an estimate of the memory a step needs
//! is compared with the memory the system has available, so that an input too large for the
//! machine stops with one clear error instead of being killed by the operating system.

use crate::error::{Error, Result};

/// The most subdivisions per patch edge of a tessellation (`export --tess` and the renderer's
/// `--tessellate`): 4096² triangles per patch is already far beyond any display.
pub const MAX_TESS: usize = 4096;

/// Environment variable that sets the memory limit in bytes (instead of the system's
/// available memory); it can raise the limit as well as lower it. It bounds the whole
/// process: what the process already holds counts against it.
pub(crate) const MEMORY_LIMIT_VAR: &str = "SMOOTHLAB_MEMORY_LIMIT";

/// The memory limit in bytes and where it comes from: [`MEMORY_LIMIT_VAR`] when set,
/// otherwise `MemAvailable` of `/proc/meminfo` (Linux); `None` where neither is known.
pub(crate) fn memory_limit() -> Result<Option<(f64, &'static str)>> {
    if let Ok(text) = std::env::var(MEMORY_LIMIT_VAR) {
        return match text.trim().parse::<f64>() {
            Ok(bytes) if bytes > 0.0 => Ok(Some((bytes, MEMORY_LIMIT_VAR))),
            _ => Err(Error::Invalid(format!(
                "{MEMORY_LIMIT_VAR}='{text}' is not a positive number of bytes"
            ))),
        };
    }
    let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
    Ok(mem_available(&meminfo).map(|bytes| (bytes, "available memory (MemAvailable)")))
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
fn mem_available(meminfo: &str) -> Option<f64> {
    status_kib(meminfo, "MemAvailable:").map(|kib| kib * 1024.0)
}

/// Fails with [`Error::TooLarge`] when `bytes` (the estimate for `what`) does not fit in the
/// [`memory_limit`]; `remedy` says how to need less. The system's available memory already
/// excludes what this process holds; a limit set by [`MEMORY_LIMIT_VAR`] is for the whole
/// process, so the process's resident memory is added to the estimate.
pub(crate) fn check_memory(what: &str, bytes: f64, remedy: &str) -> Result<()> {
    let Some((limit, source)) = memory_limit()? else {
        return Ok(());
    };
    let held = if source == MEMORY_LIMIT_VAR {
        resident_bytes().unwrap_or(0.0)
    } else {
        0.0
    };
    if bytes + held <= limit {
        return Ok(());
    }
    let estimate = if held > 0.0 {
        format!(
            "{} (+ {} the process already holds)",
            format_bytes(bytes),
            format_bytes(held)
        )
    } else {
        format_bytes(bytes)
    };
    Err(Error::TooLarge {
        what: what.to_string(),
        estimate,
        limit: format!("{} ({source})", format_bytes(limit)),
        remedy: format!("{remedy}, or set {MEMORY_LIMIT_VAR} (bytes) to raise the limit"),
    })
}

/// The resident memory of this process (`VmRSS` of `/proc/self/status`, Linux), in bytes.
pub(crate) fn resident_bytes() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status_kib(&status, "VmRSS:").map(|kib| kib * 1024.0)
}

/// The value in KiB of the `/proc` line starting with `key` (e.g. `MemAvailable:`).
fn status_kib(text: &str, key: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Environment variable through which rayon takes its number of worker threads.
pub(crate) const THREADS_VAR: &str = "RAYON_NUM_THREADS";

/// The most worker threads per core: the work is split into fixed tiles and chunks, so more
/// threads than cores only add start-up cost and contention (1,000 threads took 1.8 s and
/// 3,000 took 10.9 s for a 1,024-pixel render on 2 cores; 100,000 did not finish in 120 s).
pub(crate) const MAX_THREADS_PER_CORE: usize = 4;

/// The thread count to use instead of `requested` (the text of [`THREADS_VAR`]) on a machine
/// with `cores` cores, with the warning that says so: `None` when the request is at most
/// [`MAX_THREADS_PER_CORE`] × `cores` or is not a number (rayon then applies its own rule).
pub(crate) fn capped_threads(requested: &str, cores: usize) -> Option<(usize, String)> {
    let wanted: u128 = requested.trim().parse().ok()?;
    let cap = MAX_THREADS_PER_CORE * cores.max(1);
    (wanted > cap as u128).then(|| {
        (
            cap,
            format!(
                "{THREADS_VAR}={wanted} is more than {MAX_THREADS_PER_CORE} threads per core; \
                 using {cap} threads ({cores} cores; results do not depend on the count)"
            ),
        )
    })
}

/// `bytes` in GB or MB with three significant digits.
pub(crate) fn format_bytes(bytes: f64) -> String {
    if bytes >= 1e9 {
        format!("{:.3} GB", bytes / 1e9)
    } else {
        format!("{:.3} MB", bytes / 1e6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mem_available_in_bytes() {
        let text = "MemTotal:       32000000 kB\nMemFree:  100 kB\nMemAvailable:   2000000 kB\n";
        assert_eq!(mem_available(text), Some(2_048_000_000.0));
        assert_eq!(mem_available("MemTotal: 5 kB\n"), None);
    }

    #[test]
    fn this_process_holds_some_resident_memory() {
        let held = resident_bytes().expect("VmRSS of /proc/self/status");
        // At least the test binary's touched pages, and less than the whole machine.
        assert!(held > 1e5 && held < 1e12, "{held}");
    }

    #[test]
    fn thread_requests_beyond_four_per_core_are_capped() {
        assert_eq!(capped_threads("8", 2), None);
        assert_eq!(capped_threads("1", 2), None);
        assert_eq!(capped_threads("zero", 2), None);
        for huge in ["9", "100000", "99999999999999999999999"] {
            let (threads, warning) = capped_threads(huge, 2).expect(huge);
            assert_eq!(threads, 8, "{huge}");
            assert!(
                warning.contains(huge) && warning.contains("8 threads"),
                "{warning}"
            );
        }
        assert_eq!(capped_threads("1000", 64).map(|c| c.0), Some(256));
    }

    #[test]
    fn bytes_are_formatted_with_their_unit() {
        assert_eq!(format_bytes(2.5e10), "25.000 GB");
        assert_eq!(format_bytes(3.2e6), "3.200 MB");
    }
}
