//! Tutorial 5: analysis of a run directory.
//!
//! The committed 1 mm run of case 4 (`data/runs/case4-paper`, to 22.3 ms): the PSD of the
//! rim's lateral vibration from the lateral-motion start (16 ms), its dominant peaks with the
//! wheel modes that explain them and each peak's rim-mean/rim-point ratio (near 1: the whole
//! rim moves, no nodal diameter; near 0: nodal diameters), then the wavelet-ridge growth of the
//! squeal modes' bands. The same from the command line: `squeal identify data/runs/case4-paper
//! --from-ms 16` and `squeal growth data/runs/case4-paper --from-ms 16`.
//!
//!     cargo run --release --example ex5_analyse_run

use squeal::analysis::growth::{band_growth, bands_for_modes, read_column};
use squeal::analysis::{analyse_run, AnalysisOptions};

fn main() -> squeal::Result<()> {
    let run = std::path::Path::new("data/runs/case4-paper");
    let analysis = analyse_run(
        run,
        &AnalysisOptions {
            from_s: Some(0.016),
            peaks: 5,
            ..Default::default()
        },
    )?;
    println!(
        "{} over {:.1}-{:.1} ms: {}",
        analysis.column,
        analysis.window.from_s * 1e3,
        analysis.window.to_s * 1e3,
        analysis.window.spectrum
    );
    for p in &analysis.identifications {
        println!(
            "  {:7.1} Hz  rim mean/point {:5.2}  {}",
            p.peak_frequency_hz,
            p.rim_mean_over_point.unwrap_or(f64::NAN),
            p.mode
                .as_ref()
                .map(|m| format!("{:?} {}", m.family, m.label()))
                .unwrap_or_else(|| "unexplained".into())
        );
    }
    let modes: Vec<squeal::analysis::identify::ModeRef> =
        squeal::input::read_json(&run.join("modes.json"))?;
    let bands = bands_for_modes(&modes, &[(0, 3), (0, 4)], 0.05)?;
    let series = read_column(run, "lateral_velocity_m_per_s")?;
    let growth = band_growth(&series, &bands, 0.016, 0.002)?;
    print!("{}", squeal::analysis::growth::to_markdown(&growth));
    Ok(())
}
