//! squeal: railway wheel squeal toolkit.
//!
//! Coordinates (used everywhere): x along the track (rolling direction), y lateral (towards the
//! field side), z vertical up; the wheel axis is y. Units are SI (m, kg, s, N, Pa) except where a
//! name says otherwise (e.g. `_mm` in profile tables).

pub mod analysis;
pub mod contact;
pub mod error;
pub mod explicit;
pub mod fem;
pub mod friction;
pub mod geometry;
pub mod input;
pub mod kalker;
pub mod linalg;
pub mod material;
pub mod mesh;
pub mod modal;
pub mod model;
pub mod output;
pub mod pipeline;
pub mod random;
pub mod report;
pub mod rolling;
pub mod scenario;
pub mod signal;
pub mod stability;
pub mod table;
pub mod testdata;
pub use error::{Error, Result};
