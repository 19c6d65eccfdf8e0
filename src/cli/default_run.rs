//! `squeal` with no arguments: the main job on the embedded default scenario. It builds and
//! describes the default meshes (reports/default/model/), then runs the pipeline: wheel modes,
//! the default rolling case (paper case 3 on the demo meshes with 2 mm inserts over the paper's
//! patch snapshots, 40 ms, `data/cases/case3-demo-inserts.json`) and the report over it
//! (reports/default/index.html).

use std::fmt::Write as _;
use std::path::Path;

use squeal::mesh::quality::dilatational_wave_speed;
use squeal::mesh::wheel::{wheel_mesh, WheelPlacement};
use squeal::scenario::LoadedScenario;
use squeal::{Error, Result};

use super::mesh::{mass_kg, write_json, write_mesh};

/// Run the default job, writing into `out_dir`.
pub fn run(out_dir: &Path) -> Result<()> {
    let wall = std::time::Instant::now();
    write_model_page(&out_dir.join("model"))?;
    let case = squeal::rolling::embedded_default_case()?;
    println!(
        "default case: {} ({} ms simulated); progress below",
        case.case.name,
        case.case.end_time_s * 1e3
    );
    let summary = squeal::pipeline::run_pipeline(
        &case,
        &squeal::pipeline::PipelineOptions {
            out_dir: out_dir.to_path_buf(),
            end_time_s: None,
            progress: true,
        },
    )?;
    for (stage, s) in &summary.stage_wall_s {
        println!("  {stage}: {s:.1} s");
    }
    println!("sections: {}", summary.sections.join("; "));
    println!(
        "finished in {:.0} s; report: {}",
        wall.elapsed().as_secs_f64(),
        summary.report_html.display()
    );
    Ok(())
}

/// The model page: default meshes, their quality and section charts, into `out_dir`.
fn write_model_page(out_dir: &Path) -> Result<()> {
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

    write_section_charts(&loaded, out_dir)?;
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
    let _ = writeln!(md, "## Sections\n");
    let _ = writeln!(md, "![S1002 profile](s1002.png)\n\n![wheel section mesh](wheel_section.png) ![rail section mesh](rail_section.png)\n");
    let _ = writeln!(md, "Files: `wheel.vtu`, `model.vtu` (open in ParaView; cell field `material`, point fields `set_<name>`), `*_quality.json`, charts as PNG and SVG.");
    let index = out_dir.join("index.md");
    std::fs::write(&index, md).map_err(|e| Error::io(&index, e))?;
    println!("{}", model_q.summary());
    println!("report: {}", index.display());
    Ok(())
}

/// Charts of the S1002 profile and of the wheel and rail cross-section meshes.
fn write_section_charts(loaded: &LoadedScenario, out_dir: &Path) -> Result<()> {
    use squeal::geometry::s1002;
    use squeal::mesh::rail::{rail_section, RailSectionSizes};
    use squeal::mesh::wheel::mesh_section;
    use squeal::report::chart::{quad_mesh_series, write, LineChart, Series};

    let table = s1002::point_table(0.1);
    let profile = LineChart {
        title: "S1002 wheel profile (EN 13715)".into(),
        x_label: "lateral position S from the tape circle (mm)".into(),
        y_label: "radius increment F (mm)".into(),
        series: vec![Series::line(
            "S1002 (flange at S < 0)",
            table.iter().map(|p| p.0).collect(),
            table.iter().map(|p| p.1).collect(),
            0,
        )],
        ..Default::default()
    };
    write(
        &profile,
        Some(&out_dir.join("s1002.png")),
        Some(&out_dir.join("s1002.svg")),
    )?;

    let section = mesh_section(&loaded.wheel, loaded.scenario.tread_band.as_ref());
    let mut series = quad_mesh_series(&section.body.nodes, &section.body.quads, 0, "wheel body");
    if let Some(band) = &section.band {
        series.extend(quad_mesh_series(
            &band.nodes,
            &band.quads,
            1,
            "tread band (tied)",
        ));
    }
    let wheel = LineChart {
        title: format!("Wheel section mesh: {}", loaded.wheel.name),
        x_label: "S (mm)".into(),
        y_label: "radius (mm)".into(),
        series,
        x_range: Some((-150.0, 100.0)),
        y_range: Some((0.0, 500.0)),
        size_px: Some((620, 1180)),
        stroke_width: Some(1),
        ..Default::default()
    };
    write(
        &wheel,
        Some(&out_dir.join("wheel_section.png")),
        Some(&out_dir.join("wheel_section.svg")),
    )?;

    let t = &loaded.scenario.track.rail;
    let rail = rail_section(RailSectionSizes {
        running_surface_mm: t.running_surface_element_mm,
        body_mm: t.section_element_mm,
        band_rows_at_least: 1,
    });
    let mut series = quad_mesh_series(&rail.body.nodes, &rail.body.quads, 0, "rail body");
    if let Some(band) = &rail.band {
        series.extend(quad_mesh_series(
            &band.nodes,
            &band.quads,
            1,
            "running band (tied)",
        ));
    }
    let rail_chart = LineChart {
        title: "54E1 rail section mesh (upright)".into(),
        x_label: "y (mm)".into(),
        y_label: "z (mm)".into(),
        series,
        x_range: Some((-80.0, 80.0)),
        y_range: Some((-165.0, 10.0)),
        size_px: Some((900, 1000)),
        stroke_width: Some(1),
        ..Default::default()
    };
    write(
        &rail_chart,
        Some(&out_dir.join("rail_section.png")),
        Some(&out_dir.join("rail_section.svg")),
    )
}
