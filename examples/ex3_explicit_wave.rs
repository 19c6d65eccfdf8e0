//! Tutorial 3: a wave in the explicit engine.
//!
//! A steel bar 1 m long and 5 mm square, 400 one-point hexahedra, loaded by a step force at one
//! end: the central-difference engine carries the front at the bar speed `sqrt(E / rho)` =
//! 5172 m/s, and the far end's velocity doubles when it arrives (a free end reflects the wave).
//!
//!     cargo run --release --example ex3_explicit_wave

use std::collections::BTreeMap;

use squeal::explicit::element::{ElasticMaterial, Formulation};
use squeal::explicit::model::Model;
use squeal::explicit::{Curve, Solver};
use squeal::mesh::cuboid;

fn main() -> squeal::Result<()> {
    let steel = ElasticMaterial {
        density_kg_per_m3: 7850.0,
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    let (length_m, side_m, force_n) = (1.0, 0.005, 1000.0);
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, steel)].into_iter().collect();
    let mut model = Model::from_mesh(
        cuboid([400, 1, 1], [length_m, side_m, side_m], 1),
        &materials,
        Formulation::default(),
        "ex3",
    )?;
    model.add_load("x0", [force_n, 0.0, 0.0], Curve::constant(1.0))?;
    let far = model.node_set("x1")?;
    let mut solver = Solver::new(model, None)?;
    let c0 = (steel.youngs_modulus_pa / steel.density_kg_per_m3).sqrt();
    // The incident particle velocity F / (rho A c0); the far end crosses it when the front's
    // middle arrives.
    let v_incident = force_n / (steel.density_kg_per_m3 * side_m * side_m * c0);
    while solver.time_s < 2.0 * length_m / c0 {
        solver.step()?;
        let v = far.iter().map(|&n| solver.v[n][0]).sum::<f64>() / far.len() as f64;
        if v >= v_incident {
            let c = length_m / solver.time_s;
            println!(
                "front at the far end after {:.1} us: {c:.0} m/s against sqrt(E / rho) = {c0:.0} m/s \
                 ({:+.2} %), time step {:.0} ns",
                solver.time_s * 1e6,
                100.0 * (c / c0 - 1.0),
                solver.dt_s * 1e9
            );
            assert!((c / c0 - 1.0).abs() < 0.02);
            return Ok(());
        }
    }
    Err(squeal::Error::Numerical("the front did not arrive".into()))
}
