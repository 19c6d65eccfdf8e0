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
//! * lateral: a lateral-torsional beam. The shear centre S's lateral deflection `v` and
//!   bending rotation `psi` (Timoshenko, lateral bending `E I_z`), and the twist `phi` about S
//!   with Saint-Venant and warping torsion, `G J phi'^2 + E I_w phi''^2` (Vlasov's thin-walled
//!   beam; Timoshenko & Gere, Theory of Elastic Stability, 1961, ch. 5). A point at height z of
//!   the section moves laterally by `v - (z - z_S) phi`, so the section's kinetic energy per
//!   length is `rho A v_C^2 + rho I_pS phi^2` with `v_C = v - (z_C - z_S) phi` at the centroid
//!   and `I_pS` the polar moment about S: the mass couples bending and twist. The pads act at
//!   the foot: in shear (the case's `shear_fraction` of the vertical stiffness and damping) on
//!   the foot's lateral motion `v + (z_S - z_foot) phi`, and vertically on the twist through
//!   the foot nodes' lateral arms (`k sum share_i y_i^2`, the FE pads' node shares). Sleepers
//!   held laterally and in roll; rail ends clamped (the FE track holds the end faces along and
//!   across the track: no deflection, bending rotation, twist or warping). The contact is on the
//!   crown, `v - (z_crown - z_S) phi`; the FE comparison observes the centroid. The section's
//!   torsion constant, warping constant and shear centre come from our own solve of the 54E1
//!   section ([`crate::fem::section_properties`]);
//! * longitudinal: a bar (E A, rho A) on the pads in shear; rail ends held.
//!
//! Elements: two-node Timoshenko elements with linear interpolation of deflection and rotation,
//! bending integrated exactly and shear at one point (reduced integration: no shear locking;
//! Hughes, The Finite Element Method, 1987, section 5.3), consistent mass; the bar likewise.
//! With 10 mm elements the bending wavelength at 5 kHz (about 0.4 m) has 40 elements.
//!
//! The receptance `H(w) = u_c / F_c` at the contact node solves `(K + i w C - w^2 M) u = e_c`
//! ([`super::banded`]). Left out (documented in docs/stability.md): web bending and foot
//! flapping (a beam has no cross-section deformation: the lateral receptance of the real rail
//! head above about 1 kHz is larger; the cross receptances, vertical-lateral through the 1:40
//! inclination and a contact off the centre line, longitudinal-vertical through the crown's
//! height above the bending axis, are the rail body's: [`super::rail_modes::rail_body`]), the
//! sleeper's own flexibility and rocking, and the wheel's motion along the rail (the receptance is that of a
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
    /// Saint-Venant torsion constant J (m^4).
    pub torsion_constant_m4: f64,
    /// Warping constant `I_w` about the shear centre (m^6).
    pub warping_constant_m6: f64,
    /// Depth of the centroid below the crown (m).
    pub centroid_below_crown_m: f64,
    /// Depth of the shear centre below the crown (m).
    pub shear_centre_below_crown_m: f64,
    /// Depth of the foot's underside below the crown: the rail's height (m).
    pub height_m: f64,
}

impl RailSection {
    /// 54E1 (EN 13674-1 catalogue values; docs/references.md section 2) in the wheel's steel.
    /// Shear coefficients: 0.4 in vertical bending, the value commonly used for a rail (a
    /// thin web carries the shear; Thompson, Railway Noise and Vibration, 2009, ch. 3), and
    /// 0.5 laterally (the head and foot carry it; an assumption, an input). Torsion constant,
    /// warping constant, centroid and shear centre: [`crate::fem::section_properties`] on the
    /// project's 54E1 outline meshed at 1 mm (tests/section_properties.rs recomputes them:
    /// 190.0 cm^4, 11 435 cm^6, 83.86 and 113.48 mm below the crown; the catalogue gives no
    /// torsion figures).
    pub const UIC54: RailSection = RailSection {
        material: Material::STEEL,
        area_m2: 69.77e-4,
        second_moment_vertical_m4: 2337.9e-8,
        second_moment_lateral_m4: 419.1e-8,
        shear_coefficient_vertical: 0.4,
        shear_coefficient_lateral: 0.5,
        torsion_constant_m4: 190.0e-8,
        warping_constant_m6: 11435.0e-12,
        centroid_below_crown_m: 83.86e-3,
        shear_centre_below_crown_m: 113.48e-3,
        height_m: crate::geometry::rail54e1::HEIGHT_MM * 1e-3,
    };

