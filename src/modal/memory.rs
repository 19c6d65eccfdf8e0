//! The process's resident memory for the solver's trace (`SQUEAL_MODAL_TRACE=1`), so that a
//! trace shows which phase sets the peak: the current and the peak resident set from
//! `/proc/self/status` (`VmRSS`, `VmHWM`). Elsewhere than on Linux the note is empty.

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
