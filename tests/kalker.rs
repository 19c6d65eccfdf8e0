//! Integration tests of `squeal::kalker` against independent references (docs/references.md, section 5:
//! Hertz check values, Kalker's Table E.3, Carter's 2D theory).

use squeal::kalker::halfspace::Grid;
use squeal::kalker::normal::solve_normal;
use squeal::kalker::{
    kalker_creep_coefficients, solve_force_prescribed, Creepages, ElementState, HertzContact,
    Material, Method, RollingSolver,
};
use squeal::Error;

fn relative_error(value: f64, reference: f64) -> f64 {
    (value / reference - 1.0).abs()
}

/// The check case of docs/references.md, section 5: R = 0.46 m flat tread on a R300 crown, steel.
fn reference_contact(normal_force_n: f64) -> HertzContact {
    HertzContact::wheel_on_rail(0.46, 0.3, normal_force_n, Material::STEEL).unwrap()
}

#[test]
fn hertz_matches_data_md() {
    // The reference gives 3 significant digits (7.16 mm: +-0.07 %); 0.5 % as the brief requires.
    for (force, a_mm, b_mm, p0_mpa) in [(100e3, 7.16, 5.39, 1238.0), (50e3, 5.68, 4.28, 982.0)] {
        let hertz = reference_contact(force);
        let errors = [
            relative_error(hertz.semi_axis_a_m * 1e3, a_mm),
            relative_error(hertz.semi_axis_b_m * 1e3, b_mm),
            relative_error(hertz.peak_pressure_pa * 1e-6, p0_mpa),
        ];
        println!(
            "Hertz {force} N: a {:.4} mm b {:.4} mm p0 {:.2} MPa errors {errors:?}",
            hertz.semi_axis_a_m * 1e3,
            hertz.semi_axis_b_m * 1e3,
            hertz.peak_pressure_pa * 1e-6
        );
        assert!(errors.iter().all(|&e| e < 0.005), "{errors:?}");
        // the closed form (docs/references.md, section 5) c = sqrt(ab) = [3 F rho E(e) / (4 pi E* sqrt(g))]^(1/3).
        let g = hertz.semi_axis_b_m / hertz.semi_axis_a_m;
        let (_, elliptic_e) =
            squeal::kalker::elliptic::complete_elliptic_integrals((1.0 - g * g).sqrt()).unwrap();
        let rho = 2.0 / (hertz.curvature_x_per_m + hertz.curvature_y_per_m);
        let c = (3.0 * force * rho * elliptic_e
            / (4.0 * std::f64::consts::PI * Material::STEEL.combined_modulus_pa() * g.sqrt()))
        .cbrt();
        assert!(relative_error(hertz.mean_semi_axis_m(), c) < 1e-12);
    }
}

#[test]
fn exact_normal_solver_reproduces_hertz() {
    let hertz = reference_contact(100e3);
    let (a, b) = (hertz.semi_axis_a_m, hertz.semi_axis_b_m);
    let grid = Grid::centered(1.1 * a, 1.1 * b, 60, 60);
    let mut gap = vec![0.0; grid.len()];
    for i in 0..grid.nx {
        for j in 0..grid.ny {
            gap[grid.index(i, j)] = hertz.curvature_x_per_m * grid.x_m(i).powi(2)
                + hertz.curvature_y_per_m * grid.y_m(j).powi(2);
        }
    }
    let normal = solve_normal(&grid, &gap, 100e3, &Material::STEEL, 1e-12).unwrap();
    // Semi-axes from the pressure moments: for Hertz, sum x^2 p / sum p = a^2 / 5.
    let (mut sum, mut sum_x2, mut sum_y2, mut peak) = (0.0, 0.0, 0.0, 0.0_f64);
    for i in 0..grid.nx {
        for j in 0..grid.ny {
            let p = normal.pressure_pa[grid.index(i, j)];
            sum += p;
            sum_x2 += p * grid.x_m(i).powi(2);
            sum_y2 += p * grid.y_m(j).powi(2);
            peak = peak.max(p);
        }
    }
    let a_est = (5.0 * sum_x2 / sum).sqrt();
    let b_est = (5.0 * sum_y2 / sum).sqrt();
    let area = normal.contact_elements() as f64 * grid.element_area_m2();
    let force = sum * grid.element_area_m2();
    let errors = [
        relative_error(a_est, a),
        relative_error(b_est, b),
        relative_error(peak, hertz.peak_pressure_pa),
        relative_error(area, std::f64::consts::PI * a * b),
        relative_error(force, 100e3),
        relative_error(normal.approach_m, hertz.approach_m),
    ];
    println!(
        "normal solver vs Hertz (a, b, p0, area, Fn, approach): {errors:?}, {} iterations",
        normal.iterations
    );
    // 2 % (brief): discretisation error of piecewise-constant pressure on ~27 elements per semi-axis.
    assert!(errors.iter().all(|&e| e < 0.02), "{errors:?}");
}

