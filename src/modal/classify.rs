//! Classification of wheel modes (axis = y through `centre`; x along the track, z up).
//!
//! For a mode shape `u` (per node) and nodal mass weights `w` (element volume / 8 per node, the
//! row-sum lumped mass up to the density):
//! - cylindrical components about the axis: radial `u_r`, circumferential `u_t`, axial `u_y`;
//! - family: the component with the largest share of modal kinetic energy `sum w |u_c|²`;
//! - nodal diameters n: circumferential Fourier amplitudes of the rim motion (nodes with
//!   radius > 0.9 R_max), `a_0 = |sum w u| / sum w`, `a_n = 2 |sum w u e^{-i n theta}| / sum w`,
//!   summed in power over the three components; n maximises it;
//! - axle family: a wheel with its half axle has modes that are mostly the axle's; a mode with at
//!   least [`crate::modal::mode::AXLE_FAMILY_SHARE`] of its kinetic energy on the nodes that only
//!   axle elements hold is of the axle family (as in the axisymmetric solver);
//! - nodal circles m: at the angle of largest rim motion, the family component (axial for axial
//!   modes, radial for radial, circumferential otherwise) of the wheel's nodes (not the axle's)
//!   averaged in radial bins from the innermost to the outermost radius; m = number of sign
//!   changes between bins whose value is above 5 % of the largest (smaller ones are treated as
//!   near a node line and skipped); plus, with an axle, the sign changes of the axle's dominant
//!   component binned along the axle on the same meridian (counted where the axle moves at
//!   least 5 % as much as the wheel); an axle-family mode counts along the axle only;
//! - repeated pairs: neighbours with the same n > 0, same family and `|f1 - f2| / f < 1e-3`.

#![allow(clippy::needless_range_loop)]

use serde::Serialize;

use crate::mesh::Mesh;
use crate::modal::mode::{ModeFamily, ModeRef};

/// A classified mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModeRecord {
    /// 0-based index in the classified list (pairs count once).
    pub index: usize,
    /// Frequency (Hz; the mean of a pair).
    pub frequency_hz: f64,
    /// Family (rigid modes: `Rigid`).
    pub family: ModeFamily,
    /// Nodal circles.
    pub nodal_circles: u32,
    /// Nodal diameters.
    pub nodal_diameters: u32,
    /// Largest relative residual of the members.
    pub residual: f64,
    /// Largest rounding floor of the members' residuals ([`crate::modal::residual`]); set by
    /// the pipeline from the solution (0 where classified without one).
    pub residual_floor: f64,
    /// Two members (sin/cos pair).
    pub is_pair: bool,
    /// Rigid-body mode.
    pub rigid: bool,
    /// Indices of the member modes in the solver's list.
    pub members: Vec<usize>,
    /// Kinetic energy shares (axial, radial, circumferential).
    pub energy_share: [f64; 3],
}

impl ModeRecord {
    /// The identification's view of the mode.
    pub fn mode_ref(&self) -> ModeRef {
        ModeRef {
            frequency_hz: self.frequency_hz,
            family: self.family,
            nodal_circles: self.nodal_circles,
            nodal_diameters: self.nodal_diameters,
        }
    }
}

/// Shape descriptors of one mode.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeClass {
    /// Family by energy share.
    pub family: ModeFamily,
    /// Nodal diameters.
    pub nodal_diameters: u32,
    /// Nodal circles.
    pub nodal_circles: u32,
    /// Energy shares (axial, radial, circumferential).
    pub energy_share: [f64; 3],
}

/// Nodal weights: element volume / 8 to each node.
pub fn nodal_weights(mesh: &Mesh) -> Vec<f64> {
    let mut w = vec![0.0; mesh.node_count()];
    for (e, conn) in mesh.elements.iter().enumerate() {
        let x = mesh.element_coords(e);
        let v = crate::mesh::hex::volume(&x).abs();
        for &n in conn {
            w[n] += v / 8.0;
        }
    }
    w
}

