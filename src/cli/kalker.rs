//! `squeal kalker`: Hertz, creepage-prescribed and force-prescribed rolling contact.
//!
//! `squeal kalker --normal-force-n 120e3 ...` without a subcommand is the previous release's
//! spelling of `squeal kalker solve ...`: still accepted, with a note.

use clap::{Args, Subcommand, ValueEnum};
use serde_json::json;
use squeal::kalker::rolling::{DEFAULT_GRID, DEFAULT_RAIL_CROWN_RADIUS_M, DEFAULT_WHEEL_RADIUS_M};
use squeal::kalker::{
    solve_force_prescribed, Creepages, HertzContact, Material, Method, RollingContactSolution,
    RollingSolver,
};
use squeal::output::{Commit, StagedDir};
use squeal::{Error, Result};
use std::path::PathBuf;

use super::grammar::{input_name, note, out_dir};

/// Arguments of `squeal kalker`.
#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, allow_negative_numbers = true)]
pub struct KalkerArgs {
    #[command(subcommand)]
    command: Option<KalkerCommand>,
    /// Force-prescribed mode when no subcommand is given.
    #[command(flatten)]
    solve: SolveArgs,
}

#[derive(Subcommand, Debug)]
enum KalkerCommand {
    /// Hertz contact patch for a wheel on a crowned rail.
    #[command(allow_negative_numbers = true)]
    Hertz(HertzArgs),
    /// Force-prescribed: find creepages xi, eta for given Fx, Fy (as CONTACT does).
    #[command(allow_negative_numbers = true)]
    Solve(SolveArgs),
    /// Creepage-prescribed: creep forces and traction for given xi, eta, phi.
    #[command(allow_negative_numbers = true)]
    Creep(CreepArgs),
    /// Compare an FE contact-patch snapshot (JSON) with Kalker: creepages from the FE forces,
    /// Kalker's adhesion/slip map beside the FE map, orientation angles.
    #[command(allow_negative_numbers = true)]
    Compare(CompareArgs),
}

#[derive(Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
struct CompareArgs {
    /// Snapshot JSON: {time_s, normal_force_n, force_x_n, force_y_n, mu,
    /// points: [{x_m, y_m, pressure_pa, slip}]}.
    #[arg(long)]
    snapshot: PathBuf,
    /// Wheel tape-circle lateral position (m) for S1002-on-54E1 curvatures (default: flat
    /// tread of --wheel-radius-m on a crown of --rail-radius-m).
    #[arg(long = "wheel-y-m", alias = "wheel-y", allow_hyphen_values = true)]
    wheel_y_m: Option<f64>,
    /// Wheel radius (m).
    #[arg(long = "wheel-radius-m", alias = "wheel-radius", default_value_t = DEFAULT_WHEEL_RADIUS_M, allow_hyphen_values = true)]
    wheel_radius_m: f64,
    /// Rail crown radius (m).
    #[arg(long = "rail-radius-m", alias = "rail-radius", default_value_t = DEFAULT_RAIL_CROWN_RADIUS_M, allow_hyphen_values = true)]
    rail_radius_m: f64,
    /// Spin creepage phi (1/m) of the FE contact, prescribed with its forces. Default: the
    /// snapshot's `normal_lateral_fraction` (sine of the contact angle) over --wheel-radius-m,
    /// or 0 when the snapshot has none.
    #[arg(long = "phi-per-m", alias = "phi", allow_hyphen_values = true)]
    phi_per_m: Option<f64>,
    /// Solve Kalker's exact problem on the undeformed gap of the S1002 and 54E1 profiles at
    /// --wheel-y-m (non-Hertzian, as CONTACT does) instead of a Hertz ellipse (needs
    /// --wheel-y-m and the exact method).
    #[arg(long)]
    profile_gap: bool,
    /// Theory.
    #[arg(long, value_enum, default_value_t = MethodArg::from(Method::default()))]
    method: MethodArg,
    /// Elements per axis.
    #[arg(long, default_value_t = DEFAULT_GRID)]
    grid: usize,
    /// Output folder (comparison.json, patch_fe.png/svg, patch_kalker.png/svg). Default:
    /// out/kalker/compare/<snapshot name>.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Contact geometry, load and material shared by all modes.
#[derive(Args, Debug, Clone)]
struct ContactArgs {
    /// Normal force Fn (N).
    #[arg(
        long = "normal-force-n",
        alias = "fn",
        value_name = "N",
        allow_hyphen_values = true
    )]
    normal_force_n: Option<f64>,
    /// Wheel rolling radius (m); flat tread assumed.
    #[arg(long = "wheel-radius-m", alias = "wheel-radius", default_value_t = DEFAULT_WHEEL_RADIUS_M, allow_hyphen_values = true)]
    wheel_radius_m: f64,
    /// Rail crown radius (m).
    #[arg(long = "rail-radius-m", alias = "rail-radius", default_value_t = DEFAULT_RAIL_CROWN_RADIUS_M, allow_hyphen_values = true)]
    rail_radius_m: f64,
    /// Lateral position (m) of the wheel's tape circle relative to the rail centre (crown top of
    /// the upright 54E1): the S1002 on 54E1 (1:40) contact point and its curvatures are used
    /// instead of --wheel-radius-m/--rail-radius-m (-0.0025 is a centred wheelset: tape
    /// circles 1500 mm apart on 1435 mm gauge).
    #[arg(long = "wheel-y-m", alias = "wheel-y", allow_hyphen_values = true)]
    wheel_y_m: Option<f64>,
    /// Young's modulus (Pa).
    #[arg(long = "youngs-modulus-pa", alias = "e", default_value_t = Material::STEEL.youngs_modulus_pa, allow_hyphen_values = true)]
    youngs_modulus_pa: f64,
    /// Poisson's ratio.
    #[arg(long = "poisson-ratio", alias = "nu", default_value_t = Material::STEEL.poisson_ratio, allow_hyphen_values = true)]
    poisson_ratio: f64,
}

