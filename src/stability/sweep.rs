//! Sweeps of one operating-point parameter, and the eigenvalues grouped into curves (one per
//! mode) for the stability map.
//!
//! Each sweep point is analysed alone (contact linearisation and eigenvalues); the points run
//! in parallel. An eigenvalue belongs to the curve of its dominant participant (the mode with
//! the largest energy share); where several eigenvalues share a dominant mode at one point, the
//! curve takes the one with the largest growth rate (the one that decides stability).

use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use super::model::StabilityModel;
use super::operating::OperatingPoint;
use super::system::{Body, ModalBody, SystemEigen};
use crate::modal::mode::ModeFamily;
use crate::{Error, Result};

/// The swept parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepParameter {
    /// Lateral creepage eta (-), the longitudinal one held.
    Eta,
    /// Longitudinal creepage xi (-), the lateral one held.
    Xi,
    /// Friction coefficient (-).
    Mu,
    /// Falling-friction slope dmu/dv (s/m).
    FrictionSlope,
    /// Lateral contact position on the wheel tread, profile coordinate S (mm); contact angle,
    /// curvatures and forces held (the contact's offset from the web alone).
    ContactS,
}

impl SweepParameter {
    /// All, with their command-line names.
    pub const ALL: [(SweepParameter, &'static str); 5] = [
        (SweepParameter::Eta, "eta"),
        (SweepParameter::Xi, "xi"),
        (SweepParameter::Mu, "mu"),
        (SweepParameter::FrictionSlope, "friction-slope-s-per-m"),
        (SweepParameter::ContactS, "contact-s-mm"),
    ];

    /// Command-line name.
    pub fn name(&self) -> &'static str {
        SweepParameter::ALL
            .iter()
            .find(|(p, _)| p == self)
            .map_or("?", |(_, n)| n)
    }

    /// Axis label with unit.
    pub fn axis_label(&self) -> &'static str {
        match self {
            SweepParameter::Eta => "lateral creepage eta (-)",
            SweepParameter::Xi => "longitudinal creepage xi (-)",
            SweepParameter::Mu => "friction coefficient mu (-)",
            SweepParameter::FrictionSlope => "falling-friction slope dmu/dv (s/m)",
            SweepParameter::ContactS => "contact position on the tread S (mm)",
        }
    }

    /// The operating point with the parameter set to `value`.
    pub fn apply(&self, op: &OperatingPoint, value: f64) -> OperatingPoint {
        let mut p = op.clone();
        match self {
            SweepParameter::Eta => p.creepages.eta = value,
            SweepParameter::Xi => p.creepages.xi = value,
            SweepParameter::Mu => p.mu = value,
            SweepParameter::FrictionSlope => p.friction_slope_s_per_m = value,
            SweepParameter::ContactS => p.contact_s_mm = value,
        }
        p
    }
}

/// A sweep: parameter, range, points.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SweepSpec {
    /// Parameter.
    pub parameter: SweepParameter,
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of points (>= 2).
    pub points: usize,
}

impl SweepSpec {
    /// The values, evenly spaced from `from` to `to`.
    pub fn values(&self) -> Vec<f64> {
        (0..self.points)
            .map(|i| self.from + (self.to - self.from) * i as f64 / (self.points - 1) as f64)
            .collect()
    }
}

/// Largest number of sweep points accepted.
pub const MAX_SWEEP_POINTS: usize = 2000;

/// Parses `NAME=FROM..TO:POINTS`, e.g. `eta=0..0.01:50`.
pub fn parse_sweep(text: &str) -> Result<SweepSpec> {
    let bad = |why: &str| {
        Error::input(
            "command line",
            "--sweep",
            format!(
                "{why}; expected NAME=FROM..TO:POINTS with NAME one of {} and 2..={MAX_SWEEP_POINTS} points, e.g. eta=0..0.01:50, got `{text}`",
                SweepParameter::ALL.map(|p| p.1).join(", ")
            ),
        )
    };
    let (name, range) = text.split_once('=').ok_or_else(|| bad("no `=`"))?;
    let parameter = SweepParameter::ALL
        .iter()
        .find(|(_, n)| *n == name.trim())
        .map(|(p, _)| *p)
        .ok_or_else(|| bad("unknown parameter"))?;
    let (span, count) = range.split_once(':').ok_or_else(|| bad("no `:POINTS`"))?;
    let (from, to) = span.split_once("..").ok_or_else(|| bad("no `..`"))?;
    let number = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    let (from, to) = (
        number(from).ok_or_else(|| bad("FROM is not a number"))?,
        number(to).ok_or_else(|| bad("TO is not a number"))?,
    );
    let points: usize = count
        .trim()
        .parse()
        .map_err(|_| bad("POINTS is not a whole number"))?;
    if !(2..=MAX_SWEEP_POINTS).contains(&points) {
        return Err(bad("POINTS out of range"));
    }
    if from == to {
        return Err(bad("FROM equals TO"));
    }
    Ok(SweepSpec {
        parameter,
        from,
        to,
        points,
    })
}

