//! Charts of the squeal stability analysis (`squeal stability`): the stability map (growth rate
//! against the swept parameter, one curve per mode) and the eigenvalue map of one operating
//! point (growth rate against frequency).

use std::path::Path;

use super::chart::{write, LineChart, Series, Stroke};
use crate::stability::model::PointAnalysis;
use crate::stability::sweep::SweepResult;
use crate::stability::system::Body;
use crate::Result;

/// Curves drawn at most: every curve that grows somewhere, then the least stable others, up to
/// this many (more would not be readable; stability.csv has them all).
pub const MAX_CURVES: usize = 8;

/// Growth rate against the swept parameter, one line per dominant mode, with the zero line.
pub fn write_stability_map(
    sweep: &SweepResult,
    png: Option<&Path>,
    svg: Option<&Path>,
) -> Result<()> {
    let x: Vec<f64> = sweep.points.iter().map(|p| p.value).collect();
    let mut series = Vec::new();
    for (k, curve) in sweep.curves.iter().take(MAX_CURVES).enumerate() {
        // One series per run of consecutive points where the mode dominates an eigenvalue.
        let mut first = true;
        let mut run: (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
        let flush = |run: &mut (Vec<f64>, Vec<f64>), series: &mut Vec<Series>, first: &mut bool| {
            if !run.0.is_empty() {
                series.push(Series {
                    label: if *first {
                        curve.label.clone()
                    } else {
                        String::new()
                    },
                    x: std::mem::take(&mut run.0),
                    y: std::mem::take(&mut run.1),
                    stroke: if curve.body == Body::Rail {
                        Stroke::Dotted
                    } else {
                        Stroke::SolidWithPoints
                    },
                    color: k,
                });
                *first = false;
            }
        };
        for (i, g) in curve.growth_rate_per_s.iter().enumerate() {
            match g {
                Some(g) => {
                    run.0.push(x[i]);
                    run.1.push(*g);
                }
                None => flush(&mut run, &mut series, &mut first),
            }
        }
        flush(&mut run, &mut series, &mut first);
    }
    if let (Some(&a), Some(&b)) = (x.first(), x.last()) {
        series.push(Series {
            label: String::new(),
            x: vec![a, b],
            y: vec![0.0, 0.0],
            stroke: Stroke::Dotted,
            color: 6,
        });
    }
    let chart = LineChart {
        title: format!(
            "Stability map: growth rate against {} (modes labelled (nodal circles, nodal diameters))",
            sweep.spec.parameter.name()
        ),
        x_label: sweep.spec.parameter.axis_label().into(),
        y_label: "growth rate (1/s), > 0 unstable".into(),
        series,
        size_px: Some((1200, 720)),
        ..LineChart::default()
    };
    write(&chart, png, svg)
}

/// Growth rate against frequency of every eigenvalue of one operating point: wheel-dominated
/// and rail-dominated ones apart, with the zero line.
pub fn write_eigenvalue_map(
    point: &PointAnalysis,
    png: Option<&Path>,
    svg: Option<&Path>,
) -> Result<()> {
    let mut series = Vec::new();
    for (body, label, color) in [
        (Body::Wheel, "wheel-dominated", 0),
        (Body::Rail, "rail-dominated", 1),
    ] {
        Series::push_points(
            &mut series,
            label,
            point
                .eigen
                .iter()
                .filter(|e| e.dominant().body == body)
                .map(|e| (e.frequency_hz, e.growth_rate_per_s)),
            color,
        );
    }
    let f_max = point
        .eigen
        .iter()
        .fold(0.0f64, |m, e| m.max(e.frequency_hz));
    series.push(Series {
        label: String::new(),
        x: vec![0.0, f_max],
        y: vec![0.0, 0.0],
        stroke: Stroke::Dotted,
        color: 6,
    });
    let chart = LineChart {
        title: "Eigenvalues of the coupled wheel-rail system at the operating point".into(),
        x_label: "frequency (Hz)".into(),
        y_label: "growth rate (1/s), > 0 unstable".into(),
        series,
        size_px: Some((1200, 720)),
        ..LineChart::default()
    };
    write(&chart, png, svg)
}
