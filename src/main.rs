//! The `squeal` command: parse, call the library, print. No numerics here.
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

mod cli;

#[derive(Parser)]
#[command(name = "squeal", version, about = "Railway wheel squeal toolkit", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Build the wheel or the whole model mesh; print quality; write VTU / Gmsh MSH 4.1.
    Mesh(cli::mesh::MeshArgs),
    /// Dominant peaks of a run's wheel vibration and the wheel modes that explain them.
    Identify(cli::identify::IdentifyArgs),
    /// Exit 0 only if the required modes are identified among the dominant peaks (for CI).
    CheckModes(cli::identify::CheckModesArgs),
    /// Wavelet-ridge growth rates of wheel vibration in the bands of chosen modes.
    Growth(cli::growth::GrowthArgs),
    /// Report (markdown + HTML, charts, tables, WAV) over run directories.
    Report(cli::report::ReportArgs),
    /// Standard profiles (S1002 wheel, 54E1 rail) as point tables.
    Profile(cli::profile::ProfileArgs),
    /// Welch power spectral density and dominant peaks of a column of a run or CSV file.
    Psd(cli::signal::PsdArgs),
    /// Morlet wavelet power (time x frequency) of a column, with the cone of influence.
    Cwt(cli::signal::CwtArgs),
    /// A column as a mono 16-bit WAV file (resampled, peak at 0.9 full scale).
    Wav(cli::signal::WavArgs),
    /// Kalker's rolling contact theory: Hertz, creep forces, force-prescribed creepages.
    Kalker(cli::kalker::KalkerArgs),
    /// Roll the wheel on the track: one rolling-contact case (or the five) into a run directory.
    Simulate(cli::simulate::SimulateArgs),
    /// Wheel modes by the axisymmetric (Fourier-harmonic) solver: modes.json / modes.csv.
    Axisym(cli::axisym::AxisymArgs),
    /// Wheel natural frequencies and mode shapes (3D FE), classified; hammer-test comparison.
    Modes(cli::modes::ModesArgs),
    /// Benchmarks that print the figures of docs/performance.md.
    Bench(cli::bench::BenchArgs),
    /// Squeal stability: complex eigenvalues of the wheel-rail system at an operating point.
    Stability(cli::stability::StabilityArgs),
    /// Hammer-test modal analysis: frequencies, damping and shapes from FRFs in a universal
    /// file (LSCF with a stabilisation diagram, or peak picking).
    Ema(cli::ema::EmaArgs),
}

/// Every option that takes a value accepts a negative number (`--density-kg-per-m3 -7850`),
/// so that the range check, not the parser, answers with the field and its allowed range.
fn negative_numbers_as_values(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(negative_numbers_as_values)
}

/// A closed pipe ends the program quietly, as it ends `cat` or `grep` (`squeal profile s1002
/// --csv - | head`): Rust ignores SIGPIPE, so `println!` would panic on the closed stdout
/// instead. Restoring the default action needs the C library's `signal` (POSIX.1).
#[cfg(unix)]
fn quiet_on_closed_pipe() {
    extern "C" {
        fn signal(signum: i32, handler: usize) -> usize;
    }
    const SIGPIPE: i32 = 13; // POSIX, on Linux and the BSDs
    const SIG_DFL: usize = 0;
    // SAFETY: resetting a signal to its default action, before any other thread exists.
    unsafe {
        signal(SIGPIPE, SIG_DFL);
    }
}

#[cfg(not(unix))]
fn quiet_on_closed_pipe() {}

fn main() {
    quiet_on_closed_pipe();
    cli::grammar::warn_deprecated(&std::env::args_os().collect::<Vec<_>>());
    let matches = negative_numbers_as_values(Cli::command()).get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let result: squeal::Result<()> = match cli.command {
        None => {
            cli::default_run::run(&std::path::Path::new(cli::grammar::REPORTS_ROOT).join("default"))
        }
        Some(Command::Mesh(args)) => cli::mesh::run(args),
        Some(Command::Profile(args)) => cli::profile::run(args),
        Some(Command::Identify(args)) => cli::identify::run_identify(args),
        Some(Command::Report(args)) => cli::report::run(args),
        Some(Command::Growth(args)) => cli::growth::run(args),
        Some(Command::CheckModes(args)) => match cli::identify::run_check_modes(args) {
            Ok(true) => Ok(()),
            Ok(false) => std::process::exit(1),
            Err(e) => Err(e),
        },
        Some(Command::Psd(args)) => cli::signal::run_psd(args),
        Some(Command::Cwt(args)) => cli::signal::run_cwt(args),
        Some(Command::Wav(args)) => cli::signal::run_wav(args),
        Some(Command::Kalker(args)) => cli::kalker::run(args),
        Some(Command::Modes(args)) => cli::modes::run(args),
        Some(Command::Bench(args)) => cli::bench::run(args),
        Some(Command::Simulate(args)) => cli::simulate::run(args),
        Some(Command::Axisym(args)) => cli::axisym::run(args),
        Some(Command::Stability(args)) => cli::stability::run(args),
        Some(Command::Ema(args)) => cli::ema::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
