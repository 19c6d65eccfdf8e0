//! The choice of hexahedron for the modal assembly: the standard trilinear element
//! ([`super::hex8`]) or the one with incompatible modes ([`super::hex8_incompatible`]).

use super::hex8::{ElasticMaterial, ElementMatrices};
use crate::mesh::P3;

/// Which hexahedron stiffness the modal assembly uses (the mass is the same for both). The
/// default is the incompatible-modes element, which does not lock in bending (docs/modal.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Hex8Kind {
    /// The trilinear (conforming) element of this module: exact for linear fields, but it locks
    /// in bending (parasitic shear) when a bent plate or beam is only one or two elements thick.
    Standard,
    /// Wilson–Taylor incompatible modes ("QM6"), [`super::hex8_incompatible`]: three statically
    /// condensed bubble modes per displacement component represent the quadratic bending field.
    #[default]
    Incompatible,
}

/// Stiffness and mass of one element of the given kind; `None` as for [`super::hex8::element_matrices`].
pub fn element_matrices_of_kind(
    kind: Hex8Kind,
    x: &[P3; 8],
    mat: &ElasticMaterial,
    lumped: bool,
) -> Option<ElementMatrices> {
    match kind {
        Hex8Kind::Standard => super::hex8::element_matrices(x, mat, lumped),
        Hex8Kind::Incompatible => super::hex8_incompatible::element_matrices(x, mat, lumped),
    }
}
