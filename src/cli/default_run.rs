//! `squeal` with no arguments: the main job on the embedded default scenario. Until the
//! simulation issues land it builds and reports the default meshes into reports/default/.

use std::fmt::Write as _;
use std::path::Path;

use squeal::mesh::quality::dilatational_wave_speed;
use squeal::mesh::wheel::{wheel_mesh, WheelPlacement};
use squeal::scenario::LoadedScenario;
use squeal::{Error, Result};

use super::mesh::{mass_kg, write_json, write_mesh};

/// Run the default job, writing into `out_dir`.
pub fn run(out_dir: &Path) -> Result<()> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let loaded = LoadedScenario::embedded_default()?;
    let steel = loaded.wheel.material;
    let c_l = dilatational_wave_speed(
        steel.youngs_modulus_pa,
        steel.poisson_ratio,
        steel.density_kg_per_m3,
    );
    println!(
        "scenario: {} ({})",
        loaded.scenario.name, loaded.source_name
    );

    let t = std::time::Instant::now();
    let wheel = wheel_mesh(&loaded.wheel, None, &WheelPlacement::default());
    let wheel_time = t.elapsed().as_secs_f64();
    let wheel_q = wheel.quality(c_l);
    let t = std::time::Instant::now();
    let model = loaded.model_mesh();
    let model_time = t.elapsed().as_secs_f64();
    let model_q = model.quality(c_l);
    wheel_q.check_valid()?;
    model_q.check_valid()?;
    write_mesh(&wheel, &out_dir.join("wheel.vtu"))?;
    write_mesh(&model, &out_dir.join("model.vtu"))?;
    write_json(&out_dir.join("wheel_quality.json"), &wheel_q)?;
    write_json(&out_dir.join("model_quality.json"), &model_q)?;

    use squeal::mesh::material;
    let wheel_mass = mass_kg(&wheel, &[material::WHEEL], steel.density_kg_per_m3);
    let axle_mass = mass_kg(&wheel, &[material::AXLE], steel.density_kg_per_m3);
    let mut md = String::new();
    let _ = writeln!(md, "# squeal default run: {}\n", loaded.scenario.name);
    let _ = writeln!(md, "{}\n", loaded.scenario.description);
    let _ = writeln!(
        md,
        "Coordinates: x along the track, y lateral (towards the field side), z up; wheel axis y.\n"
    );
    let _ = writeln!(
        md,
        "## Wheel `{}` (body mesh, no band)\n",
        loaded.wheel.name
    );
    let _ = writeln!(
        md,
        "- wheel mass {wheel_mass:.1} kg, half-axle mass {axle_mass:.1} kg"
    );
    let _ = writeln!(
        md,
        "- built in {wheel_time:.2} s\n\n```\n{}\n```\n",
        wheel_q.summary()
    );
    let _ = writeln!(md, "## Model (wheel with tread band + track)\n");
    let _ = writeln!(md, "- built in {model_time:.2} s");
    for t in &model.ties {
        let _ = writeln!(
            md,
            "- tied interface `{}`: {} slave nodes, largest offset {:.3} mm",
            t.name,
            t.pairs.len(),
            t.max_gap_m() * 1e3
        );
    }
    let _ = writeln!(md, "\n```\n{}\n```\n", model_q.summary());
    let _ = writeln!(md, "Files: `wheel.vtu`, `model.vtu` (open in ParaView; cell field `material`, point fields `set_<name>`), `*_quality.json`.");
    let index = out_dir.join("index.md");
    std::fs::write(&index, md).map_err(|e| Error::io(&index, e))?;
    println!("{}", model_q.summary());
    println!("report: {}", index.display());
    Ok(())
}
