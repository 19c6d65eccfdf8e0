//! Finite elements for modal analysis: the 8-node hexahedron (standard or incompatible modes) and
//! the 10-node tetrahedron (stiffness, consistent and lumped mass), materials per element id, and
//! parallel sparse assembly with constraint elimination (clamped node sets, tied interfaces);
//! and the properties of a beam's cross-section from a plane quad mesh (torsion constant, shear
//! centre, warping constant).

pub mod assembly;
pub mod axis;
pub mod hex27;
pub mod hex8;
pub mod hex8_incompatible;
pub mod hex8_kind;
pub mod jacobian;
pub mod measure;
pub mod section_properties;
pub mod tet10;
pub mod tet4;

pub use assembly::{assemble, assemble_volume, Assembled, Constraints, MassKind, Materials};
pub use hex8::{ElasticMaterial, ElementMatrices};
pub use hex8_kind::Hex8Kind;
