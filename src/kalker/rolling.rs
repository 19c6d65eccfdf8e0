//! Creepage-prescribed (forward) steady rolling: one entry point over both methods.
//!
//! * [`Method::Exact`]: the half-space boundary-element solution (normal problem by
//!   [`super::normal`], then tangential by [`super::tangential`]), on a grid of `n x n` elements
//!   covering the Hertz ellipse with a 10 % margin (or on any user gap via
//!   [`RollingSolver::exact_from_gap`]).
//! * [`Method::Fastsim`]: Kalker's simplified theory on `n x n` points ([`super::fastsim`]).

use super::creep_coefficients::{kalker_creep_coefficients, CreepCoefficients};
use super::fastsim::fastsim;
use super::halfspace::Grid;
use super::hertz::HertzContact;
use super::normal::{solve_normal, NormalSolution};
use super::tangential::{Creepages, ElementState, TangentialOptions, TangentialSolver};
use super::Material;
use crate::{Error, Result};

/// Which theory to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub enum Method {
    /// Exact half-space theory (CONTACT-like boundary elements).
    #[default]
    Exact,
    /// Kalker's simplified theory FASTSIM.
    Fastsim,
}

impl Method {
    /// Lower-case name.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Fastsim => "fastsim",
        }
    }
}

/// Potential contact area margin around the Hertz ellipse (fraction of the semi-axes).
pub const GRID_MARGIN: f64 = 0.1;
/// Default elements (exact theory) or points (FASTSIM) per axis of the potential contact
/// area: 60 x 60 puts the adhesion/slip boundary of a ~6 mm patch within 0.2 mm, and the
/// exact solution takes about 0.2-0.4 s (docs/performance.md).
pub const DEFAULT_GRID: usize = 60;
/// Default wheel rolling radius (m): the nominal radius of the 920 mm NS intercity wheel of
/// Yang & Li (2019) (data/wheels/ns_intercity_920.json).
pub const DEFAULT_WHEEL_RADIUS_M: f64 = 0.46;
/// Default rail crown radius (m): the 300 mm crown of the 54E1 head (EN 13674-1).
pub const DEFAULT_RAIL_CROWN_RADIUS_M: f64 = crate::geometry::rail54e1::CROWN_RADIUS_MM * 1e-3;
/// Fewest elements across the contact patch for a meaningful solution.
pub const MIN_ELEMENTS_ACROSS_PATCH: usize = 8;

/// A forward solution with its fields (one entry per element / point).
#[derive(Debug, Clone, serde::Serialize)]
pub struct RollingContactSolution {
    /// Method used.
    pub method: Method,
    /// Creepages prescribed.
    pub creepages: Creepages,
    /// Friction coefficient.
    pub mu: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Longitudinal creep force on body 1 (N).
    pub force_x_n: f64,
    /// Lateral creep force on body 1 (N).
    pub force_y_n: f64,
    /// Element / point centres x (m).
    pub x_m: Vec<f64>,
    /// Element / point centres y (m).
    pub y_m: Vec<f64>,
    /// Element areas (m^2).
    pub area_m2: Vec<f64>,
    /// Pressure (Pa).
    pub pressure_pa: Vec<f64>,
    /// Traction px (Pa).
    pub traction_x_pa: Vec<f64>,
    /// Traction py (Pa).
    pub traction_y_pa: Vec<f64>,
    /// Adhesion / slip map.
    pub state: Vec<ElementState>,
}

impl RollingContactSolution {
    /// Fraction of the loaded area in adhesion.
    pub fn adhesion_area_fraction(&self) -> f64 {
        let (mut adhesion, mut contact) = (0.0, 0.0);
        for (state, area) in self.state.iter().zip(&self.area_m2) {
            match state {
                ElementState::Adhesion => {
                    adhesion += area;
                    contact += area;
                }
                ElementState::Slip => contact += area,
                ElementState::Exterior => {}
            }
        }
        if contact > 0.0 {
            adhesion / contact
        } else {
            0.0
        }
    }
}

