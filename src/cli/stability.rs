//! `squeal stability [RUN_DIR --time-ms T] --case CASE [--sweep eta=0..0.01:50] [--out DIR]`:
//! complex eigenvalues of the rolling wheel-rail system linearised at an operating point
//! (docs/stability.md).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use squeal::kalker::{solve_force_prescribed, HertzContact, Method, RollingSolver};
use squeal::model::case::load_case;
use squeal::report::stability_charts::{write_eigenvalue_map, write_stability_map};
use squeal::stability::contact::TangentialModel;
use squeal::stability::model::{Settings, StabilityModel, RAIL_TRUNCATION_FACTOR};
use squeal::stability::operating::{self, OperatingPoint, KALKER_ELEMENTS};
use squeal::stability::output::StabilityReport;
use squeal::stability::sweep::{parse_sweep, run_sweep};
use squeal::stability::wheel::{check_fmax, WheelDamping};
use squeal::{Error, Result};

use super::grammar::{input_name, note, out_dir};

/// The tangential contact law.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ContactLaw {
    /// Kalker's exact half-space theory (creep-force derivatives by central differences).
    Exact,
    /// Kalker's FASTSIM.
    Fastsim,
    /// Saturated Coulomb friction (full sliding).
    Coulomb,
}

/// Arguments of `squeal stability`.
#[derive(Args, Debug)]
pub struct StabilityArgs {
    /// Rolling case file (wheel, track, speed, load, friction law), e.g.
    /// data/cases/case3-demo.json.
    #[arg(long)]
    pub case: PathBuf,
    /// Run directory of that case: take the operating point from its contact forces at
    /// --time-ms.
    #[arg(requires = "time_ms")]
    pub run_dir: Option<PathBuf>,
    /// Deprecated: RUN_DIR (positional).
    #[arg(long, hide = true, conflicts_with = "run_dir", requires = "time_ms")]
    pub run: Option<PathBuf>,
    /// Time in the run (ms).
    #[arg(long, allow_negative_numbers = true)]
    pub time_ms: Option<f64>,
    /// Sweep one parameter: NAME=FROM..TO:POINTS, NAME one of eta, xi, mu,
    /// friction-slope-s-per-m, contact-s-mm.
    #[arg(long)]
    pub sweep: Option<String>,
    /// Wheel modes (and reported eigenvalues) up to this frequency (Hz), at most 10000.
    #[arg(long, default_value_t = Settings::default().fmax_hz)]
    pub fmax_hz: f64,
    /// Override the normal force (N).
    #[arg(long = "normal-force-n", alias = "fn", allow_negative_numbers = true)]
    pub normal_force_n: Option<f64>,
    /// Prescribe the creep forces Fx, Fy (N, both): the creepages then come from Kalker's
    /// exact theory (as CONTACT does).
    #[arg(
        long = "force-x-n",
        alias = "fx",
        requires = "force_y_n",
        allow_negative_numbers = true
    )]
    pub force_x_n: Option<f64>,
    /// See --force-x-n.
    #[arg(
        long = "force-y-n",
        alias = "fy",
        requires = "force_x_n",
        allow_negative_numbers = true
    )]
    pub force_y_n: Option<f64>,
    /// Lateral creepage of a case-file operating point (default 0.0018, signed as the lateral
    /// motion), or an override of the run's.
    #[arg(long, allow_negative_numbers = true)]
    pub eta: Option<f64>,
    /// Override the longitudinal creepage.
    #[arg(long, allow_negative_numbers = true)]
    pub xi: Option<f64>,
    /// Override the friction coefficient.
    #[arg(long, allow_negative_numbers = true)]
    pub mu: Option<f64>,
    /// Override the falling-friction slope dmu/dv (s/m; negative for falling friction).
    #[arg(
        long = "friction-slope-s-per-m",
        alias = "friction-slope",
        allow_negative_numbers = true
    )]
    pub friction_slope_s_per_m: Option<f64>,
    /// Override the contact position on the wheel tread (profile coordinate S, mm).
    #[arg(long, allow_negative_numbers = true)]
    pub contact_s_mm: Option<f64>,
    /// Tangential contact law.
    #[arg(long, value_enum, default_value_t = ContactLaw::of(Settings::default().tangential))]
    pub contact_law: ContactLaw,
    /// Elements (points) per axis of the Kalker solutions of the linearisation.
    #[arg(long, default_value_t = default_kalker_elements())]
    pub kalker_elements: usize,
    /// Split the wheel's n-diameter pairs by its rotation (omega +- n Omega).
    #[arg(long)]
    pub rotation: bool,
    /// Modal loss factor of wheel modes with n >= 2 nodal diameters.
    #[arg(long, default_value_t = WheelDamping::default().loss_factor_n2_plus)]
    pub loss_n2: f64,
    /// Modal loss factor of wheel modes with n = 1.
    #[arg(long, default_value_t = WheelDamping::default().loss_factor_n1)]
    pub loss_n1: f64,
    /// Modal loss factor of wheel modes with n = 0.
    #[arg(long, default_value_t = WheelDamping::default().loss_factor_n0)]
    pub loss_n0: f64,
    /// Modal loss factor of axle-family modes.
    #[arg(long, default_value_t = WheelDamping::default().loss_factor_axle)]
    pub loss_axle: f64,
    /// Output folder (stability.json, stability.csv, charts). Default: out/stability/<case
    /// name>, or out/stability/<run name>-<T>ms with a run.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

