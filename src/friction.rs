//! Friction laws of the contact (Yang & Li 2019): a constant Coulomb coefficient, or falling
//! friction `mu(v) = mu_d + (mu_s - mu_d) exp(-c |v|)` of the slip speed v; and the one check of
//! a friction coefficient that the contact, Kalker's theory and the command line share; and
//! which slip speed a falling law reads in the explicit contact ([`SlipSpeed`]).

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// Largest friction coefficient accepted: wheel-rail friction lies well below 1 (0.1-0.6 dry);
/// 2 leaves room for experiments and catches a percentage typed for a coefficient.
pub const MAX_FRICTION_COEFFICIENT: f64 = 2.0;

/// Checks a friction coefficient: `[0, 2]`, or `(0, 2]` when `zero_allowed` is false (Kalker's
/// tangential problem has no solution without friction); the error names `field` and the
/// range.
pub fn check_coefficient(mu: f64, source: &str, field: &str, zero_allowed: bool) -> Result<()> {
    let low_ok = if zero_allowed { mu >= 0.0 } else { mu > 0.0 };
    if !(low_ok && mu <= MAX_FRICTION_COEFFICIENT) {
        return Err(Error::input(
            source,
            field,
            format!(
                "must lie in {}0, {MAX_FRICTION_COEFFICIENT}] (got {mu})",
                if zero_allowed { "[" } else { "(" }
            ),
        ));
    }
    Ok(())
}

/// Friction law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum FrictionLaw {
    /// Constant coefficient.
    Coulomb {
        /// Friction coefficient.
        mu: f64,
    },
    /// Velocity-dependent (falling) friction `mu_d + (mu_s - mu_d) exp(-c |v|)`.
    Falling {
        /// Static coefficient.
        mu_static: f64,
        /// Dynamic coefficient.
        mu_dynamic: f64,
        /// Decay `c` (s/m).
        decay_s_per_m: f64,
    },
}

/// The slip speed `v` at which the explicit contact evaluates a velocity-dependent law.
///
/// `Node` (the default, LS-DYNA's and the paper's way): each slave node's own relative
/// tangential speed in the last step. With a falling law every node then carries a negative
/// damping `N_node |dmu/dv|` of its own against its tangential penalty spring and its nodal mass:
/// an oscillator at `sqrt(k / m)` (tens of kHz) that the falling slope drives into stick-slip
/// whatever the patch does (E. Vollebregt's objection to Zhao & Li 2016, on a 1D slider; in
/// the 10 mrad curve run the nodes slide at 0.15-0.22 m/s where the wheel slides at 0.083 m/s,
/// docs/curving.md). The law measured on a tribometer or fitted to creep curves (the paper's
/// 0.5 / 0.32 / 6 s/m) is a law of the sliding of the whole contact, not of a node.
///
/// `Patch`: every node reads the patch's sliding velocity, the normal-force-weighted mean of
/// the slaves' slip velocity vectors in the last step, `v = |sum_i N_i v_i| / sum_i N_i`. The
/// nodes' own oscillations cancel in the mean; the patch's sliding, and with it the wheel's
/// vibration at the contact, still sets `mu`: the route by which falling friction drives a
/// wheel mode in curve-squeal models, which take the friction coefficient at the contact's
/// sliding velocity, the creepage's plus the wheel's vibration velocity (Heckl & Abrahams,
/// J. Sound Vib. 229, 2000). One contact patch per pair:
/// two patches (tread and flange) would be averaged together.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlipSpeed {
    /// Each node's own slip speed.
    #[default]
    Node,
    /// The patch's mean sliding velocity, one for all nodes.
    Patch,
}

impl SlipSpeed {
    /// The word a case file uses.
    pub fn word(self) -> &'static str {
        match self {
            SlipSpeed::Node => "node",
            SlipSpeed::Patch => "patch",
        }
    }
}

impl FrictionLaw {
    /// Coefficient at slip speed `v` (m/s).
    #[inline]
    pub fn mu(&self, slip_speed_m_per_s: f64) -> f64 {
        match *self {
            FrictionLaw::Coulomb { mu } => mu,
            FrictionLaw::Falling {
                mu_static,
                mu_dynamic,
                decay_s_per_m,
            } => {
                mu_dynamic
                    + (mu_static - mu_dynamic) * (-decay_s_per_m * slip_speed_m_per_s.abs()).exp()
            }
        }
    }

    /// Range checks: coefficients in [0, 2], `mu_d <= mu_s`, `c >= 0`.
    pub fn validate(&self, source_name: &str, field: &str) -> Result<()> {
        let check = |name: &str, v: f64| {
            check_coefficient(v, source_name, &format!("{field}.{name}"), true)
        };
        match *self {
            FrictionLaw::Coulomb { mu } => check("mu", mu),
            FrictionLaw::Falling {
                mu_static,
                mu_dynamic,
                decay_s_per_m,
            } => {
                check("mu_static", mu_static)?;
                check("mu_dynamic", mu_dynamic)?;
                if mu_dynamic > mu_static {
                    return Err(Error::input(
                        source_name,
                        format!("{field}.mu_dynamic"),
                        format!("must not exceed mu_static ({mu_dynamic} > {mu_static})"),
                    ));
                }
                if !(decay_s_per_m >= 0.0 && decay_s_per_m.is_finite()) {
                    return Err(Error::input(
                        source_name,
                        format!("{field}.decay_s_per_m"),
                        format!("must be >= 0 (got {decay_s_per_m})"),
                    ));
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_range_for_every_friction_coefficient() {
        assert!(check_coefficient(0.0, "case", "friction.mu", true).is_ok());
        let e = check_coefficient(0.0, "command line", "--mu", false).unwrap_err();
        assert!(
            e.to_string().contains("--mu") && e.to_string().contains("(0, 2]"),
            "{e}"
        );
        for bad in [-0.1, 2.5, f64::NAN, f64::INFINITY] {
            let e = check_coefficient(bad, "case", "friction.mu", true).unwrap_err();
            assert!(e.to_string().contains("[0, 2]"), "{e}");
            assert_eq!(e.exit_code(), 2);
        }
        // The laws use it for each of their coefficients.
        let law = FrictionLaw::Falling {
            mu_static: 0.5,
            mu_dynamic: 3.0,
            decay_s_per_m: 6.0,
        };
        let e = law.validate("case.json", "friction").unwrap_err();
        assert!(e.to_string().contains("friction.mu_dynamic"), "{e}");
    }
}
