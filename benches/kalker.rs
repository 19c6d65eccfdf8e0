//! `cargo bench --bench kalker`: timing of the exact steady-rolling solver (60 x 60 elements) and
//! FASTSIM (100 x 100 points) on the reference contact of docs/references.md, section 5 (R 0.46 m on a R300 crown, 100 kN).
//! Plain `std::time::Instant` timing (harness = false): the median of several runs is printed.

use squeal::kalker::{Creepages, HertzContact, Material, Method, RollingSolver};
use std::time::Instant;

fn median_seconds(runs: usize, mut work: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            work();
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(|a, b| a.total_cmp(b));
    times[runs / 2]
}

fn main() {
    let hertz =
        HertzContact::wheel_on_rail(0.46, 0.3, 100e3, Material::STEEL).expect("reference contact");
    let mu = 0.3;
    let cases = [
        (
            "small creepage xi 1e-5",
            Creepages {
                xi: 1e-5,
                eta: 0.0,
                phi_per_m: 0.0,
            },
        ),
        (
            "mid-range xi 1e-3",
            Creepages {
                xi: 1e-3,
                eta: 0.0,
                phi_per_m: 0.0,
            },
        ),
        (
            "mid-range xi 1e-3 eta 1e-3 phi 0.5",
            Creepages {
                xi: 1e-3,
                eta: 1e-3,
                phi_per_m: 0.5,
            },
        ),
        (
            "full slip xi 1e-2",
            Creepages {
                xi: 1e-2,
                eta: 0.0,
                phi_per_m: 0.0,
            },
        ),
    ];

    let setup = median_seconds(3, || {
        RollingSolver::new(&hertz, mu, Method::Exact, 60).expect("exact setup");
    });
    println!(
        "exact 60 x 60: setup (normal problem + influence kernels): {:.3} s",
        setup
    );
    let exact = RollingSolver::new(&hertz, mu, Method::Exact, 60).expect("exact setup");
    for (name, creepages) in &cases {
        let seconds = median_seconds(3, || {
            exact.solve(creepages).expect("exact solve");
        });
        println!(
            "exact 60 x 60: tangential steady rolling, {name}: {seconds:.3} s (target < 0.5 s)"
        );
    }

    let fastsim = RollingSolver::new(&hertz, mu, Method::Fastsim, 100).expect("fastsim setup");
    for (name, creepages) in &cases {
        let seconds = median_seconds(21, || {
            fastsim.solve(creepages).expect("fastsim");
        });
        println!(
            "FASTSIM 100 x 100: {name}: {:.3} ms (target < 5 ms)",
            seconds * 1e3
        );
    }
}
