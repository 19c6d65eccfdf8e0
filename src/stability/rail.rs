//! The rail as beams on discrete supports, and its point receptances at the contact by direct
//! frequency-response solves.
//!
//! The track of the rolling model (docs/physics.md, "Rolling model"; Yang & Li 2019): a rail of
//! the scenario's length on rail pads over sleepers every `sleeper_spacing_m`, each sleeper
//! (here a rigid mass: the half sleeper block's mass) on ballast springs; rail ends and sleepers
//! held laterally and longitudinally. The rail is 54E1 (EN 13674-1: area 69.77 cm^2, second
//! moments 2337.9 cm^4 about the horizontal axis and 419.1 cm^4 about the vertical axis). Three
//! uncoupled one-dimensional models, each a finite-element beam with a node at the contact:
//!
//! * vertical: Timoshenko beam (bending stiffness E I_y, shear stiffness kappa G A, mass rho A,
//!   rotary inertia rho I_y; Timoshenko 1921), each pad a spring-damper from the rail nodes
//!   under it (the pad length, shared equally) to the sleeper mass, the sleeper on the ballast
//!   spring-damper to the ground; rail ends free to move vertically with their rotation held
//!   (the rolling model holds every node of the end faces along and across the track, which
//!   holds the section's rotation: the comparison with the FE track, [`super::rail_fe`], found
//!   this, 10 dB at 3-4 kHz on a 1.8 m track with free ends);
//! * lateral: Timoshenko beam in lateral bending (I_z), the pads in shear (the case's
//!   `shear_fraction` of the vertical stiffness and damping) to the sleepers, held laterally;
//!   rail ends clamped;
//! * longitudinal: a bar (E A, rho A) on the pads in shear; rail ends held.
//!
//! Elements: two-node Timoshenko elements with linear interpolation of deflection and rotation,
//! bending integrated exactly and shear at one point (reduced integration: no shear locking;
//! Hughes, The Finite Element Method, 1987, section 5.3), consistent mass; the bar likewise.
//! With 10 mm elements the bending wavelength at 5 kHz (about 0.4 m) has 40 elements.
//!
//! The receptance `H(w) = u_c / F_c` at the contact node solves `(K + i w C - w^2 M) u = e_c`
//! ([`super::banded`]). Left out (documented in docs/stability.md): rail torsion, web bending
//! and foot flapping (a beam has no cross-section deformation: the lateral receptance of the
//! real rail head above about 1 kHz is larger), the cross receptances (vertical-lateral through
//! the head's offset from the shear centre and the 1:40 inclination), the sleeper's own
//! flexibility and rocking, and the wheel's motion along the rail (the receptance is that of a
//! fixed point; the wheel covers 0.5 m of rail in the 18 ms the demo cases roll).

// Index loops mirror the matrix formulas term by term.
#![allow(clippy::needless_range_loop)]

use faer::c64;
use serde::Serialize;

use super::banded::BandMatrix;
use crate::material::Material;
use crate::{Error, Result};

/// Rail section and material (SI).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RailSection {
    /// The rail's steel.
    pub material: Material,
    /// Area (m^2).
    pub area_m2: f64,
    /// Second moment for vertical bending (m^4).
    pub second_moment_vertical_m4: f64,
    /// Second moment for lateral bending (m^4).
    pub second_moment_lateral_m4: f64,
    /// Timoshenko shear coefficient in vertical bending.
    pub shear_coefficient_vertical: f64,
    /// Timoshenko shear coefficient in lateral bending.
    pub shear_coefficient_lateral: f64,
}

impl RailSection {
    /// 54E1 (EN 13674-1 catalogue values; docs/references.md section 2) in the wheel's steel.
    /// Shear coefficients: 0.4 in vertical bending, the value commonly used for a rail (a
    /// thin web carries the shear; Thompson, Railway Noise and Vibration, 2009, ch. 3), and
    /// 0.5 laterally (the head and foot carry it; an assumption, an input).
    pub const UIC54: RailSection = RailSection {
        material: Material::STEEL,
        area_m2: 69.77e-4,
        second_moment_vertical_m4: 2337.9e-8,
        second_moment_lateral_m4: 419.1e-8,
        shear_coefficient_vertical: 0.4,
        shear_coefficient_lateral: 0.5,
    };
}

