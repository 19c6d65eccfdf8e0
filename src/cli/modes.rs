//! `squeal modes`: wheel natural frequencies in a band (3D hex8, shift-invert Lanczos), mode
//! classification, modes.json / modes.csv / modes.vtu, optional hammer-test comparison and
//! Matrix Market export of K and M.

use std::collections::BTreeMap;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use squeal::fem::assembly::write_matrix_market;
use squeal::fem::{assemble, Constraints, ElasticMaterial, MassKind};
use squeal::geometry::wheel::WheelSpec;
use squeal::mesh::wheel::{wheel_mesh, WheelPlacement};
use squeal::mesh::{material, vtu};
use squeal::modal::classify::classify_modes;
use squeal::modal::{solve, ModalOptions};
use squeal::{Error, Result};

/// Which nodes are clamped.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Clamp {
    /// The hub bore (wheel without axle: the wheel seat).
    HubBore,
    /// Both axle end faces.
    AxleEnds,
    /// Free-free (six rigid modes).
    None,
}

/// Arguments of `squeal modes`.
#[derive(Args, Debug)]
pub struct ModesArgs {
    /// Wheel file, e.g. data/wheels/ns_intercity_920.json.
    #[arg(long)]
    pub wheel: PathBuf,
    /// Element size (mm), overriding the wheel file's mesh.element_size_mm.
    #[arg(long)]
    pub element_size_mm: Option<f64>,
    /// Upper band edge (Hz).
    #[arg(long, default_value_t = 10_000.0)]
    pub fmax_hz: f64,
    /// Boundary condition.
    #[arg(long, value_enum, default_value_t = Clamp::None)]
    pub clamp: Clamp,
    /// Hammer-test CSV to compare with (data/hammer/).
    #[arg(long)]
    pub hammer: Option<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "out/modes")]
    pub out: PathBuf,
    /// Write K.mtx and M.mtx (Matrix Market) to this directory.
    #[arg(long)]
    pub export_mtx: Option<PathBuf>,
}

