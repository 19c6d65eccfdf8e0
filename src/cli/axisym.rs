//! `squeal axisym`: wheel modes by the axisymmetric (Fourier-harmonic) solver.
//!
//! `squeal axisym --wheel data/wheels/ns_intercity_920.json --harmonics 0..12 --fmax-hz 10000
//! --out out/axisym` (default folder: out/axisym/<wheel name>) writes `modes.json` (ModeRef-compatible entries plus harmonic, residual,
//! multiplicity, energy shares), `modes.csv` and `harmonics.json` (per-harmonic statistics),
//! and prints the mode table and the solve time.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use squeal::input::wheel::WheelSpec;
use squeal::modal::axisym::{self, AxisymModel, AxisymOptions, WheelClamp, WheelModelOptions};
use squeal::output::{Commit, StagedDir};
use squeal::{Error, Result};

use super::grammar::{input_name, out_dir};

/// Largest harmonic accepted on the command line (a 920 mm wheel has no mode below 10 kHz
/// beyond n ~ 12; 200 keeps typing errors from starting huge runs).
const MAX_HARMONIC: u32 = 200;

/// Clamp choice on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ClampArg {
    /// Free-free (rigid modes reported at n = 0 and 1).
    None,
    /// Hub bore held.
    HubBore,
    /// Both ends of the half axle held.
    AxleEnds,
}

/// Arguments of `squeal axisym`.
#[derive(Args, Debug)]
pub struct AxisymArgs {
    /// Wheel file, e.g. data/wheels/ns_intercity_920.json.
    #[arg(long)]
    pub wheel: PathBuf,
    /// Harmonics (nodal diameters) to solve: `A..B` (inclusive) or a single `N`.
    #[arg(long, default_value_t = default_harmonics())]
    pub harmonics: String,
    /// Upper frequency (Hz): all modes below it.
    #[arg(long, default_value_t = AxisymOptions::default().fmax_hz)]
    pub fmax_hz: f64,
    /// Section element size (mm), overriding the wheel file's mesh.element_size_mm.
    #[arg(long)]
    pub element_size_mm: Option<f64>,
    /// Leave the half axle out (the section ends at the hub bore).
    #[arg(long)]
    pub without_axle: bool,
    /// Clamped lines.
    #[arg(long, value_enum, default_value_t = ClampArg::of(WheelModelOptions::default().clamp))]
    pub clamp: ClampArg,
    /// Output folder for modes.json, modes.csv, harmonics.json and the modal chart. Default:
    /// out/axisym/<wheel name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Hammer test drawn solid beside the computed modes on the modal chart: a CSV of
    /// labelled modes (data/hammer/), or a universal file (.uff/.unv) whose modes (LSCF on its
    /// FRFs, or its mode shapes) are paired with the FE modes by frequency.
    #[arg(long)]
    pub hammer: Option<PathBuf>,
}

/// The library's default harmonics as `A..B`.
fn default_harmonics() -> String {
    let h = AxisymOptions::default().harmonics;
    match (h.first(), h.last()) {
        (Some(a), Some(b)) if a != b => format!("{a}..{b}"),
        (Some(a), _) => a.to_string(),
        _ => "0".to_string(),
    }
}

impl ClampArg {
    /// The command-line name of a clamp.
    fn of(clamp: WheelClamp) -> ClampArg {
        match clamp {
            WheelClamp::None => ClampArg::None,
            WheelClamp::HubBore => ClampArg::HubBore,
            WheelClamp::AxleEnds => ClampArg::AxleEnds,
        }
    }
}

/// Parse `A..B` (inclusive) or `N`.
pub fn parse_harmonics(text: &str) -> Result<Vec<u32>> {
    let bad = |why: String| Error::input("command line", "--harmonics", why);
    let num = |s: &str| -> Result<u32> {
        let v: u32 = s.trim().parse().map_err(|_| {
            bad(format!(
                "`{text}`: expected `A..B` or `N` with non-negative integers, got `{s}`"
            ))
        })?;
        if v > MAX_HARMONIC {
            return Err(bad(format!(
                "`{text}`: harmonics must be in 0..={MAX_HARMONIC}"
            )));
        }
        Ok(v)
    };
    let (a, b) = match text.split_once("..") {
        Some((a, b)) => (num(a)?, num(b.trim_start_matches('='))?),
        None => {
            let v = num(text)?;
            (v, v)
        }
    };
    if a > b {
        return Err(bad(format!(
            "`{text}`: the range is empty (start {a} > end {b})"
        )));
    }
    Ok((a..=b).collect())
}