/// The track around the contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Track {
    /// Rail.
    pub rail: RailSection,
    /// Rail length (m); the rail runs from x = 0.
    pub length_m: f64,
    /// Sleeper spacing (m).
    pub sleeper_spacing_m: f64,
    /// x of the first sleeper (m).
    pub first_sleeper_x_m: f64,
    /// Pad length along the rail (m).
    pub pad_length_m: f64,
    /// Pad vertical stiffness (N/m) and damping (N s/m) per sleeper.
    pub pad: [f64; 2],
    /// Shear (lateral, longitudinal) values as a fraction of the vertical ones.
    pub pad_shear_fraction: f64,
    /// Ballast stiffness (N/m) and damping (N s/m) per (half) sleeper.
    pub ballast: [f64; 2],
    /// Sleeper mass (kg) per rail.
    pub sleeper_mass_kg: f64,
    /// Element length (m).
    pub element_length_m: f64,
}

/// Default element length (m): 40 elements per bending wavelength at 5 kHz (see module docs).
pub const ELEMENT_LENGTH_M: f64 = 0.01;

/// A direction of the rail's motion at the contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, PartialOrd, Ord, Hash)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Along the track (x).
    Longitudinal,
    /// Lateral (y).
    Lateral,
    /// Vertical (z).
    Vertical,
}

impl Direction {
    /// The three, in axis order x, y, z.
    pub const ALL: [Direction; 3] = [
        Direction::Longitudinal,
        Direction::Lateral,
        Direction::Vertical,
    ];
    /// Global axis index.
    pub fn axis(&self) -> usize {
        match self {
            Direction::Longitudinal => 0,
            Direction::Lateral => 1,
            Direction::Vertical => 2,
        }
    }
    /// Lower-case name.
    pub fn name(&self) -> &'static str {
        match self {
            Direction::Longitudinal => "longitudinal",
            Direction::Lateral => "lateral",
            Direction::Vertical => "vertical",
        }
    }
}

/// The assembled one-dimensional model: M, C, K as (i, j, value) entries, its band and the
/// contact dof.
pub struct BeamModel {
    /// Degrees of freedom.
    pub dofs: usize,
    /// Entries (i, j, m, c, k).
    pub entries: Vec<(usize, usize, f64, f64, f64)>,
    /// Lower = upper bandwidth.
    pub bandwidth: usize,
    /// The dof of the contact point's displacement in the direction.
    pub contact_dof: usize,
}

