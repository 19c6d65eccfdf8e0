//! The tangential steady-rolling problem on the half-space grid (Kalker 1990, sections 2.2, 5.4).
//!
//! Continuum: slip per unit rolled distance `s = w - du/dx`, with rigid slip
//! `w = (xi - phi y, eta + phi x)` (see the module conventions in `kalker`).
//! Discretisation (Kalker's steady-state scheme, his "time step" equal to one element length): a
//! material particle at element I was one element upstream (x + dx) one step ago, so the slip
//! distance over the step is
//! `S_I = dx w_I + u(x_I) - u(x_I + dx) = dx w_I + sum_J C(I - J) p_J`,
//! `C(di, dj) = A(di dx, dj dy) - A((di + 1) dx, dj dy)`,
//! with the half-space influence coefficients A of [`super::halfspace`]. `u(x + dx)` is evaluated
//! exactly (not by traction at the upstream element), so the leading column sees the displacement
//! field of the whole patch. Conditions per element with traction bound `g_I = mu pn_I`:
//! adhesion `S_I = 0, |p_I| <= g_I`; slip `p_I = -g_I S_I / |S_I|`.
//!
//! Solver: Newton's method combined with an active set, in the manner of Kalker's TANG (1990,
//! section 5.4). Unknowns: tractions `p_H` of adhesion elements and slip angles `theta` of slip
//! elements (`p = -g n`, `n = (cos theta, sin theta)`). Equations: `S_H = 0`, and `t . S = 0` on
//! slip elements (`t = (-n_y, n_x)`: slip parallel to n). Each Newton step solves the Jacobian
//! system matrix-free by right-preconditioned restarted GMRES (the system is non-symmetric) with
//! FFT influence products; rotations are damped to 0.5 rad. Between steps the element division
//! is updated: adhesion elements whose traction exceeds the bound slip (direction `-p/|p|`);
//! slip elements whose local sticking traction (`-S0/d`, own contribution removed) fits within
//! the bound stick again. Converged when the division is unchanged and the residual is below
//! `relative_tolerance` times the rigid-slip norm.
//! (Tried first and rejected: a Gauss-Seidel march from the leading edge, unstable because
//! marching the first-order difference of the half-space operator amplifies errors from column to
//! column; and fixed-point updates `n <- S/|S|` of the slip directions, which oscillate because an
//! element's own traction dominates its slip.)

use super::halfspace::{tangential_influence, Convolver, Grid, OffsetKernel};
use super::Material;
use crate::{Error, Result};
use nalgebra::{Rotation2, Vector2};
use rustfft::num_complex::Complex;

/// Creepages (rigid slip per unit rolled distance).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Creepages {
    /// Longitudinal creepage xi (-).
    pub xi: f64,
    /// Lateral creepage eta (-).
    pub eta: f64,
    /// Spin creepage phi (1/m).
    pub phi_per_m: f64,
}

/// Contact state of an element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum ElementState {
    /// No pressure: outside the contact area.
    Exterior,
    /// In contact and sticking (|p| < mu pn).
    Adhesion,
    /// In contact and sliding (|p| = mu pn).
    Slip,
}

impl ElementState {
    /// Short name for maps and CSV files.
    pub fn name(&self) -> &'static str {
        match self {
            ElementState::Exterior => "exterior",
            ElementState::Adhesion => "adhesion",
            ElementState::Slip => "slip",
        }
    }
}

/// How often an element may go back from slip to adhesion. Elements at the rim of the contact
/// (tiny traction bound) can otherwise flip between the two states forever, the discrete
/// counterpart of a point where adhesion and slip meet with |p| = g and S = 0; after this many
/// returns such an element stays in slip, which changes the forces by far less than the
/// discretisation error (its bound is tiny).
const MAX_RETURNS_TO_ADHESION: u32 = 2;

