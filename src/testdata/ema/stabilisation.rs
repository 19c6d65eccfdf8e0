//! The stabilisation diagram of LSCF poles and the selection of physical modes.
//!
//! Poles are computed at the model orders 2, 4, ..., `max_order`. Each pole is compared with the
//! nearest pole (in frequency) of the previous order and labelled (Peeters et al., "The PolyMAX
//! frequency-domain method", Shock and Vibration 11, 2004, section 4; the usual criteria):
//! - `New`: no pole of the previous order within 1 % in frequency;
//! - `Frequency`: within 1 % in frequency, damping changed by more than 5 %;
//! - `Stable`: within 1 % in frequency and 5 % in damping.
//!
//! Selection (stated before looking at any data, never tuned to a test): the stable poles are
//! grouped in columns (sorted by frequency; a pole joins the column whose median frequency is
//! within 1 % of it); a column holding stable poles at no fewer than a third of the orders (and
//! at least 3) is a physical mode, reported with the median frequency and damping ratio of the
//! column. Computational poles move from order to order and rarely stay stable that long.

use serde::Serialize;

use super::lscf::{Lscf, Pole};
use crate::Result;

/// Relative frequency change allowed for a stable pole.
pub const FREQUENCY_TOLERANCE: f64 = 0.01;
/// Relative damping change allowed for a stable pole.
pub const DAMPING_TOLERANCE: f64 = 0.05;
/// A mode is a column stable at no fewer than this fraction of the orders.
pub const MIN_STABLE_FRACTION: f64 = 1.0 / 3.0;

/// Stability of a pole against the previous order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PoleStatus {
    /// No counterpart at the previous order.
    New,
    /// Stable in frequency only.
    Frequency,
    /// Stable in frequency and damping.
    Stable,
}

impl PoleStatus {
    /// Name in files.
    pub fn name(&self) -> &'static str {
        match self {
            PoleStatus::New => "new",
            PoleStatus::Frequency => "frequency",
            PoleStatus::Stable => "stable",
        }
    }
}

/// One point of the diagram.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagramPole {
    /// Model order.
    pub order: usize,
    /// The pole.
    pub pole: Pole,
    /// Its stability.
    pub status: PoleStatus,
}

/// A selected physical mode: a column of stable poles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelectedPole {
    /// The pole with the median frequency and damping of the column.
    pub pole: Pole,
    /// Number of orders at which the column was stable.
    pub stable_orders: usize,
}

/// The stabilisation diagram of `lscf` at orders 2, 4, ..., its maximum.
pub fn diagram(lscf: &Lscf) -> Result<Vec<DiagramPole>> {
    let mut points = Vec::new();
    let mut previous: Vec<Pole> = Vec::new();
    for order in (2..=lscf.max_order()).step_by(2) {
        let poles = lscf.poles(order)?;
        for pole in &poles {
            let nearest = previous.iter().min_by(|a, b| {
                (a.frequency_hz - pole.frequency_hz)
                    .abs()
                    .total_cmp(&(b.frequency_hz - pole.frequency_hz).abs())
            });
            let status = match nearest {
                Some(p)
                    if (p.frequency_hz - pole.frequency_hz).abs()
                        <= FREQUENCY_TOLERANCE * pole.frequency_hz =>
                {
                    if (p.damping_ratio - pole.damping_ratio).abs()
                        <= DAMPING_TOLERANCE * pole.damping_ratio
                    {
                        PoleStatus::Stable
                    } else {
                        PoleStatus::Frequency
                    }
                }
                _ => PoleStatus::New,
            };
            points.push(DiagramPole {
                order,
                pole: *pole,
                status,
            });
        }
        previous = poles;
    }
    Ok(points)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// The physical modes of a diagram computed at `order_count` orders (module documentation).
pub fn select(points: &[DiagramPole], order_count: usize) -> Vec<SelectedPole> {
    let mut stable: Vec<&DiagramPole> = points
        .iter()
        .filter(|p| p.status == PoleStatus::Stable)
        .collect();
    stable.sort_by(|a, b| a.pole.frequency_hz.total_cmp(&b.pole.frequency_hz));
    let mut columns: Vec<Vec<&DiagramPole>> = Vec::new();
    for p in stable {
        let joins = columns.last().is_some_and(|column| {
            let centre = median(column.iter().map(|q| q.pole.frequency_hz).collect());
            (p.pole.frequency_hz - centre).abs() <= FREQUENCY_TOLERANCE * centre
        });
        if joins {
            columns.last_mut().expect("a column").push(p);
        } else {
            columns.push(vec![p]);
        }
    }
    let needed = ((MIN_STABLE_FRACTION * order_count as f64).ceil() as usize).max(3);
    columns
        .into_iter()
        .filter_map(|column| {
            let mut orders: Vec<usize> = column.iter().map(|p| p.order).collect();
            orders.sort_unstable();
            orders.dedup();
            (orders.len() >= needed).then(|| {
                let frequency_hz = median(column.iter().map(|p| p.pole.frequency_hz).collect());
                let damping_ratio = median(column.iter().map(|p| p.pole.damping_ratio).collect());
                let w = 2.0 * std::f64::consts::PI * frequency_hz;
                SelectedPole {
                    pole: Pole::new(rustfft::num_complex::Complex::new(
                        -damping_ratio * w,
                        w * (1.0 - damping_ratio * damping_ratio).sqrt(),
                    )),
                    stable_orders: orders.len(),
                }
            })
        })
        .collect()
}