#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
struct HertzArgs {
    #[command(flatten)]
    contact: ContactArgs,
    /// Also write the printed JSON to this file.
    #[arg(long, num_args = 0..=1)]
    json: Option<Option<PathBuf>>,
}

#[derive(Copy, Clone, Debug, ValueEnum)]
enum MethodArg {
    Exact,
    Fastsim,
}

impl From<Method> for MethodArg {
    fn from(method: Method) -> MethodArg {
        match method {
            Method::Exact => MethodArg::Exact,
            Method::Fastsim => MethodArg::Fastsim,
        }
    }
}

#[derive(Args, Debug, Clone)]
struct SolutionArgs {
    /// Friction coefficient.
    #[arg(long, allow_hyphen_values = true)]
    mu: Option<f64>,
    /// Spin creepage phi (1/m).
    #[arg(long = "phi-per-m", alias = "phi", default_value_t = Creepages::default().phi_per_m, allow_hyphen_values = true)]
    phi_per_m: f64,
    /// Theory: exact half-space (CONTACT-like) or FASTSIM.
    #[arg(long, value_enum, default_value_t = MethodArg::from(Method::default()))]
    method: MethodArg,
    /// Elements (exact) or points (FASTSIM) per axis.
    #[arg(long, default_value_t = DEFAULT_GRID)]
    grid: usize,
    /// Folder for the traction/slip map (traction.csv) and summary.json. Default:
    /// out/kalker/solve or out/kalker/creep.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
struct SolveArgs {
    #[command(flatten)]
    contact: ContactArgs,
    #[command(flatten)]
    solution: SolutionArgs,
    /// Longitudinal creep force Fx on the wheel (N).
    #[arg(long = "force-x-n", alias = "fx", allow_hyphen_values = true)]
    force_x_n: Option<f64>,
    /// Lateral creep force Fy on the wheel (N).
    #[arg(long = "force-y-n", alias = "fy", allow_hyphen_values = true)]
    force_y_n: Option<f64>,
}

#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
struct CreepArgs {
    #[command(flatten)]
    contact: ContactArgs,
    #[command(flatten)]
    solution: SolutionArgs,
    /// Longitudinal creepage xi (-).
    #[arg(long, default_value_t = Creepages::default().xi, allow_hyphen_values = true)]
    xi: f64,
    /// Lateral creepage eta (-).
    #[arg(long, default_value_t = Creepages::default().eta, allow_hyphen_values = true)]
    eta: f64,
}

/// Runs `squeal kalker`.
pub fn run(args: KalkerArgs) -> Result<()> {
    match args.command {
        Some(KalkerCommand::Hertz(hertz)) => run_hertz(hertz),
        Some(KalkerCommand::Solve(solve)) => run_solve(solve, "kalker/solve"),
        Some(KalkerCommand::Creep(creep)) => run_creep(creep),
        Some(KalkerCommand::Compare(compare)) => run_compare(compare),
        None => {
            note("squeal kalker OPTIONS", "squeal kalker solve OPTIONS");
            run_solve(args.solve, "kalker/solve")
        }
    }
}

fn required(value: Option<f64>, option: &str) -> Result<f64> {
    value.ok_or_else(|| Error::input("command line", option, "is required"))
}

fn hertz_of(contact: &ContactArgs) -> Result<HertzContact> {
    let normal_force_n = required(contact.normal_force_n, "--normal-force-n")?;
    squeal::kalker::validate_normal_force(normal_force_n, "command line")?;
    let material = Material::validated(
        contact.youngs_modulus_pa,
        contact.poisson_ratio,
        "command line",
    )?;
    if let Some(y) = contact.wheel_y_m {
        // S1002 on 54E1 at 1:40: curvatures at the first point of contact.
        let pc = squeal::kalker::profiles::s1002_on_54e1(y, contact.wheel_radius_m)?;
        eprintln!(
            "S1002 on 54E1 (1:40), tape circle at y = {y} m: contact at y = {:.4} m (S = {:.2} mm), curvatures A = {:.4}, B = {:.4} 1/m",
            pc.contact_y_m, pc.contact_s_mm, pc.curvature_x_per_m, pc.curvature_y_per_m
        );
        return HertzContact::from_curvatures(
            pc.curvature_x_per_m,
            pc.curvature_y_per_m,
            normal_force_n,
            material,
        );
    }
    HertzContact::wheel_on_rail(
        contact.wheel_radius_m,
        contact.rail_radius_m,
        normal_force_n,
        material,
    )
}

fn hertz_json(hertz: &HertzContact) -> serde_json::Value {
    json!({
        "normal_force_n": hertz.normal_force_n,
        "semi_axis_a_m": hertz.semi_axis_a_m,
        "semi_axis_b_m": hertz.semi_axis_b_m,
        "peak_pressure_pa": hertz.peak_pressure_pa,
        "approach_m": hertz.approach_m,
        "ellipticity": hertz.ellipticity,
    })
}

fn run_hertz(args: HertzArgs) -> Result<()> {
    let hertz = hertz_of(&args.contact)?;
    let text = serde_json::to_string_pretty(&hertz_json(&hertz)).unwrap_or_default();
    println!("{text}");
    match args.json {
        Some(Some(path)) => {
            super::mesh::write_json(&path, &hertz_json(&hertz))?;
            println!("wrote {}", path.display());
        }
        Some(None) => note(
            "--json (no value)",
            "nothing (the JSON is printed) or --json FILE",
        ),
        None => {}
    }
    Ok(())
}

fn solver_of(hertz: &HertzContact, solution: &SolutionArgs) -> Result<RollingSolver> {
    let mu = required(solution.mu, "--mu")?;
    squeal::kalker::validate_friction(mu, "command line")?;
    let method = match solution.method {
        MethodArg::Exact => Method::Exact,
        MethodArg::Fastsim => Method::Fastsim,
    };
    RollingSolver::new(hertz, mu, method, solution.grid)
}

fn run_solve(args: SolveArgs, command: &str) -> Result<()> {
    let hertz = hertz_of(&args.contact)?;
    let solver = solver_of(&hertz, &args.solution)?;
    let force_x_n = required(args.force_x_n, "--force-x-n")?;
    let force_y_n = required(args.force_y_n, "--force-y-n")?;
    let result = solve_force_prescribed(
        &solver,
        (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
        force_x_n,
        force_y_n,
        args.solution.phi_per_m,
    )?;
    let summary = json!({
        "mode": "force-prescribed",
        "method": solver.method().name(),
        "xi": result.creepages.xi,
        "eta": result.creepages.eta,
        "phi_per_m": result.creepages.phi_per_m,
        "unique": result.unique,
        "note": result.note,
        "force_x_n": result.solution.force_x_n,
        "force_y_n": result.solution.force_y_n,
        "normal_force_n": hertz.normal_force_n,
        "mu": solver.mu(),
        "adhesion_area_fraction": result.solution.adhesion_area_fraction(),
        "hertz": hertz_json(&hertz),
    });
    let out = out_dir(args.solution.out, command, "");
    finish(&summary, &result.solution, &out)
}

fn run_creep(args: CreepArgs) -> Result<()> {
    let hertz = hertz_of(&args.contact)?;
    let solver = solver_of(&hertz, &args.solution)?;
    let creepages = Creepages {
        xi: args.xi,
        eta: args.eta,
        phi_per_m: args.solution.phi_per_m,
    };
    let solution = solver.solve(&creepages)?;
    let summary = json!({
        "mode": "creepage-prescribed",
        "method": solver.method().name(),
        "xi": creepages.xi,
        "eta": creepages.eta,
        "phi_per_m": creepages.phi_per_m,
        "force_x_n": solution.force_x_n,
        "force_y_n": solution.force_y_n,
        "normal_force_n": hertz.normal_force_n,
        "mu": solver.mu(),
        "adhesion_area_fraction": solution.adhesion_area_fraction(),
        "hertz": hertz_json(&hertz),
    });
    let out = out_dir(args.solution.out, "kalker/creep", "");
    finish(&summary, &solution, &out)
}

/// Prints the summary and writes `traction.csv` and `summary.json` into `out`.
fn finish(
    summary: &serde_json::Value,
    solution: &RollingContactSolution,
    out: &std::path::Path,
) -> Result<()> {
    let text = serde_json::to_string_pretty(summary).unwrap_or_default();
    println!("{text}");
    {
        // Written beside the output folder and moved into it when complete.
        let stage = StagedDir::new(out)?;
        let directory = stage.path();
        let csv_path = directory.join("traction.csv");
        let mut writer = csv::Writer::from_path(&csv_path)
            .map_err(|e| Error::io(&csv_path, std::io::Error::other(e)))?;
        let csv_error = |e: csv::Error| Error::io(&csv_path, std::io::Error::other(e));
        writer
            .write_record(["x_m", "y_m", "pn_pa", "px_pa", "py_pa", "state"])
            .map_err(csv_error)?;
        for k in 0..solution.x_m.len() {
            writer
                .write_record([
                    format!("{:e}", solution.x_m[k]),
                    format!("{:e}", solution.y_m[k]),
                    format!("{:e}", solution.pressure_pa[k]),
                    format!("{:e}", solution.traction_x_pa[k]),
                    format!("{:e}", solution.traction_y_pa[k]),
                    solution.state[k].name().to_string(),
                ])
                .map_err(csv_error)?;
        }
        writer.flush().map_err(|e| Error::io(&csv_path, e))?;
        drop(writer);
        let summary_path = directory.join("summary.json");
        std::fs::write(&summary_path, text + "\n").map_err(|e| Error::io(&summary_path, e))?;
        stage.commit(Commit::Merge)?;
        println!("wrote {}", out.display());
    }
    Ok(())
}

fn run_compare(args: CompareArgs) -> Result<()> {
    squeal::output::protect_inputs([&args.snapshot]);
    use squeal::kalker::snapshot::{compare_snapshot, compare_snapshot_on_profiles, PatchSnapshot};
    let snapshot: PatchSnapshot = squeal::input::read_json(&args.snapshot)?;
    let source = args.snapshot.display().to_string();
    squeal::kalker::validate_normal_force_field(
        snapshot.normal_force_n,
        &source,
        "normal_force_n",
    )?;
    squeal::kalker::validate_friction_field(snapshot.mu, &source, "mu")?;
    squeal::kalker::snapshot::require_points(&snapshot, &source)?;
    let curvatures = match args.wheel_y_m {
        Some(y) => {
            let pc = squeal::kalker::profiles::s1002_on_54e1(y, args.wheel_radius_m)?;
            (pc.curvature_x_per_m, pc.curvature_y_per_m)
        }
        None => (0.5 / args.wheel_radius_m, 0.5 / args.rail_radius_m),
    };
    let material = Material::STEEL;
    let method = match args.method {
        MethodArg::Exact => Method::Exact,
        MethodArg::Fastsim => Method::Fastsim,
    };
    let (phi_per_m, phi_source) = match (args.phi_per_m, snapshot.normal_lateral_fraction) {
        (Some(phi), _) => (phi, "--phi-per-m"),
        (None, Some(sine)) => (sine / args.wheel_radius_m, "normal_lateral_fraction / R"),
        (None, None) => (0.0, "none (0)"),
    };
    if !phi_per_m.is_finite() {
        return Err(Error::input(
            &source,
            phi_source,
            format!("the spin creepage must be finite (got {phi_per_m})"),
        ));
    }
    let cmp = if args.profile_gap {
        let Some(wheel_y_m) = args.wheel_y_m else {
            return Err(Error::input(
                "command line",
                "--profile-gap",
                "needs --wheel-y-m (the tape circle's lateral position on the rail)",
            ));
        };
        if method != Method::Exact {
            return Err(Error::input(
                "command line",
                "--profile-gap",
                "needs --method exact (FASTSIM is Hertzian)",
            ));
        }
        compare_snapshot_on_profiles(
            &snapshot,
            wheel_y_m,
            args.wheel_radius_m,
            material,
            args.grid,
            phi_per_m,
        )?
    } else {
        compare_snapshot(
            &snapshot, curvatures, material, method, args.grid, phi_per_m,
        )?
    };
    let solution = &cmp.kalker.solution;
    let kalker_area_m2: f64 = (0..solution.x_m.len())
        .filter(|&k| solution.pressure_pa[k] > 0.0)
        .map(|k| solution.area_m2[k])
        .sum();
    let kalker_peak_pa = solution.pressure_pa.iter().copied().fold(0.0, f64::max);
    let fe_peak_pa = snapshot
        .points
        .iter()
        .map(|p| p.pressure_pa)
        .fold(0.0, f64::max);
    let out = out_dir(
        args.out.clone(),
        "kalker/compare",
        &input_name(&args.snapshot),
    );
    let stage = StagedDir::new(&out)?;
    squeal::report::kalker_charts::write_comparison_charts(&snapshot, &cmp, stage.path())?;
    let summary = json!({
        "time_s": snapshot.time_s,
        "xi": cmp.kalker.creepages.xi,
        "eta": cmp.kalker.creepages.eta,
        "phi_per_m": phi_per_m,
        "phi_source": phi_source,
        "kalker_geometry": if args.profile_gap { "profiles" } else { "hertz" },
        "kalker_contact_area_m2": kalker_area_m2,
        "kalker_peak_pressure_pa": kalker_peak_pa,
        "fe_contact_points": snapshot.points.iter().filter(|p| p.pressure_pa > 0.0).count(),
        "fe_peak_pressure_pa": fe_peak_pa,
        "unique": cmp.kalker.unique,
        "note": cmp.kalker.note,
        "fe_orientation_deg": cmp.fe_orientation_deg,
        "kalker_orientation_deg": cmp.kalker_orientation_deg,
        "fe_adhesion_fraction": cmp.fe_adhesion_fraction,
        "kalker_adhesion_fraction": cmp.kalker_adhesion_fraction,
    });
    let path = stage.path().join("comparison.json");
    std::fs::write(
        &path,
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )
    .map_err(|e| Error::io(&path, e))?;
    stage.commit(Commit::Merge)?;
    println!(
        "{}",
        serde_json::to_string_pretty(&summary).unwrap_or_default()
    );
    Ok(())
}
