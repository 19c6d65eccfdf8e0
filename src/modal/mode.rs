//! The wheel-mode record every stage after the modal solvers reads (`modes.json`): frequency,
//! family and the paper's label (nodal circles, nodal diameters); how the solvers find the
//! label is in docs/modal.md.

use serde::{Deserialize, Serialize};

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