/// Kalker's linear theory, C interpolated at the actual a/b and nu.
fn linear_coefficients(hertz: &HertzContact) -> squeal::kalker::CreepCoefficients {
    kalker_creep_coefficients(
        hertz.semi_axis_a_m / hertz.semi_axis_b_m,
        hertz.material.poisson_ratio,
    )
    .unwrap()
}

#[test]
fn small_creepage_approaches_linear_theory() {
    let hertz = reference_contact(100e3);
    let solver = RollingSolver::new(&hertz, 0.3, Method::Exact, 60).unwrap();
    let coefficients = linear_coefficients(&hertz);
    let g = Material::STEEL.shear_modulus_pa();
    let c2 = hertz.semi_axis_a_m * hertz.semi_axis_b_m;
    let c3 = c2 * c2.sqrt();
    let creep = |xi, eta, phi_per_m| solver.solve(&Creepages { xi, eta, phi_per_m }).unwrap();
    let longitudinal = -creep(1e-6, 0.0, 0.0).force_x_n / (g * c2 * 1e-6);
    let lateral = -creep(0.0, 1e-6, 0.0).force_y_n / (g * c2 * 1e-6);
    let spin = -creep(0.0, 0.0, 1e-4).force_y_n / (g * c3 * 1e-4);
    let errors = [
        relative_error(longitudinal, coefficients.c11),
        relative_error(lateral, coefficients.c22),
        relative_error(spin, coefficients.c23),
    ];
    println!("linear theory: C11 {longitudinal:.4} C22 {lateral:.4} C23 {spin:.4} vs table {coefficients:?}: errors {errors:?}");
    // Measured (60 x 60): 1.0 %, 1.5 %, 1.3 %. Tolerance 3 %: ~1-2 % discretisation error of
    // the first-order steady-rolling scheme plus ~1 % from interpolating the coarse table rows.
    assert!(errors.iter().all(|&e| e < 0.03), "{errors:?}");
}

#[test]
fn large_creepage_is_full_slip() {
    let hertz = reference_contact(100e3);
    let mu = 0.3;
    let exact = RollingSolver::new(&hertz, mu, Method::Exact, 40)
        .unwrap()
        .solve(&Creepages {
            xi: 0.05,
            eta: 0.02,
            phi_per_m: 0.0,
        })
        .unwrap();
    let fastsim = RollingSolver::new(&hertz, mu, Method::Fastsim, 100)
        .unwrap()
        .solve(&Creepages {
            xi: 0.05,
            eta: 0.02,
            phi_per_m: 0.0,
        })
        .unwrap();
    for solution in [&exact, &fastsim] {
        let ratio = solution.force_x_n.hypot(solution.force_y_n) / (mu * 100e3);
        println!(
            "{:?}: |F|/(mu Fn) = {ratio:.8}, adhesion {}",
            solution.method,
            solution.adhesion_area_fraction()
        );
        // All elements slip; the exact theory's slip directions still deviate slightly from the
        // rigid slip (Poisson coupling), so |F| is below mu Fn by < 1e-3 (measured 6e-6 at xi 0.05, eta 0.02).
        assert!(ratio <= 1.0 + 1e-12 && ratio > 0.999, "{ratio}");
        assert!(solution.state.iter().all(|s| *s != ElementState::Adhesion));
        // Force opposes the creepage.
        assert!(solution.force_x_n < 0.0 && solution.force_y_n < 0.0);
    }
}

/// Carter's 2D result integrated strip by strip over a very elongated ellipse (b >> a): each
/// strip y is a 2D problem with peak pressure p0 sqrt(1 - y^2/b^2), and Carter gives
/// Fx/(mu Fn) = 2k - k^2 with k = |xi| E* / (2 mu p0(y)) (k = |xi| R/(mu a) with p0 = a E*/(2R)),
/// or 1 beyond saturation.
fn carter_strip_integral(kappa_centre: f64) -> f64 {
    let steps = 200_000;
    let (mut weighted, mut weights) = (0.0, 0.0);
    for step in 0..steps {
        let s = -1.0 + (step as f64 + 0.5) * 2.0 / steps as f64;
        let weight = 1.0 - s * s; // strip load ~ p0(y) a(y) ~ 1 - s^2
        let kappa = kappa_centre / weight.sqrt();
        let fraction = if kappa >= 1.0 {
            1.0
        } else {
            2.0 * kappa - kappa * kappa
        };
        weighted += weight * fraction;
        weights += weight;
    }
    weighted / weights
}