    /// `int |p - S|^2 dA` (m^4): the polar moment about the shear centre.
    pub fn polar_moment_about_shear_centre_m4(&self) -> f64 {
        let d = self.shear_centre_below_crown_m - self.centroid_below_crown_m;
        self.second_moment_vertical_m4 + self.second_moment_lateral_m4 + self.area_m2 * d * d
    }
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
    /// The pad's arm in roll (m): `sqrt(sum share_i y_i^2)` over the rail-foot nodes that carry
    /// the pad's vertical springs, y from the rail's centre line; its vertical stiffness times
    /// the arm squared resists the twist.
    pub pad_roll_arm_m: f64,
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

/// The assembled one-dimensional model: M, C, K as (i, j, value) entries, its band, and the
/// contact point's and the centroid's displacement in the direction as weighted sums of dofs.
pub struct BeamModel {
    /// Degrees of freedom.
    pub dofs: usize,
    /// Entries (i, j, m, c, k).
    pub entries: Vec<(usize, usize, f64, f64, f64)>,
    /// Lower = upper bandwidth.
    pub bandwidth: usize,
    /// The contact point's displacement `sum w_i u_i` as (dof, w): the crown at the contact
    /// station (laterally the shear centre's deflection and the twist).
    pub contact: Vec<(usize, f64)>,
    /// The section centroid's displacement at the contact station, likewise (the FE track's
    /// mass-weighted section mean).
    pub centroid: Vec<(usize, f64)>,
    /// The twist (rad) at the contact station (lateral model only; empty otherwise): a point of
    /// the crown `y'` off the rail's centre line moves vertically by `y' phi`.
    pub twist: Vec<(usize, f64)>,
    /// The crown's longitudinal motion from vertical bending, `-d_C theta` with `d_C` the
    /// crown's height above the centroid (vertical model only; empty otherwise): a section
    /// rotated by theta moves a point at height z along the rail by `-z theta`.
    pub crown_axial: Vec<(usize, f64)>,
}

/// Which point of the section a transfer function loads and observes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionPoint {
    /// The crown: where the wheel acts.
    Crown,
    /// The centroid: a load through the centre of mass, its mean displacement.
    Centroid,
}

impl BeamModel {
    /// The weights of `point`.
    pub fn point(&self, point: SectionPoint) -> &[(usize, f64)] {
        match point {
            SectionPoint::Crown => &self.contact,
            SectionPoint::Centroid => &self.centroid,
        }
    }