enum Engine {
    Exact {
        grid: Grid,
        normal: NormalSolution,
        tangential: Box<TangentialSolver>,
        options: TangentialOptions,
    },
    Fastsim {
        hertz: HertzContact,
        coefficients: CreepCoefficients,
        points: usize,
    },
}

/// A contact (geometry, load, material, friction) ready to be solved for any creepages.
pub struct RollingSolver {
    engine: Engine,
    mu: f64,
    normal_force_n: f64,
    material: Material,
}

impl RollingSolver {
    /// Sets up a Hertzian contact with `elements_per_axis` elements (exact) or points (FASTSIM)
    /// in each direction. The normal problem is solved here once.
    pub fn new(
        hertz: &HertzContact,
        mu: f64,
        method: Method,
        elements_per_axis: usize,
    ) -> Result<RollingSolver> {
        super::validate_friction(mu, "command line")?;
        let minimum = match method {
            Method::Exact => {
                ((1.0 + GRID_MARGIN) * MIN_ELEMENTS_ACROSS_PATCH as f64).ceil() as usize
            }
            Method::Fastsim => MIN_ELEMENTS_ACROSS_PATCH,
        };
        if elements_per_axis < minimum || elements_per_axis > 1000 {
            return Err(Error::input(
                "command line",
                "--grid",
                format!(
                    "must be in {minimum}..=1000 elements per axis (at least {MIN_ELEMENTS_ACROSS_PATCH} across the contact patch), got {elements_per_axis}"
                ),
            ));
        }
        match method {
            Method::Exact => {
                let grid = Grid::centered(
                    (1.0 + GRID_MARGIN) * hertz.semi_axis_a_m,
                    (1.0 + GRID_MARGIN) * hertz.semi_axis_b_m,
                    elements_per_axis,
                    elements_per_axis,
                );
                let mut gap_m = vec![0.0; grid.len()];
                for i in 0..grid.nx {
                    for j in 0..grid.ny {
                        gap_m[grid.index(i, j)] = hertz.curvature_x_per_m * grid.x_m(i).powi(2)
                            + hertz.curvature_y_per_m * grid.y_m(j).powi(2);
                    }
                }
                RollingSolver::exact_from_gap(
                    grid,
                    &gap_m,
                    hertz.normal_force_n,
                    hertz.material,
                    mu,
                )
            }
            Method::Fastsim => {
                let coefficients = kalker_creep_coefficients(
                    hertz.semi_axis_a_m / hertz.semi_axis_b_m,
                    hertz.material.poisson_ratio,
                )?;
                Ok(RollingSolver {
                    engine: Engine::Fastsim {
                        hertz: *hertz,
                        coefficients,
                        points: elements_per_axis,
                    },
                    mu,
                    normal_force_n: hertz.normal_force_n,
                    material: hertz.material,
                })
            }
        }
    }

    /// Exact solver on any undeformed gap (e.g. from [`super::geometry::profile_gap`]).
    pub fn exact_from_gap(
        grid: Grid,
        gap_m: &[f64],
        normal_force_n: f64,
        material: Material,
        mu: f64,
    ) -> Result<RollingSolver> {
        super::validate_friction(mu, "command line")?;
        let normal = solve_normal(&grid, gap_m, normal_force_n, &material, 1e-12)?;
        let tangential = Box::new(TangentialSolver::new(grid, &material));
        Ok(RollingSolver {
            engine: Engine::Exact {
                grid,
                normal,
                tangential,
                options: TangentialOptions::default(),
            },
            mu,
            normal_force_n,
            material,
        })
    }

