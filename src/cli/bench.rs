//! `squeal bench`: the performance figures the README quotes.

use clap::{Args, Subcommand};
use squeal::Result;

/// Arguments of `squeal bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
}

/// What to benchmark.
#[derive(Subcommand, Debug)]
pub enum BenchWhat {
    /// Explicit element-update throughput on a block; ends with `ns_per_element_step=<value>`.
    Explicit(ExplicitBenchArgs),
}

/// Arguments of `squeal bench explicit`.
#[derive(Args, Debug)]
pub struct ExplicitBenchArgs {
    /// Number of elements (a cube of about this many hexahedra).
    #[arg(long, default_value_t = 100_000)]
    pub elements: usize,
    /// Threads.
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Steps timed.
    #[arg(long, default_value_t = 200)]
    pub steps: usize,
}

/// Run `squeal bench`.
pub fn run(args: BenchArgs) -> Result<()> {
    match args.what {
        BenchWhat::Explicit(a) => {
            let r = squeal::explicit::bench::element_throughput(a.elements, a.threads, a.steps)?;
            println!(
                "elements={} nodes={} threads={} steps={} seconds={:.3}",
                r.elements, r.nodes, r.threads, r.steps, r.seconds
            );
            println!(
                "element_loop_ns_per_element={:.1}",
                r.element_loop_ns_per_element
            );
            println!(
                "bytes_per_element_step={:.0} implied_bandwidth_gb_per_s={:.2}",
                r.bytes_per_element_step, r.gigabytes_per_second
            );
            println!("ns_per_element_step={:.1}", r.ns_per_element_step);
            Ok(())
        }
    }
}
