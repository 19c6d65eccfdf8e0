//! `squeal ema --uff FILE [--method lscf|peak-picking] [--fmin-hz F] [--fmax-hz F]
//! [--max-order N] --out DIR`: natural frequencies, damping ratios and mode shapes of a hammer
//! test from its FRFs in a universal file (docs/ema.md).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use rustfft::num_complex::Complex;
use serde_json::json;
use squeal::output::{Commit, StagedDir};
use squeal::report::ema_charts::write_stabilisation_chart;
use squeal::testdata::ema::peak_picking::peak_picking;
use squeal::testdata::ema::{estimate_lscf, FrfSet, TestDof, TestMode};
use squeal::testdata::uff::{self, NodalData, NodalValues, UffFile};
use squeal::{Error, Result};

use super::grammar::{input_name, out_dir};

/// Estimator.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum EmaMethod {
    /// Least-squares complex frequency (poles at orders 2..max, stabilisation diagram).
    Lscf,
    /// Peaks of the mean FRF magnitude, half-power damping (well-separated modes only).
    PeakPicking,
}

/// Arguments of `squeal ema`.
#[derive(Args, Debug)]
pub struct EmaArgs {
    /// Universal file with the FRFs (datasets 58, function type 4; ASCII or binary 58b), one
    /// reference DOF, e.g. tests/fixtures/uff/frf_ascii.uff.
    #[arg(long)]
    pub uff: PathBuf,
    /// Estimator.
    #[arg(long, value_enum, default_value_t = EmaMethod::Lscf)]
    pub method: EmaMethod,
    /// Lowest frequency analysed (Hz; default: the FRFs' first line).
    #[arg(long, allow_negative_numbers = true)]
    pub fmin_hz: Option<f64>,
    /// Highest frequency analysed (Hz; default: the FRFs' last line).
    #[arg(long, allow_negative_numbers = true)]
    pub fmax_hz: Option<f64>,
    /// Highest LSCF model order (even, 2..=200); orders 2, 4, ... up to it are computed.
    #[arg(long, default_value_t = squeal::testdata::ema::uff_modes::DEFAULT_MAX_ORDER as i64, allow_negative_numbers = true)]
    pub max_order: i64,
    /// Output folder (replaced whole). Default: out/ema/<universal file name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `squeal ema`.
pub fn run(args: EmaArgs) -> Result<()> {
    squeal::output::protect_inputs([&args.uff]);
    let name = args.uff.display().to_string();
    let file = uff::read_uff(&args.uff)?;
    let set = FrfSet::from_uff(&file, &name)?;
    let (first, last) = (
        set.frequency_hz[0],
        set.frequency_hz[set.frequency_hz.len() - 1],
    );
    let fmin = args.fmin_hz.unwrap_or(first);
    let fmax = args.fmax_hz.unwrap_or(last);
    if !(fmin.is_finite() && fmax.is_finite() && first <= fmin && fmin < fmax && fmax <= last) {
        return Err(Error::input(
            "command line",
            "--fmin-hz/--fmax-hz",
            format!(
                "[{fmin}, {fmax}] Hz; allowed: {first} <= fmin < fmax <= {last} Hz (the FRFs' \
                 lines)"
            ),
        ));
    }
    if !(2..=200).contains(&args.max_order) || args.max_order % 2 != 0 {
        return Err(Error::input(
            "command line",
            "--max-order",
            format!("{}; allowed: an even number in 2..=200", args.max_order),
        ));
    }
    let max_order = args.max_order as usize;
    println!(
        "{}: {} FRFs, reference node {} direction {}, {} lines {first}..{last} Hz",
        name,
        set.frf.len(),
        set.reference.node,
        set.reference.direction,
        set.frequency_hz.len()
    );
    let out = out_dir(args.out.clone(), "ema", &input_name(&args.uff));
    let stage = StagedDir::new(&out)?;
    let dir = stage.path();
    let modes = match args.method {
        EmaMethod::PeakPicking => peak_picking(&set, fmin, fmax)?,
        EmaMethod::Lscf => {
            let estimate = estimate_lscf(&set, fmin, fmax, max_order)?;
            let mut csv = String::from("order,frequency_hz,damping_ratio,status\n");
            for p in &estimate.diagram {
                let _ = writeln!(
                    csv,
                    "{},{:.6},{:.6e},{}",
                    p.order,
                    p.pole.frequency_hz,
                    p.pole.damping_ratio,
                    p.status.name()
                );
            }
            write(&dir.join("stabilisation.csv"), csv)?;
            let band = set.band(fmin, fmax);
            write_stabilisation_chart(
                &estimate.diagram,
                max_order,
                &estimate.modes,
                &set.frequency_hz[band.clone()],
                &set.mean_magnitude()[band],
                Some(&dir.join("stabilisation.png")),
                Some(&dir.join("stabilisation.svg")),
            )?;
            println!(
                "LSCF: {} poles over orders 2..={max_order}",
                estimate.diagram.len()
            );
            estimate.modes
        }
    };
    println!("{:>4} {:>12} {:>10} {:>8}", "#", "f (Hz)", "zeta", "stable");
    let mut csv = String::from("index,method,frequency_hz,damping_ratio,stable_orders\n");
    for (k, m) in modes.iter().enumerate() {
        println!(
            "{:>4} {:>12.3} {:>10.5} {:>8}",
            k + 1,
            m.frequency_hz,
            m.damping_ratio,
            m.stable_orders
        );
        let _ = writeln!(
            csv,
            "{},{},{:.6},{:.6e},{}",
            k + 1,
            m.method.name(),
            m.frequency_hz,
            m.damping_ratio,
            m.stable_orders
        );
    }
    write(&dir.join("modes.csv"), csv)?;
    let json_modes: Vec<_> = modes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            json!({
                "index": k + 1,
                "method": m.method.name(),
                "frequency_hz": m.frequency_hz,
                "damping_ratio": m.damping_ratio,
                "stable_orders": m.stable_orders,
                "shape": set.responses.iter().zip(&m.shape).map(|(d, v)| json!({
                    "node": d.node, "direction": d.direction, "re": v.re, "im": v.im
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let summary = json!({
        "file": name,
        "method": format!("{:?}", args.method),
        "band_hz": [fmin, fmax],
        "max_order": max_order,
        "reference": set.reference,
        "modes": json_modes,
    });
    write(
        &dir.join("modes.json"),
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )?;
    let shapes = shapes_file(&file, &set.responses, &modes, set.response_quantity);
    uff::write::write_uff(&dir.join("modes.uff"), &shapes, false)?;
    let written = stage.commit(Commit::Replace)?;
    println!("wrote {}", written.display());
    Ok(())
}

fn write(path: &Path, text: String) -> Result<()> {
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// The estimated shapes as a universal file: the test's units and nodes, and one dataset 55 per
/// mode (complex eigenvalue, X/Y/Z translations per node; a DOF's value lands on its axis with
/// its sign).
fn shapes_file(test: &UffFile, dofs: &[TestDof], modes: &[TestMode], quantity: i64) -> UffFile {
    let mut nodes: Vec<i64> = dofs.iter().map(|d| d.node).collect();
    nodes.sort_unstable();
    nodes.dedup();
    let nodal_data = modes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let w = 2.0 * std::f64::consts::PI * m.frequency_hz;
            let lambda = Complex::new(
                -m.damping_ratio * w,
                w * (1.0 - m.damping_ratio * m.damping_ratio).max(0.0).sqrt(),
            );
            let values = nodes
                .iter()
                .map(|&node| {
                    let mut xyz = vec![Complex::new(0.0, 0.0); 3];
                    for (d, v) in dofs.iter().zip(&m.shape) {
                        let axis = d.direction.unsigned_abs() as usize;
                        if d.node == node && (1..=3).contains(&axis) {
                            xyz[axis - 1] += v * d.direction.signum() as f64;
                        }
                    }
                    NodalValues { node, values: xyz }
                })
                .collect();
            NodalData {
                id_lines: [
                    format!("squeal ema: mode {}", k + 1),
                    format!("method {}", m.method.name()),
                    String::new(),
                    String::new(),
                    format!(
                        "{:.3} Hz, damping ratio {:.5}",
                        m.frequency_hz, m.damping_ratio
                    ),
                ],
                model_type: 1,
                analysis_type: 3,
                data_characteristic: 2,
                specific_data_type: if quantity > 0 { quantity } else { 8 },
                complex: true,
                values_per_node: 3,
                integers: vec![1, k as i64 + 1],
                reals: vec![lambda.re, lambda.im, 0.0, 0.0, 0.0, 0.0],
                nodes: values,
            }
        })
        .collect();
    UffFile {
        units: test.units.clone(),
        nodes: test
            .nodes
            .iter()
            .filter(|n| nodes.contains(&n.label))
            .cloned()
            .collect(),
        nodal_data,
        ..Default::default()
    }
}
