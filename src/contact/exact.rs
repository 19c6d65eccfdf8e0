//! Exact contact: forward-increment Lagrange multipliers (Carpenter, Taylor & Katona,
//! Int. J. Numer. Meth. Eng. 32 (1991) 103-128), the enforcement explicit codes use when a
//! penalty's compliance must not enter the answer.
//!
//! The contact forces of t_n are chosen so that the state the step ends in satisfies the
//! contact conditions. For a slave `s` over master face `F` (bilinear weights `w_j`, unit
//! normal `n` out of the master, gap `g_n = (x_s - sum w_j x_j) . n` at t_n), with the
//! coefficients `c = (1, -w_0, .., -w_3)` on the nodes `(s, F_0, .., F_3)`:
//!
//! ```text
//! relative velocity   v_rel = sum_j c_j v_j,{n+1/2},   v_j,{n+1/2} = v*_j + dt f_j / m_j
//! gap at t_{n+1}      g_{n+1} = g_n + dt v_rel . n            (n and w held over the step)
//! normal              f_N >= 0,  g_{n+1} >= g_target,  f_N (g_{n+1} - g_target) = 0
//! tangential (stick)  v_rel,T = 0  while |f_T| < mu f_N;  else |f_T| = mu f_N against the slip
//! ```
//!
//! where `v*` is the velocity the node reaches without contact ([`StepPredictor`]) and the
//! multiplier `f` acts on node `j` as `c_j f`. One constraint alone is solved in closed form:
//! its effective inverse mass is `W = sum_j c_j^2 / m_j`, so a force increment `df` changes its
//! relative velocity by `dt W df`. Slaves that share master nodes are coupled; the set is solved
//! by projected Gauss-Seidel sweeps in slave order (serial, so the result does not depend on
//! the thread count), normal then tangential per slave, until no force changes by more than
//! [`RELATIVE_TOLERANCE`] of the largest normal force, at most [`MAX_SWEEPS`] sweeps.
//!
//! Unlike a penalty, the contact adds no stiffness and no step bound: a slave lands on the face
//! (a lone node's impact is perfectly plastic, as in Carpenter et al.) and the normal
//! compliance is the elastic bodies' own. The friction law reads the slip speed of the last
//! step (the node's own, or the patch's: [`super::SlipSpeed`]), as the penalty contact does.
//!
//! `g_target` is 0 for a slave that is not penetrating. A penetration left by the penalty
//! preload (the run starts from the penalty's static equilibrium) or by the faceting of the
//! master surface is not closed in one step, which would throw the slave off at `g_n / dt`:
//! it is relaxed, `g_target = g_n (1 - dt / tau)` with [`GAP_RELAXATION_S`].
//!
//! A tie slave among the nodes (the refined tread band's and rail zone's hanging nodes) moves
//! with its master face, `v = sum t_k v_k`, and passes its force on as `t_k f`: the constraint
//! acts on its masters with the coefficients `c_j t_k`. Nodes the step does not move freely
//! (fixed or prescribed components, rigid bodies) are held at their own velocity for the
//! contact (infinite mass); the count of such node-steps is reported (on the rolling models,
//! the fixed rail ends, which the contact never reaches).

// Index loops mirror the vector notation of the equations.
#![allow(clippy::needless_range_loop)]

use crate::explicit::aux::StepPredictor;
use crate::mesh::P3;
use rayon::prelude::*;

/// Sweeps of the projected Gauss-Seidel iteration at most. A contact patch of a few hundred
/// slaves on a rail face converges in a few tens (docs/physics.md); the last iterate is used
/// after this many, and the step counted as unconverged.
pub const MAX_SWEEPS: usize = 200;

/// The iteration stops when no multiplier changed by more than this fraction of the largest
/// normal force in the last sweep: far below the 1e-6 to which a patch's force resultants are
/// read (contact_forces.csv is written with 7 significant digits).
pub const RELATIVE_TOLERANCE: f64 = 1e-10;

/// Time constant of the relaxation of an existing penetration (s). One millisecond: the
/// preload's penalty penetration (tens of micrometres) then closes at a few centimetres per
/// second, four orders below the rolling speed, and is gone within the first few milliseconds
/// of rolling, before any analysis window opens.
pub const GAP_RELAXATION_S: f64 = 1e-3;

/// Nodes a constraint can act on: the slave and the face's four, each a tie slave moving with
/// four masters at most.
pub(super) const MAX_CONSTRAINT_NODES: usize = 20;

