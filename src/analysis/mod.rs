//! Analysis of a run's vibration: the window after the lateral-motion onset, the PSD at a
//! requested resolution, the dominant peaks and the wheel modes that explain them, and the
//! growth of mode bands over time.
//!
//! - [`run`]: a run directory -> window -> Welch PSD -> peaks (with their rim-mean /
//!   rim-point ratios) -> identification ([`RunAnalysis`]).
//! - [`identify`]: spectral peaks <-> wheel modes (families by signal direction, tolerance,
//!   nodal diameters gated by the rim ratio).
//! - [`per_n`]: the rim ring's spectra per nodal diameter (a frequency x n map), each
//!   harmonic's peaks named from the modes of its n, and the per-n check of required modes.
//! - [`creep_check`]: a yawed wheelset's quasi-steady creep forces against Kalker's exact theory.
//! - [`growth`]: wavelet-ridge amplitude and growth rate per mode band and time window.
//! - [`ring_growth`]: each ring harmonic's envelope, growth rate and limit cycle, and the squeal
//!   verdict by the criteria of docs/curving.md.
//!
//! It reads run directories and mode files and never draws: `report` renders what it returns.

pub mod creep_check;
pub mod growth;
pub mod identify;
pub mod per_n;
pub mod ring_growth;
pub mod run;

pub use run::{
    analyse_run, lateral_onset_s, resolve_column, rim_ratio, AnalysisOptions, AnalysisWindow,
    RunAnalysis, DEFAULT_FMAX_HZ, DEFAULT_RESOLUTION_HZ,
};
