//! `squeal modes` end to end on a coarse wheel (fast), and its error exit code.

use std::process::Command;

#[test]
fn coarse_wheel_writes_mode_files() {
    let out = std::env::temp_dir().join(format!("squeal_cli_modes_{}", std::process::id()));
    let mtx = out.join("mtx");
    let status = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "modes",
            "--wheel",
            "data/wheels/ns_intercity_920.json",
            "--element-size-mm",
            "40",
            "--fmax-hz",
            "1500",
            "--hammer",
            "data/hammer/synthetic_example.csv",
            "--out",
        ])
        .arg(&out)
        .arg("--export-mtx")
        .arg(&mtx)
        .status()
        .unwrap();
    assert!(status.success());
    for f in [
        "modes.json",
        "modes.csv",
        "modes.vtu",
        "comparison.md",
        "comparison.csv",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let modes: Vec<squeal::identify::ModeRef> =
        serde_json::from_str(&std::fs::read_to_string(out.join("modes.json")).unwrap()).unwrap();
    use squeal::identify::ModeFamily;
    // free wheel: six rigid modes, then the axial (0,2) and (0,3) pairs in the band
    assert_eq!(
        modes
            .iter()
            .filter(|m| m.family == ModeFamily::Rigid)
            .count(),
        6
    );
    for n in [2, 3] {
        assert!(
            modes
                .iter()
                .any(|m| m.family == ModeFamily::Axial && m.nodal_diameters == n),
            "no axial n={n}: {modes:?}"
        );
    }
    let k = std::fs::read_to_string(mtx.join("K.mtx")).unwrap();
    assert!(k.starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn missing_wheel_file_exits_2() {
    let out = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "modes",
            "--wheel",
            "data/wheels/no_such_wheel.json",
            "--out",
            "/tmp/x",
        ])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