#[test]
fn elongated_contact_matches_carter() {
    let material = Material::STEEL;
    let mu = 0.3;
    let normal_force_n = 100e3;
    // Curvature ratio 60 gives b/a ~ 11: nearly plane strain in each strip.
    let hertz =
        HertzContact::from_curvatures(1.0 / 0.92, 1.0 / 0.92 / 60.0, normal_force_n, material)
            .unwrap();
    let (a, b) = (hertz.semi_axis_a_m, hertz.semi_axis_b_m);
    let grid = Grid::centered(1.05 * a, 1.02 * b, 60, 50);
    let mut gap = vec![0.0; grid.len()];
    for i in 0..grid.nx {
        for j in 0..grid.ny {
            gap[grid.index(i, j)] = hertz.curvature_x_per_m * grid.x_m(i).powi(2)
                + hertz.curvature_y_per_m * grid.y_m(j).powi(2);
        }
    }
    let solver = RollingSolver::exact_from_gap(grid, &gap, normal_force_n, material, mu).unwrap();
    let saturation_creepage = 2.0 * mu * hertz.peak_pressure_pa / material.combined_modulus_pa();
    println!("b/a = {:.2}", b / a);
    for kappa in [0.2, 0.5, 0.8] {
        let xi = kappa * saturation_creepage;
        let solution = solver
            .solve(&Creepages {
                xi,
                eta: 0.0,
                phi_per_m: 0.0,
            })
            .unwrap();
        let ratio = -solution.force_x_n / (mu * normal_force_n);
        let reference = carter_strip_integral(kappa);
        // Centre strip: adhesion must be one block at the leading edge, of length ~ 2a' with
        // a'/a = 1 - kappa (Carter).
        let j_centre = grid.ny / 2;
        let states: Vec<ElementState> = (0..grid.nx)
            .map(|i| solution.state[grid.index(i, j_centre)])
            .collect();
        let leading = states
            .iter()
            .rposition(|s| *s != ElementState::Exterior)
            .unwrap();
        let first_adhesion = states
            .iter()
            .position(|s| *s == ElementState::Adhesion)
            .unwrap();
        let last_adhesion = states
            .iter()
            .rposition(|s| *s == ElementState::Adhesion)
            .unwrap();
        // One block, reaching the leading edge (the rim element itself, where the traction bound
        // vanishes, may be discretely in slip).
        assert!(
            leading - last_adhesion <= 1,
            "adhesion not at the leading edge: {states:?}"
        );
        assert!(
            states[first_adhesion..=last_adhesion]
                .iter()
                .all(|s| *s == ElementState::Adhesion),
            "{states:?}"
        );
        let adhesion_length = (leading - first_adhesion + 1) as f64 * grid.dx_m;
        let centre_half_width = a; // centre strip half-width
        let expected_length = 2.0 * centre_half_width * (1.0 - kappa);
        println!(
            "kappa {kappa}: Fx/(mu Fn) {ratio:.5} vs Carter strips {reference:.5} ({:.2} %), adhesion {:.3} mm vs {:.3} mm",
            100.0 * relative_error(ratio, reference),
            adhesion_length * 1e3,
            expected_length * 1e3
        );
        // 2 % (brief). Measured (b/a = 13.5, 60 x 50 elements): 1.05 %, 0.69 %, 0.19 % at
        // kappa 0.2, 0.5, 0.8: residual 3D effect of a finite b/a plus the first-order scheme.
        assert!(relative_error(ratio, reference) < 0.02);
        // Adhesion length within two elements plus 3 % of a (measured: within 0.06 mm, < 0.5 element).
        assert!((adhesion_length - expected_length).abs() < 2.0 * grid.dx_m + 0.03 * a);
    }
}

