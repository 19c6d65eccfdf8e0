//! The plain data the engine keeps and reports: energies and work totals, rigid-body states,
//! and the node fields of an output step.

use serde::{Deserialize, Serialize};

use crate::mesh::P3;

/// Energies at one instant (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyReport {
    /// Time (s).
    pub time_s: f64,
    /// Kinetic energy.
    pub kinetic_j: f64,
    /// Stored strain energy of the elements.
    pub strain_j: f64,
    /// Hourglass energy (stiffness form).
    pub hourglass_j: f64,
    /// Energy stored in the discrete springs.
    pub spring_j: f64,
    /// Energy dissipated by dampers (springs, Rayleigh, viscous hourglass).
    pub damping_j: f64,
    /// Energy absorbed by auxiliary (contact) forces: penalty energy + friction.
    pub contact_j: f64,
    /// Work of external loads (gravity, nodal loads, torque) and constraint reactions.
    pub external_work_j: f64,
    /// `kinetic + strain + hourglass + spring + damping + contact - external_work`.
    pub balance_error_j: f64,
    /// `|balance_error| / max(kinetic + strain + hourglass + spring, |external_work|)`.
    pub balance_ratio: f64,
    /// Smallest `det F` over the elements.
    pub min_det_f: f64,
    /// Element with the smallest `det F`.
    pub min_det_f_element: usize,
}

/// Work accumulators (J), advanced every step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WorkTotals {
    /// Work of internal (element) forces, `sum dt f_int . vbar`.
    pub internal_j: f64,
    /// Work of the auxiliary force array (springs, loads, contact).
    pub aux_j: f64,
    /// Work of gravity.
    pub gravity_j: f64,
    /// Energy dissipated by mass-proportional damping.
    pub mass_damping_j: f64,
    /// Work of constraint reactions (prescribed motions).
    pub reaction_j: f64,
    /// Work of the springs' forces on the nodes.
    pub spring_j: f64,
    /// Energy dissipated by spring dampers.
    pub spring_damping_j: f64,
    /// Work of nodal loads.
    pub load_j: f64,
    /// Work of applied torques.
    pub torque_j: f64,
    /// Energy present when the bookkeeping started (initial kinetic energy, preload): the
    /// balance error of the first report, so that later reports measure the change.
    pub initial_j: f64,
}

impl WorkTotals {
    /// The totals in a fixed order (a checkpoint's): internal, auxiliary, gravity, mass
    /// damping, reaction, spring, spring damping, load, torque, initial.
    pub fn to_array(&self) -> [f64; 10] {
        [
            self.internal_j,
            self.aux_j,
            self.gravity_j,
            self.mass_damping_j,
            self.reaction_j,
            self.spring_j,
            self.spring_damping_j,
            self.load_j,
            self.torque_j,
            self.initial_j,
        ]
    }

    /// The totals from [`WorkTotals::to_array`]'s order.
    pub fn from_array(t: [f64; 10]) -> WorkTotals {
        WorkTotals {
            internal_j: t[0],
            aux_j: t[1],
            gravity_j: t[2],
            mass_damping_j: t[3],
            reaction_j: t[4],
            spring_j: t[5],
            spring_damping_j: t[6],
            load_j: t[7],
            torque_j: t[8],
            initial_j: t[9],
        }
    }

    pub(super) fn add_scaled(&mut self, o: &WorkTotals, s: f64) {
        self.internal_j += s * o.internal_j;
        self.aux_j += s * o.aux_j;
        self.gravity_j += s * o.gravity_j;
        self.mass_damping_j += s * o.mass_damping_j;
        self.reaction_j += s * o.reaction_j;
        self.spring_j += s * o.spring_j;
        self.spring_damping_j += s * o.spring_damping_j;
        self.load_j += s * o.load_j;
        self.torque_j += s * o.torque_j;
        self.initial_j += s * o.initial_j;
    }
}

/// State of a rigid body.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidState {
    /// Body mass (kg).
    pub mass_kg: f64,
    /// Reference centre of mass.
    pub centre0_m: P3,
    /// Current centre of mass (t_n).
    pub centre_m: P3,
    /// Centre velocity (t_{n-1/2}).
    pub velocity_m_per_s: P3,
    /// Rotation from the reference (t_n).
    pub rotation: [[f64; 3]; 3],
    /// Angular momentum about the centre (t_{n-1/2}).
    pub angular_momentum: P3,
    /// Inertia tensor about the centre, reference orientation (kg m^2).
    pub inertia0: [[f64; 3]; 3],
    /// Its inverse.
    pub inertia0_inv: [[f64; 3]; 3],
}

/// Sampled node quantities of an output step (filled only on output steps).
#[derive(Clone, Debug, Default)]
pub struct OutputFields {
    /// Displacement at t_n.
    pub displacement: Vec<P3>,
    /// Centred velocity at t_n.
    pub velocity: Vec<P3>,
    /// Acceleration at t_n.
    pub acceleration: Vec<P3>,
    /// Per rigid body, the force that holds its prescribed translations (N, zero in the free
    /// directions): `m (v_(n+1/2) - v_(n-1/2)) / dt - F`, what the guide applies to the body.
    pub rigid_reaction_force_n: Vec<P3>,
}

/// The nodes whose auxiliary force a step zeroes and reads, ascending, with the counts of
/// springs and loads they were built from (a model changed since falls back to every node;
/// `aux_nodes.rs`).
#[derive(Clone, Debug, Default)]
pub(super) struct AuxNodeSet {
    pub(super) nodes: Vec<u32>,
    pub(super) springs: usize,
    pub(super) loads: usize,
}

/// What a run returns.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunSummary {
    /// "completed", "unstable" or "interrupted" (stopped on request; a checkpoint of the step
    /// reached was written, `--resume` goes on); "running" in the record written with each
    /// periodic checkpoint while the run goes on (left so when the process ended without a
    /// record of its own: killed, or the machine stopped).
    pub status: String,
    /// Diagnosis when unstable, or where an interrupted run stopped.
    pub diagnosis: Option<String>,
    /// Steps taken (in total, across resumes).
    pub steps: u64,
    /// Simulated time reached (s).
    pub time_s: f64,
    /// Time step (s).
    pub time_step_s: f64,
    /// What limits the stable step.
    pub time_step_limited_by: String,
    /// Wall-clock time of this invocation (s).
    pub wall_s: f64,
    /// Steps per second of this invocation.
    pub steps_per_second: f64,
    /// Largest energy balance ratio seen.
    pub max_balance_ratio: f64,
    /// Last energy report.
    pub last_energy: Option<EnergyReport>,
    /// Whether the run resumed from a checkpoint, and from which time.
    pub resumed_from_s: Option<f64>,
}
