//! The rim ring's nodal-diameter decomposition on a free wheel struck at one rim point, in the
//! explicit engine (issue 57, item 3): each harmonic n of the ring's lateral velocity peaks at
//! the axisymmetric solver's frequency of the lowest axial mode of that n, within 2 %, for
//! n = 0..6; and at that frequency the other harmonics are far below it, so that modes of
//! different n are never confused.
//!
//! Independent reference: `squeal axisym` (Fourier-harmonic Q9 section, free, the same wheel
//! and half axle), a different discretisation and solver from the explicit engine's 3D one-point
//! hexahedra.
//!
//! Set-up: the default wheel with its half axle, 20 mm body elements, free. The hammer is a
//! half-sine force pulse of 0.3 ms on the rim-face nodes within 25 mm of one point, lateral and
//! radial (a velocity kick of one node instead rings the one-point hexahedra's local modes of
//! several kHz, which swamp every harmonic: measured 2026-11-29). The engine runs undamped;
//! the ring (64 nodes to n = 10) is read every 50 us. Each harmonic's power
//! `PSD(c_n) + PSD(s_n)` is one Hann segment of the whole record, zero-padded to bins of at
//! most 2 Hz; its peak near the mode is refined by the log-parabola of the peak finder.
//! The suite's test runs the demo wheel's 64 divisions around; the long one 256, where the 2 %
//! of the issue is met (the coarse circumference's error is measured in the suite test's
//! comment).
use std::collections::BTreeMap;
use std::path::Path;

use squeal::analysis::identify::{ModeFamily, ModeRef};

mod common;
use squeal::explicit::{ElasticMaterial, Formulation, Model, Solver};
use squeal::input::wheel::WheelSpec;
use squeal::mesh::material;
use squeal::mesh::wheel::{wheel_mesh, WheelPlacement};
use squeal::model::rolling::{rim_face_nodes, ring_nodes};
use squeal::signal::resolution::welch_for_resolution;
use squeal::signal::ring::RingDft;
use squeal::signal::{find_spectral_peaks, welch, PeakSearch};

const RING_NODES: usize = 64;
const N_MAX: usize = 10;

/// The free wheel's modes from the axisymmetric solver.
fn axisym_modes(out: &Path) -> Vec<ModeRef> {
    let wheel = "data/wheels/ns_intercity_920.json";
    common::squeal_modes(&["axisym", "--wheel", wheel, "--clamp", "none"], out)
}