/// Nodes that only axle elements hold (`mesh::material::AXLE`); all false without an axle.
pub fn axle_only_nodes(mesh: &Mesh) -> Vec<bool> {
    axle_only_nodes_of(
        mesh.node_count(),
        mesh.elements
            .iter()
            .zip(&mesh.material)
            .map(|(conn, &m)| (conn.as_slice(), m)),
    )
}

/// [`axle_only_nodes`] for any mesh given as (element nodes, material id) pairs.
pub fn axle_only_nodes_of<'a>(
    n: usize,
    elements: impl Iterator<Item = (&'a [usize], u32)>,
) -> Vec<bool> {
    let (mut axle, mut other) = (vec![false; n], vec![false; n]);
    for (conn, material) in elements {
        let is_axle = material == crate::mesh::material::AXLE;
        for &i in conn {
            if is_axle {
                axle[i] = true;
            } else {
                other[i] = true;
            }
        }
    }
    (0..n).map(|i| axle[i] && !other[i]).collect()
}

/// Classify one shape `u` (per node) about the y-parallel axis through `centre`.
pub fn classify_shape(
    mesh: &Mesh,
    weights: &[f64],
    centre: [f64; 3],
    u: &[[f64; 3]],
) -> ShapeClass {
    classify_shape_points(&mesh.nodes, weights, &axle_only_nodes(mesh), centre, u)
}

/// Sign changes of binned values, skipping bins below `threshold` in magnitude.
fn sign_changes_above(values: &[f64], threshold: f64) -> u32 {
    let mut last_sign = 0.0;
    let mut count = 0;
    for &v in values {
        if v.abs() < threshold || v == 0.0 {
            continue;
        }
        let s = v.signum();
        if last_sign != 0.0 && s != last_sign {
            count += 1;
        }
        last_sign = s;
    }
    count
}

/// [`classify_shape`] on bare node coordinates (any mesh kind); `axle` flags the nodes of the
/// half axle (empty: no axle).
///
/// The family, nodal-diameter and nodal-circle tests read the same shape samples (cylindrical
/// components, radii and angles of the nodes), computed once.
pub fn classify_shape_points(
    nodes: &[[f64; 3]],
    weights: &[f64],
    axle: &[bool],
    centre: [f64; 3],
    u: &[[f64; 3]],
) -> ShapeClass {
    let (samples, energy) = ShapeSamples::new(nodes, weights, axle, centre, u);
    let family = samples.family(energy);
    let rim: Vec<usize> = (0..nodes.len())
        .filter(|&i| samples.radius[i] > 0.9 * samples.r_max)
        .collect();
    let nodal_diameters = samples.nodal_diameters(&rim);
    let nodal_circles = samples.nodal_circles(&rim, family.component, family.axle_mode);
    ShapeClass {
        family: family.family,
        nodal_diameters,
        nodal_circles,
        energy_share: family.share,
    }
}

/// A shape's samples about the axis, shared by the family, nodal-diameter and nodal-circle
/// tests.
struct ShapeSamples<'a> {
    nodes: &'a [[f64; 3]],
    weights: &'a [f64],
    axle: &'a [bool],
    u: &'a [[f64; 3]],
    /// Per node: axial, radial, circumferential displacement.
    cyl: Vec<[f64; 3]>,
    /// Per node: distance from the axis.
    radius: Vec<f64>,
    /// Per node: angle about the axis.
    angle: Vec<f64>,
    /// The largest radius.
    r_max: f64,
}

/// A shape's family and what decided it.
struct FamilyTest {
    family: ModeFamily,
    /// The component with the largest energy share (0 axial, 1 radial, 2 circumferential).
    component: usize,
    /// Whether the axle holds at least the axle family's share of the kinetic energy.
    axle_mode: bool,
    /// Energy shares (axial, radial, circumferential).
    share: [f64; 3],
}

