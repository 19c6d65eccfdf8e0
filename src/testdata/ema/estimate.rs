//! The LSCF pipeline: poles at every order, the stabilisation diagram, the selected modes and
//! their shapes by LSFD.

use super::frf::FrfSet;
use super::lscf::Lscf;
use super::lsfd::residues;
use super::stabilisation::{diagram, select, DiagramPole};
use super::test_mode::{EstimationMethod, TestMode};
use crate::{Error, Result};

/// What an LSCF estimate gives.
#[derive(Clone, Debug)]
pub struct LscfEstimate {
    /// Every pole of every order, with its stability.
    pub diagram: Vec<DiagramPole>,
    /// Orders computed (2, 4, ..., max).
    pub orders: Vec<usize>,
    /// The selected physical modes, by increasing frequency, with LSFD shapes.
    pub modes: Vec<TestMode>,
}

/// LSCF modes of `set` in `fmin_hz..=fmax_hz` at orders up to `max_order` (even, >= 2).
pub fn estimate_lscf(
    set: &FrfSet,
    fmin_hz: f64,
    fmax_hz: f64,
    max_order: usize,
) -> Result<LscfEstimate> {
    if !(fmin_hz.is_finite() && fmax_hz.is_finite() && 0.0 <= fmin_hz && fmin_hz < fmax_hz) {
        return Err(Error::input(
            "lscf",
            "--fmin-hz/--fmax-hz",
            format!("[{fmin_hz}, {fmax_hz}] Hz; allowed: 0 <= fmin < fmax"),
        ));
    }
    let lscf = Lscf::new(set, fmin_hz, fmax_hz, max_order)?;
    let points = diagram(&lscf)?;
    let orders: Vec<usize> = (2..=max_order).step_by(2).collect();
    let selected = select(&points, orders.len());
    let lambdas: Vec<_> = selected.iter().map(|s| s.pole.lambda).collect();
    let shapes = if lambdas.is_empty() {
        Vec::new()
    } else {
        residues(set, &lambdas, fmin_hz, fmax_hz)?
    };
    let modes = selected
        .iter()
        .zip(shapes.into_iter().chain(std::iter::repeat(Vec::new())))
        .map(|(s, shape)| TestMode {
            frequency_hz: s.pole.frequency_hz,
            damping_ratio: s.pole.damping_ratio,
            shape,
            method: EstimationMethod::Lscf,
            stable_orders: s.stable_orders,
        })
        .collect();
    Ok(LscfEstimate {
        diagram: points,
        orders,
        modes,
    })
}
