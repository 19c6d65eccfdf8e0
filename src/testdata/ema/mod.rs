//! Experimental modal analysis: natural frequencies, damping ratios and mode shapes estimated
//! from measured frequency response functions (hammer tests), and their pairing with FE modes.
//!
//! One concept per file:
//! - [`frf`]: the FRFs of a test (one reference, several responses, one frequency axis), from a
//!   universal file's datasets 58;
//! - [`peak_picking`]: resonances as peaks of the mean FRF magnitude, damping from the
//!   half-power bandwidth, shapes by quadrature picking;
//! - [`lscf`]: the least-squares complex-frequency (LSCF) estimator: a common-denominator model
//!   in the z-domain, poles at every model order;
//! - [`stabilisation`]: the stabilisation diagram of the LSCF poles and the selection of the
//!   physical modes (columns of poles stable in frequency and damping);
//! - [`lsfd`]: mode shapes (residues) for given poles by a least-squares frequency-domain fit;
//! - [`mac`]: the modal assurance criterion;
//! - [`pairing`]: test modes paired with FE modes by MAC (when shapes exist) or frequency;
//! - [`test_mode`]: an identified mode; [`estimate`]: the LSCF pipeline (diagram, selection,
//!   shapes).

pub mod estimate;
pub mod fe_comparison;
pub mod frf;
pub mod lscf;
pub mod lsfd;
pub mod mac;
pub mod pairing;
pub mod peak_picking;
pub mod stabilisation;
pub mod test_mode;
pub mod uff_modes;

pub use estimate::{estimate_lscf, LscfEstimate};
pub use frf::{FrfSet, TestDof};
pub use test_mode::{EstimationMethod, TestMode};