impl<'a> ShapeSamples<'a> {
    /// The cylindrical components of `u` about the y-parallel axis through `centre`, and the
    /// kinetic energy per component (`sum w |u_c|²`).
    fn new(
        nodes: &'a [[f64; 3]],
        weights: &'a [f64],
        axle: &'a [bool],
        centre: [f64; 3],
        u: &'a [[f64; 3]],
    ) -> (Self, [f64; 3]) {
        let n_nodes = nodes.len();
        let mut cyl = vec![[0.0; 3]; n_nodes]; // axial, radial, circumferential
        let mut radius = vec![0.0; n_nodes];
        let mut angle = vec![0.0; n_nodes];
        let mut energy = [0.0; 3];
        for i in 0..n_nodes {
            let dx = nodes[i][0] - centre[0];
            let dz = nodes[i][2] - centre[2];
            radius[i] = dx.hypot(dz);
            angle[i] = dz.atan2(dx);
        }
        let r_max = radius.iter().cloned().fold(0.0, f64::max);
        // A node on the axis (a revolved section's solid core) has no radial direction: its
        // in-plane motion is radial along one meridian and circumferential along the one at 90
        // degrees, so it counts half to each (the average over the circle of a translation's
        // u_r² and u_t²); in the nodal-circle walk it is projected on the walked meridian.
        let on_axis = |i: usize| radius[i] <= 1e-9 * r_max;
        for i in 0..n_nodes {
            if on_axis(i) {
                cyl[i] = [u[i][1], 0.0, 0.0];
                let in_plane = u[i][0] * u[i][0] + u[i][2] * u[i][2];
                energy[0] += weights[i] * u[i][1] * u[i][1];
                energy[1] += 0.5 * weights[i] * in_plane;
                energy[2] += 0.5 * weights[i] * in_plane;
                continue;
            }
            let (c, s) = (
                (nodes[i][0] - centre[0]) / radius[i],
                (nodes[i][2] - centre[2]) / radius[i],
            );
            let ur = u[i][0] * c + u[i][2] * s;
            let ut = -u[i][0] * s + u[i][2] * c;
            cyl[i] = [u[i][1], ur, ut];
            for k in 0..3 {
                energy[k] += weights[i] * cyl[i][k] * cyl[i][k];
            }
        }
        let samples = ShapeSamples {
            nodes,
            weights,
            axle,
            u,
            cyl,
            radius,
            angle,
            r_max,
        };
        (samples, energy)
    }

    /// Whether node `i` is one of the axle's.
    fn is_axle(&self, i: usize) -> bool {
        self.axle.get(i).copied().unwrap_or(false)
    }

    /// Whether node `i` lies on the axis (no radial direction of its own).
    fn on_axis(&self, i: usize) -> bool {
        self.radius[i] <= 1e-9 * self.r_max
    }

    /// The family: the axle's when the axle holds enough of the kinetic energy, else the
    /// component with the largest share of `energy`.
    fn family(&self, energy: [f64; 3]) -> FamilyTest {
        let (weights, u) = (self.weights, self.u);
        let n_nodes = self.nodes.len();
        let total: f64 = energy.iter().sum::<f64>().max(1e-300);
        let share = energy.map(|e| e / total);
        let fam_k = (0..3)
            .max_by(|&a, &b| share[a].total_cmp(&share[b]))
            .unwrap_or(0);
        let axle_energy: f64 = (0..n_nodes)
            .filter(|&i| self.is_axle(i))
            .map(|i| weights[i] * (u[i][0] * u[i][0] + u[i][1] * u[i][1] + u[i][2] * u[i][2]))
            .sum();
        let all_energy: f64 = (0..n_nodes)
            .map(|i| weights[i] * (u[i][0] * u[i][0] + u[i][1] * u[i][1] + u[i][2] * u[i][2]))
            .sum();
        let axle_mode =
            all_energy > 0.0 && axle_energy / all_energy >= crate::modal::mode::AXLE_FAMILY_SHARE;
        let family = if axle_mode {
            ModeFamily::Axle
        } else {
            [
                ModeFamily::Axial,
                ModeFamily::Radial,
                ModeFamily::Circumferential,
            ][fam_k]
        };
        FamilyTest {
            family,
            component: fam_k,
            axle_mode,
            share,
        }
    }

