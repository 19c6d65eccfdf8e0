//! `squeal simulate`: one rolling case, or the five, into run directories.

use std::path::PathBuf;

use clap::Args;
use squeal::model::case::{MultiRateMode, PreloadMethod};
use squeal::rolling::{load_case, simulate, SimulateOptions, StopFlag};
use squeal::{Error, Result};

use super::grammar::{input_name, out_dir};

/// The five cases of the paper (Yang & Li 2019) at a resolution: the case files
/// `data/cases/case1-<resolution>.json` .. `case5-<resolution>.json`.
pub fn all_cases(resolution: Resolution) -> Vec<String> {
    let tag = match resolution {
        Resolution::Demo => "demo",
        Resolution::Paper => "paper",
    };
    (1..=5)
        .map(|n| format!("data/cases/case{n}-{tag}.json"))
        .collect()
}

/// Mesh resolution of `--all-cases`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Resolution {
    /// Demo meshes (data/models/demo.json): a case in a few minutes on 2 cores.
    Demo,
    /// The paper's 1 mm contact zone (data/models/paper.json, 716 k elements): hours per
    /// case on 2 cores.
    Paper,
}

/// Arguments of `squeal simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// Case file, e.g. data/cases/case3-demo.json.
    #[arg(long, alias = "scenario", required_unless_present = "all_cases")]
    pub case: Option<PathBuf>,
    /// Run the five cases (data/cases/case1-<resolution>.json .. case5-...), each into
    /// OUT/<case name>/.
    #[arg(long, conflicts_with = "case")]
    pub all_cases: bool,
    /// Resolution of --all-cases: `demo` or `paper`.
    #[arg(long, value_enum, default_value = "demo", requires = "all_cases")]
    pub resolution: Resolution,
    /// Output folder: the run directory (with --all-cases, the parent of one per case).
    /// Default: out/simulate/<case name> (with --all-cases: out/simulate).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Resume from the checkpoint in the output directory.
    #[arg(long, conflicts_with = "overwrite")]
    pub resume: bool,
    /// Replace the run in a non-empty output directory (it is cleared first). Without it a
    /// non-empty output directory is refused.
    #[arg(long)]
    pub overwrite: bool,
    /// Stop at this simulated time instead of the case's end time (ms).
    #[arg(long)]
    pub end_time_ms: Option<f64>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Multi-rate (subcycled) stepping of the rolling run: elements at power-of-two multiples
    /// of the finest step by their own stable steps, the contact's nodes at the finest
    /// (docs/rolling.md). Without this or --single-rate the case's `time_stepping` decides
    /// (automatic by default: multi-rate where it saves enough element work).
    #[arg(long, conflicts_with = "single_rate")]
    pub multi_rate: bool,
    /// Single-rate stepping: every element at the smallest stable step (the reference).
    #[arg(long)]
    pub single_rate: bool,
    /// How to find the static preload, instead of the case's `preload.method`: `implicit`
    /// (Newton's method with a sparse Cholesky), `implicit-iterative` (Newton's method with
    /// conjugate gradients) or `dynamic-relaxation`.
    #[arg(long, value_enum)]
    pub preload: Option<PreloadChoice>,
}

/// `--preload` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum PreloadChoice {
    /// Newton's method on the static problem (docs/rolling.md, "Static preload").
    Implicit,
    /// Dynamic relaxation.
    DynamicRelaxation,
    /// Newton's method with conjugate gradients instead of a Cholesky factor (for models whose
    /// factor does not fit in memory).
    ImplicitIterative,
}

impl PreloadChoice {
    /// The library's method.
    pub fn method(self) -> PreloadMethod {
        match self {
            PreloadChoice::Implicit => PreloadMethod::Implicit,
            PreloadChoice::DynamicRelaxation => PreloadMethod::DynamicRelaxation,
            PreloadChoice::ImplicitIterative => PreloadMethod::ImplicitIterative,
        }
    }
}

/// A stop flag set by Ctrl-C, SIGTERM or SIGHUP: the first signal asks the run to stop at the
/// next step (it then writes a checkpoint and `status.json`, so `--resume` goes on), a second
/// one exits at once. Without a handler (it cannot be installed twice) the flag is never set.
fn stop_on_signal() -> StopFlag {
    let stop = StopFlag::new();
    let flag = stop.clone();
    let installed = ctrlc::set_handler(move || {
        if flag.is_requested() {
            eprintln!("\nsecond interrupt: exiting without a checkpoint");
            std::process::exit(130);
        }
        eprintln!(
            "\ninterrupt: stopping at the next step and writing a checkpoint \
             (interrupt again to exit at once)"
        );
        flag.request();
    });
    if let Err(e) = installed {
        eprintln!("warning: no Ctrl-C handler ({e}); an interrupt will lose the work since the last checkpoint");
    }
    stop
}

