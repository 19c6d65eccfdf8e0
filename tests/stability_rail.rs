//! The stability analysis's rail (`squeal::stability::rail`, `rail_modes`, `rail_fe`): the
//! beam elements against closed forms, the modal models against direct solves of the same
//! beams (point and cross receptances), and the beams against the project's FE track.

mod stability_case;
use stability_case::case3_track;

/// Frequencies (Hz, ascending) of `K x = w^2 M x` through `M = L L^T`: `L^-1 K L^-T` is
/// symmetric.
fn eigenfrequencies_hz(k: &faer::Mat<f64>, m: &faer::Mat<f64>) -> Vec<f64> {
    use faer::linalg::solvers::DenseSolveCore;
    let l = m.llt(faer::Side::Lower).unwrap().L().to_owned();
    let linv = l.as_ref().partial_piv_lu().inverse();
    let sym = &linv * k * linv.transpose();
    let sym = faer::Mat::<f64>::from_fn(sym.nrows(), sym.ncols(), |i, j| {
        0.5 * (sym[(i, j)] + sym[(j, i)])
    });
    let mut f: Vec<f64> = sym
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .unwrap()
        .iter()
        .map(|&l2| l2.max(0.0).sqrt() / std::f64::consts::TAU)
        .collect();
    f.sort_by(f64::total_cmp);
    f
}

/// The lateral-torsional element against the closed form of a fork-supported bay (v = phi = 0
/// at both ends, bending rotation and warping free): `v = V sin kx, psi = P cos kx,
/// phi = F sin kx` with `k = j pi / L` decouple by j into the 3 x 3 problem
/// `K = [[kGA k^2, -kGA k, 0], [-kGA k, EI k^2 + kGA, 0], [0, 0, GJ k^2 + E I_w k^4]]`,
/// `M = [[rho A, 0, -rho A d], [0, rho I, 0], [-rho A d, 0, rho I_pS + rho I_w k^2]]`
/// (module docs of `stability::rail`): the centroid's offset d couples bending and twist.
#[test]
fn lateral_torsional_elements_match_the_fork_supported_bay_closed_form() {
    use squeal::stability::rail::{lateral_torsional_element, RailSection};
    let r = RailSection::UIC54;
    let length = 0.6;
    let elements = 60; // the rail model's 10 mm elements
    let h = length / elements as f64;
    let n = 4 * (elements + 1);
    let mut k = faer::Mat::<f64>::zeros(n, n);
    let mut m = faer::Mat::<f64>::zeros(n, n);
    let (ke, me) = lateral_torsional_element(&r, h);
    for e in 0..elements {
        for a in 0..8 {
            for b in 0..8 {
                k[(4 * e + a, 4 * e + b)] += ke[a][b];
                m[(4 * e + a, 4 * e + b)] += me[a][b];
            }
        }
    }
    // v (dof 0) and phi (dof 2) held at both ends.
    let last = 4 * elements;
    let held = [0, 2, last, last + 2];
    let free: Vec<usize> = (0..n).filter(|d| !held.contains(d)).collect();
    let kf = faer::Mat::<f64>::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let mf = faer::Mat::<f64>::from_fn(free.len(), free.len(), |i, j| m[(free[i], free[j])]);
    let fe = eigenfrequencies_hz(&kf, &mf);
    let mat = r.material;
    let (rho, e, g) = (
        mat.density_kg_per_m3,
        mat.youngs_modulus_pa,
        mat.shear_modulus_pa(),
    );
    let (a, iz) = (r.area_m2, r.second_moment_lateral_m4);
    let kga = r.shear_coefficient_lateral * g * a;
    let d = r.shear_centre_below_crown_m - r.centroid_below_crown_m;
    let mut exact = Vec::new();
    for j in 1..=6 {
        let kk = j as f64 * std::f64::consts::PI / length;
        let kj = faer::Mat::<f64>::from_fn(3, 3, |p, q| match (p, q) {
            (0, 0) => kga * kk * kk,
            (0, 1) | (1, 0) => -kga * kk,
            (1, 1) => e * iz * kk * kk + kga,
            (2, 2) => g * r.torsion_constant_m4 * kk * kk + e * r.warping_constant_m6 * kk.powi(4),
            _ => 0.0,
        });
        let mj = faer::Mat::<f64>::from_fn(3, 3, |p, q| match (p, q) {
            (0, 0) => rho * a,
            (0, 2) | (2, 0) => -rho * a * d,
            (1, 1) => rho * iz,
            (2, 2) => {
                rho * r.polar_moment_about_shear_centre_m4() + rho * r.warping_constant_m6 * kk * kk
            }
            _ => 0.0,
        });
        // The two lower roots: bending-twist pairs; the third is the shear branch.
        exact.extend(eigenfrequencies_hz(&kj, &mj).into_iter().take(2));
    }
    exact.sort_by(f64::total_cmp);
    for (i, &x) in exact.iter().take(6).enumerate() {
        let got = *fe
            .iter()
            .min_by(|a, b| (*a - x).abs().total_cmp(&(*b - x).abs()))
            .unwrap();
        println!("fork-supported bay, root {i}: FE {got:.1} Hz, closed form {x:.1} Hz");
        // Linear bending and cubic torsion on 10 mm elements: the bending part converges as
        // (k h)^2 / 12 (0.4 % at the 4th half-wave, as the vertical test), the cubic torsion
        // faster; 0.5 % bounds both.
        assert!((got / x - 1.0).abs() < 5e-3, "root {i}: {got} vs {x}");
    }
    // The coupling is there: the first twist without it, with the FE's roots beside it.
    let uncoupled_twist = {
        let kk = std::f64::consts::PI / length;
        ((g * r.torsion_constant_m4 * kk * kk + e * r.warping_constant_m6 * kk.powi(4))
            / (rho * r.polar_moment_about_shear_centre_m4()
                + rho * r.warping_constant_m6 * kk * kk))
            .sqrt()
            / std::f64::consts::TAU
    };
    // Measured 755 Hz against the coupled roots 495 and 887 Hz: the offset matters, and the FE
    // model has no root near the uncoupled one.
    let nearest = fe
        .iter()
        .map(|f| (f / uncoupled_twist - 1.0).abs())
        .fold(f64::INFINITY, f64::min);
    println!(
        "uncoupled first twist {uncoupled_twist:.1} Hz; nearest FE root {:.1} % away",
        100.0 * nearest
    );
    assert!(nearest > 0.05);
}