    /// The nodal diameters: the circumferential harmonic (up to 24) with the largest Fourier
    /// power of the `rim` nodes' motion, summed over the three components.
    fn nodal_diameters(&self, rim: &[usize]) -> u32 {
        let (weights, cyl, angle) = (self.weights, &self.cyl, &self.angle);
        let wsum: f64 = rim.iter().map(|&i| weights[i]).sum::<f64>().max(1e-300);
        let n_max = 24usize;
        let mut best = (0u32, -1.0);
        for n in 0..=n_max {
            let mut power = 0.0;
            for k in 0..3 {
                let (mut re, mut im) = (0.0, 0.0);
                for &i in rim {
                    let a = n as f64 * angle[i];
                    re += weights[i] * cyl[i][k] * a.cos();
                    im -= weights[i] * cyl[i][k] * a.sin();
                }
                let amp = re.hypot(im) / wsum * if n == 0 { 1.0 } else { 2.0 };
                power += amp * amp;
            }
            // strictly larger by a relative margin: prefer the lower harmonic on ties (round-off)
            if power > best.1 * (1.0 + 1e-9) {
                best = (n as u32, power);
            }
        }
        best.0
    }

    /// The nodal circles along the meridian of largest rim motion in component `comp`: sign
    /// changes of the wheel's binned radial profile, plus those along the axle where it moves
    /// enough (an axle-family mode, `axle_mode`, counts along the axle only). 0 without rim
    /// nodes.
    fn nodal_circles(&self, rim: &[usize], comp: usize, axle_mode: bool) -> u32 {
        let cyl = &self.cyl;
        // Nodal circles along the radius at the angle of largest rim motion.
        let peak = rim
            .iter()
            .copied()
            .max_by(|&a, &b| cyl[a][comp].abs().total_cmp(&cyl[b][comp].abs()));
        let mut nodal_circles = 0;
        if let Some(p) = peak {
            let theta0 = self.angle[p];
            let (c0, s0) = (theta0.cos(), theta0.sin());
            let meridian = self.meridian(theta0);
            let wheel: Vec<usize> = meridian
                .iter()
                .copied()
                .filter(|&i| !self.is_axle(i))
                .collect();
            let shaft: Vec<usize> = meridian
                .iter()
                .copied()
                .filter(|&i| self.is_axle(i))
                .collect();
            let wheel_vals = self.binned(&wheel, &|i| self.radius[i], comp, (c0, s0));
            // The axle's dominant component on the meridian, binned along the axle (y).
            let mut axle_e = [0.0f64; 3];
            for &i in &shaft {
                for (k, e) in axle_e.iter_mut().enumerate() {
                    *e += self.weights[i]
                        * self.component(i, k, (c0, s0))
                        * self.component(i, k, (c0, s0));
                }
            }
            let axle_k = (0..3).fold(0, |b, k| if axle_e[k] > axle_e[b] { k } else { b });
            let axle_vals = if shaft.is_empty() {
                Vec::new()
            } else {
                self.binned(&shaft, &|i| self.nodes[i][1], axle_k, (c0, s0))
            };
            let peak_of = |v: &[f64]| v.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
            nodal_circles = if axle_mode {
                sign_changes_above(&axle_vals, 0.05 * peak_of(&axle_vals))
            } else {
                let scale = peak_of(&wheel_vals).max(peak_of(&axle_vals));
                sign_changes_above(&wheel_vals, 0.05 * scale)
                    + sign_changes_above(&axle_vals, 0.05 * scale)
            };
        }
        nodal_circles
    }

