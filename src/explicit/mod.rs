//! The explicit dynamics engine: central differences on 8-node
//! hexahedra with lumped mass, discrete parts (point masses, spring-dampers, rigid node sets,
//! tied interfaces), loads and constraints, energy bookkeeping, and run output (streamed time
//! histories, VTU snapshots, checkpoints).
//!
//! - [`element`]: the element kernels (one-point + hourglass, fully integrated), total
//!   Lagrangian so that large rigid rotations produce no strain;
//! - [`model`]: what the engine integrates;
//! - [`solver`]: the time step, the central-difference update and the energy balance;
//! - [`run`]: a run with output, progress, checkpoints and resume;
//! - [`preload`]: static equilibrium by dynamic relaxation;
//! - [`levels`], [`multirate`]: the power-of-two level partition and subcycled stepping;
//! - `tie_update`: the tied interfaces' force pass and follow step, in parallel;
//! - [`phase_clock`]: wall time by phase of a step, for the benchmarks.
//!
//! Time curves ([`Curve`]) and spring-dampers ([`Spring`]) are the model stage's
//! ([`crate::model`]), re-exported here.

pub mod aux;
mod aux_nodes;
pub mod batch;
pub mod bench;
pub mod checkpoint;
mod colour;
pub mod element;
pub mod energy;
mod forces;
pub mod levels;
pub mod linearised;
pub mod model;
pub mod multirate;
mod node_update;
mod one_point_setup;
pub mod phase_clock;
pub mod preload;
mod rigid_body;
mod rotation;
pub mod run;
pub mod solver;
pub mod state;
pub mod statics;
mod tie_update;
mod timestep;

pub use crate::model::curve::Curve;
pub use element::{ElasticMaterial, Formulation, Hourglass};
pub use model::{Model, MotionKind, Spring};
pub use solver::{AuxForces, EnergyReport, NoAux, Solver};
