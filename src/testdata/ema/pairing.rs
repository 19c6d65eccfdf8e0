//! Test modes paired with FE modes.
//!
//! With shapes on both sides (FE shapes sampled at the test DOFs), each test mode is paired with
//! the FE mode of highest MAC, taking pairs greedily from the highest MAC down so no FE mode is
//! used twice. Without shapes, the pairing is by nearest frequency in the same greedy way (and
//! says so: a frequency match alone does not show the modes are the same).

use serde::Serialize;

use super::mac::subspace_mac;
use super::test_mode::TestMode;
use rustfft::num_complex::Complex;

/// One pair.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModePairing {
    /// Index of the test mode.
    pub test_index: usize,
    /// Index of the FE mode.
    pub fe_index: usize,
    /// Test frequency, Hz.
    pub test_frequency_hz: f64,
    /// FE frequency, Hz.
    pub fe_frequency_hz: f64,
    /// `100 (f_FE - f_test) / f_test`.
    pub error_percent: f64,
    /// MAC of the pair (None when paired by frequency).
    pub mac: Option<f64>,
}

/// An FE mode's shape at the test DOFs: one vector, or the two of a doublet (any combination
/// of them is a mode; the MAC is then taken with the subspace, [`subspace_mac`]).
pub type FeShape = Vec<Vec<Complex<f64>>>;

/// Pairs `test` with FE modes of frequencies `fe_frequency_hz` and, when given, shapes at the
/// test DOFs `fe_shapes[j]` (same DOF order as the test shapes).
pub fn pair_modes(
    test: &[TestMode],
    fe_frequency_hz: &[f64],
    fe_shapes: Option<&[FeShape]>,
) -> Vec<ModePairing> {
    let with_shapes = fe_shapes.filter(|_| test.iter().all(|t| !t.shape.is_empty()));
    // Score of every (test, FE) combination: MAC, or the negative relative frequency distance.
    let mut candidates: Vec<(f64, usize, usize, Option<f64>)> = Vec::new();
    for (i, t) in test.iter().enumerate() {
        for (j, &f) in fe_frequency_hz.iter().enumerate() {
            match with_shapes {
                Some(shapes) => {
                    let value = subspace_mac(&t.shape, &shapes[j]);
                    candidates.push((value, i, j, Some(value)));
                }
                None => candidates.push((-(f - t.frequency_hz).abs() / t.frequency_hz, i, j, None)),
            }
        }
    }
    candidates.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut test_used, mut fe_used) =
        (vec![false; test.len()], vec![false; fe_frequency_hz.len()]);
    let mut pairs = Vec::new();
    for (_, i, j, mac_value) in candidates {
        if test_used[i] || fe_used[j] {
            continue;
        }
        test_used[i] = true;
        fe_used[j] = true;
        let (ft, ff) = (test[i].frequency_hz, fe_frequency_hz[j]);
        pairs.push(ModePairing {
            test_index: i,
            fe_index: j,
            test_frequency_hz: ft,
            fe_frequency_hz: ff,
            error_percent: 100.0 * (ff - ft) / ft,
            mac: mac_value,
        });
    }
    pairs.sort_by_key(|p| p.test_index);
    pairs
}
