//! Charts of an experimental modal analysis: the LSCF stabilisation diagram (poles by model
//! order over frequency, the mean FRF magnitude behind them) and the MAC matrix of test modes
//! against FE modes.

use std::path::Path;

use super::chart::{write, write_heatmap, Heatmap, LineChart, Series, Stroke, PALE};
use crate::testdata::ema::stabilisation::{DiagramPole, PoleStatus};
use crate::testdata::ema::TestMode;
use crate::Result;

/// The stabilisation diagram: one marker per pole (new, stable in frequency, stable in
/// frequency and damping), the selected modes as vertical lines, and the mean FRF magnitude
/// (log scale, mapped onto the order axis) for orientation.
pub fn write_stabilisation_chart(
    points: &[DiagramPole],
    max_order: usize,
    selected: &[TestMode],
    frequency_hz: &[f64],
    mean_magnitude: &[f64],
    png: Option<&Path>,
    svg: Option<&Path>,
) -> Result<()> {
    let top = max_order as f64 + 2.0;
    let mut series = Vec::new();
    // Mean |H| in log scale, spread over the order axis (0 .. top).
    let positive: Vec<f64> = mean_magnitude
        .iter()
        .copied()
        .filter(|v| *v > 0.0)
        .collect();
    if !positive.is_empty() {
        let (lo, hi) = positive.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| {
            (a.min(v.ln()), b.max(v.ln()))
        });
        let span = (hi - lo).max(1e-12);
        let (x, y): (Vec<f64>, Vec<f64>) = frequency_hz
            .iter()
            .zip(mean_magnitude)
            .filter(|(_, v)| **v > 0.0)
            .map(|(f, v)| (*f, (v.ln() - lo) / span * top))
            .unzip();
        series.push(Series {
            label: "mean |H| (log scale)".into(),
            x,
            y,
            stroke: Stroke::Solid,
            color: PALE,
        });
    }
    for (status, label, color) in [
        (PoleStatus::New, "new pole", 3),
        (PoleStatus::Frequency, "stable frequency", 1),
        (PoleStatus::Stable, "stable frequency and damping", 2),
    ] {
        Series::push_points(
            &mut series,
            label,
            points
                .iter()
                .filter(|p| p.status == status)
                .map(|p| (p.pole.frequency_hz, p.order as f64)),
            color,
        );
    }
    for (k, m) in selected.iter().enumerate() {
        series.push(Series {
            label: if k == 0 {
                "selected mode".into()
            } else {
                String::new()
            },
            x: vec![m.frequency_hz, m.frequency_hz],
            y: vec![0.0, top],
            stroke: Stroke::Dotted,
            color: 0,
        });
    }
    let (fmin, fmax) = (
        frequency_hz.first().copied().unwrap_or(0.0),
        frequency_hz.last().copied().unwrap_or(1.0),
    );
    let chart = LineChart {
        title: "LSCF stabilisation diagram".into(),
        x_label: "frequency (Hz)".into(),
        y_label: "model order".into(),
        series,
        x_range: Some((fmin, fmax.max(fmin + 1.0))),
        y_range: Some((0.0, top)),
        ..Default::default()
    };
    write(&chart, png, svg)
}

/// The MAC matrix, test modes along x and FE modes along y, on a linear colour scale 0..1.
pub fn write_mac_chart(
    mac: &[Vec<f64>],
    test_frequency_hz: &[f64],
    fe_frequency_hz: &[f64],
    png: Option<&Path>,
    svg: Option<&Path>,
) -> Result<()> {
    let (nt, nf) = (test_frequency_hz.len(), fe_frequency_hz.len());
    let mut values = Vec::with_capacity(nt * nf);
    for row in mac.iter().take(nt) {
        values.extend(row.iter().take(nf));
    }
    let map = Heatmap {
        title: format!(
            "MAC: test modes ({:.0}..{:.0} Hz) against FE modes ({:.0}..{:.0} Hz)",
            test_frequency_hz.first().unwrap_or(&0.0),
            test_frequency_hz.last().unwrap_or(&0.0),
            fe_frequency_hz.first().unwrap_or(&0.0),
            fe_frequency_hz.last().unwrap_or(&0.0)
        ),
        x_label: "test mode (number, by frequency)".into(),
        y_label: "FE mode (number, by frequency); colour: MAC 0 (dark) to 1 (yellow)".into(),
        x: (1..=nt).map(|k| k as f64).collect(),
        y: (1..=nf).map(|k| k as f64).collect(),
        values,
        range_db: 20.0,
        linear_range: Some((0.0, 1.0)),
        ..Default::default()
    };
    write_heatmap(&map, png, svg)
}
