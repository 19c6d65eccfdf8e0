//! Squeal stability analysis (`squeal::stability`, `squeal stability`): each check against an
//! independent reference (closed forms, a second solution method, the modal solver's own
//! normalisation, bad input exit codes).

use squeal::stability::contact::{ContactFrame, TangentialLaw};
use squeal::stability::system::{Body, CoupledSystem, DofTag, ModalBody, ModalDof};

/// A unit-mass coordinate of body `body`.
fn dof(body: Body, mode: usize, omega: f64, zeta: f64, shape: [f64; 3]) -> ModalDof {
    ModalDof {
        omega_rad_per_s: omega,
        damping_ratio: zeta,
        contact_shape: shape,
        tag: DofTag {
            body,
            mode,
            label: format!("{body:?} {mode}"),
            family: None,
            circles_diameters: None,
            frequency_hz: omega / std::f64::consts::TAU,
        },
    }
}

/// Hoffmann, Fischer, Begout, Gaul (2002): a mass m on a belt, held by two springs k1, k2 at
/// angles a1, a2 to the belt, pressed on it by a normal contact spring k3, with Coulomb
/// friction mu (belt sliding under the mass). In (x tangential, y normal) the structure's
/// stiffness is `[[k11, k12], [k12, k22]]`, `k11 = k1 c1^2 + k2 c2^2`, `k12 = k1 s1 c1 - k2 s2
/// c2`, `k22 = k1 s1^2 + k2 s2^2`; friction adds `mu k3` to (x, y) and the contact spring k3 to
/// (y, y). `det(K - m w^2 I) = 0` gives `w^2 = (tr +- sqrt(D)) / 2m` with `D = (k11 - k22')^2 +
/// 4 k12 (k12 + mu k3)`, `k22' = k22 + k3`: flutter (a complex pair, one growing) where D < 0,
/// from `mu_c = -((k11 - k22')^2 + 4 k12^2) / (4 k3 k12)` (k12 < 0), the two modes merging at
/// `w^2 = (k11 + k22') / 2m`.
struct Hoffmann {
    m: f64,
    k11: f64,
    k12: f64,
    k22: f64,
    k3: f64,
}

impl Hoffmann {
    fn new() -> Hoffmann {
        let (k1, k2, a1, a2) = (0.5e6_f64, 1.0e6_f64, 30f64.to_radians(), 45f64.to_radians());
        Hoffmann {
            m: 1.0,
            k11: k1 * a1.cos().powi(2) + k2 * a2.cos().powi(2),
            k12: k1 * a1.sin() * a1.cos() - k2 * a2.sin() * a2.cos(),
            k22: k1 * a1.sin().powi(2) + k2 * a2.sin().powi(2),
            k3: 1.0e6,
        }
    }

    fn mu_critical(&self) -> f64 {
        let kk = self.k22 + self.k3;
        -((self.k11 - kk).powi(2) + 4.0 * self.k12 * self.k12) / (4.0 * self.k3 * self.k12)
    }

    fn merging_omega(&self) -> f64 {
        ((self.k11 + self.k22 + self.k3) / (2.0 * self.m)).sqrt()
    }

    /// The growth rate above mu_c from the closed form: lambda^2 = -(tr -+ i sqrt(-D)) / 2m.
    fn growth_rate(&self, mu: f64) -> f64 {
        let kk = self.k22 + self.k3;
        let d = (self.k11 - kk).powi(2) + 4.0 * self.k12 * (self.k12 + mu * self.k3);
        assert!(d < 0.0);
        let l2 = faer::c64::new(-(self.k11 + kk), (-d).sqrt()) / (2.0 * self.m);
        l2.sqrt().re.abs()
    }

    /// The model through the library: the structure's two modes (unit modal mass) as the
    /// "wheel" body in (x, z) (z the contact normal), the belt as rigid ground, the Coulomb law
    /// of the belt sliding under the mass (slip of the mass over the belt along -x).
    fn system(&self, mu: f64) -> CoupledSystem {
        // Closed-form 2 x 2 symmetric eigen-decomposition of the structure (no friction, no k3).
        let (a, b, c) = (self.k11 / self.m, self.k12 / self.m, self.k22 / self.m);
        let mean = 0.5 * (a + c);
        let half = (0.25 * (a - c).powi(2) + b * b).sqrt();
        let mut wheel = ModalBody::default();
        for (mode, l) in [mean - half, mean + half].into_iter().enumerate() {
            // (b, l - a) is an eigenvector of [[a, b], [b, c]] for eigenvalue l.
            let v = [b, l - a];
            let norm = (v[0] * v[0] + v[1] * v[1]).sqrt() * self.m.sqrt();
            wheel.dofs.push(dof(
                Body::Wheel,
                mode,
                l.sqrt(),
                0.0,
                [v[0] / norm, 0.0, v[1] / norm],
            ));
        }
        let law = TangentialLaw::coulomb(1.0e3, self.k3, 1.0, [-1.0, 0.0], mu).unwrap();
        CoupledSystem {
            wheel,
            rail: ModalBody::default(),
            contact: law.linear_contact(&ContactFrame::wheel_rail(0.0)),
        }
    }

