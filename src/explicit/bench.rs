//! Element-update throughput of the engine: a block of
//! about N one-point elements (linear elastic, physical hourglass control), clamped at one end
//! and set vibrating, stepped with a fixed number of rayon threads. The figure is the wall time
//! of whole steps (element loop, node update, constraints) per element and step.

use std::collections::BTreeMap;
use std::time::Instant;

use serde::Serialize;

use super::element::{ElasticMaterial, Formulation};
use super::model::Model;
use super::solver::Solver;
use crate::mesh::cuboid;
use crate::{Error, Result};

/// Result of a throughput measurement.
#[derive(Clone, Debug, Serialize)]
pub struct ThroughputReport {
    /// Elements.
    pub elements: usize,
    /// Nodes.
    pub nodes: usize,
    /// Threads.
    pub threads: usize,
    /// Steps timed.
    pub steps: usize,
    /// Wall time of the timed steps (s).
    pub seconds: f64,
    /// Nanoseconds per element and step.
    pub ns_per_element_step: f64,
    /// Of which the element loop alone (ns per element).
    pub element_loop_ns_per_element: f64,
    /// Bytes that must move per element-step at least: the element record once, plus the
    /// node data (displacement, velocity, force, mass and role) streamed once per node.
    pub bytes_per_element_step: f64,
    /// Implied memory traffic (GB/s) = bytes / time.
    pub gigabytes_per_second: f64,
}

/// Builds a block of about `elements` hexahedra (a cube of n^3 cells) and times `steps` steps
/// with `threads` threads.
pub fn element_throughput(
    elements: usize,
    threads: usize,
    steps: usize,
) -> Result<ThroughputReport> {
    if !(1000..=20_000_000).contains(&elements) {
        return Err(Error::input(
            "command line",
            "--elements",
            format!("must lie in 1000..=20000000 (got {elements})"),
        ));
    }
    if !(1..=256).contains(&threads) {
        return Err(Error::input(
            "command line",
            "--threads",
            format!("must lie in 1..=256 (got {threads})"),
        ));
    }
    let n = (elements as f64).cbrt().round().max(2.0) as usize;
    let mesh = cuboid(
        [n, n, n],
        [0.01 * n as f64, 0.01 * n as f64, 0.01 * n as f64],
        1,
    );
    let steel = ElasticMaterial {
        density_kg_per_m3: 7850.0,
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, steel)].into_iter().collect();
    let mut model = Model::from_mesh(mesh, &materials, Formulation::default(), "bench")?;
    model.fix_set("x0", [true, true, true])?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Numerical(format!("thread pool: {e}")))?;
    pool.install(|| {
        let mut solver = Solver::new(model, None)?;
        let len = 0.01 * n as f64;
        for i in 0..solver.u.len() {
            let x = solver.model.mesh.nodes[i];
            solver.v[i] = [0.0, 0.1 * (x[0] / len), 0.3 * (x[0] / len).powi(2)];
        }
        for _ in 0..5 {
            solver.step()?;
        }
        let start = Instant::now();
        for _ in 0..steps {
            solver.step()?;
        }
        let seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        for _ in 0..steps {
            solver.compute_internal_forces();
        }
        let element_seconds = start.elapsed().as_secs_f64();
        let n_el = solver.model.elements.len();
        let n_nodes = solver.u.len();
        let element_bytes = solver.element_bytes_per_step() as f64;
        // Per node per step: u (24 B read + write), v (24 + 24), f_int (24 zero + 24 read),
        // f_aux (24 zero + 24 read), mass and inverse mass (16), role (1).
        let node_bytes = 24.0 * 8.0 + 17.0;
        let bytes = element_bytes + node_bytes * n_nodes as f64 / n_el as f64;
        let ns = seconds * 1e9 / (steps as f64 * n_el as f64);
        Ok(ThroughputReport {
            elements: n_el,
            nodes: n_nodes,
            threads,
            steps,
            seconds,
            ns_per_element_step: ns,
            element_loop_ns_per_element: element_seconds * 1e9 / (steps as f64 * n_el as f64),
            bytes_per_element_step: bytes,
            gigabytes_per_second: bytes / ns,
        })
    })
}
