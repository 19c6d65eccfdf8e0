//! `squeal bench`: the performance figures docs/performance.md quotes.

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
    /// Modal band solve of exported matrices (`squeal modes --export-mtx DIR`): reads DIR/K.mtx
    /// and DIR/M.mtx, ends with `seconds=<total> modes=<count below fmax, rigid included>`.
    Modal(ModalBenchArgs),
    /// Stability analysis: one operating point with N wheel modes and an eta sweep; ends with
    /// `point_seconds=<value> sweep_seconds=<value>`.
    Stability(StabilityBenchArgs),
    /// One rolling step of a case split into element forces, contact and the rest, with the
    /// projected wall time of the case's time loop; ends with `ms_per_step=<value>`.
    Rolling(RollingBenchArgs),
    /// The static preload of a rolling case (model built, preload timed, no rolling run);
    /// ends with `preload_seconds=<value>`.
    Preload(PreloadBenchArgs),
}

/// Arguments of `squeal bench preload`.
#[derive(Args, Debug)]
pub struct PreloadBenchArgs {
    /// Rolling case file (e.g. data/cases/case3-demo.json).
    #[arg(long, alias = "scenario")]
    pub case: std::path::PathBuf,
    /// The method (default: the case's `preload.method`).
    #[arg(long, value_enum)]
    pub preload: Option<super::simulate::PreloadChoice>,
}

fn preload(a: PreloadBenchArgs) -> Result<()> {
    let loaded = squeal::rolling::load_case(&a.case)?;
    let method = a
        .preload
        .map(super::simulate::PreloadChoice::method)
        .unwrap_or(loaded.case.preload.method);
    let p = squeal::rolling::bench::preload_profile(&loaded, method)?;
    println!(
        "elements={} method={:?} build_s={:.1} iterations_or_steps={} factor_entries={} \
         relative_residual={:.2e} load_error={:+.2e}",
        p.elements,
        p.method,
        p.build_s,
        p.iterations_or_steps,
        p.factor_entries,
        p.relative_residual,
        p.load_error
    );
    println!("preload_seconds={:.2}", p.preload_s);
    Ok(())
}

/// Arguments of `squeal bench rolling`.
#[derive(Args, Debug)]
pub struct RollingBenchArgs {
    /// Rolling case file (e.g. data/cases/case3-demo.json).
    #[arg(long, alias = "scenario")]
    pub case: std::path::PathBuf,
    /// Steps timed per part, 1 to 1000000.
    #[arg(long, default_value_t = 200)]
    pub steps: usize,
    /// Contact search: `region` (the slaves near the rail, the default) or `full` (every
    /// slave every step, for comparison).
    #[arg(long, value_enum, default_value_t = SearchArg::Region)]
    pub contact_search: SearchArg,
    /// Time the steps with multi-rate stepping (as `simulate --multi-rate`): prints each
    /// level's element cost. Without this or --single-rate the case's `time_stepping` decides.
    #[arg(long, conflicts_with = "single_rate")]
    pub multi_rate: bool,
    /// Time the steps single rate (as `simulate --single-rate`).
    #[arg(long)]
    pub single_rate: bool,
}

/// `--contact-search`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum SearchArg {
    /// Region of interest.
    Region,
    /// Every slave every step.
    Full,
}

/// `k:value` for each level k, space separated.
fn by_level<T>(values: &[T], show: impl Fn(&T) -> String) -> String {
    values
        .iter()
        .enumerate()
        .map(|(k, v)| format!("{k}:{}", show(v)))
        .collect::<Vec<_>>()
        .join(" ")
}