    fn largest_growth(&self, mu: f64) -> f64 {
        self.system(mu)
            .eigen()
            .unwrap()
            .iter()
            .map(|e| e.growth_rate_per_s)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

#[test]
fn hoffmann_flutter_onset_and_merging_frequency_match_the_closed_form() {
    let h = Hoffmann::new();
    let mu_c = h.mu_critical();
    assert!(mu_c > 0.1 && mu_c < 2.0, "mu_c {mu_c}");
    // Below mu_c the undamped system is neutrally stable: every growth rate is rounding.
    // Threshold 1e-3 /s: the eigenvalues of the nearly defective matrix carry errors of order
    // sqrt(eps) |lambda| = 1e-5 /s; above mu_c the growth rises as sqrt(mu - mu_c) and passes
    // 1e-3 /s within 1e-10 of mu_c (sqrt(4 k3 |k12| dmu) / (4 w) with k3 |k12| = 2.8e11).
    let threshold = 1e-3;
    assert!(h.largest_growth(0.5 * mu_c).abs() < threshold);
    let (mut lo, mut hi) = (0.5 * mu_c, 1.5 * mu_c);
    assert!(h.largest_growth(hi) > threshold);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if h.largest_growth(mid) > threshold {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let onset = 0.5 * (lo + hi);
    assert!(
        (onset / mu_c - 1.0).abs() < 1e-6,
        "onset {onset} vs closed form {mu_c}"
    );
    // Just above the onset both modes sit at the merging frequency.
    let eig = h.system(mu_c * (1.0 + 1e-6)).eigen().unwrap();
    let growing = eig.iter().find(|e| e.growth_rate_per_s > 0.0).unwrap();
    let w = h.merging_omega();
    assert!(
        (growing.omega_rad_per_s / w - 1.0).abs() < 1e-3,
        "merging {} vs {w}",
        growing.omega_rad_per_s
    );
    // Above it the growth rate follows the closed form.
    for factor in [1.1, 1.5] {
        let mu = factor * mu_c;
        let got = h.largest_growth(mu);
        let want = h.growth_rate(mu);
        assert!((got / want - 1.0).abs() < 1e-8, "mu {mu}: {got} vs {want}");
    }
    println!(
        "Hoffmann: mu_c closed form {mu_c:.9}, eigenvalue onset {onset:.9}; merging {:.3} Hz",
        w / std::f64::consts::TAU
    );
}

#[test]
fn falling_friction_oscillator_grows_at_minus_c_plus_n_slope_over_2m() {
    // m x'' + c x' + k x = N mu(v_belt - x'): linearised, m x'' + (c + N mu') x' + k x = 0, whose
    // eigenvalues have the real part -(c + N mu') / 2m exactly (underdamped).
    let (m, k, c, n) = (2.5_f64, 4.0e6_f64, 30.0_f64, 2.0e3_f64);
    for slope in [-0.2, -0.02, 0.0, 0.05] {
        let omega = (k / m).sqrt();
        let zeta = c / (2.0 * (k * m).sqrt());
        let wheel = ModalBody {
            dofs: vec![dof(Body::Wheel, 0, omega, zeta, [1.0 / m.sqrt(), 0.0, 0.0])],
            gyroscopic: Vec::new(),
        };
        let mut law = TangentialLaw::coulomb(n, 1.0e9, 10.0, [-1.0, 0.0], 0.4).unwrap();
        law.friction_slope_s_per_m = slope;
        let system = CoupledSystem {
            wheel,
            rail: ModalBody::default(),
            contact: law.linear_contact(&ContactFrame::wheel_rail(0.0)),
        };
        let eig = system.eigen().unwrap();
        assert_eq!(eig.len(), 1);
        let want = -(c + n * slope) / (2.0 * m);
        let got = eig[0].growth_rate_per_s;
        assert!(
            (got - want).abs() <= 1e-9 * want.abs().max(1.0),
            "slope {slope}: {got} vs {want}"
        );
    }
}