/// Run `squeal modes`.
pub fn run(args: ModesArgs) -> Result<()> {
    if !(args.fmax_hz.is_finite() && args.fmax_hz > 0.0 && args.fmax_hz <= 1e6) {
        return Err(Error::input(
            "command line",
            "--fmax-hz",
            format!("{} is outside the allowed range (0, 1e6] Hz", args.fmax_hz),
        ));
    }
    // An unreadable wheel file is bad input (exit code 2), named with the option.
    let mut spec: WheelSpec = squeal::input::read_json(&args.wheel).map_err(|e| match e {
        Error::Io { path, source } => Error::input(
            path,
            "--wheel",
            format!("cannot read the wheel file ({source}); expected a JSON file like data/wheels/ns_intercity_920.json"),
        ),
        other => other,
    })?;
    if let Some(h) = args.element_size_mm {
        if !(h.is_finite() && (2.0..=200.0).contains(&h)) {
            return Err(Error::input(
                "command line",
                "--element-size-mm",
                format!("{h} is outside the allowed range [2, 200] mm"),
            ));
        }
        spec.mesh.element_size_mm = h;
    }
    spec.validate(&args.wheel.display().to_string())?;
    let started = std::time::Instant::now();
    let mut mesh = wheel_mesh(&spec, None, &WheelPlacement::default());
    // Exact rigid modes through the tied web zones (see `Mesh::snap_tie_slaves`).
    mesh.snap_tie_slaves();
    let steel = ElasticMaterial {
        youngs_modulus_pa: spec.material.youngs_modulus_pa,
        poisson_ratio: spec.material.poisson_ratio,
        density_kg_per_m3: spec.material.density_kg_per_m3,
    };
    let materials: BTreeMap<u32, ElasticMaterial> =
        [material::WHEEL, material::AXLE, material::TREAD_BAND]
            .into_iter()
            .map(|id| (id, steel))
            .collect();
    let clamped_sets: Vec<String> = match args.clamp {
        Clamp::None => vec![],
        Clamp::HubBore => vec!["hub_bore".into()],
        Clamp::AxleEnds => vec!["axle_inner_end".into(), "axle_outer_end".into()],
    };
    let asm = assemble(
        &mesh,
        &materials,
        &Constraints {
            clamped_sets,
            ties: true,
        },
        MassKind::Consistent,
    )?;
    println!(
        "mesh: {} nodes, {} elements, {} dofs after constraints (assembled in {:.2} s)",
        mesh.node_count(),
        mesh.element_count(),
        asm.n_reduced,
        started.elapsed().as_secs_f64()
    );
    if let Some(dir) = &args.export_mtx {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        write_matrix_market(&asm.k, &dir.join("K.mtx"))?;
        write_matrix_market(&asm.m, &dir.join("M.mtx"))?;
        println!("wrote {}/K.mtx and M.mtx", dir.display());
    }
    let sol = solve(
        &asm.k,
        &asm.m,
        &ModalOptions {
            fmax_hz: args.fmax_hz,
            // Tie slaves are snapped onto their faces, so the free wheel's rigid modes are exact
            // (below 1e-2 Hz); its first flexible mode is hundreds of Hz.
            rigid_below_hz: 1.0,
            ..Default::default()
        },
    )?;
    println!(
        "solved: {} modes below {} Hz in {:.2} s (factorisation {:.2} s, Krylov basis {}, {} runs)",
        sol.modes.len(),
        args.fmax_hz,
        sol.solve_seconds,
        sol.factor_seconds,
        sol.basis_size,
        sol.runs
    );
    // wheel centre: the axis passes through the tape-circle centre (x = z = 0 by placement)
    let centre = WheelPlacement::default().tape_circle_centre_m;
    let shapes: Vec<(f64, f64, bool, Vec<[f64; 3]>)> = sol
        .modes
        .iter()
        .map(|m| (m.frequency_hz, m.residual, m.rigid, asm.expand(&m.vector)))
        .collect();
    let records = classify_modes(&mesh, centre, &shapes);
    std::fs::create_dir_all(&args.out).map_err(|e| Error::io(&args.out, e))?;
    let refs: Vec<_> = records.iter().map(|r| r.mode_ref()).collect();
    let json = serde_json::to_string_pretty(&refs).expect("serialisable");
    let p = args.out.join("modes.json");
    std::fs::write(&p, json).map_err(|e| Error::io(&p, e))?;
    let p = args.out.join("modes_detail.json");
    let json = serde_json::to_string_pretty(&records).expect("serialisable");
    std::fs::write(&p, json).map_err(|e| Error::io(&p, e))?;
    let mut csv = String::from(
        "index,frequency_hz,family,nodal_circles,nodal_diameters,residual,pair,rigid\n",
    );
    println!(
        "{:>4} {:>10} {:>16} {:>6} {:>10} {:>5}",
        "#", "f (Hz)", "family", "(m,n)", "residual", "pair"
    );
    for r in &records {
        let fam = serde_json::to_value(r.family)
            .expect("family")
            .as_str()
            .unwrap_or("")
            .to_string();
        csv.push_str(&format!(
            "{},{:.6},{},{},{},{:.3e},{},{}\n",
            r.index,
            r.frequency_hz,
            fam,
            r.nodal_circles,
            r.nodal_diameters,
            r.residual,
            r.is_pair,
            r.rigid
        ));
        println!(
            "{:>4} {:>10.2} {:>16} {:>6} {:>10.2e} {:>5}",
            r.index,
            r.frequency_hz,
            fam,
            format!("({},{})", r.nodal_circles, r.nodal_diameters),
            r.residual,
            if r.is_pair { "yes" } else { "" }
        );
    }
    let p = args.out.join("modes.csv");
    std::fs::write(&p, csv).map_err(|e| Error::io(&p, e))?;
    let names: Vec<String> = sol
        .modes
        .iter()
        .enumerate()
        .map(|(i, m)| format!("mode_{:03}_{:.1}Hz", i, m.frequency_hz))
        .collect();
    let fields: Vec<vtu::PointVectorField> = shapes
        .iter()
        .zip(&names)
        .map(|(s, name)| vtu::PointVectorField {
            name: name.clone(),
            values: &s.3,
        })
        .collect();
    vtu::write(&mesh, &args.out.join("modes.vtu"), &fields)?;
    if let Some(h) = &args.hammer {
        let measured = squeal::hammer::read_hammer_csv(h)?;
        let cmp = squeal::hammer::compare(&measured, &refs);
        let p = args.out.join("comparison.md");
        std::fs::write(&p, cmp.to_markdown()).map_err(|e| Error::io(&p, e))?;
        let p = args.out.join("comparison.csv");
        std::fs::write(&p, cmp.to_csv()).map_err(|e| Error::io(&p, e))?;
        squeal::hammer::write_modal_chart(
            &refs,
            Some(&measured),
            Some(&args.out.join("modal_chart.png")),
            Some(&args.out.join("modal_chart.svg")),
        )?;
        println!("{}", cmp.to_markdown());
    }
    println!("wrote {}", args.out.display());
    Ok(())
}