/// One analysed point of a sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    /// The parameter's value.
    pub value: f64,
    /// Creep force over the traction bound there.
    pub creep_over_bound: Option<f64>,
    /// Eigenvalues up to fmax.
    pub eigen: Vec<SystemEigen>,
    /// Why the point has no result (e.g. a creepage the Coulomb law cannot linearise).
    pub error: Option<String>,
}

/// One mode's curve across the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct Curve {
    /// The dominant mode's label.
    pub label: String,
    /// Body.
    pub body: Body,
    /// Wheel mode family.
    pub family: Option<ModeFamily>,
    /// (nodal circles, nodal diameters).
    pub circles_diameters: Option<(u32, u32)>,
    /// Growth rate (1/s) at each point (None where no eigenvalue has it dominant).
    pub growth_rate_per_s: Vec<Option<f64>>,
    /// Frequency (Hz) at each point.
    pub frequency_hz: Vec<Option<f64>>,
}

impl Curve {
    /// Largest growth rate over the sweep.
    pub fn peak_growth(&self) -> f64 {
        self.growth_rate_per_s
            .iter()
            .flatten()
            .fold(f64::NEG_INFINITY, |m, &g| m.max(g))
    }
}

/// A sweep's result.
#[derive(Clone, Debug, Serialize)]
pub struct SweepResult {
    /// The sweep.
    pub spec: SweepSpec,
    /// Points.
    pub points: Vec<SweepPoint>,
    /// One curve per dominant mode, the most unstable first.
    pub curves: Vec<Curve>,
    /// Wall time (s).
    pub seconds: f64,
}

/// Run a sweep about `base` with the bodies of the base point (the wheel's is rebuilt at each
/// point of a contact-position sweep).
pub fn run_sweep(
    model: &StabilityModel,
    base: &OperatingPoint,
    wheel: &ModalBody,
    rail: &ModalBody,
    spec: &SweepSpec,
) -> Result<SweepResult> {
    let t0 = Instant::now();
    let values = spec.values();
    let points: Vec<Result<SweepPoint>> = values
        .par_iter()
        .map(|&value| {
            let op = spec.parameter.apply(base, value);
            let rebuilt;
            let wheel_here = if spec.parameter == SweepParameter::ContactS {
                rebuilt = model.wheel_body(&op)?;
                &rebuilt
            } else {
                wheel
            };
            match model.analyse(&op, wheel_here, rail) {
                Ok(a) => Ok(SweepPoint {
                    value,
                    creep_over_bound: Some(a.law.creep_over_bound()),
                    eigen: a.eigen,
                    error: None,
                }),
                // A point the law cannot linearise is recorded, not fatal; anything else is.
                Err(Error::Input { field, message, .. }) => Ok(SweepPoint {
                    value,
                    creep_over_bound: None,
                    eigen: Vec::new(),
                    error: Some(format!("{field}: {message}")),
                }),
                Err(e) => Err(e),
            }
        })
        .collect();
    let points: Vec<SweepPoint> = points.into_iter().collect::<Result<_>>()?;
    let curves = curves(&points);
    Ok(SweepResult {
        spec: *spec,
        points,
        curves,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// Group the points' eigenvalues into one curve per dominant mode, most unstable first.
pub fn curves(points: &[SweepPoint]) -> Vec<Curve> {
    let mut out: Vec<Curve> = Vec::new();
    for (k, point) in points.iter().enumerate() {
        for e in &point.eigen {
            let tag = e.dominant();
            let index = match out
                .iter()
                .position(|c| c.body == tag.body && c.label == tag.label)
            {
                Some(i) => i,
                None => {
                    out.push(Curve {
                        label: tag.label.clone(),
                        body: tag.body,
                        family: tag.family,
                        circles_diameters: tag.circles_diameters,
                        growth_rate_per_s: vec![None; points.len()],
                        frequency_hz: vec![None; points.len()],
                    });
                    out.len() - 1
                }
            };
            let curve = &mut out[index];
            if curve.growth_rate_per_s[k].is_none_or(|g| e.growth_rate_per_s > g) {
                curve.growth_rate_per_s[k] = Some(e.growth_rate_per_s);
                curve.frequency_hz[k] = Some(e.frequency_hz);
            }
        }
    }
    out.sort_by(|a, b| b.peak_growth().total_cmp(&a.peak_growth()));
    out
}
