//! The process's resident memory: the solver's trace (`SQUEAL_MODAL_TRACE=1`) shows which
//! phase sets the peak (the current and the peak resident set from `/proc/self/status`,
//! `VmRSS` and `VmHWM`; elsewhere than on Linux the note is empty), and the freed heap is
//! handed back to the system before the factor and the basis are allocated
//! ([`release_free_heap`]).

/// `", resident R MB (peak P MB)"`, or an empty string where `/proc/self/status` is missing.
pub(super) fn resident_note() -> String {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else {
        return String::new();
    };
    let field_mb = |name: &str| -> Option<f64> {
        let line = status.lines().find(|l| l.starts_with(name))?;
        let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kb / 1024.0)
    };
    match (field_mb("VmRSS:"), field_mb("VmHWM:")) {
        (Some(now), Some(peak)) => format!(", resident {now:.0} MB (peak {peak:.0} MB)"),
        _ => String::new(),
    }
}

/// Hands the allocator's free memory back to the operating system (glibc's `malloc_trim`);
/// returns whether it could. Elsewhere than on glibc it does nothing and returns `false`.
///
/// Why: glibc keeps what a thread frees in that thread's arena, and returns to the system only
/// blocks above its mmap threshold (which grows to 32 MB) and the top of each heap. The
/// symbolic analysis (AMD and nested dissection side by side on rayon's threads, millions of
/// small allocations) leaves its freed graphs resident that way: 293 MB on the 294 k dof
/// wheel (trace: resident 803 MB after the analysis, 510 MB after this call; measured
/// 2026-11-27), which the factor and the Lanczos basis, allocated after it, would otherwise
/// stack on top of in the peak.
pub fn release_free_heap() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        extern "C" {
            // glibc, malloc.h: `int malloc_trim(size_t pad)`.
            fn malloc_trim(pad: usize) -> i32;
        }
        // SAFETY: malloc_trim takes no pointer and may be called from any thread at any time;
        // it only releases pages of free chunks (glibc's allocator locks each arena).
        unsafe {
            malloc_trim(0);
        }
        true
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_note_reports_a_peak_at_least_the_current_resident_set() {
        let note = resident_note();
        if !std::path::Path::new("/proc/self/status").exists() {
            assert!(note.is_empty());
            return;
        }
        // ", resident R MB (peak P MB)": both parse and P >= R (the peak includes now).
        let numbers: Vec<f64> = note
            .split(|c: char| !c.is_ascii_digit())
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().expect("number"))
            .collect();
        assert_eq!(numbers.len(), 2, "{note}");
        assert!(numbers[0] > 0.0 && numbers[1] >= numbers[0], "{note}");
    }
}
