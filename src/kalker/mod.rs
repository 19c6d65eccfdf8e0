//! Kalker's rolling contact theory: Hertz, linear theory, FASTSIM and an exact
//! half-space steady-rolling solver in the manner of Kalker's CONTACT, plus a force-prescribed
//! (inverse) mode.
//!
//! Conventions used throughout this module (Kalker, *Three-dimensional elastic bodies in rolling
//! contact*, 1990, ch. 1-2):
//! * x is the rolling direction; the contact patch moves in +x over both bodies, so material enters
//!   at the leading edge x = +a and leaves at the trailing edge x = -a.
//! * Tractions `p = (px, py)` act on body 1 (the wheel); body 2 (the rail) carries `-p`.
//!   Displacements are differences `u = u(body 1) - u(body 2)`.
//! * Creepages: longitudinal `xi`, lateral `eta`, spin `phi` (1/m). Rigid slip
//!   `w = (xi - phi y, eta + phi x)`; local slip (per unit rolled distance) `s = w - du/dx`.
//! * Coulomb friction: `|p| <= mu pn`; where `|p| < mu pn` the slip is zero (adhesion), otherwise
//!   `p = -mu pn s/|s|` (slip). Hence at small creepage `Fx = -G c^2 C11 xi`,
//!   `Fy = -G c^2 C22 eta - G c^3 C23 phi` (the creep force opposes the creepage).
//! * Identical elastic bodies (wheel and rail steel); normal-tangential coupling vanishes
//!   ("quasi-identity"), so the normal and tangential problems are solved one after the other.

pub mod creep_coefficients;
pub mod elliptic;
pub mod fastsim;
pub mod geometry;
pub mod halfspace;
pub mod hertz;
pub mod inverse;
pub mod normal;
pub mod profiles;
pub mod rolling;
pub mod snapshot;
pub mod tangential;

pub use creep_coefficients::{kalker_creep_coefficients, linear_creep_forces, CreepCoefficients};
pub use hertz::HertzContact;
pub use inverse::{solve_force_prescribed, ForcePrescribedResult};
pub use rolling::{Method, RollingContactSolution, RollingSolver};
pub use tangential::{Creepages, ElementState};

use crate::{Error, Result};

/// Elastic constants of the two (identical) bodies: the crate's one material type
/// ([`Material::validated`], [`Material::combined_modulus_pa`]).
pub use crate::material::Material;

/// Checks a friction coefficient for Kalker's theory: in (0, 2]. Its field is `--mu` (a
/// command-line value); [`validate_friction_field`] names another.
pub fn validate_friction(mu: f64, source: &str) -> Result<()> {
    validate_friction_field(mu, source, "--mu")
}

/// Checks a friction coefficient read from `field` of `source` (e.g. a snapshot's `mu`).
pub fn validate_friction_field(mu: f64, source: &str, field: &str) -> Result<()> {
    // The tangential problem needs friction: zero is refused here, unlike in the FE contact.
    crate::friction::check_coefficient(mu, source, field, false)
}

/// Largest normal force Kalker's solvers take (N): 1e8 N, a thousand times a heavy-haul wheel
/// load (about 1.6e5 N). Far above it the half-space's influence sums overflow or lose their
/// digits (a force of 1e300 N used to end as "all pressure vanished").
pub const MAX_NORMAL_FORCE_N: f64 = 1e8;

/// Checks a normal force: in (0, [`MAX_NORMAL_FORCE_N`]] N.
pub fn validate_normal_force(normal_force_n: f64, source: &str) -> Result<()> {
    validate_normal_force_field(normal_force_n, source, "--normal-force-n")
}

/// Checks a normal force read from `field` of `source`.
pub fn validate_normal_force_field(normal_force_n: f64, source: &str, field: &str) -> Result<()> {
    if !(normal_force_n.is_finite() && normal_force_n > 0.0 && normal_force_n <= MAX_NORMAL_FORCE_N)
    {
        return Err(Error::input(
            source,
            field,
            format!("normal force must lie in (0, {MAX_NORMAL_FORCE_N:e}] N, got {normal_force_n}"),
        ));
    }
    Ok(())
}
