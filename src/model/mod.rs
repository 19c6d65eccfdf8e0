//! The model stage: what is simulated, described without a solver.
//!
//! Between the meshes (`mesh`, `fem`, `scenario`) and the solvers (`modal`, `axisym`,
//! `explicit`, `rolling`), this stage turns input files into models:
//! - [`case`]: a rolling case file (the track's discrete parts, the vehicle load, the rolling
//!   conditions, the friction law, what to write), with [`lateral`] (the axle's C1 lateral
//!   motion) and [`curve`] (piecewise curves of time);
//! - [`rolling`]: the rolling model of a case (mesh, materials, supports, springs, the axle
//!   body, the sprung mass, the contact pair's definition, the output nodes), which
//!   `rolling::build` applies to the explicit engine;
//! - [`modal`]: the modal model of a wheel file or an imported mesh (assembled stiffness and
//!   mass, clamps), which `modal::pipeline` solves and classifies;
//! - [`spring`]: a spring-damper between two nodes or to the ground;
//! - [`time_stepping`]: single rate or multi-rate, and the levels' scheme.
//!
//! One material type serves every stage ([`Material`]); it sits at the bottom of the import
//! order (`crate::material`) because the wheel file, read before this stage, already carries
//! it. The friction law is owned and validated in `crate::friction` for the same reason.

pub mod case;
pub mod curve;
pub mod enforcement;
pub mod lateral;
pub mod modal;
pub mod rolling;
pub mod spring;
pub mod time_stepping;

pub use crate::material::Material;
