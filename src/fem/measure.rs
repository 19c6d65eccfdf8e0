//! Measures of a volume mesh that need its elements' shape functions: element volumes (by
//! each element's quadrature), the total volume, nodal weights (each element's volume shared
//! equally by its nodes, for mode classification) and the volume centroid.

use crate::mesh::volume::{VolumeElement, VolumeMesh};
use crate::mesh::P3;

use super::{hex27, tet10, tet4};

/// Element volume (m³).
pub fn element_volume(mesh: &VolumeMesh, e: usize) -> f64 {
    match &mesh.elements[e] {
        VolumeElement::Hex8(c) => crate::mesh::hex::volume(&c.map(|n| mesh.nodes[n])),
        VolumeElement::Tet10(c) => tet10::volume(&c.map(|n| mesh.nodes[n])),
        VolumeElement::Tet4(c) => tet4::volume(&c.map(|n| mesh.nodes[n])),
        VolumeElement::Hex27(c) => hex27::volume(&c.map(|n| mesh.nodes[n])),
    }
}

/// Total volume (m³).
pub fn volume(mesh: &VolumeMesh) -> f64 {
    (0..mesh.elements.len())
        .map(|e| element_volume(mesh, e))
        .sum()
}

/// Nodal weights for mode classification: each element's volume shared equally by its
/// nodes.
pub fn nodal_weights(mesh: &VolumeMesh) -> Vec<f64> {
    let mut w = vec![0.0; mesh.nodes.len()];
    for (e, el) in mesh.elements.iter().enumerate() {
        let v = element_volume(mesh, e).abs() / el.nodes().len() as f64;
        for &n in el.nodes() {
            w[n] += v;
        }
    }
    w
}

/// Volume centroid (m), from the nodal weights.
pub fn centroid(mesh: &VolumeMesh) -> P3 {
    let w = nodal_weights(mesh);
    let total: f64 = w.iter().sum::<f64>().max(1e-300);
    [0, 1, 2].map(|d| {
        mesh.nodes
            .iter()
            .zip(&w)
            .map(|(p, w)| p[d] * w)
            .sum::<f64>()
            / total
    })
}
