//! Tutorial 4: a rolling case on the tiny test model.
//!
//! `data/cases/case3-ci.json`: the half wheelset on 54E1 with the forward guide, the
//! driving torque and a smooth lateral motion, on coarse meshes, for 2 ms. It builds the model,
//! preloads it statically, rolls it and writes a run directory: `histories.csv`,
//! `contact_forces.csv`, a patch snapshot, `run.json` (where the contact sits, the flange
//! clearance, the invariants). The demo cases run the same code on finer meshes for 40 ms
//! (`squeal simulate --case data/cases/case3-demo.json --out out/case3`).
//!
//!     cargo run --release --example ex4_tiny_rolling [OUT_DIR]

use squeal::rolling::{load_case, simulate, SimulateOptions};

fn main() -> squeal::Result<()> {
    let out = std::env::args()
        .nth(1)
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("squeal-ex4"));
    let _ = std::fs::remove_dir_all(&out);
    let case = load_case(std::path::Path::new("data/cases/case3-ci.json"))?;
    let record = simulate(&case, &SimulateOptions::new(out.clone()))?;
    println!(
        "{}: {} elements, {} steps of {:.0} ns, status {}",
        record.case,
        record.model.elements,
        record.run.steps,
        record.model.time_step_s * 1e9,
        record.run.status
    );
    let forces = squeal::table::Table::read(&out.join("contact_forces.csv"))?;
    let last = |c: &str| {
        forces
            .column(c)
            .and_then(|v| v.last().copied())
            .unwrap_or(f64::NAN)
    };
    println!(
        "at {:.2} ms: normal {:.1} kN, longitudinal creep {:.1} kN, lateral creep {:.1} kN",
        last("time_s") * 1e3,
        last("normal_force_n") * 1e-3,
        last("longitudinal_creep_force_n") * 1e-3,
        last("lateral_creep_force_n") * 1e-3
    );
    if let Some(p) = &record.contact_point {
        println!(
            "contact at S = {:.1} mm on the wheel, y = {:.1} mm on the rail, {:.1} degrees; \
             flange clearance at least {:.1} mm",
            p.initial_wheel_s_mm,
            p.initial_rail_y_mm,
            p.initial_contact_angle_deg,
            p.smallest_flange_clearance_mm
        );
    }
    println!(
        "largest |f_T| / (mu f_N) at any node and step: {:.12}",
        record.largest_node_shear_over_bound
    );
    assert_eq!(record.run.status, "completed");
    println!("run directory: {}", out.display());
    Ok(())
}
