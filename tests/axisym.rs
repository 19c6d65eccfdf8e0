//! Axisymmetric (Fourier-harmonic) modal solver against independent references
//! (docs/references.md, section 4): thin annular and solid free plates (Kirchhoff), thin rings
//! (in-plane and out-of-plane flexure), residuals, Sturm counts, rigid modes, refinement.

use std::f64::consts::TAU;

use squeal::analysis::identify::ModeFamily;
use squeal::input::wheel::WheelSpec;
use squeal::modal::axisym::{
    self, AxisymModel, AxisymOptions, Material, WheelClamp, WheelModelOptions,
};

const STEEL: Material = Material {
    youngs_modulus_pa: 210e9,
    poisson_ratio: 0.3,
    density_kg_per_m3: 7850.0,
};

/// Kirchhoff plate frequency (Hz) for a given lambda^2 (docs/references.md, section 4):
/// omega = lambda^2 / a^2 sqrt(D / (rho h)), D = E h^3 / (12 (1 - nu^2)).
fn plate_hz(lambda2: f64, a: f64, h: f64) -> f64 {
    let m = STEEL;
    let d = m.youngs_modulus_pa * h.powi(3) / (12.0 * (1.0 - m.poisson_ratio.powi(2)));
    lambda2 / (a * a) * (d / (m.density_kg_per_m3 * h)).sqrt() / TAU
}

fn opts(harmonics: std::ops::RangeInclusive<u32>, fmax_hz: f64) -> AxisymOptions {
    AxisymOptions {
        harmonics: harmonics.collect(),
        fmax_hz,
    }
}

/// Elastic modes of harmonic n and family, ascending.
fn elastic(res: &axisym::AxisymResult, n: u32, family: ModeFamily) -> Vec<f64> {
    res.modes
        .iter()
        .filter(|m| m.harmonic == n && m.family == family)
        .map(|m| m.frequency_hz)
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b) / b
}

/// Free-free annular plate, b/a = 0.3, a = 0.25 m, h = 5 mm (a/h = 50): the two lowest
/// (n = 0..5) and the lowest ones' nodal circles. Tolerance 2 %: the solid model
/// lands below Kirchhoff by the shear / rotary-inertia correction, of order
/// (h/a)^2 lambda^2 / 10 ~ 0.1-2 % over these modes.
#[test]
fn annular_plate_matches_kirchhoff() {
    let (a, b, h) = (0.25, 0.075, 0.005);
    let model = AxisymModel::rectangle(b, a, h, 40, 1, STEEL);
    let fmax = plate_hz(100.0, a, h);
    let res = axisym::solve(&model, &opts(0..=5, fmax)).unwrap();
    // docs/references.md, section 4, free-free annular plate, b/a = 0.3.
    let table: [[f64; 2]; 6] = [
        [8.3535, 50.353],
        [18.292, 58.784],
        [4.9060, 32.973],
        [12.266, 51.005],
        [21.783, 72.360],
        [33.481, 96.222],
    ];
    for (n, row) in table.iter().enumerate() {
        let fe = elastic(&res, n as u32, ModeFamily::Axial);
        for (k, &l2) in row.iter().enumerate() {
            let f_ref = plate_hz(l2, a, h);
            let e = rel(fe[k], f_ref);
            println!(
                "n={n} k={k}: FE {:.2} Hz, Kirchhoff {:.2} Hz, {:+.3} %",
                fe[k],
                f_ref,
                100.0 * e
            );
            assert!(e.abs() < 0.02, "n={n} root {k}: {e}");
        }
        let first = res
            .modes
            .iter()
            .find(|m| m.harmonic == n as u32 && m.family == ModeFamily::Axial)
            .unwrap();
        // Lowest elastic out-of-plane mode of each n: for n = 0 and 1 the zero-circle shapes
        // are the rigid translation and tilt, so the lowest elastic ones have one nodal
        // circle (as the solid plate's (1,0) and (1,1)); n >= 2 none.
        let expect_m = if n <= 1 { 1 } else { 0 };
        assert_eq!(first.nodal_circles, expect_m, "n={n}");
        assert_eq!(first.nodal_diameters, n as u32);
    }
    for m in &res.modes {
        assert!(m.residual < 1e-8, "{m:?}");
    }
}