    /// Friction coefficient.
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// Normal force (N).
    pub fn normal_force_n(&self) -> f64 {
        self.normal_force_n
    }
    /// Material.
    pub fn material(&self) -> Material {
        self.material
    }
    /// Method.
    pub fn method(&self) -> Method {
        match self.engine {
            Engine::Exact { .. } => Method::Exact,
            Engine::Fastsim { .. } => Method::Fastsim,
        }
    }
    /// Pressure of the exact normal solution (None for FASTSIM).
    pub fn normal_solution(&self) -> Option<(&Grid, &NormalSolution)> {
        match &self.engine {
            Engine::Exact { grid, normal, .. } => Some((grid, normal)),
            Engine::Fastsim { .. } => None,
        }
    }

    /// Creep forces `(Fx, Fy)` (N) for the creepages.
    pub fn forces(&self, creepages: &Creepages) -> Result<(f64, f64)> {
        let solution = self.solve(creepages)?;
        Ok((solution.force_x_n, solution.force_y_n))
    }

    /// Full forward solution for the creepages.
    pub fn solve(&self, creepages: &Creepages) -> Result<RollingContactSolution> {
        self.solve_warm(creepages, None)
    }

    /// Creep forces, warm-started from a nearby solution of the same solver (exact method: its
    /// tractions and element division are the starting point of the Newton iteration).
    pub fn forces_warm(
        &self,
        creepages: &Creepages,
        warm: Option<&RollingContactSolution>,
    ) -> Result<(f64, f64)> {
        let solution = self.solve_warm(creepages, warm)?;
        Ok((solution.force_x_n, solution.force_y_n))
    }

    /// [`RollingSolver::solve`] with an optional warm start (ignored by FASTSIM, which is direct).
    pub fn solve_warm(
        &self,
        creepages: &Creepages,
        warm: Option<&RollingContactSolution>,
    ) -> Result<RollingContactSolution> {
        for (value, name) in [
            (creepages.xi, "--xi"),
            (creepages.eta, "--eta"),
            (creepages.phi_per_m, "--phi-per-m"),
        ] {
            if !value.is_finite() {
                return Err(Error::input(
                    "command line",
                    name,
                    format!("must be finite, got {value}"),
                ));
            }
        }
        match &self.engine {
            Engine::Exact {
                grid,
                normal,
                tangential,
                options,
            } => {
                let solution = tangential.solve(
                    &normal.pressure_pa,
                    self.mu,
                    creepages,
                    options,
                    warm.map(|w| (w.traction_x_pa.as_slice(), w.traction_y_pa.as_slice())),
                )?;
                let mut x_m = Vec::with_capacity(grid.len());
                let mut y_m = Vec::with_capacity(grid.len());
                for i in 0..grid.nx {
                    for j in 0..grid.ny {
                        x_m.push(grid.x_m(i));
                        y_m.push(grid.y_m(j));
                    }
                }
                Ok(RollingContactSolution {
                    method: Method::Exact,
                    creepages: *creepages,
                    mu: self.mu,
                    normal_force_n: self.normal_force_n,
                    force_x_n: solution.force_x_n,
                    force_y_n: solution.force_y_n,
                    x_m,
                    y_m,
                    area_m2: vec![grid.element_area_m2(); grid.len()],
                    pressure_pa: normal.pressure_pa.clone(),
                    traction_x_pa: solution.traction_x_pa,
                    traction_y_pa: solution.traction_y_pa,
                    state: solution.state,
                })
            }
            Engine::Fastsim {
                hertz,
                coefficients,
                points,
            } => {
                let solution = fastsim(hertz, coefficients, self.mu, creepages, *points, *points)?;
                Ok(RollingContactSolution {
                    method: Method::Fastsim,
                    creepages: *creepages,
                    mu: self.mu,
                    normal_force_n: self.normal_force_n,
                    force_x_n: solution.force_x_n,
                    force_y_n: solution.force_y_n,
                    x_m: solution.x_m,
                    y_m: solution.y_m,
                    area_m2: solution.area_m2,
                    pressure_pa: solution.pressure_pa,
                    traction_x_pa: solution.traction_x_pa,
                    traction_y_pa: solution.traction_y_pa,
                    state: solution.state,
                })
            }
        }
    }
}