    /// Component `k` (axial, radial, circumferential) of node `i`'s motion on the meridian
    /// whose direction is `(cos, sin)` of its angle: a node on the axis is projected on it.
    fn component(&self, i: usize, k: usize, (c0, s0): (f64, f64)) -> f64 {
        let u = self.u;
        if self.on_axis(i) {
            [
                u[i][1],
                u[i][0] * c0 + u[i][2] * s0,
                -u[i][0] * s0 + u[i][2] * c0,
            ][k]
        } else {
            self.cyl[i][k]
        }
    }

    /// The nodes on the meridian at angle `theta0`.
    fn meridian(&self, theta0: f64) -> Vec<usize> {
        let (angle, radius, r_max) = (&self.angle, &self.radius, self.r_max);
        // nodes within a small angular window of theta0 (revolved meshes: the same meridian)
        let window = 0.02;
        (0..self.nodes.len())
            .filter(|&i| {
                let mut d = (angle[i] - theta0).rem_euclid(std::f64::consts::TAU);
                if d > std::f64::consts::PI {
                    d -= std::f64::consts::TAU;
                }
                d.abs() * radius[i] <= window * r_max
            })
            .collect()
    }

    /// Component `k` of `members` averaged (mass-weighted) in 24 bins of `coord` from its
    /// smallest to its largest value; empty bins are left out.
    fn binned(
        &self,
        members: &[usize],
        coord: &dyn Fn(usize) -> f64,
        k: usize,
        meridian: (f64, f64),
    ) -> Vec<f64> {
        let weights = self.weights;
        let bins = 24usize;
        let lo = members
            .iter()
            .map(|&i| coord(i))
            .fold(f64::INFINITY, f64::min);
        let hi = members
            .iter()
            .map(|&i| coord(i))
            .fold(f64::NEG_INFINITY, f64::max);
        let mut sum = vec![0.0; bins];
        let mut cnt = vec![0.0; bins];
        for &i in members {
            let b = (((coord(i) - lo) / (hi - lo + 1e-300)) * bins as f64) as usize;
            let b = b.min(bins - 1);
            sum[b] += weights[i] * self.component(i, k, meridian);
            cnt[b] += weights[i];
        }
        (0..bins)
            .filter(|&b| cnt[b] > 0.0)
            .map(|b| sum[b] / cnt[b])
            .collect()
    }
}

/// Classify solver modes (ascending frequency); merges sin/cos pairs and flags rigid modes.
pub fn classify_modes(
    mesh: &Mesh,
    centre: [f64; 3],
    modes: &[(f64, f64, bool, Vec<[f64; 3]>)],
) -> Vec<ModeRecord> {
    classify_modes_points(
        &mesh.nodes,
        &nodal_weights(mesh),
        &axle_only_nodes(mesh),
        centre,
        modes,
    )
}