    /// `sum w_i x_i` over the weights of `point`.
    pub fn at(&self, point: SectionPoint, x: impl Fn(usize) -> f64) -> f64 {
        self.point(point).iter().map(|&(d, w)| w * x(d)).sum()
    }
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
            (self.pad_roll_arm_m, "rail pad roll arm"),
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
    /// The phases index the same nodes and sleepers: node positions, the pads' footprints, the
    /// dof numbering (sleepers beside their pads), the held dofs, the element and support
    /// entries, the renumbering without the held dofs, and the observed points' weights.
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
        let per_node = dofs_per_node(direction);
        let pad_nodes = self.pad_nodes(&x);
        let dofs = DofNumbering::new(direction, x.len(), per_node, &pad_nodes);
        let fixed = dofs.held(direction, per_node);
        let mut entries: Vec<Entry> = Vec::new();
        self.element_entries(direction, &x, &dofs.node, &mut entries);
        self.support_entries(direction, &pad_nodes, &dofs, &mut entries);
        entries.retain(|&(i, j, ..)| !fixed[i] && !fixed[j]);
        let (map, free) = renumber(&fixed);
        for entry in entries.iter_mut() {
            entry.0 = map[entry.0];
            entry.1 = map[entry.1];
        }
        let bandwidth = entries
            .iter()
            .map(|&(i, j, ..)| i.abs_diff(j))
            .max()
            .unwrap_or(0);
        let weights = SectionWeights::new(&self.rail, direction, map[dofs.node[contact_node]]);
        Ok(BeamModel {
            dofs: free,
            entries,
            bandwidth,
            contact: weights.contact,
            centroid: weights.centroid,
            twist: weights.twist,
            crown_axial: weights.crown_axial,
        })
    }

    /// The rail nodes under each sleeper's pad (within half the pad length of its centre; the
    /// nearest node when none is), in the sleepers' order.
    fn pad_nodes(&self, x: &[f64]) -> Vec<Vec<usize>> {
        let sleepers = self.sleepers();
        // Pad footprint nodes of each sleeper.
        sleepers
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
            .collect()
    }

    /// The elements' stiffness and mass entries along the rail at nodes `x`: Timoshenko beams
    /// (vertical), lateral-torsional beams (lateral) or bars (longitudinal).
    fn element_entries(
        &self,
        direction: Direction,
        x: &[f64],
        node_dof: &[usize],
        entries: &mut Vec<Entry>,
    ) {
        let rail = &self.rail;
        let g = rail.material.shear_modulus_pa();
        let (rho, e, a) = (
            rail.material.density_kg_per_m3,
            rail.material.youngs_modulus_pa,
            rail.area_m2,
        );
        let mut add_block = |idx: &[usize], km: &[&[f64]], mm: &[&[f64]]| {
            for r in 0..idx.len() {
                for c in 0..idx.len() {
                    entries.push((idx[r], idx[c], mm[r][c], 0.0, km[r][c]));
                }
            }
        };
        for el in 0..x.len() - 1 {
            let l = x[el + 1] - x[el];
            let (d0, d1) = (node_dof[el], node_dof[el + 1]);
            match direction {
                Direction::Vertical => {
                    let (km, mm) = timoshenko_element(
                        e * rail.second_moment_vertical_m4,
                        rail.shear_coefficient_vertical * g * a,
                        rho * a,
                        rho * rail.second_moment_vertical_m4,
                        l,
                    );
                    add_block(
                        &[d0, d0 + 1, d1, d1 + 1],
                        &km.each_ref().map(|r| r.as_slice()),
                        &mm.each_ref().map(|r| r.as_slice()),
                    );
                }
                Direction::Lateral => {
                    let (km, mm) = lateral_torsional_element(rail, l);
                    let idx: Vec<usize> = (0..4)
                        .map(|d| d0 + d)
                        .chain((0..4).map(|d| d1 + d))
                        .collect();
                    add_block(
                        &idx,
                        &km.each_ref().map(|r| r.as_slice()),
                        &mm.each_ref().map(|r| r.as_slice()),
                    );
                }
                Direction::Longitudinal => {
                    let (k, m) = (e * a / l, rho * a * l / 6.0);
                    add_block(
                        &[d0, d1],
                        &[&[k, -k], &[-k, k]],
                        &[&[2.0 * m, m], &[m, 2.0 * m]],
                    );
                }
            }
        }
    }

    /// The supports' entries, sleeper by sleeper: each pad shared equally by the rail nodes of
    /// its footprint (vertically to the sleeper mass, in shear to the ground otherwise, and
    /// laterally also resisting the twist), and vertically the sleeper on the ballast.
    fn support_entries(
        &self,
        direction: Direction,
        pad_nodes: &[Vec<usize>],
        dofs: &DofNumbering,
        entries: &mut Vec<Entry>,
    ) {
        let rail = &self.rail;
        let shear = if direction == Direction::Vertical {
            1.0
        } else {
            self.pad_shear_fraction
        };
        // Lateral: the foot's lateral motion is v + (z_S - z_foot) phi.
        let foot_arm_m = rail.height_m - rail.shear_centre_below_crown_m;
        for (s, nodes) in pad_nodes.iter().enumerate() {
            let share = 1.0 / nodes.len() as f64;
            let (kp, cp) = (self.pad[0] * shear * share, self.pad[1] * shear * share);
            for &i in nodes {
                let d = dofs.node[i];
                match direction {
                    Direction::Vertical => {
                        let sd = dofs.sleeper[s];
                        entries.push((d, d, 0.0, cp, kp));
                        entries.push((sd, sd, 0.0, cp, kp));
                        entries.push((d, sd, 0.0, -cp, -kp));
                        entries.push((sd, d, 0.0, -cp, -kp));
                    }
                    Direction::Longitudinal => entries.push((d, d, 0.0, cp, kp)),
                    Direction::Lateral => {
                        // Shear spring on (v, phi) with the arm: [1, h; h, h^2] k.
                        let (v, phi) = (d, d + 2);
                        let h = foot_arm_m;
                        for (r, c, w) in [(v, v, 1.0), (v, phi, h), (phi, v, h), (phi, phi, h * h)]
                        {
                            entries.push((r, c, 0.0, w * cp, w * kp));
                        }
                        // The vertical springs' resistance to the twist.
                        let roll = self.pad_roll_arm_m * self.pad_roll_arm_m * share;
                        entries.push((phi, phi, 0.0, self.pad[1] * roll, self.pad[0] * roll));
                    }
                }
            }
            if direction == Direction::Vertical {
                let sd = dofs.sleeper[s];
                entries.push((
                    sd,
                    sd,
                    self.sleeper_mass_kg,
                    self.ballast[1],
                    self.ballast[0],
                ));
            }
        }
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

/// An entry of the assembled matrices: (i, j, m, c, k).
type Entry = (usize, usize, f64, f64, f64);

/// The number of dofs at each rail node of `direction`'s model.
fn dofs_per_node(direction: Direction) -> usize {
    // Dofs per rail node: longitudinal u; vertical (w, theta); lateral (v, psi, phi, phi').
    match direction {
        Direction::Longitudinal => 1,
        Direction::Vertical => 2,
        Direction::Lateral => 4,
    }
}

/// The dof numbering of one direction's model, held dofs included.
struct DofNumbering {
    /// First dof of each rail node.
    node: Vec<usize>,
    /// The dof of each sleeper (vertical model only; `usize::MAX` otherwise).
    sleeper: Vec<usize>,
    /// Dofs in all.
    count: usize,
}

impl DofNumbering {
    /// Numbers `n_nodes` rail nodes of `per_node` dofs in order and, vertically, each sleeper's
    /// dof right after the middle node of its pad (`pad_nodes`), so that the band stays narrow.
    fn new(
        direction: Direction,
        n_nodes: usize,
        per_node: usize,
        pad_nodes: &[Vec<usize>],
    ) -> Self {
        // Dof numbering: rail nodes in order, each sleeper's dof (vertical only) right after
        // the middle node of its pad, so that the band stays narrow.
        let mut node_dof = vec![usize::MAX; n_nodes];
        let mut sleeper_dof = vec![usize::MAX; pad_nodes.len()];
        let mut next = 0usize;
        for i in 0..n_nodes {
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
        DofNumbering {
            node: node_dof,
            sleeper: sleeper_dof,
            count: next,
        }
    }

    /// The held dofs (true) at the rail ends.
    fn held(&self, direction: Direction, per_node: usize) -> Vec<bool> {
        let n_nodes = self.node.len();
        // Held rail ends: the dof is removed by a flag; entries on it are dropped. The rolling
        // model holds every node of the rail's end faces along and across the track, which
        // also holds the section's bending rotations there (u_x = z theta_y = 0 for all z, and
        // likewise about z), its twist (u_y = -(z - z_S) phi = 0) and its warping
        // (u_x = omega phi' = 0). Vertically the ends stay free to move.
        let mut f = vec![false; self.count];
        for i in [0, n_nodes - 1] {
            let first = if direction == Direction::Vertical {
                1
            } else {
                0
            };
            for d in first..per_node {
                f[self.node[i] + d] = true;
            }
        }
        f
    }
}

/// The free dofs' numbers without the held ones (`usize::MAX` for a held dof), and their count.
fn renumber(fixed: &[bool]) -> (Vec<usize>, usize) {
    // Renumber without the held dofs.
    let mut map = vec![usize::MAX; fixed.len()];
    let mut free = 0;
    for d in 0..fixed.len() {
        if !fixed[d] {
            map[d] = free;
            free += 1;
        }
    }
    (map, free)
}

/// The weights of the observed points at the contact station, whose (renumbered) first dof
/// is `c`: see the fields of [`BeamModel`].
struct SectionWeights {
    contact: Vec<(usize, f64)>,
    centroid: Vec<(usize, f64)>,
    twist: Vec<(usize, f64)>,
    crown_axial: Vec<(usize, f64)>,
}

impl SectionWeights {
    /// The contact (crown), centroid, twist and crown-axial weights of `direction`'s model
    /// (the lateral ones through the shear centre's deflection and the twist).
    fn new(rail: &RailSection, direction: Direction, c: usize) -> Self {
        // Where the contact and the centroid sit on the section: the lateral motion at depth
        // h below the crown is v - (z - z_S) phi = v - (d_S - h) phi, d_S the shear centre's
        // depth.
        let (contact, centroid, twist) = if direction == Direction::Lateral {
            let d_s = rail.shear_centre_below_crown_m;
            (
                vec![(c, 1.0), (c + 2, -d_s)],
                vec![(c, 1.0), (c + 2, -(d_s - rail.centroid_below_crown_m))],
                vec![(c + 2, 1.0)],
            )
        } else {
            (vec![(c, 1.0)], vec![(c, 1.0)], Vec::new())
        };
        let crown_axial = if direction == Direction::Vertical {
            vec![(c + 1, -rail.centroid_below_crown_m)]
        } else {
            Vec::new()
        };
        SectionWeights {
            contact,
            centroid,
            twist,
            crown_axial,
        }
    }
}

impl BeamModel {
    /// `u_c / F_c` at each frequency (Hz).
    pub fn receptance(&self, frequencies_hz: &[f64]) -> Result<Vec<c64>> {
        let s: Vec<c64> = frequencies_hz
            .iter()
            .map(|&f| c64::new(0.0, std::f64::consts::TAU * f))
            .collect();
        self.transfer(&s, 0.0, SectionPoint::Crown)
    }

    /// The transfer function `u_c / F_c = e_c^T (K + s (C + alpha M) + s^2 M)^-1 e_c` at each
    /// Laplace variable `s` (1/s), with mass-proportional damping `alpha` (1/s) added: on the
    /// imaginary axis the receptance; at `s = sigma + i w` the Fourier transform of the impulse
    /// response windowed by `exp(-sigma t)`, which is how a measured (or simulated) impulse
    /// response is compared with it ([`super::rail_fe`]). The load acts at `point` and the
    /// displacement is observed there.
    pub fn transfer(
        &self,
        s: &[c64],
        mass_damping_per_s: f64,
        point: SectionPoint,
    ) -> Result<Vec<c64>> {
        let weights = self.point(point);
        self.transfer_between(s, mass_damping_per_s, weights, weights)
    }

    /// The transfer function from a load `sum w_i f_i` (the weights `load`: the generalised
    /// force of a unit force there) to the displacement `sum v_i u_i` (`response`).
    pub fn transfer_between(
        &self,
        s: &[c64],
        mass_damping_per_s: f64,
        load: &[(usize, f64)],
        response: &[(usize, f64)],
    ) -> Result<Vec<c64>> {
        s.iter()
            .map(|&s| {
                let mut a = BandMatrix::zeros(self.dofs, self.bandwidth, self.bandwidth);
                for &(i, j, m, c, k) in &self.entries {
                    a.add(i, j, s * s * m + s * (c + mass_damping_per_s * m) + k)?;
                }
                let mut b = vec![c64::new(0.0, 0.0); self.dofs];
                for &(d, w) in load {
                    b[d] += c64::new(w, 0.0);
                }
                a.solve(&mut b)?;
                Ok(response
                    .iter()
                    .fold(c64::new(0.0, 0.0), |sum, &(d, w)| sum + b[d] * w))
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

/// Hermite cubics on an element of length `l` at `xi = x / l`: values, first and second
/// derivatives in x, for the dofs (phi1, phi1', phi2, phi2').
fn hermite(xi: f64, l: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    (
        [
            1.0 - 3.0 * x2 + 2.0 * x3,
            l * (xi - 2.0 * x2 + x3),
            3.0 * x2 - 2.0 * x3,
            l * (x3 - x2),
        ],
        [
            6.0 * (x2 - xi) / l,
            1.0 - 4.0 * xi + 3.0 * x2,
            6.0 * (xi - x2) / l,
            3.0 * x2 - 2.0 * xi,
        ],
        [
            (12.0 * xi - 6.0) / (l * l),
            (6.0 * xi - 4.0) / l,
            (6.0 - 12.0 * xi) / (l * l),
            (6.0 * xi - 2.0) / l,
        ],
    )
}

/// Stiffness and consistent mass of a two-node lateral-torsional element, dofs
/// `(v1, psi1, phi1, phi1', v2, psi2, phi2, phi2')` (module docs): lateral Timoshenko bending
/// on (v, psi) ([`timoshenko_element`]); torsion on Hermite cubics,
/// `G J int phi'^2 + E I_w int phi''^2` and mass `rho I_pS int phi^2 + rho I_w int phi'^2`
/// (the warping's own inertia); the centroid's offset above the shear centre, `d = z_C - z_S`,
/// couples the linear v and the cubic phi in the mass by `-rho A d int v phi`. Integrated by
/// four Gauss points, exact for these polynomials (degree 6 at most).
pub fn lateral_torsional_element(rail: &RailSection, l: f64) -> ([[f64; 8]; 8], [[f64; 8]; 8]) {
    let mat = rail.material;
    let (rho, e, g) = (
        mat.density_kg_per_m3,
        mat.youngs_modulus_pa,
        mat.shear_modulus_pa(),
    );
    let a = rail.area_m2;
    let iz = rail.second_moment_lateral_m4;
    let mut k = [[0.0; 8]; 8];
    let mut m = [[0.0; 8]; 8];
    let (kb, mb) = timoshenko_element(
        e * iz,
        rail.shear_coefficient_lateral * g * a,
        rho * a,
        rho * iz,
        l,
    );
    let bending = [0, 1, 4, 5];
    let torsion = [2, 3, 6, 7];
    for r in 0..4 {
        for c in 0..4 {
            k[bending[r]][bending[c]] = kb[r][c];
            m[bending[r]][bending[c]] = mb[r][c];
        }
    }
    let gj = g * rail.torsion_constant_m4;
    let eiw = e * rail.warping_constant_m6;
    let rho_ip = rho * rail.polar_moment_about_shear_centre_m4();
    let rho_iw = rho * rail.warping_constant_m6;
    let offset = rail.shear_centre_below_crown_m - rail.centroid_below_crown_m;
    // Gauss-Legendre, 4 points on [-1, 1].
    let gauss = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    for (t, w) in gauss {
        let xi = 0.5 * (t + 1.0);
        let dx = 0.5 * w * l;
        let (h, h1, h2) = hermite(xi, l);
        let lin = [1.0 - xi, xi];
        for r in 0..4 {
            for c in 0..4 {
                k[torsion[r]][torsion[c]] += dx * (gj * h1[r] * h1[c] + eiw * h2[r] * h2[c]);
                m[torsion[r]][torsion[c]] += dx * (rho_ip * h[r] * h[c] + rho_iw * h1[r] * h1[c]);
            }
            for (n, &vd) in [0usize, 4].iter().enumerate() {
                let coupling = -dx * rho * a * offset * lin[n] * h[r];
                m[vd][torsion[r]] += coupling;
                m[torsion[r]][vd] += coupling;
            }
        }
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
            pad_roll_arm_m: pad_roll_arm_m(layout),
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

/// The pad's arm in roll (m) on the rail section that `layout` meshes: the rms lateral position
/// of the rail-foot nodes that carry the pad springs (equal shares, as
/// [`crate::model::rolling::track_supports`] spreads them), from the rail's centre line.
pub fn pad_roll_arm_m(layout: &crate::mesh::track::TrackLayout) -> f64 {
    use crate::mesh::rail::{rail_section, RailSectionSizes};
    let section = rail_section(RailSectionSizes {
        running_surface_mm: layout.running_surface_element_mm,
        body_mm: layout.section_element_mm,
        band_rows_at_least: 1,
    });
    let foot = section
        .body
        .tags
        .get("foot_bottom")
        .map(|v| v.as_slice())
        .unwrap_or(&[]);
    if foot.is_empty() {
        // The section builder always tags the foot; a uniform foot of the catalogue width
        // otherwise (rms of a uniform distribution: b / sqrt(12)).
        return crate::geometry::rail54e1::FOOT_WIDTH_MM * 1e-3 / 12f64.sqrt();
    }
    let mean_y2 = foot
        .iter()
        .map(|&i| section.body.nodes[i][0].powi(2))
        .sum::<f64>()
        / foot.len() as f64;
    mean_y2.sqrt() * 1e-3
}
