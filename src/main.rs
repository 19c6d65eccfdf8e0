//! The `squeal` command: parse, call the library, print. No numerics here.
use clap::{Parser, Subcommand};

mod cli;

#[derive(Parser)]
#[command(name = "squeal", version, about = "Railway wheel squeal toolkit", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Kalker's rolling contact theory: Hertz, creep forces, force-prescribed creepages.
    Kalker(cli::kalker::KalkerArgs),
}

fn main() {
    let cli = Cli::parse();
    let result: squeal::Result<()> = match cli.command {
        Some(Command::Kalker(args)) => cli::kalker::run(args),
        None => Ok(()),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