/// [`classify_modes`] on bare node coordinates and nodal weights (any mesh kind, e.g. a
/// [`crate::mesh::volume::VolumeMesh`] with its `nodal_weights`); the axis is y-parallel through
/// `centre`.
pub fn classify_modes_points(
    nodes: &[[f64; 3]],
    weights: &[f64],
    axle: &[bool],
    centre: [f64; 3],
    modes: &[(f64, f64, bool, Vec<[f64; 3]>)],
) -> Vec<ModeRecord> {
    let classes: Vec<ShapeClass> = modes
        .iter()
        .map(|(_, _, _, u)| classify_shape_points(nodes, weights, axle, centre, u))
        .collect();
    let mut out: Vec<ModeRecord> = Vec::new();
    let mut i = 0;
    while i < modes.len() {
        let (f, res, rigid, _) = &modes[i];
        let c = &classes[i];
        let pair = !rigid
            && i + 1 < modes.len()
            && !modes[i + 1].2
            && c.nodal_diameters > 0
            && classes[i + 1].nodal_diameters == c.nodal_diameters
            && classes[i + 1].family == c.family
            // 1e-3: a revolved mesh makes the pair equal to round-off; a real pair split
            // (asymmetric mesh, ties) stays far below it, distinct modes far above.
            && (modes[i + 1].0 - f).abs() / f.abs().max(1e-300) < 1e-3;
        let members: Vec<usize> = if pair { vec![i, i + 1] } else { vec![i] };
        // A pair's members are any orthonormal basis of its plane, and the nodal circles are
        // counted along one meridian: count them on the member combination whose rim motion is
        // a cosine about theta = 0 (basis independent), not on whichever member came first.
        let nodal_circles = if pair {
            let aligned = aligned_pair(
                nodes,
                weights,
                centre,
                [&modes[i].3, &modes[i + 1].3],
                c.nodal_diameters,
                c.family,
            );
            classify_shape_points(nodes, weights, axle, centre, &aligned).nodal_circles
        } else {
            c.nodal_circles
        };
        let freq = members.iter().map(|&k| modes[k].0).sum::<f64>() / members.len() as f64;
        let residual = members.iter().map(|&k| modes[k].1).fold(0.0, f64::max);
        out.push(ModeRecord {
            index: out.len(),
            frequency_hz: freq,
            family: if *rigid { ModeFamily::Rigid } else { c.family },
            nodal_circles,
            nodal_diameters: c.nodal_diameters,
            residual,
            residual_floor: 0.0,
            is_pair: pair,
            rigid: *rigid,
            members,
            energy_share: c.energy_share,
        });
        let _ = res;
        i += if pair { 2 } else { 1 };
    }
    out
}

/// The combination `a u_1 + b u_2` (`a² + b² = 1`) of a sin/cos pair with `n` nodal diameters
/// whose rim motion in the family's component has a real n-th Fourier coefficient
/// `sum w u e^{-i n theta}`, i.e. is `A cos(n theta)`: a standing wave with an antinode at
/// theta = 0, the same whichever basis of the pair the solver returned (up to sign).
fn aligned_pair(
    nodes: &[[f64; 3]],
    weights: &[f64],
    centre: [f64; 3],
    members: [&[[f64; 3]]; 2],
    n: u32,
    family: ModeFamily,
) -> Vec<[f64; 3]> {
    let radius = |p: &[f64; 3]| (p[0] - centre[0]).hypot(p[2] - centre[2]);
    let r_max = nodes.iter().map(radius).fold(0.0, f64::max);
    // Fourier coefficient of the family component over the rim nodes (as in the n count).
    let coefficient = |u: &[[f64; 3]]| {
        let (mut re, mut im) = (0.0, 0.0);
        for (i, p) in nodes.iter().enumerate() {
            let r = radius(p);
            if r <= 0.9 * r_max {
                continue;
            }
            let (c, s) = ((p[0] - centre[0]) / r, (p[2] - centre[2]) / r);
            let value = match family {
                ModeFamily::Radial => u[i][0] * c + u[i][2] * s,
                ModeFamily::Circumferential => -u[i][0] * s + u[i][2] * c,
                _ => u[i][1],
            };
            let a = n as f64 * s.atan2(c);
            re += weights[i] * value * a.cos();
            im -= weights[i] * value * a.sin();
        }
        (re, im)
    };
    let (c1, c2) = (coefficient(members[0]), coefficient(members[1]));
    // Im(a c1 + b c2) = 0 with (a, b) on the unit circle; of the two signs, the one with a
    // positive real part.
    let (mut a, mut b) = (c2.1, -c1.1);
    let norm = a.hypot(b);
    if norm <= 0.0 {
        return members[0].to_vec();
    }
    a /= norm;
    b /= norm;
    if a * c1.0 + b * c2.0 < 0.0 {
        a = -a;
        b = -b;
    }
    members[0]
        .iter()
        .zip(members[1])
        .map(|(x, y)| [0, 1, 2].map(|k| a * x[k] + b * y[k]))
        .collect()
}
