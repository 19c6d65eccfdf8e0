//! Wall time of the parts of a central-difference step: a lap clock the solver reads between
//! its phases when asked to ([`super::Solver::time_phases`]), so that `squeal bench rolling`
//! can say where a step's time goes without a profiler. Off by default, and then the solver
//! never reads the clock; on, it reads it about ten times a step (tens of nanoseconds each,
//! against milliseconds a step) and changes no arithmetic.

use std::time::Instant;

/// The parts of a step, in the order the solver runs them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepPhase {
    /// Element forces (zeroing the internal-force array included).
    Elements,
    /// Zeroing the auxiliary-force array.
    AuxZero,
    /// Nodal loads and springs: their forces, and after the update their work.
    Discrete,
    /// The caller's forces ([`super::AuxForces`]: contact).
    Contact,
    /// Tie slaves' forces passed to their masters.
    TiePass,
    /// The central-difference update of the nodes with its work bookkeeping.
    NodeUpdate,
    /// Rigid bodies.
    RigidBodies,
    /// Tie slaves following their masters.
    TieFollow,
    /// Everything else: prescribed motions, the energy report, and what the caller does
    /// between steps.
    Other,
}

/// Every phase, in step order.
pub const STEP_PHASES: [StepPhase; 9] = [
    StepPhase::Elements,
    StepPhase::AuxZero,
    StepPhase::Discrete,
    StepPhase::Contact,
    StepPhase::TiePass,
    StepPhase::NodeUpdate,
    StepPhase::RigidBodies,
    StepPhase::TieFollow,
    StepPhase::Other,
];

impl StepPhase {
    /// A short name for tables (`snake_case`).
    pub fn name(self) -> &'static str {
        match self {
            StepPhase::Elements => "elements",
            StepPhase::AuxZero => "aux_zero",
            StepPhase::Discrete => "loads_springs",
            StepPhase::Contact => "contact",
            StepPhase::TiePass => "tie_pass",
            StepPhase::NodeUpdate => "node_update",
            StepPhase::RigidBodies => "rigid_bodies",
            StepPhase::TieFollow => "tie_follow",
            StepPhase::Other => "other",
        }
    }
}

/// Seconds spent in each [`StepPhase`] since the clock started.
#[derive(Clone, Debug)]
pub struct PhaseClock {
    last: Instant,
    seconds: [f64; STEP_PHASES.len()],
}

impl Default for PhaseClock {
    fn default() -> Self {
        PhaseClock::new()
    }
}

impl PhaseClock {
    /// A clock at zero, its first lap starting now.
    pub fn new() -> PhaseClock {
        PhaseClock {
            last: Instant::now(),
            seconds: [0.0; STEP_PHASES.len()],
        }
    }

    /// Charges the time since the last lap (or the start) to `phase`.
    #[inline]
    pub fn lap(&mut self, phase: StepPhase) {
        let now = Instant::now();
        self.seconds[phase as usize] += now.duration_since(self.last).as_secs_f64();
        self.last = now;
    }

    /// Seconds charged to `phase`.
    pub fn seconds(&self, phase: StepPhase) -> f64 {
        self.seconds[phase as usize]
    }

    /// Seconds charged to all phases together.
    pub fn total_seconds(&self) -> f64 {
        self.seconds.iter().sum()
    }
}