/// One slave's constraint in a step.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Constraint {
    /// Index of the slave in the pair.
    pub(super) slave: u32,
    /// Master face and the projection's bilinear weights.
    pub(super) face: u32,
    pub(super) weights: [f64; 4],
    /// Nodes: the slave, then the face's four; [`ExactSolver::predict`] replaces each tie
    /// slave among them by its masters (`count` in use, each node once).
    pub(super) nodes: [usize; MAX_CONSTRAINT_NODES],
    /// Coefficients `c_j`: 1 on the slave, `-w_j` on the face's nodes (times the tie weights
    /// on a tie slave's masters).
    pub(super) coefficients: [f64; MAX_CONSTRAINT_NODES],
    pub(super) count: usize,
    /// Unit normal out of the master.
    pub(super) normal: P3,
    /// Gap at t_n (m; negative: penetration).
    pub(super) gap_m: f64,
    /// `(g_n - g_target) / dt` (m/s): the normal relative velocity must be at least minus this.
    pub(super) gap_rate_m_per_s: f64,
    /// Effective inverse mass `W = sum c_j^2 / m_j` (1/kg).
    pub(super) inverse_mass: f64,
    /// Friction coefficient of the step.
    pub(super) mu: f64,
    /// Normal multiplier (N, >= 0) and tangential multiplier (N, in the tangent plane).
    pub(super) normal_force_n: f64,
    pub(super) tangential_force_n: P3,
}

/// The solver's buffers, allocated once at the pair's size (the step allocates nothing).
pub(super) struct ExactSolver {
    /// This step's constraints, in slave order.
    pub(super) constraints: Vec<Constraint>,
    /// Per node: v* (valid where `predicted`), 1 / m (0: held), and the velocity correction.
    v_star: Vec<P3>,
    inverse_mass: Vec<f64>,
    correction: Vec<P3>,
    predicted: Vec<bool>,
    /// Nodes whose entries were written this step (to clear them afterwards).
    touched: Vec<usize>,
    /// Sweeps of the last step, the most of any step, and the steps that hit [`MAX_SWEEPS`].
    pub(super) last_sweeps: usize,
    pub(super) largest_sweeps: usize,
    pub(super) unconverged_steps: usize,
    /// Contact node-steps so far whose node the step does not move freely (held for the contact).
    pub(super) held_node_steps: usize,
}

fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl ExactSolver {
    /// Buffers for `slave_count` slaves on a mesh of `node_count` nodes.
    pub(super) fn new(slave_count: usize, node_count: usize) -> ExactSolver {
        ExactSolver {
            constraints: Vec::with_capacity(slave_count),
            v_star: vec![[0.0; 3]; node_count],
            inverse_mass: vec![0.0; node_count],
            correction: vec![[0.0; 3]; node_count],
            predicted: vec![false; node_count],
            touched: Vec::with_capacity(MAX_CONSTRAINT_NODES * slave_count),
            last_sweeps: 0,
            largest_sweeps: 0,
            unconverged_steps: 0,
            held_node_steps: 0,
        }
    }

    /// Replaces the tie slaves among a constraint's nodes by their masters, and merges
    /// repeated nodes (a node's coefficients add: the effective inverse mass needs each once).
    fn expand_ties(c: &mut Constraint, predictor: &StepPredictor) {
        let (raw_nodes, raw_coefficients, raw_count) = (c.nodes, c.coefficients, c.count);
        c.count = 0;
        let mut push =
            |nd: usize, coefficient: f64| match c.nodes[..c.count].iter().position(|&m| m == nd) {
                Some(i) => c.coefficients[i] += coefficient,
                None => {
                    c.nodes[c.count] = nd;
                    c.coefficients[c.count] = coefficient;
                    c.count += 1;
                }
            };
        for j in 0..raw_count {
            match predictor.tie_masters(raw_nodes[j]) {
                Some((masters, weights)) => {
                    for k in 0..4 {
                        push(masters[k], raw_coefficients[j] * weights[k]);
                    }
                }
                None => push(raw_nodes[j], raw_coefficients[j]),
            }
        }
    }

    /// Predicts every node of the step's constraints (once each), and their effective inverse
    /// masses. `v` is v_{n-1/2}; `force` the auxiliary forces gathered so far (without contact).
    pub(super) fn predict(&mut self, predictor: &StepPredictor, v: &[P3], force: &[P3]) {
        for c in self.constraints.iter_mut() {
            Self::expand_ties(c, predictor);
            let mut w = 0.0;
            for (j, &nd) in c.nodes[..c.count].iter().enumerate() {
                if !self.predicted[nd] {
                    self.predicted[nd] = true;
                    self.touched.push(nd);
                    match predictor.free_update(nd, v[nd], force[nd]) {
                        Some((v_star, im)) => {
                            self.v_star[nd] = v_star;
                            self.inverse_mass[nd] = im;
                        }
                        None => {
                            self.v_star[nd] = v[nd];
                            self.inverse_mass[nd] = 0.0;
                            self.held_node_steps += 1;
                        }
                    }
                }
                w += c.coefficients[j] * c.coefficients[j] * self.inverse_mass[nd];
            }
            c.inverse_mass = w;
        }
    }

    /// The relative velocity `sum c_j (v*_j + dv_j)` of constraint `c`.
    #[inline]
    fn relative_velocity(&self, c: &Constraint) -> P3 {
        let mut vr = [0.0; 3];
        for j in 0..c.count {
            let nd = c.nodes[j];
            for d in 0..3 {
                vr[d] += c.coefficients[j] * (self.v_star[nd][d] + self.correction[nd][d]);
            }
        }
        vr
    }

    /// Adds the velocity change of a force increment `df` on constraint `c`.
    #[inline]
    fn apply(&mut self, c: &Constraint, dt_s: f64, df: P3) {
        for j in 0..c.count {
            let nd = c.nodes[j];
            let s = dt_s * c.coefficients[j] * self.inverse_mass[nd];
            for d in 0..3 {
                self.correction[nd][d] += s * df[d];
            }
        }
    }

    /// Projected Gauss-Seidel over the constraints (module docs), started from the
    /// multipliers the constraints hold (the last step's: a warm start). Returns the sweeps.
    pub(super) fn solve(&mut self, dt_s: f64) -> usize {
        let mut sweeps = 0;
        let mut constraints = std::mem::take(&mut self.constraints);
        // The velocity change of the starting multipliers: every sweep's increments are
        // relative to them.
        for c in constraints.iter() {
            let f = [0, 1, 2].map(|d| c.normal_force_n * c.normal[d] + c.tangential_force_n[d]);
            self.apply(c, dt_s, f);
        }
        while sweeps < MAX_SWEEPS {
            sweeps += 1;
            let (mut largest_change, mut largest_force) = (0.0f64, 0.0f64);
            for c in constraints.iter_mut() {
                if !(c.inverse_mass > 0.0) {
                    continue;
                }
                let n = c.normal;
                let scale = 1.0 / (dt_s * c.inverse_mass);
                // Normal: the least force that keeps g_{n+1} >= g_target.
                let vr = self.relative_velocity(c);
                let vn = dot(vr, n);
                let normal = (c.normal_force_n - (vn + c.gap_rate_m_per_s) * scale).max(0.0);
                let dn = normal - c.normal_force_n;
                if dn != 0.0 {
                    self.apply(c, dt_s, n.map(|x| x * dn));
                    c.normal_force_n = normal;
                }
                // Tangential: the force that stops the relative tangential velocity (a normal
                // increment changes only the normal component, since it acts along n), held
                // to the bound mu f_N.
                let vt = [0, 1, 2].map(|d| vr[d] - vn * n[d]);
                let mut trial = [0, 1, 2].map(|d| c.tangential_force_n[d] - vt[d] * scale);
                let on = dot(trial, n);
                trial = [0, 1, 2].map(|d| trial[d] - on * n[d]);
                let size = dot(trial, trial).sqrt();
                let bound = c.mu * normal;
                if size > bound {
                    let s = if size > 0.0 { bound / size } else { 0.0 };
                    trial = trial.map(|x| x * s);
                }
                let dt_force = [0, 1, 2].map(|d| trial[d] - c.tangential_force_n[d]);
                self.apply(c, dt_s, dt_force);
                c.tangential_force_n = trial;
                largest_change = largest_change
                    .max(dn.abs())
                    .max(dot(dt_force, dt_force).sqrt());
                largest_force = largest_force.max(normal);
            }
            if largest_change <= RELATIVE_TOLERANCE * largest_force {
                break;
            }
            if sweeps == MAX_SWEEPS {
                self.unconverged_steps += 1;
            }
        }
        self.constraints = constraints;
        self.last_sweeps = sweeps;
        self.largest_sweeps = self.largest_sweeps.max(sweeps);
        sweeps
    }

    /// The tangential relative velocity of constraint `i` at t_{n+1/2} after the solve (m/s).
    pub(super) fn slip_velocity(&self, i: usize) -> P3 {
        let c = &self.constraints[i];
        let vr = self.relative_velocity(c);
        let vn = dot(vr, c.normal);
        [0, 1, 2].map(|d| vr[d] - vn * c.normal[d])
    }

    /// Clears the per-node entries the step wrote.
    pub(super) fn clear(&mut self) {
        for &nd in &self.touched {
            self.predicted[nd] = false;
            self.correction[nd] = [0.0; 3];
        }
        self.touched.clear();
    }
}

/// The first five entries of a constraint's node or coefficient list, the rest `fill`.
fn pad<T: Copy>(first: [T; 5], fill: T) -> [T; MAX_CONSTRAINT_NODES] {
    let mut out = [fill; MAX_CONSTRAINT_NODES];
    out[..5].copy_from_slice(&first);
    out
}

