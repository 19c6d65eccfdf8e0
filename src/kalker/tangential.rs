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
//! Solver: an active-set iteration in the manner of Kalker's TANG (1990, section 5.4): with the
//! element division into adhesion (H) and slip (S) elements and the slip directions n fixed, the
//! slip tractions are `p = -g n` and the adhesion tractions solve the linear system
//! `C_HH p_H = -(dx w + C_HS p_S)` (here by restarted GMRES with FFT products: the system is
//! non-symmetric). Then adhesion elements whose traction exceeds the bound become slip elements
//! (direction `-p/|p|`), slip elements whose slip opposes their traction (`S . n < 0`) return to
//! adhesion, and slip directions are updated from the element's local problem (slip with its own
//! contribution removed, `S0 = S - d p`; solving `S = S0 + d p`, `p = -g S/|S|` exactly), under-
//! relaxed, until nothing changes. The plain update `n <- S/|S|` is unstable because an element's
//! own traction dominates its slip. (A Gauss-Seidel
//! march from the leading edge was tried first and is unstable: marching the first-order
//! difference of the half-space operator amplifies errors from column to column.)

use super::halfspace::{tangential_influence, Convolver, Grid, OffsetKernel};
use super::Material;
use crate::{Error, Result};
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

/// Under-relaxation factor of the slip-direction update.
const DIRECTION_RELAXATION: f64 = 0.5;

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
            max_sweeps: 500,
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

/// Outcome of the local problem at one element.
struct LocalSolution {
    traction: [f64; 2],
    slipping: bool,
}

