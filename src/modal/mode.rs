//! The wheel-mode record every stage after the modal solvers reads (`modes.json`): frequency,
//! family and the paper's label (nodal circles, nodal diameters); how the solvers find the
//! label is in docs/modal.md.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// The file name of the wheel modes in a run directory or a modal output folder.
pub const MODES_FILE: &str = "modes.json";

/// Kinetic energy share in the axle from which a mode belongs to the axle family. Why a half:
/// such a mode is more the axle's than the wheel's; on the default wheel the shares fall in
/// two groups, below 0.25 (wheel modes carrying some axle) and above 0.5 (module tests).
pub const AXLE_FAMILY_SHARE: f64 = 0.5;

/// Mode family by the dominant motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "lowercase")]
pub enum ModeFamily {
    /// Out-of-plane (along the wheel axis).
    Axial,
    /// In-plane, radial.
    Radial,
    /// In-plane, circumferential.
    Circumferential,
    /// Mostly the axle's motion (its axial, bending or torsional resonance carrying the wheel);
    /// the first index of its label counts nodes along the axle.
    Axle,
    /// Rigid-body mode (never used to explain a peak).
    Rigid,
}

impl ModeFamily {
    /// The family's name as `modes.json` writes it: "axial", "radial", "circumferential",
    /// "axle", "rigid".
    pub fn word(self) -> &'static str {
        match self {
            ModeFamily::Axial => "axial",
            ModeFamily::Radial => "radial",
            ModeFamily::Circumferential => "circumferential",
            ModeFamily::Axle => "axle",
            ModeFamily::Rigid => "rigid",
        }
    }
}

/// A wheel mode as the identification needs it (written by the modal module as `modes.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeRef {
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Family.
    pub family: ModeFamily,
    /// Nodal circles (first index of the paper's label).
    pub nodal_circles: u32,
    /// Nodal diameters (second index of the paper's label).
    pub nodal_diameters: u32,
}

impl ModeRef {
    /// The paper's label "(nodal circles, nodal diameters)".
    pub fn label(&self) -> String {
        format!("({},{})", self.nodal_circles, self.nodal_diameters)
    }
}

/// Write `modes.json` into `dir` (through a temporary file): the one writer of the file that
/// every later stage reads as [`ModeRef`]s. `modes` may carry more fields than a [`ModeRef`]
/// (the axisymmetric solver's harmonic, residual and energy shares); readers ignore them.
pub fn write_modes_json<T: Serialize>(dir: &Path, modes: &[T]) -> Result<PathBuf> {
    let path = dir.join(MODES_FILE);
    let text = serde_json::to_string_pretty(modes)
        .map_err(|e| Error::Numerical(format!("encoding {MODES_FILE}: {e}")))?;
    crate::output::write_file_staged(&path, |p| {
        std::fs::write(p, &text).map_err(|e| Error::io(p, e))
    })?;
    Ok(path)
}

/// Read a `modes.json` (an array of [`ModeRef`]-compatible entries); errors name the file and
/// the bad field.
pub fn read_modes_json(path: &Path) -> Result<Vec<ModeRef>> {
    crate::input::read_json(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names agree with what serde writes into `modes.json` (`rename_all = "lowercase"`).
    #[test]
    fn family_words_are_the_names_modes_json_writes() {
        for f in [
            ModeFamily::Axial,
            ModeFamily::Radial,
            ModeFamily::Circumferential,
            ModeFamily::Axle,
            ModeFamily::Rigid,
        ] {
            assert_eq!(
                serde_json::to_string(&f).unwrap(),
                format!("\"{}\"", f.word())
            );
        }
    }
}