/// Iteration controls.
#[derive(Debug, Clone, Copy)]
pub struct TangentialOptions {
    /// Final relative residual of the linear adhesion solves (GMRES).
    pub relative_tolerance: f64,
    /// Converged when no slip direction turns by more than this (rad) and no element changes state.
    pub direction_tolerance: f64,
    /// Maximum number of active-set (element division) iterations.
    pub max_sweeps: usize,
}

impl Default for TangentialOptions {
    fn default() -> Self {
        TangentialOptions {
            relative_tolerance: 1e-12,
            direction_tolerance: 1e-9,
            max_sweeps: 300,
        }
    }
}

/// Solution of the tangential problem.
#[derive(Debug, Clone)]
pub struct TangentialSolution {
    /// Traction px on body 1 per element (Pa).
    pub traction_x_pa: Vec<f64>,
    /// Traction py on body 1 per element (Pa).
    pub traction_y_pa: Vec<f64>,
    /// State per element.
    pub state: Vec<ElementState>,
    /// Total force Fx = sum px dx dy (N).
    pub force_x_n: f64,
    /// Total force Fy (N).
    pub force_y_n: f64,
    /// Active-set iterations used.
    pub sweeps: usize,
    /// Influence products (FFT convolutions) spent in GMRES.
    pub influence_products: usize,
}

/// Precomputed influence data for one grid and material.
pub struct TangentialSolver {
    grid: Grid,
    self_influence: [f64; 2],
    spectra: [Vec<Complex<f64>>; 3],
    convolver: Convolver,
}

/// Local adhesion test: with the element's own contribution removed (`S0 = S - d p`), the element
/// can stick iff the traction that zeroes its slip, `-S0/d`, lies within the bound g.
fn sticks_locally(slip_without_self: [f64; 2], self_influence: [f64; 2], bound_pa: f64) -> bool {
    (slip_without_self[0] / self_influence[0]).hypot(slip_without_self[1] / self_influence[1])
        <= bound_pa
}

