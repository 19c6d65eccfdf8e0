//! A mode identified from a test, and how it was estimated.

use rustfft::num_complex::Complex;
use serde::Serialize;

/// How a test mode was estimated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EstimationMethod {
    /// Peak picking with half-power damping.
    PeakPicking,
    /// LSCF poles, LSFD shapes.
    Lscf,
    /// Read from the file (dataset 55).
    FromFile,
}

impl EstimationMethod {
    /// Name in files and tables.
    pub fn name(&self) -> &'static str {
        match self {
            EstimationMethod::PeakPicking => "peak_picking",
            EstimationMethod::Lscf => "lscf",
            EstimationMethod::FromFile => "dataset_55",
        }
    }
}

/// A mode identified from a test.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TestMode {
    /// Natural frequency, Hz (undamped, `|lambda| / 2 pi`).
    pub frequency_hz: f64,
    /// Viscous damping ratio.
    pub damping_ratio: f64,
    /// Shape at the test's response DOFs (complex; empty when not estimated).
    #[serde(skip)]
    pub shape: Vec<Complex<f64>>,
    /// How it was estimated.
    pub method: EstimationMethod,
    /// LSCF: the number of model orders at which the pole was stable (0 otherwise).
    pub stable_orders: usize,
}
