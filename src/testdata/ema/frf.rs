//! The FRFs of one test: a single reference DOF, several response DOFs, one frequency axis.
//!
//! Built from the datasets 58 of a universal file whose function type is 4 (FRF). All must share
//! the reference DOF (a single-reference test: one hammer point, or one shaker) and the abscissa
//! (same first frequency, step and count), since the estimators fit every response on the same
//! lines.

use rustfft::num_complex::Complex;

use crate::testdata::uff::dataset58::function_type;
use crate::testdata::uff::{Abscissa, UffFile};
use crate::{Error, Result};

/// A response or reference DOF: node label and direction (1/2/3 = +X/+Y/+Z, negative: reversed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TestDof {
    /// Node label.
    pub node: i64,
    /// Direction code.
    pub direction: i64,
}

/// The FRFs of a single-reference test.
#[derive(Clone, Debug, PartialEq)]
pub struct FrfSet {
    /// Frequency of every line, Hz.
    pub frequency_hz: Vec<f64>,
    /// The excitation DOF.
    pub reference: TestDof,
    /// The response DOF of each FRF.
    pub responses: Vec<TestDof>,
    /// `frf[o][k]`: response o at line k.
    pub frf: Vec<Vec<Complex<f64>>>,
    /// Specific data type of the response (8 displacement, 11 velocity, 12 acceleration).
    pub response_quantity: i64,
}

impl FrfSet {
    /// The FRFs of `file` (datasets 58 of function type 4); `name` is the file for errors.
    pub fn from_uff(file: &UffFile, name: &str) -> Result<FrfSet> {
        let frfs: Vec<_> = file
            .functions
            .iter()
            .filter(|f| f.function_type == function_type::FRF)
            .collect();
        let Some(first) = frfs.first() else {
            return Err(Error::input(
                name,
                "dataset 58",
                format!(
                    "no FRF among its {} functions: the analysis needs FRFs (dataset 58 with \
                     function type 4)",
                    file.functions.len()
                ),
            ));
        };
        let (start, step) = match first.abscissa {
            Abscissa::Even { start, step } if step > 0.0 => (start, step),
            _ => {
                return Err(Error::input(
                    name,
                    "dataset 58, record 7",
                    "the FRFs need an even frequency axis with a step > 0",
                ))
            }
        };
        let count = first.values.len();
        let reference = TestDof {
            node: first.reference.node,
            direction: first.reference.direction,
        };
        let mut responses = Vec::with_capacity(frfs.len());
        let mut values = Vec::with_capacity(frfs.len());
        for (k, f) in frfs.iter().enumerate() {
            let this_reference = TestDof {
                node: f.reference.node,
                direction: f.reference.direction,
            };
            if this_reference != reference {
                return Err(Error::input(
                    name,
                    format!("FRF {} (dataset 58), record 6, reference", k + 1),
                    format!(
                        "node {} direction {}; every FRF must share the first one's reference \
                         (node {} direction {}): one test is one excitation point",
                        this_reference.node,
                        this_reference.direction,
                        reference.node,
                        reference.direction
                    ),
                ));
            }
            let same_axis = match f.abscissa {
                Abscissa::Even { start: s, step: d } => {
                    s == start && d == step && f.values.len() == count
                }
                Abscissa::Uneven(_) => false,
            };
            if !same_axis {
                return Err(Error::input(
                    name,
                    format!("FRF {} (dataset 58), record 7", k + 1),
                    format!(
                        "its frequency axis differs from the first FRF's ({count} lines from \
                         {start} Hz in steps of {step} Hz)"
                    ),
                ));
            }
            responses.push(TestDof {
                node: f.response.node,
                direction: f.response.direction,
            });
            values.push(f.values.to_complex());
        }
        Ok(FrfSet {
            frequency_hz: (0..count).map(|k| start + k as f64 * step).collect(),
            reference,
            responses,
            frf: values,
            response_quantity: first.axes[1].specific_data_type,
        })
    }

    /// Indices of the lines with `fmin_hz <= f <= fmax_hz`.
    pub fn band(&self, fmin_hz: f64, fmax_hz: f64) -> std::ops::Range<usize> {
        let first = self.frequency_hz.partition_point(|&f| f < fmin_hz);
        let end = self.frequency_hz.partition_point(|&f| f <= fmax_hz);
        first..end.max(first)
    }

    /// Mean magnitude over the responses at every line (a mode indicator: every resonance of
    /// the test shows as a peak).
    pub fn mean_magnitude(&self) -> Vec<f64> {
        let n = self.frf.len() as f64;
        (0..self.frequency_hz.len())
            .map(|k| self.frf.iter().map(|h| h[k].norm()).sum::<f64>() / n)
            .collect()
    }
}