impl Track {
    /// Checks the ranges; `source` names the input.
    pub fn check(&self, source: &str) -> Result<()> {
        let positive = [
            (self.length_m, "track.length_m"),
            (self.sleeper_spacing_m, "track.sleeper_spacing_m"),
            (self.pad_length_m, "track.sleeper.pad_length_mm"),
            (self.pad[0], "rail_pad.stiffness_n_per_m"),
            (self.ballast[0], "ballast.stiffness_n_per_m"),
            (self.sleeper_mass_kg, "sleeper mass"),
            (self.element_length_m, "rail element length"),
        ];
        for (v, f) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::input(source, f, format!("must be > 0, got {v}")));
            }
        }
        if !(self.pad_shear_fraction > 0.0 && self.pad_shear_fraction <= 1.0) {
            return Err(Error::input(
                source,
                "rail_pad.shear_fraction",
                format!(
                    "must be in (0, 1] for the rail's lateral and longitudinal support, got {}",
                    self.pad_shear_fraction
                ),
            ));
        }
        Ok(())
    }

    /// Sleeper centres on the rail (m).
    pub fn sleepers(&self) -> Vec<f64> {
        let mut x = self.first_sleeper_x_m;
        let mut out = Vec::new();
        while x <= self.length_m + 1e-9 {
            if x >= -1e-9 {
                out.push(x);
            }
            x += self.sleeper_spacing_m;
        }
        out
    }

    /// Node positions: uniform spacing near `element_length_m` on either side of the contact
    /// point `x_contact_m`, which is a node; returns (positions, contact node).
    fn nodes(&self, x_contact_m: f64) -> (Vec<f64>, usize) {
        let h = self.element_length_m;
        let left = (x_contact_m / h).ceil().max(1.0) as usize;
        let right = ((self.length_m - x_contact_m) / h).ceil().max(1.0) as usize;
        let mut x: Vec<f64> = (0..left)
            .map(|i| x_contact_m * i as f64 / left as f64)
            .collect();
        x.extend(
            (0..=right)
                .map(|i| x_contact_m + (self.length_m - x_contact_m) * i as f64 / right as f64),
        );
        (x, left)
    }

    /// The model of one direction with the contact at `x_contact_m`.
    ///
    /// Kept in one piece: the node positions, the dof numbering (sleepers beside their pads),
    /// the held dofs and the element and support entries all index the same nodes and
    /// sleepers.
    pub fn beam_model(&self, direction: Direction, x_contact_m: f64) -> Result<BeamModel> {
        if !(x_contact_m > 0.0 && x_contact_m < self.length_m) {
            return Err(Error::input(
                "operating point",
                "wheel x",
                format!(
                    "the contact must lie on the rail, x in (0, {}) m, got {x_contact_m}",
                    self.length_m
                ),
            ));
        }
        let (x, contact_node) = self.nodes(x_contact_m);
        let rail = &self.rail;
        let g = rail.material.shear_modulus_pa();
        let (bending, i2, kappa) = match direction {
            Direction::Vertical => (
                true,
                rail.second_moment_vertical_m4,
                rail.shear_coefficient_vertical,
            ),
            Direction::Lateral => (
                true,
                rail.second_moment_lateral_m4,
                rail.shear_coefficient_lateral,
            ),
            Direction::Longitudinal => (false, 0.0, 0.0),
        };
        let per_node = if bending { 2 } else { 1 };
        let sleepers = self.sleepers();
        // Pad footprint nodes of each sleeper.
        let pad_nodes: Vec<Vec<usize>> = sleepers
            .iter()
            .map(|&xs| {
                let mut nodes: Vec<usize> = (0..x.len())
                    .filter(|&i| (x[i] - xs).abs() <= 0.5 * self.pad_length_m + 1e-9)
                    .collect();
                if nodes.is_empty() {
                    let nearest = (0..x.len())
                        .min_by(|&a, &b| (x[a] - xs).abs().total_cmp(&(x[b] - xs).abs()))
                        .unwrap_or(0);
                    nodes.push(nearest);
                }
                nodes
            })
            .collect();
        // Dof numbering: rail nodes in order, each sleeper's dof (vertical only) right after
        // the middle node of its pad, so that the band stays narrow.
        let held = |i: usize| direction != Direction::Vertical && (i == 0 || i + 1 == x.len());
        let mut node_dof = vec![usize::MAX; x.len()];
        let mut sleeper_dof = vec![usize::MAX; sleepers.len()];
        let mut next = 0usize;
        for i in 0..x.len() {
            node_dof[i] = next;
            next += per_node;
            if direction == Direction::Vertical {
                for (s, nodes) in pad_nodes.iter().enumerate() {
                    if nodes[nodes.len() / 2] == i {
                        sleeper_dof[s] = next;
                        next += 1;
                    }
                }
            }
        }
        let mut entries: Vec<(usize, usize, f64, f64, f64)> = Vec::new();
        // Held rail ends: the dof is removed by a flag; entries on it are dropped. The rolling
        // model holds every node of the rail's end faces along and across the track, which
        // also holds the section's bending rotations there (u_x = z theta_y = 0 for all z, and
        // likewise about z): a beam end with its rotation held.
        let fixed: Vec<bool> = {
            let mut f = vec![false; next];
            for i in 0..x.len() {
                if held(i) {
                    f[node_dof[i]] = true;
                }
                if bending && (i == 0 || i + 1 == x.len()) {
                    f[node_dof[i] + 1] = true;
                }
            }
            f
        };
        let (rho, e, a) = (
            rail.material.density_kg_per_m3,
            rail.material.youngs_modulus_pa,
            rail.area_m2,
        );
        for el in 0..x.len() - 1 {
            let l = x[el + 1] - x[el];
            let (d0, d1) = (node_dof[el], node_dof[el + 1]);
            if bending {
                let idx = [d0, d0 + 1, d1, d1 + 1];
                let (km, mm) = timoshenko_element(e * i2, kappa * g * a, rho * a, rho * i2, l);
                for r in 0..4 {
                    for c in 0..4 {
                        entries.push((idx[r], idx[c], mm[r][c], 0.0, km[r][c]));
                    }
                }
            } else {
                let idx = [d0, d1];
                let (k, m) = (e * a / l, rho * a * l / 6.0);
                for r in 0..2 {
                    for c in 0..2 {
                        let same = r == c;
                        entries.push((
                            idx[r],
                            idx[c],
                            m * if same { 2.0 } else { 1.0 },
                            0.0,
                            k * if same { 1.0 } else { -1.0 },
                        ));
                    }
                }
            }
        }
        let shear = if direction == Direction::Vertical {
            1.0
        } else {
            self.pad_shear_fraction
        };
        for (s, nodes) in pad_nodes.iter().enumerate() {
            let share = 1.0 / nodes.len() as f64;
            let (kp, cp) = (self.pad[0] * shear * share, self.pad[1] * shear * share);
            for &i in nodes {
                let d = node_dof[i];
                entries.push((d, d, 0.0, cp, kp));
                if direction == Direction::Vertical {
                    let sd = sleeper_dof[s];
                    entries.push((sd, sd, 0.0, cp, kp));
                    entries.push((d, sd, 0.0, -cp, -kp));
                    entries.push((sd, d, 0.0, -cp, -kp));
                }
            }
            if direction == Direction::Vertical {
                let sd = sleeper_dof[s];
                entries.push((
                    sd,
                    sd,
                    self.sleeper_mass_kg,
                    self.ballast[1],
                    self.ballast[0],
                ));
            }
        }
        entries.retain(|&(i, j, ..)| !fixed[i] && !fixed[j]);
        // Renumber without the held dofs.
        let mut map = vec![usize::MAX; next];
        let mut free = 0;
        for d in 0..next {
            if !fixed[d] {
                map[d] = free;
                free += 1;
            }
        }
        for entry in entries.iter_mut() {
            entry.0 = map[entry.0];
            entry.1 = map[entry.1];
        }
        let bandwidth = entries
            .iter()
            .map(|&(i, j, ..)| i.abs_diff(j))
            .max()
            .unwrap_or(0);
        Ok(BeamModel {
            dofs: free,
            entries,
            bandwidth,
            contact_dof: map[node_dof[contact_node]],
        })
    }

    /// Point receptance (m/N) in `direction` at `x_contact_m` for each frequency (Hz), by direct
    /// solves.
    pub fn receptance(
        &self,
        direction: Direction,
        x_contact_m: f64,
        frequencies_hz: &[f64],
    ) -> Result<Vec<c64>> {
        let model = self.beam_model(direction, x_contact_m)?;
        model.receptance(frequencies_hz)
    }
}