/// Free solid circular plate, a = 0.25 m, h = 5 mm: (2,0), (0,1), (3,0), (1,1) within 2 %
/// of Kirchhoff (docs/references.md, section 4), with the labels (n, m) the classifier returns. Exercises the axis
/// conditions at r = 0 for n = 0, 1 and n >= 2.
#[test]
fn solid_plate_matches_kirchhoff_and_labels() {
    let (a, h) = (0.25, 0.005);
    let model = AxisymModel::rectangle(0.0, a, h, 40, 1, STEEL);
    let fmax = plate_hz(25.0, a, h);
    let res = axisym::solve(&model, &opts(0..=4, fmax)).unwrap();
    // (nodal diameters, nodal circles, lambda^2)
    let cases = [
        (2, 0, 5.3583),
        (0, 1, 9.0031),
        (3, 0, 12.4390),
        (1, 1, 20.4746),
        (4, 0, 21.8352),
    ];
    let axial: Vec<_> = res
        .modes
        .iter()
        .filter(|m| m.family == ModeFamily::Axial)
        .collect();
    assert_eq!(axial.len(), cases.len(), "{:#?}", res.harmonics);
    for (m, &(n, c, l2)) in axial.iter().zip(&cases) {
        let f_ref = plate_hz(l2, a, h);
        let e = rel(m.frequency_hz, f_ref);
        println!(
            "({c},{n}) FE {:.2} Hz, Kirchhoff {:.2} Hz, {:+.3} %",
            m.frequency_hz,
            f_ref,
            100.0 * e
        );
        assert!(e.abs() < 0.02);
        assert_eq!((m.nodal_diameters, m.nodal_circles), (n, c));
        assert_eq!(m.mode_ref().label(), format!("({c},{n})"));
    }
    // Free body: rigid modes at n = 0 (axial translation, rotation about the axis) and n = 1
    // (translation across the axis, tilt), two each; none elsewhere.
    for n in 0..=4u32 {
        let rigid = res
            .modes
            .iter()
            .filter(|m| m.harmonic == n && m.is_rigid())
            .count();
        assert_eq!(rigid, if n <= 1 { 2 } else { 0 }, "n = {n}");
    }
}

/// Thin ring, R = 1 m, square section b = 50 mm: in-plane (radial family) and out-of-plane
/// (axial family) flexure n = 2, 3, 4 within 2 % of the thin-ring formulas (Blevins; docs/references.md, section 4):
/// in-plane omega = sqrt(EI/(rho A R^4)) n (n^2-1)/sqrt(n^2+1), out-of-plane
/// omega = sqrt(EI/(rho A R^4)) n (n^2-1)/sqrt(n^2 + EI/(GJ)), with the square's torsion
/// constant J = 0.1406 b^4 (Roark, J = 2.25 (b/2)^4). Curvature, shear and rotary inertia of
/// the solid model shift these by (b/R)^2 n^2 order, well under 1 % here.
#[test]
fn thin_ring_in_and_out_of_plane() {
    let (radius, b) = (1.0, 0.05);
    let model = AxisymModel::rectangle(radius - 0.5 * b, radius + 0.5 * b, b, 2, 2, STEEL);
    let res = axisym::solve(&model, &opts(2..=4, 600.0)).unwrap();
    let m = STEEL;
    let area = b * b;
    let i = b.powi(4) / 12.0;
    let j = 0.140_625 * b.powi(4);
    let g = m.youngs_modulus_pa / (2.0 * (1.0 + m.poisson_ratio));
    let base = (m.youngs_modulus_pa * i / (m.density_kg_per_m3 * area * radius.powi(4))).sqrt();
    for n in 2..=4u32 {
        let nf = n as f64;
        let f_in = base * nf * (nf * nf - 1.0) / (nf * nf + 1.0).sqrt() / TAU;
        let f_out = base * nf * (nf * nf - 1.0)
            / (nf * nf + m.youngs_modulus_pa * i / (g * j)).sqrt()
            / TAU;
        let radial = elastic(&res, n, ModeFamily::Radial);
        let axial = elastic(&res, n, ModeFamily::Axial);
        let (e_in, e_out) = (rel(radial[0], f_in), rel(axial[0], f_out));
        println!(
            "n={n}: in-plane FE {:.2} / ring {:.2} Hz ({:+.3} %), out-of-plane FE {:.2} / ring {:.2} Hz ({:+.3} %)",
            radial[0], f_in, 100.0 * e_in, axial[0], f_out, 100.0 * e_out
        );
        assert!(e_in.abs() < 0.02 && e_out.abs() < 0.02);
    }
}

