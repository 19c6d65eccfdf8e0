//! Linear finite elements for modal analysis: the 8-node hexahedron (stiffness, consistent and
//! lumped mass), materials per element id, and parallel sparse assembly with constraint
//! elimination (clamped node sets, tied interfaces).

pub mod assembly;
pub mod hex8;

pub use assembly::{assemble, Assembled, Constraints, MassKind, Materials};
pub use hex8::{ElasticMaterial, ElementMatrices};
