//! Forcing terms of the inexact Newton iteration: how closely each step's linear system
//! `K_T dq = R` is solved when it is solved iteratively (conjugate gradients).
//!
//! A step solved to `|K_T dq - R| <= eta_k |R|` converges as Newton's method does while
//! `eta_k` falls with the residual, and a tight solve far from the solution buys nothing
//! (Dembo, Eisenstat & Steihaug 1982, "Inexact Newton methods", SIAM J. Numer. Anal. 19).
//! The choice here:
//!
//! - Eisenstat & Walker 1996 ("Choosing the forcing terms in an inexact Newton method", SIAM
//!   J. Sci. Comput. 17), choice 2 with `gamma = 0.9`, `alpha = 2`:
//!   `eta_k = gamma (|R_k| / |R_(k-1)|)^alpha`, the first step at `eta_max`. Their safeguard
//!   (`eta_k >= gamma eta_(k-1)^alpha` when that exceeds 0.1) never acts under
//!   `eta_max = 0.1`, since `gamma eta_max^2 = 0.009`.
//! - Kelley 1995 ("Iterative methods for linear and nonlinear equations", SIAM, eq. 6.20): no
//!   tighter than `0.5 tau / |R_k|`, which already brings the linear model's residual below
//!   the Newton tolerance `tau`: the last step is not over-solved.
//! - Bounded to `[LINEAR_TOLERANCE, FORCING_MAX]`: the iteration is a modified Newton one (the
//!   tangent leaves out the geometric and contact-rotation terms) contracting by 0.01-0.25 per
//!   step on the rolling models, so a solve tighter than 1e-3 cannot speed it up; 0.1 keeps a
//!   step from losing more than a tenth of its residual's reduction.

/// The tightest relative residual a linear solve is asked for: 1e-3, an order below the
/// modified Newton iteration's own contraction per step (0.01-0.25 on the rolling models), so
/// that the linear error does not slow it; a tighter solve would buy nothing, since the
/// residual the iteration stops on is the full one, evaluated afresh each step.
pub const LINEAR_TOLERANCE: f64 = 1e-3;

/// The loosest relative residual a linear solve is asked for (`eta_max`).
pub const FORCING_MAX: f64 = 0.1;

/// Eisenstat & Walker's `gamma` (choice 2).
const GAMMA: f64 = 0.9;

/// Eisenstat & Walker's `alpha` (choice 2): the convergence order the forcing terms follow.
const ALPHA: f64 = 2.0;

/// The relative residual to solve step `k` to: `relative` is the Newton measure of `R_k`,
/// `previous` that of `R_(k-1)` (None on the first step), `newton_tolerance` the measure the
/// iteration stops below.
pub fn forcing_term(relative: f64, previous: Option<f64>, newton_tolerance: f64) -> f64 {
    let eisenstat_walker = match previous {
        Some(prev) if prev > 0.0 => GAMMA * (relative / prev).powf(ALPHA),
        _ => FORCING_MAX,
    };
    let no_oversolving = if relative > 0.0 {
        0.5 * newton_tolerance / relative
    } else {
        FORCING_MAX
    };
    // `f64::max` drops a NaN operand: a NaN ratio leaves the no-oversolving bound, which is
    // finite (`relative > 0` failing takes the cap), so the clamp below sees a number.
    let eta = eisenstat_walker.max(no_oversolving);
    eta.clamp(LINEAR_TOLERANCE, FORCING_MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_step_is_loose() {
        assert_eq!(forcing_term(91.0, None, 1e-3), FORCING_MAX);
    }

    #[test]
    fn follows_the_squared_residual_ratio() {
        // |R| fell by 4: 0.9 / 16 = 0.05625, inside the bounds; the tolerance is far below.
        let eta = forcing_term(0.25, Some(1.0), 1e-8);
        assert!((eta - 0.9 / 16.0).abs() < 1e-15, "{eta}");
    }

    #[test]
    fn fast_fall_is_floored_and_slow_fall_capped() {
        // A fall by 100: 0.9e-4, below the floor.
        assert_eq!(forcing_term(0.01, Some(1.0), 1e-8), LINEAR_TOLERANCE);
        // A fall by 10 %: 0.729, above the cap.
        assert_eq!(forcing_term(0.9, Some(1.0), 1e-8), FORCING_MAX);
    }

    #[test]
    fn last_step_is_not_over_solved() {
        // |R| = 4 tau: the linear model's residual needs only 0.125 |R| to reach tau / 2;
        // the squared ratio alone would ask 0.9 (0.004 / 0.04)^2 = 0.009.
        let eta = forcing_term(4e-3, Some(4e-2), 1e-3);
        assert_eq!(eta, FORCING_MAX);
        // |R| = 20 tau: 0.5 / 20 = 0.025 beats the ratio's 0.009.
        let eta = forcing_term(2e-2, Some(2e-1), 1e-3);
        assert!((eta - 0.025).abs() < 1e-15, "{eta}");
    }

    #[test]
    fn nan_stays_in_bounds() {
        let eta = forcing_term(f64::NAN, Some(1.0), 1e-3);
        assert!((LINEAR_TOLERANCE..=FORCING_MAX).contains(&eta), "{eta}");
    }
}