#[test]
fn timoshenko_elements_match_the_simply_supported_beam_closed_form() {
    use squeal::stability::rail::{timoshenko_element, RailSection};
    // Simply supported Timoshenko beam, w = W sin(k x), theta = T cos(k x), k = j pi / L:
    // det [[kGA k^2 - rho A w^2, -kGA k], [-kGA k, EI k^2 + kGA - rho I w^2]] = 0, a quadratic
    // in w^2 whose smaller root is the bending mode (Timoshenko 1921).
    let r = RailSection::UIC54;
    let g = r.material.shear_modulus_pa();
    let (ei, kga) = (
        r.material.youngs_modulus_pa * r.second_moment_vertical_m4,
        r.shear_coefficient_vertical * g * r.area_m2,
    );
    let (rho_a, rho_i) = (
        r.material.density_kg_per_m3 * r.area_m2,
        r.material.density_kg_per_m3 * r.second_moment_vertical_m4,
    );
    let length = 0.6; // one sleeper bay: its modes span 0.3-10 kHz
    let elements = 60; // the rail model's 10 mm elements
    let h = length / elements as f64;
    let n = 2 * (elements + 1);
    let mut k = faer::Mat::<f64>::zeros(n, n);
    let mut m = faer::Mat::<f64>::zeros(n, n);
    for e in 0..elements {
        let (ke, me) = timoshenko_element(ei, kga, rho_a, rho_i, h);
        for a in 0..4 {
            for b in 0..4 {
                k[(2 * e + a, 2 * e + b)] += ke[a][b];
                m[(2 * e + a, 2 * e + b)] += me[a][b];
            }
        }
    }
    // Simple supports: w = 0 at both ends (dofs 0 and n - 2).
    let free: Vec<usize> = (0..n).filter(|&d| d != 0 && d != n - 2).collect();
    let kf = faer::Mat::<f64>::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let mf = faer::Mat::<f64>::from_fn(free.len(), free.len(), |i, j| m[(free[i], free[j])]);
    let fe = eigenfrequencies_hz(&kf, &mf);
    for j in 1..=4 {
        let kk = j as f64 * std::f64::consts::PI / length;
        // a w^4 - b w^2 + c = 0.
        let a = rho_a * rho_i;
        let b = rho_a * (ei * kk * kk + kga) + rho_i * kga * kk * kk;
        let c = kga * kk * kk * ei * kk * kk;
        let w2 = (b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
        let exact = w2.sqrt() / std::f64::consts::TAU;
        // The FE spectrum also holds the shear branch (from sqrt(kGA / rho I) = 5.6 kHz, the
        // uniform rotation with w = 0): compare with the nearest FE frequency.
        let got = *fe
            .iter()
            .min_by(|a, b| (*a - exact).abs().total_cmp(&(*b - exact).abs()))
            .unwrap();
        println!("simply supported bay, mode {j}: FE {got:.1} Hz, closed form {exact:.1} Hz");
        // Linear elements converge as h^2: (k h)^2 / 12 with k h = j pi / 60 is 0.02 % (j = 1)
        // to 0.4 % (j = 4) for the Euler part; 0.5 % bounds it.
        assert!(
            (got / exact - 1.0).abs() < 5e-3,
            "mode {j}: {got} vs {exact}"
        );
    }
}

#[test]
fn rail_modal_model_matches_the_direct_frequency_response_below_5_khz() {
    use squeal::stability::rail::Direction;
    use squeal::stability::rail_modes::{rail_modal_model, relative_error};
    let (_, track) = case3_track();
    let x = 2.0; // the demo wheel's start, 0.1 m before a sleeper
                 // 500 frequencies 50-5000 Hz, none of them a sample the model was built from (it is built
                 // from the beam's modes and one static solve).
    let check_f: Vec<f64> = (0..500).map(|i| 50.0 + 9.9 * i as f64).collect();
    for d in Direction::ALL {
        let t0 = std::time::Instant::now();
        // Modes to 1.5 fmax explicitly, the rest lumped by octave (the stability default).
        let model = rail_modal_model(&track, d, x, 7_500.0).unwrap();
        let t_modal = t0.elapsed().as_secs_f64();
        let h = track.receptance(d, x, &check_f).unwrap();
        let (max, rms) = relative_error(&model, &check_f, &h);
        let (worst_f, worst_db) = check_f
            .iter()
            .zip(&h)
            .map(|(&f, hi)| (f, 20.0 * (model.receptance(f).norm() / hi.norm()).log10()))
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap();
        println!(
            "rail {}: {} terms; 50-5000 Hz: |dH|/|H| max {:.2} % rms {:.2} %, largest level error {:+.2} dB at {:.0} Hz (modal model {:.2} s)",
            d.name(),
            model.modes.len(),
            100.0 * max,
            100.0 * rms,
            worst_db,
            worst_f,
            t_modal
        );
        // rms 3 %: the truncated modes' dynamic part (lumped by octave) and the damping coupling
        // between kept and lumped modes; the largest errors sit at antiresonances, where |H| is
        // smallest, and stay below 1.5 dB.
        assert!(rms < 0.03, "{}: rms {rms}", d.name());
        assert!(worst_db.abs() < 1.5, "{}: {worst_db} dB", d.name());
    }
}

/// A short track of the case-3 demo's supports for the fast check: 1.8 m of rail over three
/// sleepers (0.3, 0.9, 1.5 m), meshed uniformly (20 mm along the rail, 10 / 20 mm in the
/// section) so that the explicit model stays small.
fn short_track_layout() -> squeal::mesh::track::TrackLayout {
    let (loaded, _) = case3_track();
    let mut layout = loaded.scenario.track_layout();
    layout.length_m = 1.8;
    layout.first_sleeper_x_m = 0.3;
    layout.solution_zone_start_m = 0.0;
    layout.solution_zone_length_m = 1.8;
    layout.zone_element_length_m = 0.02;
    layout.far_element_length_m = 0.02;
    layout.running_zone = None;
    layout.running_surface_element_mm = 10.0;
    layout.section_element_mm = 20.0;
    layout
}

/// Print the comparison (every 500 Hz when `verbose`) and return (rms relative difference,
/// largest |level difference| in dB) over `band_hz`.
fn summarise(
    c: &squeal::stability::rail_fe::RailComparison,
    band_hz: (f64, f64),
    verbose: bool,
) -> (f64, f64) {
    let rel = c.relative_difference();
    let db = c.level_difference_db();
    let mut sum = 0.0;
    let mut count = 0;
    let mut worst_db: f64 = 0.0;
    for (i, &f) in c.frequencies_hz.iter().enumerate() {
        if f >= band_hz.0 && f <= band_hz.1 {
            sum += rel[i] * rel[i];
            count += 1;
            worst_db = if db[i].abs() > worst_db.abs() {
                db[i]
            } else {
                worst_db
            };
        }
        if verbose && i % 10 == 0 {
            println!(
                "  {:?} {f:6.0} Hz: FE {:.3e} m/N, beam {:.3e} m/N, |dH|/|H| {:.3}, {:+.2} dB",
                c.direction,
                c.fe_m_per_n[i].norm(),
                c.beam_m_per_n[i].norm(),
                rel[i],
                db[i]
            );
        }
    }
    let rms = (sum / count as f64).sqrt();
    println!(
        "{:?} at x = {:.3} m: {} elements, {} section nodes, {} steps of {:.3e} s in {:.1} s, window sigma {:.0} /s; {:.0}-{:.0} Hz: rms |dH|/|H| {:.3}, largest level difference {:+.2} dB",
        c.direction, c.x_m, c.elements, c.section_nodes, c.steps, c.time_step_s, c.seconds,
        c.window_decay_per_s, band_hz.0, band_hz.1, rms, worst_db
    );
    (rms, worst_db)
}

/// The fast comparison with the FE track: the short track at mid-span (x = 0.6 m) in
/// `direction`, a 15 ms record instead of the default 20 (a quarter less time; sigma 533 /s
/// instead of 400), 100-5000 Hz; returns (rms, largest level difference in dB).
fn short_track_comparison(direction: squeal::stability::rail::Direction) -> (f64, f64) {
    use squeal::stability::rail_fe::{compare, ImpulseSettings};
    let (loaded, _) = case3_track();
    let freqs: Vec<f64> = (1..=100).map(|i| 50.0 * i as f64).collect();
    let c = compare(
        &short_track_layout(),
        &loaded.case,
        loaded.scenario.wheel.material,
        0.6,
        direction,
        &ImpulseSettings {
            duration_s: 0.015,
            ..ImpulseSettings::default()
        },
        &freqs,
    )
    .unwrap();
    summarise(&c, (100.0, 5000.0), true)
}

#[test]
fn rail_beam_model_matches_the_fe_track_impulse_response_below_5_khz() {
    let (rms, worst_db) = short_track_comparison(squeal::stability::rail::Direction::Vertical);
    // Measured: rms 0.24, largest level difference 3.2 dB (0.27 and 3.6 dB with the 20 ms
    // record of the ignored test, whose finer mesh gives 0.28 and 3.7 dB): the FE side is
    // converged and the difference is the beam's: a
    // rigid sleeper mass where the FE sleeper is an elastic block, the pads acting on the
    // beam's axis where the FE pads pull on the rail foot, no cross-section deformation. The
    // bounds catch a model error of the size this comparison found (free instead of held rail
    // end rotations: rms 0.83, 10 dB) and leave the stated physics.
    assert!(rms < 0.4, "rms relative difference {rms}");
    assert!(worst_db.abs() < 5.0, "level difference {worst_db} dB");
}

/// The lateral-torsional beam against the FE track laterally, on the short track of the test
/// above: a force through the section's centre of mass bends and twists the rail (its shear
/// centre lies 30 mm lower), and the pads hold the foot.
#[test]
fn rail_lateral_torsional_beam_matches_the_fe_track_below_5_khz() {
    let (rms, worst_db) = short_track_comparison(squeal::stability::rail::Direction::Lateral);
    // Measured: rms 0.395, largest level difference -7.0 dB (at 4.5-4.7 kHz; within 2.7 dB
    // below 2.8 kHz). The beam without torsion was rms 1.80 and +17 dB on this track, so the
    // bounds catch a missing twist, a shear centre at the centroid or pads acting on the
    // axis; what they leave is the physics a beam lacks (web bending and foot flapping of the
    // FE section above about 3.5 kHz, the FE sleepers' roll and elasticity), for which the FE
    // track's own finer mesh moves the high-frequency peaks by up to 7 dB (docs/stability.md).
    assert!(rms < 0.6, "rms relative difference {rms}");
    assert!(worst_db.abs() < 10.0, "level difference {worst_db} dB");
}

/// The beam model against FE tracks in all three directions: the short track of the fast test
/// meshed finer (10 mm along the rail, 6 / 12 mm in the section: the FE side's mesh
/// convergence), and the case-3 demo's own track as the explicit runs mesh it (6 m, graded from
/// 6 mm at the contact to 120 mm) at the demo's contact (x = 2.0 m). About 4 minutes on the
/// 2-core machine: `cargo test --release --test stability_rail -- --ignored --exact
/// rail_beam_model_against_fe_tracks_in_three_directions --nocapture`.
#[test]
#[ignore]
fn rail_beam_model_against_fe_tracks_in_three_directions() {
    use squeal::stability::rail::Direction;
    use squeal::stability::rail_fe::{compare, ImpulseSettings};
    let (loaded, _) = case3_track();
    let freqs: Vec<f64> = (1..=100).map(|i| 50.0 * i as f64).collect();
    let mut fine = short_track_layout();
    fine.zone_element_length_m = 0.01;
    fine.far_element_length_m = 0.01;
    fine.running_surface_element_mm = 6.0;
    fine.section_element_mm = 12.0;
    let demo = loaded.scenario.track_layout();
    let demo_x = loaded.scenario.scenario.wheel_position.x_m;
    for (name, layout, x) in [
        ("short track, coarse", short_track_layout(), 0.6),
        ("short track, fine", fine, 0.6),
        ("case-3 demo track", demo, demo_x),
    ] {
        for d in [
            Direction::Vertical,
            Direction::Lateral,
            Direction::Longitudinal,
        ] {
            print!("{name}: ");
            let c = compare(
                &layout,
                &loaded.case,
                loaded.scenario.wheel.material,
                x,
                d,
                &ImpulseSettings::default(),
                &freqs,
            )
            .unwrap();
            let (rms, worst) = summarise(&c, (100.0, 5000.0), false);
            assert!(rms.is_finite() && worst.is_finite());
        }
    }
}

/// The rail body's 3 x 3 receptance at the contact, cross terms included, against direct
/// solves of the beams: `T H' T^T` with `T` the 1:40 rotation about x and `H'` the local matrix
/// in (x, y', z'): `H'_y'y'` the crown's lateral point receptance, `H'_y'z'` from a lateral
/// force to the vertical motion `y' phi` of a contact `y'` off the centre line, `H'_z'z'` the
/// vertical beam's plus `y'^2` times the twist's, `H'_xx` the bar's plus the crown's
/// longitudinal motion `-d_C theta` from vertical bending, `H'_xz'` from a vertical force to
/// that motion. Undamped (pads and ballast without damping), so the modal body's receptance is
/// exact but for its truncation.
#[test]
fn rail_cross_receptances_match_direct_solves() {
    use faer::c64;
    use squeal::stability::rail::{BeamModel, Direction, SectionPoint};
    use squeal::stability::rail_modes::{rail_body, rail_modal_model};
    let (_, mut track) = case3_track();
    track.pad[1] = 0.0;
    track.ballast[1] = 0.0;
    let (x, offset) = (2.0, 0.01);
    let models: Vec<_> = Direction::ALL
        .iter()
        .map(|&d| rail_modal_model(&track, d, x, 7_500.0).unwrap())
        .collect();
    let body = rail_body(&models, offset);
    let bar = track.beam_model(Direction::Longitudinal, x).unwrap();
    let lateral = track.beam_model(Direction::Lateral, x).unwrap();
    let vertical = track.beam_model(Direction::Vertical, x).unwrap();
    let crown = |m: &BeamModel| m.point(SectionPoint::Crown).to_vec();
    let lifted: Vec<(usize, f64)> = lateral
        .twist
        .iter()
        .map(|&(d, w)| (d, w * offset))
        .collect();
    let (sin, cos) = squeal::geometry::rail54e1::INCLINATION_RAD.sin_cos();
    let t = [[1.0, 0.0, 0.0], [0.0, cos, -sin], [0.0, sin, cos]];
    let freqs: Vec<f64> = (0..100).map(|i| 60.0 + 49.3 * i as f64).collect();
    let (mut sum, mut worst) = (0.0, 0.0f64);
    let (mut lateral_vertical, mut longitudinal_vertical) = (0.0f64, 0.0f64);
    for &f in &freqs {
        let s = [c64::new(0.0, std::f64::consts::TAU * f)];
        let one = |m: &BeamModel, a: &[(usize, f64)], b: &[(usize, f64)]| {
            m.transfer_between(&s, 0.0, a, b).unwrap()[0]
        };
        let h_ll = one(&lateral, &crown(&lateral), &crown(&lateral));
        let h_lw = one(&lateral, &crown(&lateral), &lifted);
        let h_ww =
            one(&lateral, &lifted, &lifted) + one(&vertical, &crown(&vertical), &crown(&vertical));
        let h_xx = one(&bar, &crown(&bar), &crown(&bar))
            + one(&vertical, &vertical.crown_axial, &vertical.crown_axial);
        let h_xw = one(&vertical, &crown(&vertical), &vertical.crown_axial);
        let zero = c64::new(0.0, 0.0);
        let local = [[h_xx, zero, h_xw], [zero, h_ll, h_lw], [h_xw, h_lw, h_ww]];
        let modal = body.receptance(s[0]);
        let (mut diff, mut norm) = (0.0, 0.0);
        let mut direct = [[zero; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                for i in 0..3 {
                    for j in 0..3 {
                        direct[a][b] += local[i][j] * (t[a][i] * t[b][j]);
                    }
                }
                diff += (modal[a][b] - direct[a][b]).norm().powi(2);
                norm += direct[a][b].norm().powi(2);
            }
        }
        let ratio =
            |a: usize, b: usize| direct[a][b].norm() / direct[a][a].norm().max(direct[b][b].norm());
        lateral_vertical = lateral_vertical.max(ratio(1, 2));
        longitudinal_vertical = longitudinal_vertical.max(ratio(0, 2));
        let e = (diff / norm).sqrt();
        sum += e * e;
        worst = worst.max(e);
    }
    let rms = (sum / freqs.len() as f64).sqrt();
    println!(
        "receptance matrix, 60-4941 Hz, contact {:.0} mm off the centre line: modal body \
         against direct solves rms {:.2} %, largest {:.2} %; largest cross terms against the \
         larger point receptance: lateral-vertical {lateral_vertical:.3}, \
         longitudinal-vertical {longitudinal_vertical:.3}",
        offset * 1e3,
        100.0 * rms,
        100.0 * worst,
    );
    // The point receptances' own modal models are within 1.7 % rms, 3.6 % at most
    // (rail_modal_model_matches_the_direct_frequency_response_below_5_khz); the twist's and the
    // bending rotation's residuals are not lumped, which the cross terms add.
    assert!(rms < 0.03, "{rms}");
    assert!(lateral_vertical > 0.01 && longitudinal_vertical > 0.01);
}