impl ContactLaw {
    /// The law of a tangential model.
    fn of(model: TangentialModel) -> ContactLaw {
        match model {
            TangentialModel::Kalker {
                method: Method::Exact,
                ..
            } => ContactLaw::Exact,
            TangentialModel::Kalker {
                method: Method::Fastsim,
                ..
            } => ContactLaw::Fastsim,
            TangentialModel::Coulomb | TangentialModel::Frictionless => ContactLaw::Coulomb,
        }
    }
}

/// The library's Kalker elements per axis of the linearisation.
fn default_kalker_elements() -> usize {
    match Settings::default().tangential {
        TangentialModel::Kalker { elements, .. } => elements,
        TangentialModel::Coulomb | TangentialModel::Frictionless => KALKER_ELEMENTS,
    }
}

/// The settings of the arguments (checked).
fn settings(args: &StabilityArgs) -> Result<Settings> {
    check_fmax(args.fmax_hz, "--fmax-hz")?;
    let tangential = match args.contact_law {
        ContactLaw::Exact => TangentialModel::Kalker {
            method: Method::Exact,
            elements: args.kalker_elements,
        },
        ContactLaw::Fastsim => TangentialModel::Kalker {
            method: Method::Fastsim,
            elements: args.kalker_elements,
        },
        ContactLaw::Coulomb => TangentialModel::Coulomb,
    };
    let wheel_damping = WheelDamping {
        loss_factor_n2_plus: args.loss_n2,
        loss_factor_n1: args.loss_n1,
        loss_factor_n0: args.loss_n0,
        loss_factor_axle: args.loss_axle,
    };
    wheel_damping.check("command line")?;
    Ok(Settings {
        fmax_hz: args.fmax_hz,
        rail_truncation_factor: RAIL_TRUNCATION_FACTOR,
        wheel_damping,
        rotation: args.rotation,
        tangential,
    })
}

/// The ranges of the overrides that need no model, checked before the wheel's modes are solved.
fn check_overrides(args: &StabilityArgs) -> Result<()> {
    if let Some(f) = args.normal_force_n {
        if !(f.is_finite() && f > 0.0) {
            return Err(Error::input(
                "command line",
                "--normal-force-n",
                format!("the normal force must be > 0 N (the wheel pressed on the rail), got {f}"),
            ));
        }
    }
    if let Some(v) = args.mu {
        // The project's one friction-coefficient check; mu = 0 is allowed (no friction: the
        // second-method check of the undamped frequencies).
        squeal::friction::check_coefficient(v, "command line", "--mu", true)?;
    }
    Ok(())
}

