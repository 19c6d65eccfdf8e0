//! The Q9 cross-section revolved into a 3D mesh of 27-node hexahedra: the like-for-like 3D
//! counterpart of the harmonic solver.
//!
//! Each Q9 element swept through one sector of `2 pi / sectors` becomes one triquadratic
//! hexahedron ([`crate::fem::hex27`]): its (xi, eta) are the section element's, zeta runs over
//! the three angles `theta_0`, `theta_0 + pi / sectors`, `theta_0 + 2 pi / sectors`, and every
//! node lies exactly on its circle. The (r, z) interpolation is then *identical* to the Q9 section
//! of [`super::AxisymModel`], so a 3D solve differs from the harmonic one only by the quadratic
//! interpolation of `cos(n theta)` around the circumference, an error that falls as
//! `(n / sectors)^4` (measured: `tests/modal_vs_axisym.rs`).
//!
//! Axes as the 3D wheel mesh (docs/architecture.md; [`crate::mesh::wheel`]): the axis of revolution
//! is y (z of the section = y), a section point (r, z) at angle theta goes to
//! `(r sin theta, z, -r cos theta)`, so theta = 0 is the bottom of the wheel. Nodes on the axis
//! (r = 0, the solid axle core) are one node for all angles; the elements touching the axis then
//! have a face collapsed onto a line, which is allowed: their Jacobian vanishes on that face
//! only, never at a Gauss point.

use std::f64::consts::PI;

use super::mesh::Q9Mesh;
use crate::fem::hex27;
use crate::mesh::volume::{VolumeElement, VolumeMesh};
use crate::mesh::P3;

/// The Q9 node at reference position (xi, eta), each in {-1, 0, 1} (the order of
/// [`Q9Mesh::elements`]: corners counter-clockwise, mid-sides, centre).
fn q9_node(xi: i32, eta: i32) -> usize {
    match (xi, eta) {
        (-1, -1) => 0,
        (1, -1) => 1,
        (1, 1) => 2,
        (-1, 1) => 3,
        (0, -1) => 4,
        (1, 0) => 5,
        (0, 1) => 6,
        (-1, 0) => 7,
        _ => 8,
    }
}

/// Revolve `section` into `sectors` hex27 sectors (at least 3). Material id = the section's part
/// id. Each `(name, section_node_ids)` of `sets` becomes a node set of all the revolved copies of
/// those nodes.
pub fn revolve_hex27(section: &Q9Mesh, sectors: usize, sets: &[(&str, &[usize])]) -> VolumeMesh {
    let sectors = sectors.max(3);
    let layers = 2 * sectors;
    let on_axis = section.axis_nodes();
    // first 3D node of each section node; axis nodes have one, the others `layers`
    let mut first = Vec::with_capacity(section.nodes.len());
    let mut nodes: Vec<P3> = Vec::new();
    for (i, &[r, z]) in section.nodes.iter().enumerate() {
        first.push(nodes.len());
        if on_axis[i] {
            nodes.push([0.0, z, 0.0]);
        } else {
            for layer in 0..layers {
                let theta = PI * layer as f64 / sectors as f64;
                nodes.push([r * theta.sin(), z, -r * theta.cos()]);
            }
        }
    }
    let node_of = |i: usize, layer: usize| {
        if on_axis[i] {
            first[i]
        } else {
            first[i] + layer % layers
        }
    };
    let mut elements = Vec::with_capacity(section.elements.len() * sectors);
    let mut material = Vec::with_capacity(section.elements.len() * sectors);
    for (e, q9) in section.elements.iter().enumerate() {
        for s in 0..sectors {
            let build = |flip: bool| -> [usize; 27] {
                std::array::from_fn(|a| {
                    let p = hex27::NODE_REFERENCE[a];
                    let zeta = if flip { -p[2] } else { p[2] };
                    let q = q9_node(p[0] as i32, p[1] as i32);
                    node_of(q9[q], 2 * s + (zeta as i32 + 1) as usize)
                })
            };
            let mut conn = build(false);
            // The sign of det J follows the section element's orientation in (r, z); sweep the
            // other way round the circle for a clockwise one.
            if hex27::volume(&conn.map(|n| nodes[n])) < 0.0 {
                conn = build(true);
            }
            elements.push(VolumeElement::Hex27(conn));
            material.push(section.part[e]);
        }
    }
    let mut mesh = VolumeMesh {
        nodes,
        elements,
        material,
        ..Default::default()
    };
    for (name, ids) in sets {
        let all: Vec<usize> = ids
            .iter()
            .flat_map(|&i| {
                let count = if on_axis[i] { 1 } else { layers };
                (0..count).map(move |layer| (i, layer))
            })
            .map(|(i, layer)| node_of(i, layer))
            .collect();
        mesh.set_node_set(name, all);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Volume of the revolved annulus and solid disc against pi (r1² - r0²) t: the quadratic
    /// sectors approximate the circle, so the error is the sector interpolation's, small at
    /// 16 sectors; a collapsed axis face is valid.
    #[test]
    fn revolved_volume_matches_the_body_of_revolution() {
        for (r0, nr) in [(0.1, 3), (0.0, 2)] {
            let q9 = Q9Mesh::rectangle(r0, 0.4, -0.02, 0.02, nr, 1);
            let mesh = revolve_hex27(&q9, 16, &[("inner", &q9.nodes_at_r(r0, -1.0, 1.0, 1e-9))]);
            let want = PI * (0.4f64.powi(2) - r0 * r0) * 0.04;
            let got = crate::fem::measure::volume(&mesh);
            // The quadratic arc through three points of a circle over pi/8 encloses the sector
            // area to ~1e-5 relative.
            assert!((got - want).abs() < 1e-4 * want, "{got} vs {want}");
            let inner = &mesh.node_sets["inner"];
            let expect = if r0 > 0.0 { 3 * 32 } else { 3 };
            assert_eq!(inner.len(), expect);
            assert!(mesh.elements.iter().all(|e| {
                let VolumeElement::Hex27(c) = e else {
                    return false;
                };
                hex27::volume(&c.map(|n| mesh.nodes[n])) > 0.0
            }));
        }
    }
}
