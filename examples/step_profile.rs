//! Splits the time of one rolling step (no preload, model as built) into the element forces,
//! the contact forces and the rest, to find where a demo run spends its time.
//! `RAYON_NUM_THREADS=1 cargo run --release --example step_profile -- data/scenarios/case3-demo.json 300`
use std::time::Instant;

use squeal::explicit::solver::AuxForces;
use squeal::rolling::{build, case::load_case};

fn main() -> squeal::Result<()> {
    if std::env::var("IN_POOL").is_ok() {
        // Run the whole loop on a pool worker: parallel regions then start without waking the
        // main thread's partner.
        rayon::scope(|_| run())
    } else {
        run()
    }
}

fn run() -> squeal::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let loaded = load_case(std::path::Path::new(&args[1]))?;
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300);
    let mut m = build(&loaded)?;
    let n = m.solver.u.len();
    println!(
        "nodes {n} elements {} colours/blocks {:?} dt {:.3e} s threads {}",
        m.solver.model.elements.len(),
        m.solver.colour_summary(),
        m.solver.dt_s,
        rayon::current_num_threads()
    );
    println!(
        "contact: {} slaves, {} capped at m/dt^2, largest penalty scale {:.3}, initial gap {:.2} um",
        m.info.contact_slaves,
        m.info.contact_slaves_with_capped_penalty,
        m.info.largest_penalty_scale,
        m.info.initial_gap_m * 1e6
    );
    if args.get(3).map(|s| s == "setup-only") == Some(true) {
        return Ok(());
    }
    // Warm up: a few full steps so the wheel touches the rail.
    for _ in 0..50 {
        m.solver.step_with(&mut m.contact, false, false)?;
    }
    if args.get(3).map(|s| s == "full-only") == Some(true) {
        for _ in 0..steps {
            m.solver.step_with(&mut m.contact, false, false)?;
        }
        return Ok(());
    }
    let t0 = Instant::now();
    for _ in 0..steps {
        m.solver.compute_internal_forces();
    }
    let elem = t0.elapsed().as_secs_f64() / steps as f64;
    let mut f = vec![[0.0; 3]; n];
    let t0 = Instant::now();
    for _ in 0..steps {
        let (t, dt) = (m.solver.time_s, m.solver.dt_s);
        m.contact
            .add_forces(t, dt, &m.solver.u, &m.solver.v, &mut f);
    }
    let contact = t0.elapsed().as_secs_f64() / steps as f64;
    let t0 = Instant::now();
    for _ in 0..steps {
        m.solver.step_with(&mut m.contact, false, false)?;
    }
    let full = t0.elapsed().as_secs_f64() / steps as f64;
    println!(
        "per step: full {:.3} ms, elements {:.3} ms ({:.0} ns/element), contact {:.3} ms, rest {:.3} ms",
        full * 1e3,
        elem * 1e3,
        elem * 1e9 / m.solver.model.elements.len() as f64,
        contact * 1e3,
        (full - elem - contact) * 1e3
    );
    Ok(())
}
