//! The 3D solver and the axisymmetric solver on the same wheel (40 mm elements): the
//! zero-nodal-circle axial modes (0,2), (0,3), (0,4) agree. The 3D mesh is stiffer: linear
//! hexahedra lock in bending across the web (one or two elements thick at 40 mm) and the
//! circumference is a polygon of flat facets, while the Q9 harmonic section is converged to
//! ~0.5 % at this size (tests/axisym.rs). Measured 2026-11-23: 3D above axisym by 4.1, 2.5,
//! 2.5 %; the test requires 3D above and within 6 %.
use std::path::Path;
use std::process::Command;

use squeal::identify::{ModeFamily, ModeRef};

fn modes(args: &[&str], out: &Path) -> Vec<ModeRef> {
    let status = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    squeal::input::read_json(&out.join("modes.json")).unwrap()
}

fn axial_zero_circle(modes: &[ModeRef], n: u32) -> f64 {
    modes
        .iter()
        .find(|m| m.family == ModeFamily::Axial && m.nodal_circles == 0 && m.nodal_diameters == n)
        .unwrap_or_else(|| panic!("no axial (0,{n}) mode"))
        .frequency_hz
}

#[test]
fn three_d_and_axisymmetric_solvers_agree_on_the_wheel() {
    let dir = std::env::temp_dir().join(format!("squeal_modal_vs_axisym_{}", std::process::id()));
    let wheel = "data/wheels/ns_intercity_920.json";
    let solid = modes(
        &[
            "modes",
            "--wheel",
            wheel,
            "--element-size-mm",
            "40",
            "--fmax-hz",
            "2500",
        ],
        &dir.join("3d"),
    );
    let axisym = modes(
        &[
            "axisym",
            "--wheel",
            wheel,
            "--element-size-mm",
            "40",
            "--fmax-hz",
            "2500",
        ],
        &dir.join("axisym"),
    );
    for n in 2..=4 {
        let (f3, fa) = (axial_zero_circle(&solid, n), axial_zero_circle(&axisym, n));
        let diff = f3 / fa - 1.0;
        assert!(
            diff > 0.0 && diff < 0.06,
            "(0,{n}): 3D {f3:.1} Hz vs axisym {fa:.1} Hz ({:.2} %)",
            100.0 * diff
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
