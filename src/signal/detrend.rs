//! Trend removal applied to each Welch segment before windowing (as `scipy.signal.detrend`).

use crate::{Error, Result};

/// What to subtract from a segment before it is windowed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Detrend {
    /// Nothing (SciPy `detrend=False`).
    None,
    /// The segment mean (SciPy `detrend='constant'`, the default).
    #[default]
    Constant,
    /// The least-squares straight line through the segment (SciPy `detrend='linear'`).
    Linear,
}

impl Detrend {
    /// Removes the trend from `segment` in place.
    ///
    /// Linear: with k = 0..n-1, k_mean = (n-1)/2, the least-squares slope is
    /// `b = sum (k - k_mean)(x_k - x_mean) / sum (k - k_mean)^2` and the residual is
    /// `x_k - x_mean - b (k - k_mean)` (normal equations of the line fit, centred so that the
    /// intercept and slope decouple; same residual as SciPy's `lstsq` solution).
    pub fn apply(self, segment: &mut [f64]) {
        let n = segment.len();
        if n == 0 {
            return;
        }
        match self {
            Detrend::None => {}
            Detrend::Constant => {
                let mean = segment.iter().sum::<f64>() / n as f64;
                for value in segment.iter_mut() {
                    *value -= mean;
                }
            }
            Detrend::Linear => {
                let mean = segment.iter().sum::<f64>() / n as f64;
                let k_mean = (n as f64 - 1.0) / 2.0;
                let mut covariance = 0.0;
                let mut k_variance = 0.0;
                for (k, value) in segment.iter().enumerate() {
                    let dk = k as f64 - k_mean;
                    covariance += dk * (value - mean);
                    k_variance += dk * dk;
                }
                let slope = if k_variance > 0.0 {
                    covariance / k_variance
                } else {
                    0.0
                };
                for (k, value) in segment.iter_mut().enumerate() {
                    *value -= mean + slope * (k as f64 - k_mean);
                }
            }
        }
    }

    /// The command-line / file name of the detrend option.
    pub fn name(self) -> &'static str {
        match self {
            Detrend::None => "none",
            Detrend::Constant => "constant",
            Detrend::Linear => "linear",
        }
    }
}

impl std::str::FromStr for Detrend {
    type Err = Error;
    fn from_str(text: &str) -> Result<Self> {
        match text.to_ascii_lowercase().as_str() {
            "none" | "false" => Ok(Detrend::None),
            "constant" | "mean" => Ok(Detrend::Constant),
            "linear" => Ok(Detrend::Linear),
            _ => Err(Error::input(
                "command line",
                "detrend",
                format!("unknown detrend `{text}`; allowed: constant, linear, none"),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_detrend_removes_a_line_exactly() {
        let mut x: Vec<f64> = (0..7).map(|k| 3.0 - 0.5 * k as f64).collect();
        Detrend::Linear.apply(&mut x);
        assert!(x.iter().all(|v| v.abs() < 1e-14));
    }

    #[test]
    fn constant_detrend_removes_the_mean() {
        let mut x = vec![1.0, 2.0, 6.0];
        Detrend::Constant.apply(&mut x);
        assert_eq!(x, vec![-2.0, -1.0, 3.0]);
    }
}
