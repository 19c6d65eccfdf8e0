//! Tutorial 1: the default wheel's modes, as the default pipeline computes them.
//!
//! Reads `data/wheels/ns_intercity_920.json` (a 920 mm wheel with its half axle), solves the
//! axisymmetric (Fourier-harmonic) model with the axle held at both ends, and prints the
//! zero-nodal-circle axial modes, the ones that squeal. Labels are (nodal circles, nodal
//! diameters) (docs/modal.md).
//!
//!     cargo run --release --example ex1_wheel_modes
//!
//! The same from the command line: `squeal axisym --wheel data/wheels/ns_intercity_920.json
//! --clamp axle-ends --fmax-hz 5000`.

use squeal::analysis::identify::ModeFamily;
use squeal::input::wheel::WheelSpec;
use squeal::modal::axisym::{solve, AxisymModel, AxisymOptions, WheelClamp, WheelModelOptions};

fn main() -> squeal::Result<()> {
    let wheel: WheelSpec =
        squeal::input::read_json(std::path::Path::new("data/wheels/ns_intercity_920.json"))?;
    let model = AxisymModel::from_wheel(
        &wheel,
        WheelModelOptions {
            without_axle: false,
            clamp: WheelClamp::AxleEnds,
        },
    )?;
    let result = solve(
        &model,
        &AxisymOptions {
            harmonics: (0..=8).collect(),
            fmax_hz: 5000.0,
        },
    )?;
    println!(
        "{} modes below 5 kHz in {:.2} s; zero-nodal-circle axial modes:",
        result.modes.len(),
        result.seconds
    );
    for m in &result.modes {
        if m.family == ModeFamily::Axial && m.nodal_circles == 0 {
            println!("  (0,{}) {:8.1} Hz", m.nodal_diameters, m.frequency_hz);
        }
    }
    // Thompson (2009): (0,3) near 1 kHz and (0,4) at 1.8-2 kHz for wheels of about 900 mm.
    let find = |n: u32| {
        result
            .modes
            .iter()
            .find(|m| {
                m.family == ModeFamily::Axial && m.nodal_circles == 0 && m.nodal_diameters == n
            })
            .map(|m| m.frequency_hz)
    };
    let (f3, f4) = (find(3).expect("(0,3)"), find(4).expect("(0,4)"));
    assert!((800.0..1300.0).contains(&f3) && (1500.0..2300.0).contains(&f4));
    println!("(0,3) at {f3:.0} Hz and (0,4) at {f4:.0} Hz: the squeal modes of Yang & Li (2019)");
    Ok(())
}
