//! Welch parameters chosen for a frequency resolution: the bin spacing a caller asks for, from
//! a record of given length.
//!
//! The bin spacing is `fs / nfft` and the main lobe of a Hann segment of `nperseg` samples is
//! `4 fs / nperseg` wide (`2 fs / nperseg` either side). So:
//! - a long record is averaged Welch-style over segments of the largest power of two `p` with
//!   `2 p <= n / 2` (at least 3 half-overlapping segments, as before windows existed) when
//!   their bins `fs / p` are as fine as asked: no padding;
//! - a record too short for that is one Hann segment of the whole record, zero-padded to the
//!   smallest power of two with `fs / nfft <= resolution` (and at least the next power of two
//!   of the record): the finest main lobe the record allows, on bins at least as fine as
//!   asked. Zero padding interpolates the spectrum; it does not separate two tones
//!   closer than the main lobe, which is why the report states the segment as well as the bins.
//!
//! With `nperseg` given, that segment (half overlap) is used and padded to reach the spacing.

use super::WelchParams;
use crate::{Error, Result};

/// Welch parameters for `n` samples at `fs` Hz with bins no wider than `resolution_hz`.
pub fn welch_for_resolution(
    n: usize,
    sample_rate_hz: f64,
    resolution_hz: f64,
    nperseg: Option<usize>,
) -> Result<WelchParams> {
    // The finest spacing the longest FFT gives: below it the padding would not fit.
    let finest_hz = sample_rate_hz / super::welch::MAX_NFFT as f64;
    if !(resolution_hz.is_finite() && resolution_hz >= finest_hz && resolution_hz <= sample_rate_hz)
    {
        return Err(Error::input(
            "command line",
            "--resolution-hz",
            format!(
                "must lie in [{finest_hz:.3e}, {sample_rate_hz}] Hz: from the sample rate over \
                 the longest FFT ({} points) to the sample rate (got {resolution_hz})",
                super::welch::MAX_NFFT
            ),
        ));
    }
    if n < 8 {
        return Err(Error::input(
            "command line",
            "--from-ms/--to-ms",
            format!(
                "the analysed window (--from-ms to --to-ms, by default the run's lateral onset \
                 to its end) holds {n} samples; at least 8 are needed"
            ),
        ));
    }
    let mut nfft = 8usize;
    while sample_rate_hz / (nfft as f64) > resolution_hz {
        nfft *= 2;
    }
    if let Some(seg) = nperseg {
        if seg < 2 || seg > n {
            return Err(Error::input(
                "command line",
                "--nperseg",
                format!("must lie in 2..={n}, the samples in the analysed window (got {seg})"),
            ));
        }
        return Ok(WelchParams {
            nfft: Some(nfft.max(seg)),
            ..WelchParams::new(seg)
        });
    }
    let mut p = 64usize;
    while p * 2 <= n / 2 {
        p *= 2;
    }
    if p <= n && sample_rate_hz / p as f64 <= resolution_hz {
        return Ok(WelchParams::new(p));
    }
    Ok(WelchParams {
        noverlap: 0,
        nfft: Some(nfft.max(n.next_power_of_two())),
        ..WelchParams::new(n)
    })
}

/// One line that says what the spectrum is: window, segment, padding, bins.
pub fn describe(params: &WelchParams, sample_rate_hz: f64, segments: usize) -> String {
    let nfft = params.fft_length();
    let seg_ms = 1e3 * params.nperseg as f64 / sample_rate_hz;
    let padding = if nfft > params.nperseg {
        format!(", zero-padded to {nfft} points")
    } else {
        String::new()
    };
    format!(
        "{segments} Hann segment{} of {} samples ({seg_ms:.1} ms){padding}: bins {:.1} Hz, main \
         lobe +-{:.0} Hz",
        if segments == 1 { "" } else { "s" },
        params.nperseg,
        sample_rate_hz / nfft as f64,
        2.0 * sample_rate_hz / params.nperseg as f64
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_records_are_one_padded_segment_long_ones_are_averaged() {
        // 24 ms at 50 kHz: one segment of 1200 samples padded to 2048 (24.4 Hz bins).
        let p = welch_for_resolution(1200, 50_000.0, 50.0, None).unwrap();
        assert_eq!((p.nperseg, p.fft_length(), p.noverlap), (1200, 2048, 0));
        // 1 s at 50 kHz: segments of 16384 (3.1 Hz), half overlap, at least 3 of them.
        let p = welch_for_resolution(50_000, 50_000.0, 50.0, None).unwrap();
        assert_eq!(
            (p.nperseg, p.fft_length(), p.noverlap),
            (16384, 16384, 8192)
        );
        assert!(p.segment_count(50_000) >= 3);
        // A given segment is padded to reach the bins.
        let p = welch_for_resolution(5000, 50_000.0, 50.0, Some(256)).unwrap();
        assert_eq!((p.nperseg, p.fft_length()), (256, 1024));
    }

    #[test]
    fn impossible_requests_name_the_option() {
        let e = welch_for_resolution(1000, 1000.0, 0.0, None).unwrap_err();
        assert!(e.to_string().contains("--resolution-hz"), "{e}");
        let e = welch_for_resolution(1000, 1000.0, 10.0, Some(1)).unwrap_err();
        assert!(e.to_string().contains("--nperseg"), "{e}");
        let e = welch_for_resolution(4, 1000.0, 10.0, None).unwrap_err();
        assert!(e.to_string().contains("--from-ms"), "{e}");
    }
}