/// The gap `g_target` that constraint with gap `gap_m` at t_n must reach by t_{n+1}, as a rate:
/// `(g_n - g_target) / dt` (module docs: a penetration is relaxed with [`GAP_RELAXATION_S`]).
pub(super) fn gap_rate_m_per_s(gap_m: f64, dt_s: f64) -> f64 {
    if gap_m >= 0.0 {
        gap_m / dt_s
    } else {
        gap_m / GAP_RELAXATION_S.max(dt_s)
    }
}

impl super::ContactPair {
    /// One step of exact enforcement: the search (in parallel, accepting slaves just above a
    /// face), the constraints in slave order, the prediction of their nodes, the projected
    /// Gauss-Seidel solve, then the slaves' states and forces and the common scatter.
    pub(super) fn add_exact_forces(
        &mut self,
        dt_s: f64,
        u: &[P3],
        v: &[P3],
        force: &mut [P3],
        predictor: &StepPredictor,
    ) {
        self.prepare_search(u);
        let mut found = std::mem::take(&mut self.found);
        found.clear();
        found.resize(self.region.slaves.len(), None);
        {
            let ctx = self.context(u, v, dt_s, true);
            let indices = &self.region.slaves;
            found
                .par_chunks_mut(super::SLAVE_CHUNK)
                .enumerate()
                .for_each(|(c, out)| {
                    for (j, o) in out.iter_mut().enumerate() {
                        *o = ctx.find_face(indices[c * super::SLAVE_CHUNK + j] as usize);
                    }
                });
        }
        self.build_constraints(&found, dt_s);
        self.found = found;
        self.exact.predict(predictor, v, force);
        self.exact.solve(dt_s);
        self.write_exact_states();
        self.exact.clear();
        self.scatter_forces(force);
    }

    /// This step's constraints from the faces found under the region's slaves, the solve warm
    /// started from each slave's last multipliers; slaves without a face lose their contact.
    fn build_constraints(&mut self, found: &[Option<super::FoundFace>], dt_s: f64) {
        let patch_speed = self.patch_slip_speed();
        self.exact.constraints.clear();
        for (j, &k) in self.region.slaves.iter().enumerate() {
            let k = k as usize;
            let st = self.state[k];
            let Some((gap, face, w, n)) = found[j] else {
                if st.active {
                    self.state[k] = super::SlaveState {
                        mu: st.mu,
                        ..Default::default()
                    };
                }
                self.forces[k] = super::NO_FORCE;
                continue;
            };
            let slip = st.slip_velocity_m_per_s;
            let mu = self
                .friction
                .mu(patch_speed.unwrap_or_else(|| dot(slip, slip).sqrt()));
            let f = self.faces[face as usize];
            // Warm start: the last step's multipliers, the tangential one in today's plane.
            let (normal_force_n, tangential_force_n) = if st.active {
                let t = st.tangential_force_n;
                let on = dot(t, n);
                (st.normal_force_n, [0, 1, 2].map(|d| t[d] - on * n[d]))
            } else {
                (0.0, [0.0; 3])
            };
            self.exact.constraints.push(Constraint {
                slave: k as u32,
                face,
                weights: w,
                nodes: pad([self.slaves[k], f[0], f[1], f[2], f[3]], 0),
                coefficients: pad([1.0, -w[0], -w[1], -w[2], -w[3]], 0.0),
                count: 5,
                normal: n,
                gap_m: gap,
                gap_rate_m_per_s: gap_rate_m_per_s(gap, dt_s),
                inverse_mass: 0.0,
                mu,
                normal_force_n,
                tangential_force_n,
            });
        }
    }

    /// The slaves' states and force entries from the solved multipliers: in contact when the
    /// normal multiplier is positive.
    fn write_exact_states(&mut self) {
        for i in 0..self.exact.constraints.len() {
            let c = self.exact.constraints[i];
            let k = c.slave as usize;
            if !(c.normal_force_n > 0.0) {
                self.state[k] = super::SlaveState {
                    mu: c.mu,
                    ..Default::default()
                };
                self.forces[k] = super::NO_FORCE;
                continue;
            }
            let shear = dot(c.tangential_force_n, c.tangential_force_n).sqrt();
            self.state[k] = super::SlaveState {
                active: true,
                normal_force_n: c.normal_force_n,
                tangential_force_n: c.tangential_force_n,
                normal: c.normal,
                slip_velocity_m_per_s: self.exact.slip_velocity(i),
                mu: c.mu,
                // At the bound to rounding: the projection scaled it there.
                at_bound: shear >= c.mu * c.normal_force_n * (1.0 - 1e-12),
                penetration_m: (-c.gap_m).max(0.0),
                face: c.face,
                weights: c.weights,
            };
            let total = [0, 1, 2].map(|d| c.normal_force_n * c.normal[d] + c.tangential_force_n[d]);
            self.forces[k] = (total, c.weights, c.face);
        }
    }
}
