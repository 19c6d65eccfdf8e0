//! Mesh quality: corner Jacobians, edge lengths, aspect ratio and the explicit critical time
//! step `dt = L_min / c_L` (Courant limit of the central-difference scheme for a dilatational
//! wave, with L the characteristic length V / A_max of each element).

use rayon::prelude::*;
use serde::Serialize;

use super::{hex, Mesh};

/// The fraction of the critical step an explicit run takes (Yang & Li 2019: dt = 0.9 x the
/// critical step): the margin for the step estimate (element transit `L / c`, springs, contact)
/// being an estimate.
pub const COURANT_FACTOR: f64 = 0.9;

/// Summary of a mesh's quality.
#[derive(Clone, Debug, Serialize)]
pub struct QualityReport {
    /// Nodes.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Elements with a non-positive corner Jacobian.
    pub inverted_elements: usize,
    /// First inverted element, if any.
    pub first_inverted_element: Option<usize>,
    /// Smallest scaled corner Jacobian (1 = perfect cube).
    pub min_scaled_jacobian: f64,
    /// Shortest edge (m).
    pub min_edge_m: f64,
    /// Longest edge (m).
    pub max_edge_m: f64,
    /// Largest ratio longest/shortest edge in one element.
    pub max_aspect_ratio: f64,
    /// Smallest characteristic length V / A_max (m).
    pub min_characteristic_length_m: f64,
    /// Element with the smallest characteristic length.
    pub min_characteristic_length_element: usize,
    /// Centroid of that element (m).
    pub min_characteristic_length_at_m: [f64; 3],
    /// Wave speed used for the time step (m/s).
    pub wave_speed_m_per_s: f64,
    /// Critical explicit time step L_min / c (s).
    pub critical_time_step_s: f64,
    /// Total volume (m^3).
    pub volume_m3: f64,
}

#[derive(Clone, Copy)]
struct ElementStats {
    min_scaled_jacobian: f64,
    min_edge: f64,
    max_edge: f64,
    aspect: f64,
    char_length: f64,
    volume: f64,
}

impl QualityReport {
    /// Evaluate all elements (in parallel; the reduction is order-independent).
    pub fn of(mesh: &Mesh, wave_speed_m_per_s: f64) -> Self {
        let stats: Vec<ElementStats> = (0..mesh.elements.len())
            .into_par_iter()
            .map(|e| {
                let x = mesh.element_coords(e);
                let (lo, hi) = hex::edge_range(&x);
                ElementStats {
                    min_scaled_jacobian: hex::min_scaled_jacobian(&x),
                    min_edge: lo,
                    max_edge: hi,
                    aspect: hi / lo.max(1e-300),
                    char_length: hex::characteristic_length(&x),
                    volume: hex::volume(&x),
                }
            })
            .collect();
        let mut r = QualityReport {
            nodes: mesh.nodes.len(),
            elements: mesh.elements.len(),
            inverted_elements: 0,
            first_inverted_element: None,
            min_scaled_jacobian: f64::INFINITY,
            min_edge_m: f64::INFINITY,
            max_edge_m: 0.0,
            max_aspect_ratio: 0.0,
            min_characteristic_length_m: f64::INFINITY,
            min_characteristic_length_element: 0,
            min_characteristic_length_at_m: [0.0; 3],
            wave_speed_m_per_s,
            critical_time_step_s: 0.0,
            volume_m3: 0.0,
        };
        for (e, s) in stats.iter().enumerate() {
            if s.min_scaled_jacobian <= 0.0 {
                r.inverted_elements += 1;
                r.first_inverted_element.get_or_insert(e);
            }
            r.min_scaled_jacobian = r.min_scaled_jacobian.min(s.min_scaled_jacobian);
            r.min_edge_m = r.min_edge_m.min(s.min_edge);
            r.max_edge_m = r.max_edge_m.max(s.max_edge);
            r.max_aspect_ratio = r.max_aspect_ratio.max(s.aspect);
            if s.char_length < r.min_characteristic_length_m {
                r.min_characteristic_length_m = s.char_length;
                r.min_characteristic_length_element = e;
            }
            r.volume_m3 += s.volume;
        }
        if !mesh.elements.is_empty() {
            let x = mesh.element_coords(r.min_characteristic_length_element);
            let mut c = [0.0; 3];
            for p in x {
                for d in 0..3 {
                    c[d] += p[d] / 8.0;
                }
            }
            r.min_characteristic_length_at_m = c;
        }
        r.critical_time_step_s = r.min_characteristic_length_m / wave_speed_m_per_s;
        r
    }

    /// Error if any element is inverted (the writers refuse such meshes).
    pub fn check_valid(&self) -> crate::Result<()> {
        match self.first_inverted_element {
            Some(e) => Err(crate::Error::Mesh(format!(
                "{} element(s) with a non-positive corner Jacobian (first: element {e}); refusing to write the mesh",
                self.inverted_elements
            ))),
            None => Ok(()),
        }
    }

    /// Human-readable summary.
    pub fn summary(&self) -> String {
        format!(
            "nodes {}, elements {}, inverted {}\n\
             min scaled Jacobian {:.3}, edges {:.3} .. {:.3} mm, max aspect ratio {:.1}\n\
             smallest characteristic length {:.3} mm (element {} at [{:.4}, {:.4}, {:.4}] m)\n\
             critical time step {:.1} ns (c = {:.0} m/s); explicit step 0.9 x = {:.1} ns\n\
             volume {:.6} m^3",
            self.nodes,
            self.elements,
            self.inverted_elements,
            self.min_scaled_jacobian,
            self.min_edge_m * 1e3,
            self.max_edge_m * 1e3,
            self.max_aspect_ratio,
            self.min_characteristic_length_m * 1e3,
            self.min_characteristic_length_element,
            self.min_characteristic_length_at_m[0],
            self.min_characteristic_length_at_m[1],
            self.min_characteristic_length_at_m[2],
            self.critical_time_step_s * 1e9,
            self.wave_speed_m_per_s,
            COURANT_FACTOR * self.critical_time_step_s * 1e9,
            self.volume_m3
        )
    }
}

/// Dilatational (P-wave) speed `c_L = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho))`
/// (docs/references.md, section 6).
pub fn dilatational_wave_speed(
    youngs_modulus_pa: f64,
    poisson_ratio: f64,
    density_kg_per_m3: f64,
) -> f64 {
    let nu = poisson_ratio;
    (youngs_modulus_pa * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * density_kg_per_m3)).sqrt()
}
