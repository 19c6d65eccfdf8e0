//! Modes from the time domain: an impulse on a free steel plate, then the spectrum of the
//! response shows peaks at the eigenfrequencies of the engine's own discretisation (its
//! linearised one-point + hourglass stiffness with the same lumped mass), within 1 % for the
//! first five flexible modes. The eigenvalues come from a dense cyclic Jacobi solver written
//! here, independent of the engine's code path.
#![allow(clippy::needless_range_loop)]
mod jacobi;

use std::collections::BTreeMap;

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use squeal::explicit::element::{ElasticMaterial, Formulation};
use squeal::explicit::linearised::stiffness_triplets;
use squeal::explicit::model::Model;
use squeal::explicit::Solver;
use squeal::mesh::cuboid;

use jacobi::jacobi_eigenvalues;

#[test]
fn impulse_response_peaks_at_the_discretisation_eigenfrequencies() {
    let steel = ElasticMaterial {
        density_kg_per_m3: 7850.0,
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, steel)].into_iter().collect();
    let mesh = cuboid([8, 3, 2], [0.24, 0.09, 0.02], 1);
    let model = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
    // Eigenvalues of M^-1/2 K M^-1/2 (lumped M).
    let n = 3 * model.node_count();
    let mut k = vec![vec![0.0; n]; n];
    for (i, j, v) in stiffness_triplets(&model).unwrap() {
        k[i][j] += v;
    }
    let inv_sqrt_m: Vec<f64> = (0..n)
        .map(|d| 1.0 / model.nodal_mass_kg[d / 3].sqrt())
        .collect();
    for i in 0..n {
        for j in 0..n {
            k[i][j] *= inv_sqrt_m[i] * inv_sqrt_m[j];
        }
    }
    let ev = jacobi_eigenvalues(k);
    let freqs: Vec<f64> = ev
        .iter()
        .map(|&l| l.max(0.0).sqrt() / std::f64::consts::TAU)
        .collect();
    // Six rigid modes (tiny), then the flexible ones.
    assert!(freqs[5] < 1e-3 * freqs[6], "rigid modes: {:?}", &freqs[..8]);
    let flexible = &freqs[6..11];
    eprintln!("eigenfrequencies (Hz): {:?}", &freqs[6..14]);
    // Time domain: a velocity impulse at one corner, response at the opposite corner.
    let mut s = Solver::new(model, None).unwrap();
    // Kick a node off every symmetry plane; record all components at three probe nodes and sum
    // their power spectra, so that no mode sits on a nodal line of every signal.
    let n_nodes = s.u.len();
    let kick = 10;
    let probes = [n_nodes - 1, n_nodes / 2 + 3, 7];
    s.v[kick] = [0.01, 0.02, 0.03];
    let duration_s = 0.04;
    let steps = (duration_s / s.dt_s) as usize;
    let mut signals: Vec<Vec<f64>> = (0..9).map(|_| Vec::with_capacity(steps)).collect();
    for _ in 0..steps {
        s.step().unwrap();
        for (k, &p) in probes.iter().enumerate() {
            for c in 0..3 {
                signals[3 * k + c].push(s.u[p][c]);
            }
        }
    }
    // Hann-windowed, 8x zero-padded FFT; peaks refined by a parabola through log magnitudes.
    let len = (steps * 8).next_power_of_two();
    let fft = FftPlanner::new().plan_fft_forward(len);
    let mut power = vec![0.0; len / 2];
    for signal in &signals {
        let rms = (signal.iter().map(|x| x * x).sum::<f64>() / steps as f64)
            .sqrt()
            .max(1e-300);
        let mut buf: Vec<Complex<f64>> = vec![Complex::new(0.0, 0.0); len];
        for (i, x) in signal.iter().enumerate() {
            let w = 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / (steps - 1) as f64).cos();
            buf[i] = Complex::new(w * x / rms, 0.0);
        }
        fft.process(&mut buf);
        for (p, c) in power.iter_mut().zip(&buf) {
            *p += c.norm_sqr();
        }
    }
    let df = 1.0 / (len as f64 * s.dt_s);
    let mag: Vec<f64> = power.iter().map(|p| p.max(1e-300).ln()).collect();
    for &f in flexible {
        let (lo, hi) = (((0.98 * f) / df) as usize, ((1.02 * f) / df) as usize);
        let (imax, _) =
            (lo..=hi)
                .map(|i| (i, mag[i]))
                .fold((lo, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
        assert!(
            imax > lo && imax < hi,
            "no peak near {f:.1} Hz (maximum at the window edge)"
        );
        let (y0, y1, y2) = (mag[imax - 1], mag[imax], mag[imax + 1]);
        let shift = 0.5 * (y0 - y2) / (y0 - 2.0 * y1 + y2);
        let f_peak = (imax as f64 + shift) * df;
        eprintln!(
            "mode {f:.1} Hz: peak {f_peak:.1} Hz ({:+.3} %)",
            100.0 * (f_peak / f - 1.0)
        );
        // 1 %: the tolerance; the resolution of 40 ms is 25 Hz (1 % of ~2.5 kHz) before
        // zero padding and interpolation.
        assert!(
            (f_peak / f - 1.0).abs() < 0.01,
            "peak {f_peak} Hz vs mode {f} Hz"
        );
    }
}
