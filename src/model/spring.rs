//! A spring-damper of the model: suspensions, rail pads, ballast.

use serde::{Deserialize, Serialize};

/// A linear spring-damper between two nodes, or between a node and the ground, acting on each
/// Cartesian component separately: `f = k (u_b - u_a) + c (v_b - v_a)` on node a (opposite on b).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spring {
    /// Name (for reports and errors).
    pub name: String,
    /// First node.
    pub node_a: usize,
    /// Second node; `None` = ground.
    pub node_b: Option<usize>,
    /// Stiffness per component x, y, z (N/m).
    pub stiffness_n_per_m: [f64; 3],
    /// Viscous damping per component (N s/m).
    pub damping_n_s_per_m: [f64; 3],
}
