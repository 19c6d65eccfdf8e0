//! Tutorial 2: a wheel-rail contact patch by Kalker's theory.
//!
//! A 0.46 m wheel with a flat tread on a rail crown of radius 0.3 m, 100 kN: the Hertz ellipse
//! (docs/references.md, section 5: 7.16 x 5.39 mm, 1238 MPa), the creep force of the exact
//! half-space solution for a longitudinal creepage of 0.1 %, and the creepage that gives a
//! prescribed force back (what CONTACT does with FE forces, and `squeal kalker compare`).
//!
//!     cargo run --release --example ex2_kalker_patch

use squeal::kalker::{
    solve_force_prescribed, Creepages, HertzContact, Material, Method, RollingSolver,
};

fn main() -> squeal::Result<()> {
    let normal_n = 100e3;
    let hertz = HertzContact::wheel_on_rail(0.46, 0.3, normal_n, Material::STEEL)?;
    println!(
        "Hertz: a {:.2} mm, b {:.2} mm, peak pressure {:.0} MPa",
        hertz.semi_axis_a_m * 1e3,
        hertz.semi_axis_b_m * 1e3,
        hertz.peak_pressure_pa * 1e-6
    );
    assert!((hertz.semi_axis_a_m * 1e3 - 7.16).abs() < 0.04);
    let mu = 0.45;
    let solver = RollingSolver::new(&hertz, mu, Method::Exact, 30)?;
    let creep = Creepages {
        xi: 1e-3,
        eta: 0.0,
        phi_per_m: 0.0,
    };
    let solution = solver.solve(&creep)?;
    println!(
        "exact half-space, xi 0.1 %: Fx {:.1} kN ({:.2} of mu Fn)",
        solution.force_x_n * 1e-3,
        solution.force_x_n.abs() / (mu * normal_n)
    );
    let back = solve_force_prescribed(
        &solver,
        (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
        solution.force_x_n,
        0.0,
        0.0,
    )?;
    println!(
        "force-prescribed: xi {:.4} %, eta {:.4} % (unique: {})",
        100.0 * back.creepages.xi,
        100.0 * back.creepages.eta,
        back.unique
    );
    assert!((back.creepages.xi - 1e-3).abs() < 1e-5);
    Ok(())
}