impl BeamModel {
    /// `u_c / F_c` at each frequency (Hz).
    pub fn receptance(&self, frequencies_hz: &[f64]) -> Result<Vec<c64>> {
        let s: Vec<c64> = frequencies_hz
            .iter()
            .map(|&f| c64::new(0.0, std::f64::consts::TAU * f))
            .collect();
        self.transfer(&s, 0.0)
    }

    /// The transfer function `u_c / F_c = e_c^T (K + s (C + alpha M) + s^2 M)^-1 e_c` at each
    /// Laplace variable `s` (1/s), with mass-proportional damping `alpha` (1/s) added: on the
    /// imaginary axis the receptance; at `s = sigma + i w` the Fourier transform of the impulse
    /// response windowed by `exp(-sigma t)`, which is how a measured (or simulated) impulse
    /// response is compared with it ([`super::rail_fe`]).
    pub fn transfer(&self, s: &[c64], mass_damping_per_s: f64) -> Result<Vec<c64>> {
        s.iter()
            .map(|&s| {
                let mut a = BandMatrix::zeros(self.dofs, self.bandwidth, self.bandwidth);
                for &(i, j, m, c, k) in &self.entries {
                    a.add(i, j, s * s * m + s * (c + mass_damping_per_s * m) + k)?;
                }
                let mut b = vec![c64::new(0.0, 0.0); self.dofs];
                b[self.contact_dof] = c64::new(1.0, 0.0);
                a.solve(&mut b)?;
                Ok(b[self.contact_dof])
            })
            .collect()
    }
}