#[test]
fn fastsim_versus_exact() {
    let hertz = reference_contact(100e3);
    let mu = 0.3;
    let exact = RollingSolver::new(&hertz, mu, Method::Exact, 60).unwrap();
    let fastsim = RollingSolver::new(&hertz, mu, Method::Fastsim, 100).unwrap();
    let coefficients = linear_coefficients(&hertz);
    let g = Material::STEEL.shear_modulus_pa();
    let c2 = hertz.semi_axis_a_m * hertz.semi_axis_b_m;
    // FASTSIM reproduces linear theory exactly without slip (by its flexibilities; the largest
    // friction coefficient accepted, 2, so that not even the rim slips: at xi = 1e-7 the
    // traction is of order G xi = 8 kPa, against mu p of tens of MPa in the outermost cells).
    let no_slip = RollingSolver::new(&hertz, 2.0, Method::Fastsim, 100).unwrap();
    let small = no_slip
        .solve(&Creepages {
            xi: 1e-7,
            eta: 0.0,
            phi_per_m: 0.0,
        })
        .unwrap();
    // Exact along each strip (midpoint tractions); the midpoint sum over 100 strips of the
    // quadratic strip force a(y)^2 errs by 1/(2 n^2) = 5e-5.
    let linear_error = relative_error(-small.force_x_n / (g * c2 * 1e-7), coefficients.c11);
    println!("FASTSIM linear C11 error {linear_error:e}");
    assert!(linear_error < 1e-4);
    let mut largest = 0.0_f64;
    for (xi, eta, phi_per_m) in [
        (5e-4, 0.0, 0.0),
        (1e-3, 0.0, 0.0),
        (2e-3, 0.0, 0.0),
        (0.0, 1e-3, 0.0),
        (1e-3, 1e-3, 0.0),
        (0.0, 0.0, 0.5),
    ] {
        let creepages = Creepages { xi, eta, phi_per_m };
        let reference = exact.solve(&creepages).unwrap();
        let simplified = fastsim.solve(&creepages).unwrap();
        let difference = (simplified.force_x_n - reference.force_x_n)
            .hypot(simplified.force_y_n - reference.force_y_n)
            / reference.force_x_n.hypot(reference.force_y_n);
        println!(
            "xi {xi} eta {eta} phi {phi_per_m}: exact ({:.0}, {:.0}) N, FASTSIM ({:.0}, {:.0}) N, difference {:.2} %",
            reference.force_x_n,
            reference.force_y_n,
            simplified.force_x_n,
            simplified.force_y_n,
            100.0 * difference
        );
        largest = largest.max(difference);
    }
    // Measured (exact 60 x 60, FASTSIM 100 x 100, mu = 0.3, 100 kN): FASTSIM is higher by
    // 4.1 % (xi 5e-4), 5.5 % (1e-3), 1.5 % (2e-3), 5.3 % (eta 1e-3), 4.8 % (combined) and
    // 5.3 % (pure spin 0.5 1/m); ~1-1.5 % of it is the exact solver's own offset from the
    // table coefficients FASTSIM is built on. Literature puts the mid-range difference at up to
    // 10-20 % (largest for spin); assert the measured maximum with margin.
    assert!(largest < 0.08, "{largest}");
}