/// Run `squeal axisym`.
pub fn run(args: AxisymArgs) -> Result<()> {
    squeal::output::protect_inputs(std::iter::once(&args.wheel).chain(&args.hammer));
    let harmonics = parse_harmonics(&args.harmonics)?;
    if !(args.fmax_hz.is_finite() && args.fmax_hz > 0.0 && args.fmax_hz <= 1e6) {
        return Err(Error::input(
            "command line",
            "--fmax-hz",
            format!("must be in (0, 1e6] Hz, got {}", args.fmax_hz),
        ));
    }
    let source = args.wheel.display().to_string();
    let mut spec: WheelSpec = squeal::input::read_json(&args.wheel)?;
    spec.validate(&source)?;
    if let Some(h) = args.element_size_mm {
        // 1 mm keeps the section below ~10^6 dofs; 50 mm is a few elements across the rim.
        if !(h.is_finite() && (1.0..=50.0).contains(&h)) {
            return Err(Error::input(
                "command line",
                "--element-size-mm",
                format!("must be in [1, 50] mm, got {h}"),
            ));
        }
        spec.mesh.element_size_mm = h;
    }
    let clamp = match args.clamp {
        ClampArg::None => WheelClamp::None,
        ClampArg::HubBore => WheelClamp::HubBore,
        ClampArg::AxleEnds => WheelClamp::AxleEnds,
    };
    let model = AxisymModel::from_wheel(
        &spec,
        WheelModelOptions {
            without_axle: args.without_axle,
            clamp,
        },
    )?;
    let res = axisym::solve(
        &model,
        &AxisymOptions {
            harmonics,
            fmax_hz: args.fmax_hz,
        },
    )?;
    if res.modes.is_empty() {
        return Err(Error::input(
            "command line",
            "--fmax-hz",
            format!(
                "no mode below {} Hz in harmonics {}: raise --fmax-hz or widen --harmonics",
                args.fmax_hz, args.harmonics
            ),
        ));
    }
    println!(
        "{}: section {} Q9 elements, {} nodes{}",
        spec.name,
        model.mesh.elements.len(),
        model.mesh.node_count(),
        if args.without_axle || spec.axle.is_none() {
            ", without axle"
        } else {
            ", with half axle"
        }
    );
    println!(
        "{:>5} {:>12} {:>16} {:>6} {:>3} {:>3} {:>10}",
        "index", "frequency_hz", "family", "label", "n", "m", "residual"
    );
    for (i, m) in res.modes.iter().enumerate() {
        println!(
            "{:>5} {:>12.2} {:>16} {:>6} {:>3} {:>3} {:>10.2e}",
            i,
            m.frequency_hz,
            family_name(m.family),
            m.mode_ref().label(),
            m.harmonic,
            m.nodal_circles,
            m.residual
        );
    }
    let zero_circle_axial: Vec<String> = (2..=4u32)
        .filter_map(|n| {
            res.modes
                .iter()
                .find(|m| {
                    m.harmonic == n
                        && m.nodal_circles == 0
                        && m.family == squeal::analysis::identify::ModeFamily::Axial
                })
                .map(|m| format!("(0,{n}) {:.1} Hz", m.frequency_hz))
        })
        .collect();
    if !zero_circle_axial.is_empty() {
        println!(
            "zero-nodal-circle axial modes: {}",
            zero_circle_axial.join(", ")
        );
    }
    let dofs: usize = res.harmonics.iter().map(|h| h.dofs).max().unwrap_or(0);
    println!(
        "solved {} harmonics ({} dofs each at most), {} modes below {} Hz in {:.3} s",
        res.harmonics.len(),
        dofs,
        res.modes.len(),
        args.fmax_hz,
        res.seconds
    );
    let dir = out_dir(args.out.clone(), "axisym", &input_name(&args.wheel));
    write_outputs(&dir, &res, args.hammer.as_deref(), args.fmax_hz)?;
    println!("wrote {}", dir.display());
    Ok(())
}

fn family_name(f: squeal::analysis::identify::ModeFamily) -> &'static str {
    use squeal::analysis::identify::ModeFamily::*;
    match f {
        Axial => "axial",
        Radial => "radial",
        Circumferential => "circumferential",
        Axle => "axle",
        Rigid => "rigid",
    }
}

/// modes.json, harmonics.json, modes.csv and the modal chart, written beside `out` and moved
/// into it when all are written.
fn write_outputs(
    out: &Path,
    res: &axisym::AxisymResult,
    hammer: Option<&Path>,
    fmax_hz: f64,
) -> Result<()> {
    let stage = StagedDir::new(out)?;
    let dir = stage.path();
    let refs: Vec<_> = res.modes.iter().map(|m| m.mode_ref()).collect();
    // The section's harmonic shapes are not sampled at test points: a universal file's modes
    // pair by frequency here (`squeal modes` pairs them by MAC).
    let measured = match hammer {
        Some(h) => Some(super::hammer::compare_hammer(h, &refs, None, fmax_hz, dir)?),
        None => None,
    };
    squeal::report::modal_chart::write_modal_chart(
        &refs,
        measured.as_deref(),
        Some(&dir.join("modal_chart.png")),
        Some(&dir.join("modal_chart.svg")),
    )?;
    squeal::modal::mode::write_modes_json(dir, &res.modes)?;
    let h_path = dir.join("harmonics.json");
    let text = serde_json::to_string_pretty(&res.harmonics)
        .map_err(|e| Error::Numerical(format!("encoding harmonics.json: {e}")))?;
    std::fs::write(&h_path, text).map_err(|e| Error::io(&h_path, e))?;
    let csv_path = dir.join("modes.csv");
    let mut f = std::io::BufWriter::new(
        std::fs::File::create(&csv_path).map_err(|e| Error::io(&csv_path, e))?,
    );
    let mut body =
        String::from("index,frequency_hz,family,nodal_circles,nodal_diameters,harmonic,residual\n");
    for (i, m) in res.modes.iter().enumerate() {
        body.push_str(&format!(
            "{},{:.6},{},{},{},{},{:.3e}\n",
            i,
            m.frequency_hz,
            family_name(m.family),
            m.nodal_circles,
            m.nodal_diameters,
            m.harmonic,
            m.residual
        ));
    }
    f.write_all(body.as_bytes())
        .and_then(|_| f.flush())
        .map_err(|e| Error::io(&csv_path, e))?;
    drop(f);
    stage.commit(Commit::Merge)?;
    Ok(())
}