/// `--multi-rate` / `--single-rate` as an override of the case's `time_stepping.multi_rate`
/// (None: the case decides).
pub fn stepping_override(multi_rate: bool, single_rate: bool) -> Option<MultiRateMode> {
    match (multi_rate, single_rate) {
        (true, _) => Some(MultiRateMode::On),
        (_, true) => Some(MultiRateMode::Off),
        _ => None,
    }
}

/// Run `squeal simulate`.
pub fn run(args: SimulateArgs) -> Result<()> {
    let stop = stop_on_signal();
    let cases: Vec<(PathBuf, PathBuf)> = if args.all_cases {
        let parent = out_dir(args.out.clone(), "simulate", "");
        all_cases(args.resolution)
            .iter()
            .map(|c| {
                let p = PathBuf::from(c);
                let stem = p
                    .file_stem()
                    .map(|s| s.to_string_lossy().to_string())
                    .unwrap_or_default();
                (p, parent.join(stem))
            })
            .collect()
    } else {
        let p = args.case.clone().ok_or_else(|| {
            Error::input("command line", "--case", "give a case file or --all-cases")
        })?;
        let out = out_dir(args.out.clone(), "simulate", &input_name(&p));
        vec![(p, out)]
    };
    for (case_path, out) in cases {
        if !case_path.exists() {
            return Err(Error::input(
                case_path.display().to_string(),
                "--case",
                "file does not exist",
            ));
        }
        let loaded = load_case(&case_path)?;
        squeal::output::protect_inputs([
            case_path.clone(),
            PathBuf::from(&loaded.scenario.source_name),
        ]);
        let opts = SimulateOptions {
            out_dir: out.clone(),
            resume: args.resume,
            overwrite: args.overwrite,
            progress: !args.quiet,
            end_time_s: args.end_time_ms.map(|t| t * 1e-3),
            stop: stop.clone(),
            verify_contact_region: false,
            multi_rate: stepping_override(args.multi_rate, args.single_rate),
            preload_method: args.preload.map(PreloadChoice::method),
        };
        println!(
            "case {} ({}) -> {}",
            loaded.case.name,
            case_path.display(),
            out.display()
        );
        let record = simulate(&loaded, &opts)?;
        println!(
            "  {} elements, dt {:.1} ns ({}), {} steps in {:.1} s; status {}{}",
            record.model.elements,
            record.model.time_step_s * 1e9,
            record.model.time_step_limited_by,
            record.run.steps,
            record.run.wall_s,
            record.run.status,
            record
                .run
                .diagnosis
                .as_ref()
                .map(|d| format!(": {d}"))
                .unwrap_or_default()
        );
        println!("  time stepping: {}", record.model.time_stepping);
        if let Some(mu) = record.measured_traction_coefficient {
            println!("  measured traction coefficient (last quarter) {mu:.3}");
        }
        println!(
            "  over every contact node and step: |f_T| / (mu f_N) at most {:.12}, deepest \
             penetration {:.1} um",
            record.largest_node_shear_over_bound,
            record.deepest_penetration_m * 1e6
        );
        if record.longest_contact_loss_s > squeal::rolling::LIFT_OFF_LIMIT_S {
            return Err(Error::Numerical(format!(
                "case {}: the wheel lost contact with the rail for {:.1} ms (limit {:.1} ms): \
                 lift-off or derailment; output kept in {}",
                record.case,
                record.longest_contact_loss_s * 1e3,
                squeal::rolling::LIFT_OFF_LIMIT_S * 1e3,
                out.display()
            )));
        }
        if record.run.status == "interrupted" {
            return Err(Error::Interrupted(format!(
                "case {}: {}: `squeal simulate --case {} --out {} --resume`",
                record.case,
                record.run.diagnosis.unwrap_or_default(),
                case_path.display(),
                out.display()
            )));
        }
        if record.run.status != "completed" {
            return Err(Error::Numerical(format!(
                "case {} stopped: {}",
                record.case,
                record.run.diagnosis.unwrap_or_default()
            )));
        }
    }
    Ok(())
}
