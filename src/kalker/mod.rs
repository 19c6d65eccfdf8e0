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

/// Elastic constants of the two (identical) bodies.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub young_modulus_pa: f64,
    /// Poisson's ratio nu (-), 0 <= nu <= 0.5.
    pub poisson_ratio: f64,
}

impl Material {
    /// Wheel and rail steel as in docs/references.md, section 5: E = 210 GPa, nu = 0.3.
    pub const STEEL: Material = Material {
        young_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };

    /// Checks the ranges (E > 0, 0 <= nu < 0.5) so that every formula downstream is finite.
    pub fn validated(young_modulus_pa: f64, poisson_ratio: f64, source: &str) -> Result<Material> {
        if !(young_modulus_pa.is_finite() && young_modulus_pa > 0.0) {
            return Err(Error::input(
                source,
                "--e",
                format!("Young's modulus must be > 0 Pa, got {young_modulus_pa}"),
            ));
        }
        if !(poisson_ratio.is_finite() && (0.0..0.5).contains(&poisson_ratio)) {
            return Err(Error::input(
                source,
                "--nu",
                format!("Poisson's ratio must be in [0, 0.5), got {poisson_ratio}"),
            ));
        }
        Ok(Material {
            young_modulus_pa,
            poisson_ratio,
        })
    }

    /// Shear modulus G = E / (2 (1 + nu)).
    pub fn shear_modulus_pa(&self) -> f64 {
        self.young_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Combined modulus of two identical bodies, E* = E / (2 (1 - nu^2)) (docs/references.md, section 5).
    pub fn combined_modulus_pa(&self) -> f64 {
        self.young_modulus_pa / (2.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }
}

/// Checks a friction coefficient: finite and > 0.
pub fn validate_friction(mu: f64, source: &str) -> Result<()> {
    if !(mu.is_finite() && mu > 0.0) {
        return Err(Error::input(
            source,
            "--mu",
            format!("friction coefficient must be > 0, got {mu}"),
        ));
    }
    Ok(())
}

/// Checks a normal force: finite and > 0 N.
pub fn validate_normal_force(normal_force_n: f64, source: &str) -> Result<()> {
    if !(normal_force_n.is_finite() && normal_force_n > 0.0) {
        return Err(Error::input(
            source,
            "--fn",
            format!("normal force must be > 0 N, got {normal_force_n}"),
        ));
    }
    Ok(())
}