/// Stiffness and consistent mass of a two-node Timoshenko element (w1, theta1, w2, theta2):
/// bending `EI/L` on the rotations, shear `kGA L B^T B` with `B = [-1/L, -1/2, 1/L, -1/2]`
/// (the shear strain `w' - theta` at the midpoint), mass `rho A L / 6 [2 1; 1 2]` on the
/// deflections and `rho I L / 6 [2 1; 1 2]` on the rotations.
pub fn timoshenko_element(
    ei: f64,
    kga: f64,
    rho_a: f64,
    rho_i: f64,
    l: f64,
) -> ([[f64; 4]; 4], [[f64; 4]; 4]) {
    let mut k = [[0.0; 4]; 4];
    let b = [-1.0 / l, -0.5, 1.0 / l, -0.5];
    for r in 0..4 {
        for c in 0..4 {
            k[r][c] = kga * l * b[r] * b[c];
        }
    }
    k[1][1] += ei / l;
    k[3][3] += ei / l;
    k[1][3] -= ei / l;
    k[3][1] -= ei / l;
    let mut m = [[0.0; 4]; 4];
    for (d, rho) in [(0, rho_a), (1, rho_i)] {
        m[d][d] = rho * l / 3.0;
        m[d + 2][d + 2] = rho * l / 3.0;
        m[d][d + 2] = rho * l / 6.0;
        m[d + 2][d] = rho * l / 6.0;
    }
    (k, m)
}

impl Track {
    /// The track of a rolling case: its scenario's rail length, sleeper layout and pad length,
    /// the case's pad, ballast and sleeper material (the half sleeper block's mass), 54E1 in the
    /// wheel's steel.
    pub fn from_case(loaded: &crate::model::case::LoadedCase) -> Result<Track> {
        Track::from_layout(
            &loaded.scenario.track_layout(),
            &loaded.case,
            loaded.scenario.wheel.material,
            &loaded.source.display().to_string(),
        )
    }

    /// The track of a track mesh's layout with a case's pads, ballast and sleeper material, the
    /// rail 54E1 in `rail_material` (the explicit track model of the same layout is the
    /// beam model's reference: [`super::rail_fe`]).
    pub fn from_layout(
        layout: &crate::mesh::track::TrackLayout,
        case: &crate::model::case::RollingCase,
        rail_material: Material,
        source: &str,
    ) -> Result<Track> {
        let track = Track {
            rail: RailSection {
                material: rail_material,
                ..RailSection::UIC54
            },
            length_m: layout.length_m,
            sleeper_spacing_m: layout.sleeper_spacing_m,
            first_sleeper_x_m: layout.first_sleeper_x_m,
            pad_length_m: layout.pad_length_m,
            pad: [
                case.rail_pad.stiffness_n_per_m,
                case.rail_pad.damping_n_s_per_m,
            ],
            pad_shear_fraction: case.rail_pad.shear_fraction,
            ballast: [
                case.ballast.stiffness_n_per_m,
                case.ballast.damping_n_s_per_m,
            ],
            sleeper_mass_kg: case.sleeper_material.density_kg_per_m3
                * layout.sleeper_width_m
                * layout.sleeper_height_m
                * (layout.sleeper_y_max_m - layout.sleeper_y_min_m),
            element_length_m: ELEMENT_LENGTH_M,
        };
        track.check(source)?;
        Ok(track)
    }
}