/// Local 2x2 problem: slip `S = S0 + diag(d) p`, bound g. Adhesion if the sticking traction
/// `-S0/d` is within the bound; otherwise `p = -g n`, `S = sigma n`, which gives
/// `n_k = S0_k / (sigma + g d_k)` and `|n| = 1`, a convex decreasing equation in sigma >= 0 solved
/// by Newton from sigma = 0 (monotone convergence).
fn solve_local(
    slip_without_self: [f64; 2],
    self_influence: [f64; 2],
    bound_pa: f64,
) -> LocalSolution {
    let sticking = [
        -slip_without_self[0] / self_influence[0],
        -slip_without_self[1] / self_influence[1],
    ];
    if sticking[0].hypot(sticking[1]) <= bound_pa {
        return LocalSolution {
            traction: sticking,
            slipping: false,
        };
    }
    let mut sigma = 0.0_f64;
    for _ in 0..100 {
        let nx = slip_without_self[0] / (sigma + bound_pa * self_influence[0]);
        let ny = slip_without_self[1] / (sigma + bound_pa * self_influence[1]);
        let residual = nx * nx + ny * ny - 1.0;
        let derivative = -2.0
            * (nx * nx / (sigma + bound_pa * self_influence[0])
                + ny * ny / (sigma + bound_pa * self_influence[1]));
        let step = residual / derivative;
        sigma -= step;
        if step.abs() <= 1e-15 * sigma.abs().max(f64::MIN_POSITIVE) {
            break;
        }
    }
    let nx = slip_without_self[0] / (sigma + bound_pa * self_influence[0]);
    let ny = slip_without_self[1] / (sigma + bound_pa * self_influence[1]);
    let length = nx.hypot(ny);
    LocalSolution {
        traction: [-bound_pa * nx / length, -bound_pa * ny / length],
        slipping: true,
    }
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
        let mut slip_direction = vec![[0.0_f64; 2]; n];
        for k in 0..n {
            if state[k] == ElementState::Exterior {
                traction_x_pa[k] = 0.0;
                traction_y_pa[k] = 0.0;
            } else if traction_x_pa[k].hypot(traction_y_pa[k]) >= bound_pa[k] {
                let magnitude = traction_x_pa[k].hypot(traction_y_pa[k]);
                slip_direction[k] = [-traction_x_pa[k] / magnitude, -traction_y_pa[k] / magnitude];
                state[k] = ElementState::Slip;
            }
        }
        let rigid_slip = self.rigid_slip_distances(creepages);
        // Inexact inner solves: the GMRES tolerance follows the largest slip-direction change of
        // the previous iteration (no point in solving to 1e-12 while the directions still move).
        let mut largest_turn = 1.0_f64;
        let mut last_tolerance = 1.0_f64;
        let mut total_krylov = 0;
        let mut returns_to_adhesion = vec![0_u32; n];
        for outer in 1..=options.max_sweeps {
            // Slip elements carry p = -g n; adhesion elements are the unknowns of C_HH p_H = rhs.
            for k in 0..n {
                if state[k] == ElementState::Slip {
                    traction_x_pa[k] = -bound_pa[k] * slip_direction[k][0];
                    traction_y_pa[k] = -bound_pa[k] * slip_direction[k][1];
                } else if state[k] == ElementState::Exterior {
                    traction_x_pa[k] = 0.0;
                    traction_y_pa[k] = 0.0;
                }
            }
            let adhesion: Vec<usize> = (0..n)
                .filter(|&k| state[k] == ElementState::Adhesion)
                .collect();
            if !adhesion.is_empty() {
                // Right-hand side: -(dx w + C p_S) on H, from the slip tractions alone.
                let mut slip_only_x = traction_x_pa.clone();
                let mut slip_only_y = traction_y_pa.clone();
                for &k in &adhesion {
                    slip_only_x[k] = 0.0;
                    slip_only_y[k] = 0.0;
                }
                let [from_slip_x, from_slip_y] = self.apply_influence(&slip_only_x, &slip_only_y);
                let mut rhs = Vec::with_capacity(2 * adhesion.len());
                for &k in &adhesion {
                    rhs.push(-(rigid_slip[0][k] + from_slip_x[k]));
                }
                for &k in &adhesion {
                    rhs.push(-(rigid_slip[1][k] + from_slip_y[k]));
                }
                let mut unknown: Vec<f64> = adhesion
                    .iter()
                    .map(|&k| traction_x_pa[k])
                    .chain(adhesion.iter().map(|&k| traction_y_pa[k]))
                    .collect();
                let operator = |vector: &[f64]| -> Vec<f64> {
                    let mut field_x = vec![0.0; n];
                    let mut field_y = vec![0.0; n];
                    for (position, &k) in adhesion.iter().enumerate() {
                        field_x[k] = vector[position];
                        field_y[k] = vector[position + adhesion.len()];
                    }
                    let [result_x, result_y] = self.apply_influence(&field_x, &field_y);
                    adhesion
                        .iter()
                        .map(|&k| result_x[k])
                        .chain(adhesion.iter().map(|&k| result_y[k]))
                        .collect()
                };
                // Preconditioner: the dominant part of C, self term plus the (negated) same term of the
                // upstream element, `d (q_i - q_upstream) = r_i`, inverted by marching from the
                // leading edge (FASTSIM-like). It turns C ~ A d/dx into ~ A/d, much better
                // conditioned.
                let count = adhesion.len();
                let mut upstream_position = vec![usize::MAX; count];
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
                let preconditioner = |vector: &[f64]| -> Vec<f64> {
                    let mut result = vec![0.0; 2 * count];
                    // Adhesion positions are ordered by increasing x: march backwards.
                    for position in (0..count).rev() {
                        let upstream = upstream_position[position];
                        for component in 0..2 {
                            let previous = if upstream != usize::MAX {
                                result[upstream + component * count]
                            } else {
                                0.0
                            };
                            result[position + component * count] = previous
                                + vector[position + component * count]
                                    / self.self_influence[component];
                        }
                    }
                    result
                };
                let tolerance = (1e-3 * largest_turn).clamp(options.relative_tolerance, 1e-4);
                last_tolerance = tolerance;
                total_krylov += gmres(
                    operator,
                    preconditioner,
                    &rhs,
                    &mut unknown,
                    tolerance,
                    60,
                    200,
                )?;
                for (position, &k) in adhesion.iter().enumerate() {
                    traction_x_pa[k] = unknown[position];
                    traction_y_pa[k] = unknown[position + adhesion.len()];
                }
            }
            // Check the Coulomb conditions and update the element division and slip directions.
            let [influence_x, influence_y] = self.apply_influence(&traction_x_pa, &traction_y_pa);
            let mut changes = 0;
            largest_turn = 0.0;
            for k in 0..n {
                match state[k] {
                    ElementState::Exterior => {}
                    ElementState::Adhesion => {
                        let magnitude = traction_x_pa[k].hypot(traction_y_pa[k]);
                        if magnitude > bound_pa[k] * (1.0 + 1e-12) {
                            state[k] = ElementState::Slip;
                            slip_direction[k] =
                                [-traction_x_pa[k] / magnitude, -traction_y_pa[k] / magnitude];
                            changes += 1;
                            largest_turn = 1.0;
                        }
                    }
                    ElementState::Slip => {
                        // Local problem with the element's own contribution removed (S0 = S - d p):
                        // the self term dominates the slip of a slip element, so the plain
                        // update n <- S/|S| is unstable; the local solution is not.
                        let self_influence = self.self_influence;
                        let without_self = [
                            rigid_slip[0][k] + influence_x[k]
                                - self_influence[0] * traction_x_pa[k],
                            rigid_slip[1][k] + influence_y[k]
                                - self_influence[1] * traction_y_pa[k],
                        ];
                        let local = solve_local(without_self, self_influence, bound_pa[k]);
                        if !local.slipping {
                            if returns_to_adhesion[k] < MAX_RETURNS_TO_ADHESION {
                                state[k] = ElementState::Adhesion;
                                returns_to_adhesion[k] += 1;
                                changes += 1;
                                largest_turn = 1.0;
                            }
                        } else {
                            let target = [
                                -local.traction[0] / bound_pa[k],
                                -local.traction[1] / bound_pa[k],
                            ];
                            let turn = (target[0] - slip_direction[k][0])
                                .hypot(target[1] - slip_direction[k][1]);
                            // Under-relaxed (all slip elements move at once, Jacobi-like).
                            let relaxed = [
                                slip_direction[k][0]
                                    + DIRECTION_RELAXATION * (target[0] - slip_direction[k][0]),
                                slip_direction[k][1]
                                    + DIRECTION_RELAXATION * (target[1] - slip_direction[k][1]),
                            ];
                            let length = relaxed[0].hypot(relaxed[1]).max(f64::MIN_POSITIVE);
                            let direction = [relaxed[0] / length, relaxed[1] / length];
                            largest_turn = largest_turn.max(turn);
                            if turn > options.direction_tolerance {
                                changes += 1;
                            }
                            slip_direction[k] = direction;
                        }
                    }
                }
            }
            if changes == 0 && last_tolerance > options.relative_tolerance && !adhesion.is_empty() {
                // Converged with an inexact inner solve: finish with a tight one.
                largest_turn = 0.0;
                continue;
            }
            if changes == 0 {
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
                    influence_products: total_krylov,
                });
            }
        }
        Err(Error::Numerical(format!(
            "tangential problem did not converge in {} active-set iterations",
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
        let spectrum_x = self.convolver.field_spectrum(traction_x_pa);
        let spectrum_y = self.convolver.field_spectrum(traction_y_pa);
        let [xx, xy, yy] = &self.spectra;
        let combined_x: Vec<Complex<f64>> = (0..xx.len())
            .map(|k| xx[k] * spectrum_x[k] + xy[k] * spectrum_y[k])
            .collect();
        let combined_y: Vec<Complex<f64>> = (0..xx.len())
            .map(|k| xy[k] * spectrum_x[k] + yy[k] * spectrum_y[k])
            .collect();
        [
            self.convolver.to_field(combined_x),
            self.convolver.to_field(combined_y),
        ]
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