impl TangentialSolver {
    /// Tabulates the steady-rolling influence kernels C for `grid` and `material`.
    pub fn new(grid: Grid, material: &Material) -> TangentialSolver {
        let shear_modulus_pa = material.shear_modulus_pa();
        let nu = material.poisson_ratio;
        let shifted = |component: usize| {
            OffsetKernel::new(grid.nx, grid.ny, move |di, dj| {
                let y = dj as f64 * grid.dy_m;
                tangential_influence(di as f64 * grid.dx_m, y, &grid, shear_modulus_pa, nu)
                    [component]
                    - tangential_influence(
                        (di + 1) as f64 * grid.dx_m,
                        y,
                        &grid,
                        shear_modulus_pa,
                        nu,
                    )[component]
            })
        };
        let kernels = [shifted(0), shifted(1), shifted(2)];
        let convolver = Convolver::new(grid.nx, grid.ny);
        let spectra = [
            convolver.kernel_spectrum(&kernels[0]),
            convolver.kernel_spectrum(&kernels[1]),
            convolver.kernel_spectrum(&kernels[2]),
        ];
        TangentialSolver {
            grid,
            self_influence: [kernels[0].at(0, 0), kernels[2].at(0, 0)],
            spectra,
            convolver,
        }
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Solves for the tractions given pressure (Pa per element), friction coefficient and
    /// creepages. `initial` (px, py) may warm-start the iteration.
    ///
    /// Kept in one piece: Kalker's active-set iteration over the patch elements, whose steps share
    /// the element arrays and follow the method's steps in order.
    pub fn solve(
        &self,
        pressure_pa: &[f64],
        mu: f64,
        creepages: &Creepages,
        options: &TangentialOptions,
        initial: Option<(&[f64], &[f64])>,
    ) -> Result<TangentialSolution> {
        super::validate_friction(mu, "tangential problem")?;
        let grid = self.grid;
        let n = grid.len();
        if pressure_pa.len() != n {
            return Err(Error::input(
                "tangential problem",
                "pressure",
                format!("expected {n} values, got {}", pressure_pa.len()),
            ));
        }
        let bound_pa: Vec<f64> = pressure_pa.iter().map(|&p| mu * p.max(0.0)).collect();
        let max_bound_pa = bound_pa.iter().cloned().fold(0.0, f64::max);
        if max_bound_pa <= 0.0 {
            return Err(Error::input(
                "tangential problem",
                "pressure",
                "no element carries pressure",
            ));
        }
        let (mut traction_x_pa, mut traction_y_pa) = match initial {
            Some((px, py)) if px.len() == n && py.len() == n => (px.to_vec(), py.to_vec()),
            _ => (vec![0.0; n], vec![0.0; n]),
        };
        // Start: every loaded element in adhesion (Kalker's TANG starts the same way).
        let mut state: Vec<ElementState> = bound_pa
            .iter()
            .map(|&g| {
                if g > 0.0 {
                    ElementState::Adhesion
                } else {
                    ElementState::Exterior
                }
            })
            .collect();
        // Unit slip direction n of each slip element (the traction is -g n on a slip element).
        let mut slip_direction = vec![Vector2::<f64>::zeros(); n];
        for k in 0..n {
            if state[k] == ElementState::Exterior {
                traction_x_pa[k] = 0.0;
                traction_y_pa[k] = 0.0;
            } else if traction_x_pa[k].hypot(traction_y_pa[k]) >= bound_pa[k] * (1.0 - 1e-9) {
                let magnitude = traction_x_pa[k].hypot(traction_y_pa[k]);
                slip_direction[k] = -Vector2::new(traction_x_pa[k], traction_y_pa[k]) / magnitude;
                state[k] = ElementState::Slip;
            }
        }
        let rigid_slip = self.rigid_slip_distances(creepages);
        let rigid_norm = rigid_slip[0]
            .iter()
            .chain(&rigid_slip[1])
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt()
            .max(f64::MIN_POSITIVE);
        let self_influence = self.self_influence;
        let mut returns_to_adhesion = vec![0_u32; n];
        let mut total_products = 0;
        for outer in 1..=options.max_sweeps {
            for k in 0..n {
                match state[k] {
                    ElementState::Slip => {
                        traction_x_pa[k] = -bound_pa[k] * slip_direction[k].x;
                        traction_y_pa[k] = -bound_pa[k] * slip_direction[k].y;
                    }
                    ElementState::Exterior => {
                        traction_x_pa[k] = 0.0;
                        traction_y_pa[k] = 0.0;
                    }
                    ElementState::Adhesion => {}
                }
            }
            let [influence_x, influence_y] = self.apply_influence(&traction_x_pa, &traction_y_pa);
            total_products += 1;
            let slip_x: Vec<f64> = (0..n).map(|k| rigid_slip[0][k] + influence_x[k]).collect();
            let slip_y: Vec<f64> = (0..n).map(|k| rigid_slip[1][k] + influence_y[k]).collect();

            // Element division update (Kalker's TANG): too large adhesion tractions slip; slip
            // elements whose slip opposes their traction (n . S < 0) stick again.
            let mut changes = 0;
            for k in 0..n {
                match state[k] {
                    ElementState::Adhesion => {
                        let magnitude = traction_x_pa[k].hypot(traction_y_pa[k]);
                        if magnitude > bound_pa[k] * (1.0 + 1e-12) {
                            state[k] = ElementState::Slip;
                            slip_direction[k] =
                                -Vector2::new(traction_x_pa[k], traction_y_pa[k]) / magnitude;
                            traction_x_pa[k] = -bound_pa[k] * slip_direction[k].x;
                            traction_y_pa[k] = -bound_pa[k] * slip_direction[k].y;
                            changes += 1;
                        }
                    }
                    ElementState::Slip => {
                        // The local problem with the element's own contribution removed decides.
                        let without_self = [
                            slip_x[k] - self_influence[0] * traction_x_pa[k],
                            slip_y[k] - self_influence[1] * traction_y_pa[k],
                        ];
                        if sticks_locally(without_self, self_influence, bound_pa[k])
                            && returns_to_adhesion[k] < MAX_RETURNS_TO_ADHESION
                        {
                            state[k] = ElementState::Adhesion;
                            returns_to_adhesion[k] += 1;
                            changes += 1;
                        }
                    }
                    ElementState::Exterior => {}
                }
            }
            if changes > 0 {
                continue; // recompute the slip with the new division
            }

            // Newton residual: S = 0 on adhesion elements, t . S = 0 (slip parallel to n) on slip
            // elements, t = (-n_y, n_x).
            let adhesion: Vec<usize> = (0..n)
                .filter(|&k| state[k] == ElementState::Adhesion)
                .collect();
            let slipping: Vec<usize> = (0..n).filter(|&k| state[k] == ElementState::Slip).collect();
            let (count_h, count_s) = (adhesion.len(), slipping.len());
            let mut residual = Vec::with_capacity(2 * count_h + count_s);
            residual.extend(adhesion.iter().map(|&k| slip_x[k]));
            residual.extend(adhesion.iter().map(|&k| slip_y[k]));
            residual.extend(
                slipping
                    .iter()
                    .map(|&k| slip_direction[k].perp(&Vector2::new(slip_x[k], slip_y[k]))),
            );
            let residual_norm = residual.iter().map(|v| v * v).sum::<f64>().sqrt();
            if residual_norm <= options.relative_tolerance * rigid_norm {
                let area_m2 = grid.element_area_m2();
                let force_x_n = traction_x_pa.iter().sum::<f64>() * area_m2;
                let force_y_n = traction_y_pa.iter().sum::<f64>() * area_m2;
                return Ok(TangentialSolution {
                    traction_x_pa,
                    traction_y_pa,
                    state,
                    force_x_n,
                    force_y_n,
                    sweeps: outer,
                    influence_products: total_products,
                });
            }
            // Along-slip magnitude sigma = n . S (>= 0 for a consistent slip element).
            let sigma: Vec<f64> = slipping
                .iter()
                .map(|&k| {
                    slip_direction[k]
                        .dot(&Vector2::new(slip_x[k], slip_y[k]))
                        .max(0.0)
                })
                .collect();
            // Jacobian-vector product of the residual w.r.t. (p_H, theta_S):
            // dp = v on H, dp = -g t dtheta on S; rows C dp on H, t . C dp - sigma dtheta on S.
            let jacobian = |vector: &[f64]| -> Vec<f64> {
                let mut field_x = vec![0.0; n];
                let mut field_y = vec![0.0; n];
                for (position, &k) in adhesion.iter().enumerate() {
                    field_x[k] = vector[position];
                    field_y[k] = vector[position + count_h];
                }
                for (position, &k) in slipping.iter().enumerate() {
                    let turn = vector[2 * count_h + position];
                    field_x[k] = bound_pa[k] * slip_direction[k].y * turn; // -g t_x, t_x = -n_y
                    field_y[k] = -bound_pa[k] * slip_direction[k].x * turn; // -g t_y, t_y = n_x
                }
                let [product_x, product_y] = self.apply_influence(&field_x, &field_y);
                let mut result = Vec::with_capacity(2 * count_h + count_s);
                result.extend(adhesion.iter().map(|&k| product_x[k]));
                result.extend(adhesion.iter().map(|&k| product_y[k]));
                for (position, &k) in slipping.iter().enumerate() {
                    // t . (C dp) with t = (-n_y, n_x): the 2D cross product n x (C dp).
                    let tangential =
                        slip_direction[k].perp(&Vector2::new(product_x[k], product_y[k]));
                    result.push(tangential - sigma[position] * vector[2 * count_h + position]);
                }
                result
            };
            // Preconditioner: FASTSIM-like march on the adhesion part (self term plus upstream
            // neighbour, the dominant part of C ~ A d/dx), diagonal on the slip part.
            let mut upstream_position = vec![usize::MAX; count_h];
            {
                let mut position_of = vec![usize::MAX; n];
                for (position, &k) in adhesion.iter().enumerate() {
                    position_of[k] = position;
                }
                for (position, &k) in adhesion.iter().enumerate() {
                    if k + grid.ny < n {
                        upstream_position[position] = position_of[k + grid.ny];
                    }
                }
            }
            let slip_diagonal: Vec<f64> = slipping
                .iter()
                .enumerate()
                .map(|(position, &k)| {
                    let (tx, ty) = (-slip_direction[k].y, slip_direction[k].x);
                    let diagonal = -(sigma[position]
                        + bound_pa[k]
                            * (tx * tx * self_influence[0] + ty * ty * self_influence[1]));
                    if diagonal.abs() > 0.0 {
                        diagonal
                    } else {
                        -f64::MIN_POSITIVE
                    }
                })
                .collect();
            let preconditioner = |vector: &[f64]| -> Vec<f64> {
                let mut result = vec![0.0; 2 * count_h + count_s];
                // Adhesion positions are ordered by increasing x: march backwards.
                for position in (0..count_h).rev() {
                    let upstream = upstream_position[position];
                    for component in 0..2 {
                        let previous = if upstream != usize::MAX {
                            result[upstream + component * count_h]
                        } else {
                            0.0
                        };
                        result[position + component * count_h] = previous
                            + vector[position + component * count_h] / self_influence[component];
                    }
                }
                for position in 0..count_s {
                    result[2 * count_h + position] =
                        vector[2 * count_h + position] / slip_diagonal[position];
                }
                result
            };
            let rhs: Vec<f64> = residual.iter().map(|v| -v).collect();
            let mut step = vec![0.0; 2 * count_h + count_s];
            // Inexact Newton: a modest relative tolerance is enough far from the solution.
            let tolerance =
                (0.1 * residual_norm / rigid_norm).clamp(1e-3 * options.relative_tolerance, 1e-4);
            total_products += gmres(
                jacobian,
                preconditioner,
                &rhs,
                &mut step,
                tolerance,
                60,
                100,
            )?;
            for (position, &k) in adhesion.iter().enumerate() {
                traction_x_pa[k] += step[position];
                traction_y_pa[k] += step[position + count_h];
            }
            for (position, &k) in slipping.iter().enumerate() {
                // Damped rotation of the slip direction (at most 0.5 rad per step).
                let turn = step[2 * count_h + position].clamp(-0.5, 0.5);
                slip_direction[k] = Rotation2::new(turn) * slip_direction[k];
            }
        }
        Err(Error::Numerical(format!(
            "tangential problem did not converge in {} Newton / active-set iterations",
            options.max_sweeps
        )))
    }

    /// `dx w` per element.
    fn rigid_slip_distances(&self, creepages: &Creepages) -> [Vec<f64>; 2] {
        let grid = &self.grid;
        let mut slip_x = vec![0.0; grid.len()];
        let mut slip_y = vec![0.0; grid.len()];
        for i in 0..grid.nx {
            for j in 0..grid.ny {
                let k = grid.index(i, j);
                slip_x[k] = grid.dx_m * (creepages.xi - creepages.phi_per_m * grid.y_m(j));
                slip_y[k] = grid.dx_m * (creepages.eta + creepages.phi_per_m * grid.x_m(i));
            }
        }
        [slip_x, slip_y]
    }

    /// `C p` for both components (FFT products).
    fn apply_influence(&self, traction_x_pa: &[f64], traction_y_pa: &[f64]) -> [Vec<f64>; 2] {
        self.convolver
            .convolve_pair(&self.spectra, traction_x_pa, traction_y_pa)
    }
}

/// Right-preconditioned restarted GMRES (Saad & Schultz 1986) for `A x = b`, matrix-free: Krylov
/// space of `A M^-1`, `x += M^-1 (V c)`; `x` holds the start and the result. Stops when `|b - A x| <= tolerance |b|`. Returns the number of operator applications.
fn gmres(
    operator: impl Fn(&[f64]) -> Vec<f64>,
    preconditioner: impl Fn(&[f64]) -> Vec<f64>,
    rhs: &[f64],
    solution: &mut [f64],
    tolerance: f64,
    restart: usize,
    max_restarts: usize,
) -> Result<usize> {
    let size = rhs.len();
    let rhs_norm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
    if rhs_norm == 0.0 {
        solution.iter_mut().for_each(|v| *v = 0.0);
        return Ok(0);
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut applications = 0;
    for _ in 0..max_restarts {
        let applied = operator(solution);
        applications += 1;
        let residual: Vec<f64> = (0..size).map(|k| rhs[k] - applied[k]).collect();
        let residual_norm = dot(&residual, &residual).sqrt();
        if residual_norm <= tolerance * rhs_norm {
            return Ok(applications);
        }
        let mut basis: Vec<Vec<f64>> = vec![residual.iter().map(|v| v / residual_norm).collect()];
        let mut hessenberg = vec![vec![0.0; restart]; restart + 1];
        let (mut cosines, mut sines) = (vec![0.0; restart], vec![0.0; restart]);
        let mut rotated_rhs = vec![0.0; restart + 1];
        rotated_rhs[0] = residual_norm;
        let mut used = 0;
        for column in 0..restart {
            let mut next = operator(&preconditioner(&basis[column]));
            applications += 1;
            // Modified Gram-Schmidt.
            for (row, vector) in basis.iter().enumerate() {
                let projection = dot(&next, vector);
                hessenberg[row][column] = projection;
                for (value, basis_value) in next.iter_mut().zip(vector) {
                    *value -= projection * basis_value;
                }
            }
            let next_norm = dot(&next, &next).sqrt();
            hessenberg[column + 1][column] = next_norm;
            for row in 0..column {
                let (upper, lower) = (hessenberg[row][column], hessenberg[row + 1][column]);
                hessenberg[row][column] = cosines[row] * upper + sines[row] * lower;
                hessenberg[row + 1][column] = -sines[row] * upper + cosines[row] * lower;
            }
            let (upper, lower) = (hessenberg[column][column], hessenberg[column + 1][column]);
            let radius = upper.hypot(lower);
            cosines[column] = if radius > 0.0 { upper / radius } else { 1.0 };
            sines[column] = if radius > 0.0 { lower / radius } else { 0.0 };
            hessenberg[column][column] = radius;
            hessenberg[column + 1][column] = 0.0;
            rotated_rhs[column + 1] = -sines[column] * rotated_rhs[column];
            rotated_rhs[column] *= cosines[column];
            used = column + 1;
            if rotated_rhs[column + 1].abs() <= tolerance * rhs_norm || next_norm == 0.0 {
                break;
            }
            basis.push(next.iter().map(|v| v / next_norm).collect());
        }
        // Back substitution for the Krylov coefficients, then update the solution.
        let mut coefficients = vec![0.0; used];
        for row in (0..used).rev() {
            let mut value = rotated_rhs[row];
            for later in (row + 1)..used {
                value -= hessenberg[row][later] * coefficients[later];
            }
            coefficients[row] = if hessenberg[row][row] != 0.0 {
                value / hessenberg[row][row]
            } else {
                0.0
            };
        }
        let mut combination = vec![0.0; size];
        for (coefficient, vector) in coefficients.iter().zip(&basis) {
            for (value, basis_value) in combination.iter_mut().zip(vector) {
                *value += coefficient * basis_value;
            }
        }
        for (value, correction) in solution.iter_mut().zip(preconditioner(&combination)) {
            *value += correction;
        }
    }
    Err(Error::Numerical(format!(
        "GMRES did not reach relative residual {tolerance:e}"
    )))
}
