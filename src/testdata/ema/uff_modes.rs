//! The modes of a test stored in a universal file, ready to compare with FE modes.
//!
//! A file with FRFs (datasets 58, function type 4) is analysed by LSCF ([`super::estimate`]);
//! a file with mode shapes only (datasets 55 of a modal analysis type) gives its modes as they
//! are. The test DOFs' positions come from the file's nodes (datasets 15 / 2411, in metres after
//! dataset 164's length factor); FE shapes are sampled there ([`sample_fe_shape`]) so that test
//! and FE modes can be paired by MAC.

use rustfft::num_complex::Complex;

use super::estimate::{estimate_lscf, LscfEstimate};
use super::frf::{FrfSet, TestDof};
use super::test_mode::{EstimationMethod, TestMode};
use crate::mesh::P3;
use crate::testdata::uff::dataset55::analysis_type;
use crate::testdata::uff::UffFile;
use crate::{Error, Result};

/// The modes of a test and where they were measured.
pub struct UffTest {
    /// The modes, by increasing frequency.
    pub modes: Vec<TestMode>,
    /// The DOFs of the shapes.
    pub dofs: Vec<TestDof>,
    /// Position of each DOF's node (m), when the file has every node.
    pub dof_positions_m: Option<Vec<P3>>,
    /// The LSCF analysis, when the modes came from FRFs.
    pub estimate: Option<LscfEstimate>,
    /// The FRFs, when the file has them.
    pub frf: Option<FrfSet>,
}

/// Default highest LSCF model order for a hammer test.
pub const DEFAULT_MAX_ORDER: usize = 40;

/// The test of `file` (named `name`) up to `fmax_hz` (see the module documentation).
pub fn test_from_uff(
    file: &UffFile,
    name: &str,
    fmax_hz: f64,
    max_order: usize,
) -> Result<UffTest> {
    let (modes, dofs, estimate, frf) = if file.functions.iter().any(|f| f.function_type == 4) {
        let set = FrfSet::from_uff(file, name)?;
        let first = set.frequency_hz[0];
        let last = set.frequency_hz[set.frequency_hz.len() - 1].min(fmax_hz);
        let estimate = estimate_lscf(&set, first, last, max_order)?;
        let modes = estimate.modes.clone();
        (modes, set.responses.clone(), Some(estimate), Some(set))
    } else {
        let (modes, dofs) = modes_of_datasets_55(file, name, fmax_hz)?;
        (modes, dofs, None, None)
    };
    let dof_positions_m = dofs
        .iter()
        .map(|d| file.node_position_m(d.node))
        .collect::<Option<Vec<P3>>>();
    Ok(UffTest {
        modes,
        dofs,
        dof_positions_m,
        estimate,
        frf,
    })
}

/// Modes read from datasets 55 of a modal analysis type (normal mode or complex eigenvalue),
/// with X, Y, Z translations per node; the DOFs are every node's three directions.
fn modes_of_datasets_55(
    file: &UffFile,
    name: &str,
    fmax_hz: f64,
) -> Result<(Vec<TestMode>, Vec<TestDof>)> {
    let modal: Vec<_> = file
        .nodal_data
        .iter()
        .filter(|d| {
            matches!(
                d.analysis_type,
                analysis_type::NORMAL_MODE
                    | analysis_type::COMPLEX_EIGENVALUE
                    | analysis_type::COMPLEX_EIGENVALUE_SECOND_ORDER
            ) && d.values_per_node >= 3
        })
        .collect();
    let Some(first) = modal.first() else {
        return Err(Error::input(
            name,
            "datasets",
            "neither FRFs (dataset 58, function type 4) nor mode shapes (dataset 55 of a modal \
             analysis with X, Y, Z values) to compare with",
        ));
    };
    let nodes: Vec<i64> = first.nodes.iter().map(|n| n.node).collect();
    let dofs: Vec<TestDof> = nodes
        .iter()
        .flat_map(|&node| (1..=3).map(move |direction| TestDof { node, direction }))
        .collect();
    let mut modes = Vec::new();
    for (k, d) in modal.iter().enumerate() {
        let labels: Vec<i64> = d.nodes.iter().map(|n| n.node).collect();
        if labels != nodes {
            return Err(Error::input(
                name,
                format!("mode shape {} (dataset 55)", k + 1),
                "its nodes differ from the first mode shape's: shapes are compared DOF by DOF",
            ));
        }
        let (Some(frequency_hz), Some(damping_ratio)) = (d.frequency_hz(), d.damping_ratio())
        else {
            continue;
        };
        if frequency_hz > fmax_hz {
            continue;
        }
        modes.push(TestMode {
            frequency_hz,
            damping_ratio,
            shape: d
                .nodes
                .iter()
                .flat_map(|n| n.values[..3].to_vec())
                .collect(),
            method: EstimationMethod::FromFile,
            stable_orders: 0,
        });
    }
    modes.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    Ok((modes, dofs))
}

/// An FE shape (`shape[node]`, a displacement per mesh node) sampled at test DOFs: each DOF
/// takes the component along its direction (sign included) at the mesh node nearest its
/// position. Rotational and scalar DOFs read 0.
pub fn sample_fe_shape(
    mesh_nodes_m: &[P3],
    shape: &[P3],
    dofs: &[TestDof],
    dof_positions_m: &[P3],
) -> Vec<Complex<f64>> {
    dofs.iter()
        .zip(dof_positions_m)
        .map(|(dof, p)| {
            let (nearest, _) = nearest_node(mesh_nodes_m, *p);
            let axis = dof.direction.unsigned_abs() as usize;
            let value = if (1..=3).contains(&axis) {
                shape[nearest][axis - 1] * dof.direction.signum() as f64
            } else {
                0.0
            };
            Complex::new(value, 0.0)
        })
        .collect()
}

/// Index of the mesh node nearest `p` and its distance (m); (0, infinity) for no nodes.
pub fn nearest_node(mesh_nodes_m: &[P3], p: P3) -> (usize, f64) {
    let distance2 = |q: &P3| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2);
    (0..mesh_nodes_m.len())
        .map(|k| (k, distance2(&mesh_nodes_m[k])))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or((0, f64::INFINITY), |(k, d2)| (k, d2.sqrt()))
}