fn rolling(a: RollingBenchArgs) -> Result<()> {
    let loaded = squeal::rolling::load_case(&a.case)?;
    let search = match a.contact_search {
        SearchArg::Region => squeal::contact::ContactSearch::Region,
        SearchArg::Full => squeal::contact::ContactSearch::Full,
    };
    let mode = super::simulate::stepping_override(a.multi_rate, a.single_rate);
    let p = squeal::rolling::bench::step_profile(&loaded, a.steps, search, mode)?;
    println!(
        "nodes={} elements={} contact_slaves={} threads={} dt_s={:.4e} ({}) steps={}",
        p.nodes,
        p.elements,
        p.contact_slaves,
        p.threads,
        p.time_step_s,
        p.time_step_limited_by,
        p.steps
    );
    println!("time_stepping: {}", p.time_stepping);
    if p.multi_rate {
        println!(
            "levels={} (multi-rate: level k steps every 2^k steps) ns_per_element_step_by_level {}",
            p.level_counts.len(),
            by_level(&p.level_ns_per_element_step, |ns| format!("{ns:.1}"))
        );
    } else {
        println!("levels=1 (single rate: every element at the smallest stable step)");
    }
    println!(
        "step_levels elements per level (the engine's partition: contact, tie, rigid and \
         prescribed nodes at level 0) {} \
         multi_rate_element_work={:.3} of single rate ({:.3} if the contact's nodes followed \
         their elements)",
        by_level(&p.level_counts, |c| c.to_string()),
        p.element_work_fraction,
        p.element_work_fraction_free_contact
    );
    println!(
        "element_colours={} blocks_per_colour {}",
        p.colour_blocks.len(),
        by_level(&p.colour_blocks, |c| c.to_string())
    );
    println!(
        "contact_search={:?} searched_slaves={} region_rebuild_ms={:.3}",
        a.contact_search, p.searched_slaves, p.region_rebuild_ms
    );
    println!(
        "elements_ms={:.3} contact_ms={:.3} rest_ms={:.3} contact_share={:.3}",
        p.elements_ms, p.contact_ms, p.rest_ms, p.contact_share
    );
    println!(
        "step_phases_ms {}",
        p.phase_ms
            .iter()
            .map(|(name, ms)| format!("{name}={ms:.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    println!("ns_per_element_step={:.1}", p.ns_per_element_step);
    println!(
        "case_steps={} projected_time_loop_s={:.1}",
        p.case_steps, p.projected_time_loop_s
    );
    println!("ms_per_step={:.3}", p.step_ms);
    Ok(())
}

/// Arguments of `squeal bench stability`.
#[derive(Args, Debug)]
pub struct StabilityBenchArgs {
    /// Rolling case whose wheel, track and case-file operating point are used.
    #[arg(long, default_value = "data/cases/case3-demo.json")]
    pub case: std::path::PathBuf,
    /// Wheel modal coordinates (3D modes: an n >= 1 pair counts twice).
    #[arg(long, default_value_t = 200)]
    pub wheel_modes: usize,
    /// Repeats of the single point (the median is printed).
    #[arg(long, default_value_t = 5)]
    pub repeats: usize,
    /// Sweep points (eta over 0..1 %); 0 or 1: no sweep.
    #[arg(long, default_value_t = 100)]
    pub points: usize,
}

fn stability(a: StabilityBenchArgs) -> Result<()> {
    let loaded = squeal::model::case::load_case(&a.case)?;
    let r = squeal::stability::bench::run(&loaded, a.wheel_modes, a.repeats, a.points)?;
    println!(
        "wheel: {} coordinates to {:.0} Hz (modal solve {:.2} s); rail: {} coordinates ({:.2} s)",
        r.wheel_coordinates,
        r.wheel_fmax_hz,
        r.wheel_solve_seconds,
        r.rail_coordinates,
        r.rail_model_seconds
    );
    println!(
        "one point: {:.3} s (median of {}; linearisation {:.3} s, eigenvalues {:.3} s)",
        r.point_seconds,
        r.repeats,
        r.linearise_seconds,
        r.point_seconds - r.linearise_seconds
    );
    println!(
        "sweep: {} points in {:.2} s on {} threads",
        r.sweep_points, r.sweep_seconds, r.threads
    );
    println!(
        "point_seconds={:.3} sweep_seconds={:.2}",
        r.point_seconds, r.sweep_seconds
    );
    Ok(())
}

/// Arguments of `squeal bench modal`.
#[derive(Args, Debug)]
pub struct ModalBenchArgs {
    /// Directory holding K.mtx and M.mtx (Matrix Market coordinate real symmetric).
    #[arg(long)]
    pub mtx: std::path::PathBuf,
    /// Upper band edge (Hz).
    #[arg(long = "fmax-hz", alias = "fmax", default_value_t = squeal::modal::ModalOptions::default().fmax_hz)]
    pub fmax_hz: f64,
    /// Block size of the block Lanczos (columns per operator application), 1 to 64.
    #[arg(long, default_value_t = squeal::modal::ModalOptions::default().block_size)]
    pub block_size: usize,
    /// Slices of the band, one shift each (spectrum slicing), 1 to 32.
    #[arg(long, default_value_t = 1)]
    pub slices: usize,
    /// Shift of the first slice below the spectrum, sigma = -(2 pi shift)², in (0, fmax] Hz
    /// [default: the larger of fmax / 20 and 10 Hz].
    #[arg(long)]
    pub shift_hz: Option<f64>,
}

fn modal(a: ModalBenchArgs) -> Result<()> {
    use squeal::fem::assembly::read_matrix_market;
    use squeal::modal::{solve, ModalOptions};
    if !(a.fmax_hz.is_finite() && a.fmax_hz > 0.0 && a.fmax_hz <= 1e6) {
        return Err(squeal::Error::input(
            "command line",
            "--fmax-hz",
            format!("{} is outside the allowed range (0, 1e6] Hz", a.fmax_hz),
        ));
    }
    if !(1..=64).contains(&a.block_size) {
        return Err(squeal::Error::input(
            "command line",
            "--block-size",
            format!("{} is outside the allowed range 1..=64", a.block_size),
        ));
    }
    squeal::modal::lanczos::check_slices(a.slices)?;
    if let Some(shift) = a.shift_hz {
        if !(shift.is_finite() && shift > 0.0 && shift <= a.fmax_hz) {
            return Err(squeal::Error::input(
                "command line",
                "--shift-hz",
                format!(
                    "{shift} is outside the allowed range (0, fmax = {}] Hz",
                    a.fmax_hz
                ),
            ));
        }
    }
    let started = std::time::Instant::now();
    let k = read_matrix_market(&a.mtx.join("K.mtx"))?;
    let m = read_matrix_market(&a.mtx.join("M.mtx"))?;
    if k.nrows() != m.nrows() {
        return Err(squeal::Error::input(
            a.mtx.display().to_string(),
            "M.mtx",
            format!("K is {0}x{0} but M is {1}x{1}", k.nrows(), m.nrows()),
        ));
    }
    let read_s = started.elapsed().as_secs_f64();
    println!(
        "read K ({} nonzeros) and M ({} nonzeros), {} dofs, in {:.2} s",
        k.val().len(),
        m.val().len(),
        k.nrows(),
        read_s
    );
    let sol = solve(
        &k,
        &m,
        &ModalOptions {
            fmax_hz: a.fmax_hz,
            rigid_below_hz: 1.0,
            block_size: a.block_size,
            slices: a.slices,
            shift_hz: a.shift_hz,
            ..Default::default()
        },
    )?;
    for (i, md) in sol.modes.iter().enumerate() {
        println!(
            "mode {i} frequency_hz={:.9e} residual={:.2e}{}",
            md.frequency_hz,
            md.residual,
            if md.rigid { " rigid" } else { "" }
        );
    }
    let rigid = sol.modes.iter().filter(|m| m.rigid).count();
    println!(
        "dofs={} read_seconds={:.3} solve_seconds={:.3} factor_seconds={:.3} rigid={} flexible={}",
        k.nrows(),
        read_s,
        sol.solve_seconds,
        sol.factor_seconds,
        rigid,
        sol.modes.len() - rigid
    );
    println!(
        "seconds={:.3} modes={}",
        started.elapsed().as_secs_f64(),
        sol.modes.len()
    );
    Ok(())
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
        BenchWhat::Modal(a) => modal(a),
        BenchWhat::Stability(a) => stability(a),
        BenchWhat::Rolling(a) => rolling(a),
        BenchWhat::Preload(a) => preload(a),
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