/// The lateral harmonics `c_n(t)`, `s_n(t)` of the struck free wheel's ring, and their sample
/// rate.
fn struck_wheel_ring(duration_s: f64, divisions: usize) -> (Vec<Vec<[f64; 2]>>, f64) {
    let mut spec: WheelSpec =
        squeal::input::read_json(Path::new("data/wheels/ns_intercity_920.json")).unwrap();
    spec.mesh.element_size_mm = 20.0;
    spec.mesh.circumferential_divisions = divisions;
    spec.mesh.inner_circumferential_divisions = divisions / 2;
    let mesh = wheel_mesh(&spec, None, &WheelPlacement::default());
    let centre = [0.0; 3];
    let all: Vec<usize> = (0..mesh.nodes.len()).collect();
    let rim = rim_face_nodes(&mesh.nodes, &all, centre);
    let ring = ring_nodes(&mesh.nodes, &rim, centre, RING_NODES, N_MAX, "test").unwrap();
    // The struck point: a node of the rim face, away from the ring's first node.
    let struck = rim[rim.len() / 3];
    let materials: BTreeMap<u32, ElasticMaterial> = [
        (material::WHEEL, spec.material),
        (material::AXLE, spec.material),
    ]
    .into_iter()
    .collect();
    let model = Model::from_mesh(mesh, &materials, Formulation::default(), "struck wheel").unwrap();
    let mut s = Solver::new(model, None).unwrap();
    // The hammer: a half-sine force pulse of 0.3 ms (its spectrum falls to zero at 5 kHz, as
    // a hard hammer tip's) on the rim-face nodes within 25 mm of the struck node, lateral and
    // radial, so that the axial and the in-plane modes are both rung and the local modes of
    // one kicked node (several kHz in one-point hexahedra) are not.
    let p = s.model.mesh.nodes[struck];
    let r = (p[0] * p[0] + p[2] * p[2]).sqrt();
    let direction = [0.5 * p[0] / r, 1.0, 0.5 * p[2] / r];
    let patch: Vec<usize> = rim
        .iter()
        .copied()
        .filter(|&n| {
            let q = s.model.mesh.nodes[n];
            (0..3).map(|i| (q[i] - p[i]).powi(2)).sum::<f64>() < 0.025f64.powi(2)
        })
        .collect();
    let pulse_s = 3e-4;
    let sample_interval_s = 50e-6;
    let every = (sample_interval_s / s.dt_s).round().max(1.0) as usize;
    let sample_rate_hz = 1.0 / (every as f64 * s.dt_s);
    let steps = (duration_s / s.dt_s) as usize;
    let dft = RingDft::new(RING_NODES, ring.theta0_rad, N_MAX).unwrap();
    let mut values = vec![0.0; RING_NODES];
    let (mut c, mut sn) = (vec![0.0; N_MAX + 1], vec![0.0; N_MAX + 1]);
    let mut harmonics: Vec<Vec<[f64; 2]>> = vec![Vec::new(); N_MAX + 1];
    for step in 0..steps {
        let t = step as f64 * s.dt_s;
        if t < pulse_s {
            // Velocity increments of the pulse: 1 m/s in all over the patch's pulse.
            let dv = 1.0 * (std::f64::consts::PI * t / pulse_s).sin() * std::f64::consts::PI
                / (2.0 * pulse_s)
                * s.dt_s;
            for &nd in &patch {
                for (v, d) in s.v[nd].iter_mut().zip(direction) {
                    *v += d * dv;
                }
            }
        }
        s.step().unwrap();
        if step % every != 0 {
            continue;
        }
        for (k, &nd) in ring.nodes.iter().enumerate() {
            values[k] = s.v[nd][1];
        }
        dft.transform(&values, &mut c, &mut sn);
        for n in 0..=N_MAX {
            harmonics[n].push([c[n], sn[n]]);
        }
    }
    (harmonics, sample_rate_hz)
}

/// `PSD(c_n) + PSD(s_n)` of each harmonic on common bins.
fn harmonic_psds(harmonics: &[Vec<[f64; 2]>], fs: f64) -> (Vec<f64>, Vec<Vec<f64>>) {
    let len = harmonics[0].len();
    // One Hann segment of the whole record, zero-padded to bins of at most 2 Hz.
    let params = welch_for_resolution(len, fs, 2.0, Some(len)).unwrap();
    let mut freqs = Vec::new();
    let mut out = Vec::new();
    for h in harmonics {
        let mut sum: Vec<f64> = Vec::new();
        for part in 0..2 {
            let x: Vec<f64> = h.iter().map(|v| v[part]).collect();
            let psd = welch(&x, fs, &params).unwrap();
            if sum.is_empty() {
                freqs = psd.frequency_hz.to_vec();
                sum = psd.psd_per_hz.to_vec();
            } else {
                for (a, b) in sum.iter_mut().zip(psd.psd_per_hz.iter()) {
                    *a += b;
                }
            }
        }
        out.push(sum);
    }
    (freqs, out)
}

