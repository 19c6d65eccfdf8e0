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
//! Solver: a Gauss-Seidel iteration with exact local (2 x 2) projection, sweeping columns from
//! the leading edge to the trailing edge so that the dominant upstream coupling is always up to
//! date (in the spirit of Kalker's TANG / Vollebregt's GaussSeidel solvers). Each sweep starts from
//! the exact slip of the current tractions (FFT product); within a sweep, updates are propagated
//! exactly to the columns within `window_columns` downstream of the change, and the rest is picked
//! up by the next FFT product. At convergence the changes vanish, so the fixed point satisfies the
//! exact discrete equations.

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

/// Iteration controls.
#[derive(Debug, Clone, Copy)]
pub struct TangentialOptions {
    /// Stop when the largest traction change in a sweep is below this fraction of max(mu pn).
    pub relative_tolerance: f64,
    /// Maximum number of sweeps.
    pub max_sweeps: usize,
    /// Columns downstream of a change that are updated exactly within a sweep.
    pub window_columns: usize,
}

impl Default for TangentialOptions {
    fn default() -> Self {
        TangentialOptions {
            relative_tolerance: 1e-12,
            max_sweeps: 5000,
            window_columns: 4,
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
    /// Sweeps used.
    pub sweeps: usize,
}

/// Precomputed influence data for one grid and material.
pub struct TangentialSolver {
    grid: Grid,
    kernels: [OffsetKernel; 3],
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
            kernels,
            spectra,
            convolver,
        }
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Exact slip distances `S = dx w + C p` of all elements (FFT products).
    fn slip_distances(
        &self,
        creepages: &Creepages,
        traction_x_pa: &[f64],
        traction_y_pa: &[f64],
    ) -> [Vec<f64>; 2] {
        let spectrum_x = self.convolver.field_spectrum(traction_x_pa);
        let spectrum_y = self.convolver.field_spectrum(traction_y_pa);
        let [xx, xy, yy] = &self.spectra;
        let combined_x: Vec<Complex<f64>> = (0..xx.len())
            .map(|k| xx[k] * spectrum_x[k] + xy[k] * spectrum_y[k])
            .collect();
        let combined_y: Vec<Complex<f64>> = (0..xx.len())
            .map(|k| xy[k] * spectrum_x[k] + yy[k] * spectrum_y[k])
            .collect();
        let mut slip_x = self.convolver.to_field(combined_x);
        let mut slip_y = self.convolver.to_field(combined_y);
        let grid = &self.grid;
        for i in 0..grid.nx {
            for j in 0..grid.ny {
                let k = grid.index(i, j);
                slip_x[k] += grid.dx_m * (creepages.xi - creepages.phi_per_m * grid.y_m(j));
                slip_y[k] += grid.dx_m * (creepages.eta + creepages.phi_per_m * grid.x_m(i));
            }
        }
        [slip_x, slip_y]
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
        let [kernel_xx, kernel_xy, kernel_yy] = &self.kernels;
        let self_influence = [kernel_xx.at(0, 0), kernel_yy.at(0, 0)];
        let mut state = vec![ElementState::Exterior; n];
        let mut change_x = vec![0.0; n];
        let mut change_y = vec![0.0; n];
        let ny = grid.ny as isize;
        for sweep in 1..=options.max_sweeps {
            let [slip_x, slip_y] = self.slip_distances(creepages, &traction_x_pa, &traction_y_pa);
            change_x.iter_mut().for_each(|v| *v = 0.0);
            change_y.iter_mut().for_each(|v| *v = 0.0);
            let mut largest_change_pa = 0.0_f64;
            for i in (0..grid.nx).rev() {
                let last_column = (i + options.window_columns).min(grid.nx - 1);
                for j in 0..grid.ny {
                    let k = grid.index(i, j);
                    if bound_pa[k] <= 0.0 {
                        change_x[k] = -traction_x_pa[k];
                        change_y[k] = -traction_y_pa[k];
                        state[k] = ElementState::Exterior;
                        continue;
                    }
                    // Slip with the current tractions of updated neighbours, minus self term.
                    let mut sx = slip_x[k] - self_influence[0] * traction_x_pa[k];
                    let mut sy = slip_y[k] - self_influence[1] * traction_y_pa[k];
                    for source_column in i..=last_column {
                        let di = i as isize - source_column as isize;
                        let (row_xx, row_xy, row_yy) =
                            (kernel_xx.row(di), kernel_xy.row(di), kernel_yy.row(di));
                        let base = source_column * grid.ny;
                        let offset = (j as isize + ny - 1) as usize; // index of dj = j - 0
                        for source_row in 0..grid.ny {
                            let delta_x = change_x[base + source_row];
                            let delta_y = change_y[base + source_row];
                            let kernel_index = offset - source_row;
                            sx += row_xx[kernel_index] * delta_x + row_xy[kernel_index] * delta_y;
                            sy += row_xy[kernel_index] * delta_x + row_yy[kernel_index] * delta_y;
                        }
                    }
                    let local = solve_local([sx, sy], self_influence, bound_pa[k]);
                    change_x[k] = local.traction[0] - traction_x_pa[k];
                    change_y[k] = local.traction[1] - traction_y_pa[k];
                    largest_change_pa = largest_change_pa.max(change_x[k].hypot(change_y[k]));
                    state[k] = if local.slipping {
                        ElementState::Slip
                    } else {
                        ElementState::Adhesion
                    };
                }
            }
            for k in 0..n {
                traction_x_pa[k] += change_x[k];
                traction_y_pa[k] += change_y[k];
            }
            if largest_change_pa <= options.relative_tolerance * max_bound_pa {
                let area_m2 = grid.element_area_m2();
                let force_x_n = traction_x_pa.iter().sum::<f64>() * area_m2;
                let force_y_n = traction_y_pa.iter().sum::<f64>() * area_m2;
                return Ok(TangentialSolution {
                    traction_x_pa,
                    traction_y_pa,
                    state,
                    force_x_n,
                    force_y_n,
                    sweeps: sweep,
                });
            }
        }
        Err(Error::Numerical(format!(
            "tangential problem did not converge in {} sweeps",
            options.max_sweeps
        )))
    }
}