#[test]
fn force_prescribed_inverts_creepage_prescribed() {
    let hertz = reference_contact(100e3);
    let mu = 0.3;
    for (method, grid) in [(Method::Fastsim, 100), (Method::Exact, 24)] {
        let solver = RollingSolver::new(&hertz, mu, method, grid).unwrap();
        let creepages = Creepages {
            xi: -1.2e-3,
            eta: 6e-4,
            phi_per_m: 0.1,
        };
        let forward = solver.solve(&creepages).unwrap();
        let inverse = solve_force_prescribed(
            &solver,
            (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
            forward.force_x_n,
            forward.force_y_n,
            0.1,
        )
        .unwrap();
        let errors = [
            relative_error(inverse.creepages.xi, creepages.xi),
            relative_error(inverse.creepages.eta, creepages.eta),
        ];
        println!(
            "{method:?}: forces ({:.1}, {:.1}) N -> creepage errors {errors:?} in {} iterations",
            forward.force_x_n, forward.force_y_n, inverse.iterations
        );
        assert!(inverse.unique);
        assert!(errors.iter().all(|&e| e < 1e-6), "{errors:?}");
    }
}

#[test]
fn saturated_forces_are_not_unique() {
    let hertz = reference_contact(100e3);
    let mu = 0.3;
    let solver = RollingSolver::new(&hertz, mu, Method::Fastsim, 60).unwrap();
    let limit = mu * 100e3;
    let (fx, fy) = (0.8 * limit, 0.6 * limit); // |F| = mu Fn exactly
    let result = solve_force_prescribed(
        &solver,
        (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
        fx,
        fy,
        0.0,
    )
    .unwrap();
    assert!(!result.unique);
    assert!(result.note.contains("not unique (saturated)"));
    // Creepage points against the force.
    assert!(result.creepages.xi < 0.0 && result.creepages.eta < 0.0);
    // The force is reproduced in size and direction (FASTSIM's force direction at saturation is
    // not opposite to the creepage, since L1 != L2; the solver turns the creepage angle).
    assert!(
        relative_error(result.solution.force_x_n, fx) < 2e-6,
        "{}",
        result.solution.force_x_n
    );
    assert!(
        relative_error(result.solution.force_y_n, fy) < 2e-6,
        "{}",
        result.solution.force_y_n
    );
}

#[test]
fn bad_input_is_reported() {
    let hertz = reference_contact(100e3);
    let is_input = |error: Error, field: &str| {
        matches!(&error, Error::Input { field: f, .. } if f == field) && error.exit_code() == 2
    };
    // mu <= 0.
    assert!(is_input(
        RollingSolver::new(&hertz, 0.0, Method::Fastsim, 50)
            .err()
            .unwrap(),
        "--mu"
    ));
    assert!(is_input(
        RollingSolver::new(&hertz, -0.1, Method::Exact, 50)
            .err()
            .unwrap(),
        "--mu"
    ));
    // Fn <= 0.
    assert!(is_input(
        HertzContact::wheel_on_rail(0.46, 0.3, 0.0, Material::STEEL)
            .err()
            .unwrap(),
        "--normal-force-n"
    ));
    assert!(is_input(
        HertzContact::wheel_on_rail(0.46, 0.3, -5.0, Material::STEEL)
            .err()
            .unwrap(),
        "--normal-force-n"
    ));
    // Grid too coarse.
    assert!(is_input(
        RollingSolver::new(&hertz, 0.3, Method::Exact, 6)
            .err()
            .unwrap(),
        "--grid"
    ));
    // |F_t| > mu Fn.
    let solver = RollingSolver::new(&hertz, 0.3, Method::Fastsim, 50).unwrap();
    let error = solve_force_prescribed(
        &solver,
        (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
        30e3,
        1e3,
        0.0,
    )
    .err()
    .unwrap();
    assert!(is_input(error, "--force-x-n/--force-y-n"));
    // Non-Hertzian curvature.
    assert!(HertzContact::from_curvatures(1.0, -1.0, 1e3, Material::STEEL).is_err());
}

#[test]
fn profile_gap_feeds_the_exact_solver() {
    use squeal::kalker::geometry::{curvatures_at, profile_gap, WheelCircle};
    // Flat tread on an exact R300 circular crown, given as closures (as the S1002/54E1 profile
    // code will be): curvatures by finite differences, then the exact normal problem on the
    // profile gap must reproduce Hertz on the same curvatures.
    let crown = |y: f64| -(0.3 - (0.09 - y * y).sqrt());
    let flat = |_: f64| 0.0;
    let (curvature_x, curvature_y) = curvatures_at(0.46, flat, crown, 0.0, 1e-4).unwrap();
    let hertz =
        HertzContact::from_curvatures(curvature_x, curvature_y, 100e3, Material::STEEL).unwrap();
    let grid = Grid::centered(1.1 * hertz.semi_axis_a_m, 1.1 * hertz.semi_axis_b_m, 50, 50);
    let gap = profile_gap(&grid, 0.46, flat, crown, 0.0, WheelCircle::Exact).unwrap();
    let solver = RollingSolver::exact_from_gap(grid, &gap, 100e3, Material::STEEL, 0.3).unwrap();
    let (_, normal) = solver.normal_solution().unwrap();
    // Semi-axes from the pressure moments (sum x^2 p / sum p = a^2/5 for Hertz).
    let (mut sum, mut sum_x2, mut sum_y2) = (0.0, 0.0, 0.0);
    for i in 0..grid.nx {
        for j in 0..grid.ny {
            let p = normal.pressure_pa[grid.index(i, j)];
            sum += p;
            sum_x2 += p * grid.x_m(i).powi(2);
            sum_y2 += p * grid.y_m(j).powi(2);
        }
    }
    let peak = normal.pressure_pa.iter().cloned().fold(0.0, f64::max);
    let errors = [
        relative_error((5.0 * sum_x2 / sum).sqrt(), hertz.semi_axis_a_m),
        relative_error((5.0 * sum_y2 / sum).sqrt(), hertz.semi_axis_b_m),
        relative_error(peak, hertz.peak_pressure_pa),
    ];
    println!("profile gap vs Hertz (a, b, p0): {errors:?}");
    // 2 %: the circles differ from the quadratic gap by ~x^4/(8R^3), far below the element size.
    assert!(errors.iter().all(|&e| e < 0.02), "{errors:?}");
}