/// The command-line overrides applied to an operating point.
fn apply_overrides(
    args: &StabilityArgs,
    model: &StabilityModel,
    law: &squeal::friction::FrictionLaw,
    op: &mut OperatingPoint,
) -> Result<()> {
    if let Some(f) = args.normal_force_n {
        op.normal_force_n = f;
    }
    if let Some(v) = args.mu {
        op.mu = v;
    }
    if let Some(v) = args.xi {
        op.creepages.xi = v;
    }
    if let Some(v) = args.eta {
        op.creepages.eta = v;
    }
    // A creepage override moves the slip speed: the friction law gives mu and its slope there
    // (unless they are overridden too), as the operating point's own fixed point does.
    if (args.xi.is_some() || args.eta.is_some()) && args.mu.is_none() {
        let slip_m_per_s = op.speed_m_per_s * op.creepages.xi.hypot(op.creepages.eta);
        (op.mu, op.friction_slope_s_per_m) = operating::friction_at(law, slip_m_per_s);
    }
    if let Some(v) = args.friction_slope_s_per_m {
        op.friction_slope_s_per_m = v;
    }
    if let Some(v) = args.contact_s_mm {
        op.contact_s_mm = v;
    }
    if let (Some(fx), Some(fy)) = (args.force_x_n, args.force_y_n) {
        let bound = op.mu * op.normal_force_n;
        if fx.hypot(fy) > bound {
            return Err(Error::input(
                "command line",
                "--force-x-n/--force-y-n",
                format!(
                    "the creep force {:.0} N exceeds mu Fn = {bound:.0} N (mu {}, Fn {:.0} N): outside the model, which needs |F| <= mu Fn",
                    fx.hypot(fy),
                    op.mu,
                    op.normal_force_n
                ),
            ));
        }
        let hertz = HertzContact::from_curvatures(
            op.curvature_per_m[0],
            op.curvature_per_m[1],
            op.normal_force_n,
            model.material,
        )?;
        let solver = RollingSolver::new(&hertz, op.mu, Method::Exact, KALKER_ELEMENTS)?;
        let r = solve_force_prescribed(
            &solver,
            (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
            fx,
            fy,
            op.creepages.phi_per_m,
        )?;
        op.creepages = r.creepages;
        op.creep_force_n = [fx, fy];
        op.kalker_note = r.note;
    }
    Ok(())
}

/// Run `squeal stability`.
pub fn run(args: StabilityArgs) -> Result<()> {
    squeal::output::protect_inputs(
        std::iter::once(&args.case)
            .chain(&args.run_dir)
            .chain(&args.run),
    );
    let settings = settings(&args)?;
    let sweep = args
        .sweep
        .as_deref()
        .map(|text| match text.strip_prefix("friction-slope=") {
            Some(range) => {
                note(
                    "--sweep friction-slope=...",
                    "--sweep friction-slope-s-per-m=...",
                );
                parse_sweep(&format!("friction-slope-s-per-m={range}"))
            }
            None => parse_sweep(text),
        })
        .transpose()?;
    check_overrides(&args)?;
    let run_dir = match (&args.run_dir, &args.run) {
        (Some(dir), _) => Some(dir.clone()),
        (None, Some(dir)) => {
            note("--run RUN_DIR", "RUN_DIR (positional)");
            Some(dir.clone())
        }
        (None, None) => None,
    };
    if args.time_ms.is_some() && run_dir.is_none() {
        return Err(Error::input(
            "command line",
            "--time-ms",
            "needs a run directory (RUN_DIR) to take the operating point from",
        ));
    }
    let loaded = load_case(&args.case)?;
    // The run's sample first: a time outside the run fails before the modes are solved.
    let sample = match (&run_dir, args.time_ms) {
        (Some(dir), Some(t)) => Some(operating::read_run_sample(&loaded, dir, t)?),
        _ => None,
    };
    let out = match (&run_dir, args.time_ms) {
        (Some(dir), Some(t)) => out_dir(
            args.out.clone(),
            "stability",
            &format!("{}-{t}ms", input_name(dir)),
        ),
        _ => out_dir(args.out.clone(), "stability", &input_name(&args.case)),
    };
    let t0 = std::time::Instant::now();
    let model = StabilityModel::build(&loaded, settings)?;
    let radius = model.wheel.nominal_radius_m;
    let mut op = match &sample {
        Some(sample) => operating::from_run_sample(&loaded, sample, radius, model.material)?,
        None => operating::from_case(
            &loaded,
            model.wheel.mass_kg,
            radius,
            args.eta,
            model.material,
        )?,
    };
    apply_overrides(&args, &model, &loaded.case.friction, &mut op)?;
    let (rail, rail_models) = model.rail(op.wheel_x_m, op.contact_rail_y_m)?;
    let wheel = model.wheel_body(&op)?;
    let point = model.analyse(&op, &wheel, &rail)?;
    let sweep = sweep
        .map(|s| run_sweep(&model, &op, &wheel, &rail, &s))
        .transpose()?;
    let report = StabilityReport::new(&model, &op, &rail_models, wheel.dofs.len(), point, sweep);
    print!("{}", report.summary());
    std::fs::create_dir_all(&out).map_err(|e| Error::io(&out, e))?;
    let write = |name: &str, text: String| -> Result<()> {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
    };
    write(
        "stability.json",
        serde_json::to_string_pretty(&report).map_err(|e| Error::Numerical(e.to_string()))?,
    )?;
    write("stability.csv", report.csv())?;
    write_eigenvalue_map(
        &report.point,
        Some(&out.join("eigenvalues.png")),
        Some(&out.join("eigenvalues.svg")),
    )?;
    if let Some(s) = &report.sweep {
        write_stability_map(
            s,
            Some(&out.join("stability_map.png")),
            Some(&out.join("stability_map.svg")),
        )?;
    }
    println!(
        "wrote {}/stability.{{json,csv}} and charts ({:.1} s in all)",
        out.display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