/// Uniform refinement: conforming elements with consistent mass give upper bounds that fall
/// monotonically towards the limit (Rayleigh-Ritz).
#[test]
fn refinement_decreases_frequencies_monotonically() {
    let (a, b, h) = (0.25, 0.075, 0.01);
    let mut prev: Option<Vec<f64>> = None;
    for (nr, nz) in [(4, 1), (8, 2), (16, 4)] {
        let model = AxisymModel::rectangle(b, a, h, nr, nz, STEEL);
        let res = axisym::solve(&model, &opts(0..=3, 3000.0)).unwrap();
        let f: Vec<f64> = (0..=3)
            .map(|n| elastic(&res, n, ModeFamily::Axial)[0])
            .collect();
        println!("{nr}x{nz}: {f:?}");
        if let Some(p) = &prev {
            for (new, old) in f.iter().zip(p) {
                assert!(*new <= *old * (1.0 + 1e-12), "{new} > {old}");
            }
        }
        prev = Some(f);
    }
}

/// The default wheel: solves n = 0..12 below 10 kHz, every residual below 1e-8, the Sturm
/// count equals the modes returned, rigid modes (free wheel + half axle) two at n = 0 and two
/// at n = 1; the zero-nodal-circle axial modes (0,2) < (0,3) < (0,4) lie in the ranges
/// Thompson (2009) gives for ~900 mm wheels (docs/references.md, section 7: a few hundred Hz, ~1 kHz,
/// ~1.8-2 kHz; checked loosely, these are ranges, not data). Hub-bore clamping removes the
/// rigid modes.
#[test]
fn default_wheel_modes() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/wheels/ns_intercity_920.json"
    );
    let spec: WheelSpec = squeal::input::read_json(std::path::Path::new(path)).unwrap();
    let model = AxisymModel::from_wheel(&spec, WheelModelOptions::default()).unwrap();
    let res = axisym::solve(&model, &AxisymOptions::default()).unwrap();
    println!(
        "n = 0..12 below 10 kHz: {} modes in {:.3} s",
        res.modes.len(),
        res.seconds
    );
    for s in &res.harmonics {
        println!("{s:?}");
        let count = res
            .modes
            .iter()
            .filter(|m| m.harmonic == s.harmonic)
            .count();
        assert_eq!(count, s.sturm_count);
    }
    for n in 0..=12u32 {
        let rigid = res
            .modes
            .iter()
            .filter(|m| m.harmonic == n && m.is_rigid())
            .count();
        assert_eq!(rigid, if n <= 1 { 2 } else { 0 }, "n = {n}");
    }
    let axial0 = |n: u32| {
        res.modes
            .iter()
            .find(|m| m.harmonic == n && m.family == ModeFamily::Axial && m.nodal_circles == 0)
            .map(|m| m.frequency_hz)
            .unwrap()
    };
    let (f2, f3, f4) = (axial0(2), axial0(3), axial0(4));
    println!("(0,2) {f2:.1} Hz, (0,3) {f3:.1} Hz, (0,4) {f4:.1} Hz");
    assert!((150.0..700.0).contains(&f2) && (600.0..1500.0).contains(&f3));
    assert!((1300.0..2600.0).contains(&f4));
    let clamped = AxisymModel::from_wheel(
        &spec,
        WheelModelOptions {
            without_axle: true,
            clamp: WheelClamp::HubBore,
        },
    )
    .unwrap();
    let resc = axisym::solve(&clamped, &opts(0..=3, 5000.0)).unwrap();
    assert!(resc
        .modes
        .iter()
        .all(|m| !m.is_rigid() && m.residual < 1e-8));
}
