//! A test from a universal file compared with FE modes: pairs by MAC (or frequency), the MAC
//! matrix, and the test modes labelled with their FE partners' (nodal circles, nodal
//! diameters) so they can join the modal chart and the hammer comparison table.

use super::mac::subspace_mac;
use super::pairing::{pair_modes, FeShape, ModePairing};
use super::uff_modes::UffTest;
use crate::modal::mode::ModeRef;
use crate::testdata::hammer::{HammerComparison, MeasuredMode, ModePair};

/// The comparison of a test with FE modes.
pub struct UffComparison {
    /// Test-FE pairs.
    pub pairs: Vec<ModePairing>,
    /// `mac[test][fe]`, when both sides have shapes.
    pub mac: Option<Vec<Vec<f64>>>,
    /// The paired test modes as measured modes labelled like their FE partners.
    pub measured: Vec<MeasuredMode>,
    /// The same pairs as a hammer comparison (table and CSV of the hammer CSV path).
    pub table: HammerComparison,
}

/// Compares `test` (read from `file_name`) with the FE modes `fe` and, when given, their shapes
/// at the test DOFs.
pub fn compare_with_fe(
    test: &UffTest,
    file_name: &str,
    fe: &[ModeRef],
    fe_shapes: Option<&[FeShape]>,
) -> UffComparison {
    let fe_frequency_hz: Vec<f64> = fe.iter().map(|m| m.frequency_hz).collect();
    let pairs = pair_modes(&test.modes, &fe_frequency_hz, fe_shapes);
    let mac = fe_shapes
        .filter(|_| test.modes.iter().all(|t| !t.shape.is_empty()))
        .map(|shapes| {
            test.modes
                .iter()
                .map(|t| shapes.iter().map(|s| subspace_mac(&t.shape, s)).collect())
                .collect()
        });
    let measured: Vec<MeasuredMode> = pairs
        .iter()
        .map(|p| {
            let t = &test.modes[p.test_index];
            let partner = &fe[p.fe_index];
            MeasuredMode {
                family: partner.family,
                nodal_circles: partner.nodal_circles,
                nodal_diameters: partner.nodal_diameters,
                frequency_hz: t.frequency_hz,
                damping_ratio: t.damping_ratio.is_finite().then_some(t.damping_ratio),
                source: match p.mac {
                    Some(m) => format!(
                        "{file_name}: {} mode {}, label of the FE mode with MAC {m:.3}",
                        t.method.name(),
                        p.test_index + 1
                    ),
                    None => format!(
                        "{file_name}: {} mode {}, label of the nearest FE frequency (no shapes to \
                         compare)",
                        t.method.name(),
                        p.test_index + 1
                    ),
                },
            }
        })
        .collect();
    let table = HammerComparison {
        pairs: pairs
            .iter()
            .zip(&measured)
            .map(|(p, m)| ModePair {
                measured: m.clone(),
                fe_frequency_hz: p.fe_frequency_hz,
                error_percent: p.error_percent,
            })
            .collect(),
        unmatched_measured: Vec::new(),
        unmatched_fe: fe
            .iter()
            .enumerate()
            .filter(|(j, _)| pairs.iter().all(|p| p.fe_index != *j))
            .map(|(_, m)| m.clone())
            .collect(),
    };
    UffComparison {
        pairs,
        mac,
        measured,
        table,
    }
}
