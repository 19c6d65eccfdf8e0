//! FE-snapshot comparison with Kalker: a snapshot made from Kalker's own creepage-prescribed
//! solution must come back with the same creepages and the same adhesion-zone orientation
//! (a round trip through the force-prescribed mode), and the orientation must grow with the
//! lateral creepage (PAPER.md: lateral creepage rotates the patch solution).
use squeal::kalker::hertz::HertzContact;
use squeal::kalker::rolling::{Method, RollingSolver};
use squeal::kalker::snapshot::{
    compare_snapshot, write_comparison_charts, PatchPoint, PatchSnapshot,
};
use squeal::kalker::tangential::{Creepages, ElementState};
use squeal::kalker::Material;

const CURVATURES: (f64, f64) = (1.0 / 0.92, 1.0 / 0.6); // flat 0.46 m wheel on an R300 crown

fn snapshot_from_kalker(xi: f64, eta: f64) -> PatchSnapshot {
    let material = Material::validated(210e9, 0.3, "test").expect("material");
    let hertz =
        HertzContact::from_curvatures(CURVATURES.0, CURVATURES.1, 100e3, material).expect("hertz");
    let solver = RollingSolver::new(&hertz, 0.45, Method::Exact, 40).expect("solver");
    let s = solver
        .solve(&Creepages {
            xi,
            eta,
            phi_per_m: 0.0,
        })
        .expect("solve");
    PatchSnapshot {
        time_s: 0.018,
        normal_force_n: 100e3,
        force_x_n: s.force_x_n,
        force_y_n: s.force_y_n,
        mu: 0.45,
        points: (0..s.x_m.len())
            .filter(|&k| s.state[k] != ElementState::Exterior)
            .map(|k| PatchPoint {
                x_m: s.x_m[k],
                y_m: s.y_m[k],
                pressure_pa: s.pressure_pa[k],
                slip: s.state[k] == ElementState::Slip,
            })
            .collect(),
    }
}

#[test]
fn round_trip_recovers_creepages_and_orientation() {
    let material = Material::validated(210e9, 0.3, "test").expect("material");
    let (xi, eta) = (-1e-3, -1e-3);
    let snap = snapshot_from_kalker(xi, eta);
    let cmp = compare_snapshot(&snap, CURVATURES, material, Method::Exact, 40).expect("compare");
    assert!(cmp.kalker.unique);
    // The inverse solves to 1e-6 relative in forces; creepages follow to ~1e-4 relative.
    assert!(
        (cmp.kalker.creepages.xi - xi).abs() < 1e-3 * xi.abs(),
        "xi {}",
        cmp.kalker.creepages.xi
    );
    assert!(
        (cmp.kalker.creepages.eta - eta).abs() < 1e-3 * eta.abs(),
        "eta {}",
        cmp.kalker.creepages.eta
    );
    let (fe, k) = (
        cmp.fe_orientation_deg.expect("fe angle"),
        cmp.kalker_orientation_deg.expect("kalker angle"),
    );
    assert!((fe - k).abs() < 0.5, "orientation FE {fe} vs Kalker {k}");
    assert!((cmp.fe_adhesion_fraction - cmp.kalker_adhesion_fraction).abs() < 0.05);
    let dir = std::env::temp_dir().join(format!("squeal-snapshot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    write_comparison_charts(&snap, &cmp, &dir).expect("charts");
    assert!(dir.join("patch_fe.png").exists() && dir.join("patch_kalker.svg").exists());
}

#[test]
fn orientation_grows_with_lateral_creepage() {
    let material = Material::validated(210e9, 0.3, "test").expect("material");
    let mut angles = Vec::new();
    for eta in [0.0, -0.5e-3, -1.5e-3] {
        let cmp = compare_snapshot(
            &snapshot_from_kalker(-1e-3, eta),
            CURVATURES,
            material,
            Method::Exact,
            40,
        )
        .expect("compare");
        angles.push(cmp.kalker_orientation_deg.map(f64::abs).unwrap_or(0.0));
    }
    eprintln!("orientation |angle| for eta 0, -0.5e-3, -1.5e-3: {angles:?}");
    assert!(angles[0] < angles[1] && angles[1] < angles[2], "{angles:?}");
}
