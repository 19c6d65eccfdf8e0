//! Traces the rolling model's static preload: contact normal force, residual and the motion of
//! the wheel and sprung mass per chunk of relaxation steps.
//! `cargo run --release --example preload_debug -- data/scenarios/case3-demo.json 20000 450`
use squeal::explicit::preload::{relax, PreloadOptions};
use squeal::rolling::{build, case::load_case};

fn main() -> squeal::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let loaded = load_case(std::path::Path::new(&args[1]))?;
    let alpha: f64 = args
        .get(3)
        .and_then(|s| s.parse().ok())
        .unwrap_or(loaded.case.preload.damping_per_s);
    let total: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20_000);
    let mut m = build(&loaded)?;
    if let Some(dt) = loaded.case.preload.time_step_s {
        m.solver.set_inertia_scaling(&m.preload_added_mass_kg, dt)?;
    }
    m.contact.pair.friction = squeal::contact::FrictionLaw::Coulomb { mu: 0.0 };
    let chunk = 1000;
    let hub = m.contact.hub_nodes.clone();
    for k in 0..total / chunk {
        let r = relax(
            &mut m.solver,
            &mut m.contact,
            PreloadOptions {
                tolerance: 1e-9,
                max_steps: chunk,
                fixed_damping_per_s: Some(alpha),
                require_convergence: false,
                keep_velocities: true,
                ..Default::default()
            },
        )?;
        let n: f64 = m
            .contact
            .pair
            .state
            .iter()
            .filter(|s| s.active)
            .map(|s| s.normal_force_n)
            .sum();
        let hub_z: f64 = hub.iter().map(|&h| m.solver.u[h][2]).sum::<f64>() / hub.len() as f64;
        let hub_vz: f64 = hub.iter().map(|&h| m.solver.v[h][2]).sum::<f64>() / hub.len() as f64;
        let max_v = m
            .solver
            .v
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .enumerate()
            .fold((0, 0.0), |a, (i, x)| if x > a.1 { (i, x) } else { a });
        println!(
            "steps {:6} residual {:.3e} normal {:.1} kN hub_z {:.4} mm hub_vz {:.2e} sprung_z {:.4} mm max|v| {:.2e} at node {}",
            (k + 1) * chunk,
            r.relative_residual,
            n / 1e3,
            hub_z * 1e3,
            hub_vz,
            m.solver.u[m.sprung_node][2] * 1e3,
            max_v.1, max_v.0
        );
    }
    Ok(())
}
