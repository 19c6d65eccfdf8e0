//! Tapering windows, in SciPy's *periodic* form (`scipy.signal.get_window(..., fftbins=True)`,
//! i.e. `sym=False`), which is what `scipy.signal.welch` uses.
//!
//! A periodic window of length `n` is the first `n` samples of the symmetric window of length
//! `n + 1`; its DFT has the exact cosine-sum sidelobe structure, which is why spectral analysis
//! prefers it.

use crate::{Error, Result};

/// Window applied to each segment before its FFT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Window {
    /// Hann: `w[k] = 0.5 - 0.5 cos(2 pi k / n)`, k = 0..n (periodic).
    #[default]
    Hann,
    /// Hamming: `w[k] = 0.54 - 0.46 cos(2 pi k / n)`, k = 0..n (periodic).
    Hamming,
    /// Rectangular: `w[k] = 1`.
    Boxcar,
}

impl Window {
    /// Samples of the periodic window of length `length`.
    pub fn samples(self, length: usize) -> Vec<f64> {
        let n = length as f64;
        let cosine_sum = |a0: f64, a1: f64| -> Vec<f64> {
            (0..length)
                .map(|k| a0 - a1 * (2.0 * std::f64::consts::PI * k as f64 / n).cos())
                .collect()
        };
        match self {
            Window::Hann => cosine_sum(0.5, 0.5),
            Window::Hamming => cosine_sum(0.54, 0.46),
            Window::Boxcar => vec![1.0; length],
        }
    }

    /// The command-line / file name of the window.
    pub fn name(self) -> &'static str {
        match self {
            Window::Hann => "hann",
            Window::Hamming => "hamming",
            Window::Boxcar => "boxcar",
        }
    }
}

impl std::str::FromStr for Window {
    type Err = Error;
    fn from_str(text: &str) -> Result<Self> {
        match text.to_ascii_lowercase().as_str() {
            "hann" | "hanning" => Ok(Window::Hann),
            "hamming" => Ok(Window::Hamming),
            "boxcar" | "rectangular" | "rect" => Ok(Window::Boxcar),
            _ => Err(Error::input(
                "command line",
                "window",
                format!("unknown window `{text}`; allowed: hann, hamming, boxcar"),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_hann_is_symmetric_window_of_length_plus_one_truncated() {
        let w = Window::Hann.samples(8);
        assert_eq!(w[0], 0.0);
        assert!((w[4] - 1.0).abs() < 1e-15);
        assert!((w[1] - w[7]).abs() < 1e-15);
    }

    #[test]
    fn unknown_window_is_an_input_error() {
        let err = "kaiser".parse::<Window>().unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("hann, hamming, boxcar"));
    }
}