/// Each harmonic n = 0..6 of the struck wheel's ring against the axisymmetric solver's lowest
/// axial mode of that n: its peak within `bound` of it, and 20 dB above every other harmonic
/// there.
fn check_harmonics(divisions: usize, duration_s: f64, bound: f64) {
    let dir = std::env::temp_dir().join(format!("squeal_struck_wheel_{}", std::process::id()));
    let modes = axisym_modes(&dir);
    let (harmonics, fs) = struck_wheel_ring(duration_s, divisions);
    let (freqs, psds) = harmonic_psds(&harmonics, fs);
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for n in 0..=6usize {
        // The lowest flexible axial mode of n (for n = 0 and 1 it moves the axle too).
        let f_mode = modes
            .iter()
            .filter(|m| m.nodal_diameters as usize == n && m.family == ModeFamily::Axial)
            .filter(|m| m.frequency_hz > 10.0)
            .map(|m| m.frequency_hz)
            .fold(f64::INFINITY, f64::min);
        // Its peak in harmonic n: the largest within +-10 % (wider than the 2 % asked, so that
        // a miss shows as a number rather than as no peak).
        let search = PeakSearch {
            min_frequency_hz: 0.9 * f_mode,
            max_frequency_hz: 1.1 * f_mode,
            max_peaks: 1,
            ..Default::default()
        };
        let peaks = find_spectral_peaks(&freqs[..], &psds[n][..], &search).unwrap();
        let Some(peak) = peaks.first() else {
            failures.push(format!("n = {n}: no peak within 10 % of {f_mode:.1} Hz"));
            continue;
        };
        let f = peak.refined_frequency_hz;
        let error = (f - f_mode) / f_mode;
        // The other harmonics at that bin: how far below harmonic n they lie.
        let k = peak.index;
        let others = (0..=N_MAX)
            .filter(|&m| m != n)
            .map(|m| psds[m][k])
            .fold(0.0f64, f64::max);
        let separation_db = 10.0 * (psds[n][k] / others).log10();
        report.push(format!(
            "n = {n}: {f:.1} Hz against {f_mode:.1} Hz ({:+.2} %), {separation_db:.0} dB above the other harmonics there",
            100.0 * error
        ));
        if error.abs() > bound {
            failures.push(format!("n = {n}: {:+.2} % off", 100.0 * error));
        }
        // 20 dB: a factor 100 in power, so that a peak of n is not mistaken for another n.
        if separation_db < 20.0 {
            failures.push(format!(
                "n = {n}: only {separation_db:.1} dB above another harmonic"
            ));
        }
    }
    eprintln!("{divisions} divisions:\n{}", report.join("\n"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        failures.is_empty(),
        "{}\n{}",
        failures.join("\n"),
        report.join("\n")
    );
}

/// The suite's test: the demo model's wheel (64 divisions around), 40 ms. What it checks is the
/// decomposition: each harmonic's peak is its own n's mode and stands 20 dB above the other
/// harmonics there. Its frequency bound is the coarse mesh's discretisation error, not the
/// decomposition's: measured 2026-11-29 (60 ms records) at 64 / 128 / 192 divisions, the
/// explicit wheel's (0,2) lies +7.3 / +2.9 / +2.1 % above the axisymmetric solver's, (0,3) +4.1 /
/// +1.8 / +1.2 %, (0,1) +4.9 / +2.1 / +1.6 % (the flat facets of a coarse circumference stiffen
/// the low n; the limit at infinitely many divisions, by Richardson extrapolation in 1/N^2, is
/// +1.4 % for (0,2): the 20 mm section's own error). 10 % bounds the 64-division errors with room
/// for a changed mesh generator; the 2 % accuracy is the long test's, on 256 divisions.
#[test]
fn each_harmonic_of_a_struck_free_wheel_peaks_at_its_own_mode() {
    check_harmonics(64, 0.04, 0.10);
}

/// The bound: within 2 % of the axisymmetric solver for n = 0..6, on 256 divisions
/// around (67 k elements, about 3 minutes on 2 cores): by the extrapolation above, (0,2) at
/// +1.8 % and the others lower.
#[test]
#[ignore]
fn a_struck_free_wheel_with_a_fine_circumference_peaks_within_2_percent() {
    check_harmonics(256, 0.06, 0.02);
}
