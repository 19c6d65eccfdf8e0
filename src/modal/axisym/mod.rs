//! Axisymmetric (Fourier-harmonic) modal solver for bodies of revolution.
//!
//! The cross-section is meshed once with nine-node quadrilaterals ([`mesh::Q9Mesh`]); for each
//! harmonic n the displacements vary as cos(n theta) / sin(n theta) around the axis
//! ([`element`] states the strain-displacement relations), so every mode of harmonic n has
//! exactly n nodal diameters. For each n the generalized eigenproblem
//!
//! ```text
//! K_n x = omega^2 M_n x
//! ```
//!
//! is solved for all omega below 2 pi fmax by shift-invert Lanczos with a Sturm-count check
//! ([`eigen`]). Harmonics n >= 1 stand for a pair of 3D modes (cos and sin companions) with the
//! same frequency; `multiplicity` says so.
//!
//! Axis conditions (nodes at r = 0, e.g. a solid disc or the axle core), from regularity of the
//! strains e_tt = (U_r + n U_t)/r, g_rt and g_tz at r -> 0:
//! n = 0: U_r = U_t = 0; n = 1: U_r + U_t = 0 and U_z = 0 (U_t eliminated as -U_r);
//! n >= 2: U_r = U_t = U_z = 0.
//!
//! Free bodies: rigid-body motions appear at n = 0 (axial translation, rotation about the axis)
//! and n = 1 (translation across the axis, tilt), each once per harmonic; modes below
//! [`RIGID_LIMIT_HZ`] are flagged rigid.
//!
//! Classification: family by the share of modal kinetic energy (omega^2/2 x^T M x split by
//! component, exact because M couples only like components): U_z -> axial, U_r -> radial,
//! U_t -> circumferential. A wheel on its half axle has modes that are mostly the axle's
//! (its axial, bending and torsional resonances between the clamped ends, carrying the wheel
//! along): a mode with at least [`AXLE_FAMILY_SHARE`] of its kinetic energy in the axle
//! (`sum x_j (M x)_j` over the dofs of nodes that only axle elements hold) is of the axle
//! family. Nodal circles: sign changes of the axial (axial family), radial (radial family) or
//! circumferential displacement along a radial path through the wheel section (hub, web centre
//! line and rim of a wheel, so that a nodal circle at the hub or in the rim counts as well as
//! one in the web; the mid-plane of a disc), ignoring samples below 5 % of the largest
//! magnitude on the path so that numerical noise near a node line is not counted. For the axle
//! family the path runs along the axle, inside it at half its radius, and the component is the
//! axle's own dominant one.

pub mod eigen;
pub mod element;
pub mod mesh;
pub mod revolve;

use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::input::wheel::{axle_radius_mm, WheelSpec};
use crate::mesh::material as part;
use crate::mesh::wheel::mesh_section;
use crate::modal::mode::{ModeFamily, ModeRef};
use crate::{Error, Result};
pub use element::Material;
pub use mesh::Q9Mesh;

/// Frequencies below this (Hz) are rigid-body modes.
pub const RIGID_LIMIT_HZ: f64 = 1.0;

/// The largest accepted relative residual ||K x - w^2 M x|| / ||K x||.
pub const MAX_RELATIVE_RESIDUAL: f64 = 1e-8;

/// Share of the path's largest magnitude below which a sample has no sign (nodal circles).
const NODAL_SIGN_THRESHOLD: f64 = 0.05;

pub use crate::modal::mode::AXLE_FAMILY_SHARE;

/// A body of revolution ready to solve.
#[derive(Clone, Debug)]
pub struct AxisymModel {
    /// The Q9 section mesh, (r, z) in m.
    pub mesh: Q9Mesh,
    /// Material (one for all parts; the wheel and axle are the same steel in the data files).
    pub material: Material,
    /// Nodes whose three displacement components are held at zero.
    pub clamped: Vec<usize>,
    /// Radial path for the nodal-circle count, `[r, z]` (m), from the inner to the outer end.
    pub radial_path: Vec<[f64; 2]>,
    /// Path along the axle for axle-family modes, `[r, z]` (m); empty without an axle.
    pub axle_path: Vec<[f64; 2]>,
}

/// What to hold fixed on a wheel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WheelClamp {
    /// Free-free.
    None,
    /// The hub bore (r = bore radius over the hub length).
    HubBore,
    /// Both ends of the half axle (the section lines S = first and last axle profile point).
    AxleEnds,
}

/// Wheel model options.
#[derive(Clone, Copy, Debug)]
pub struct WheelModelOptions {
    /// Leave the half-axle out (the section then ends at the hub bore).
    pub without_axle: bool,
    /// Clamped lines.
    pub clamp: WheelClamp,
}

impl Default for WheelModelOptions {
    fn default() -> Self {
        WheelModelOptions {
            without_axle: false,
            clamp: WheelClamp::None,
        }
    }
}

impl AxisymModel {
    /// Model of a wheel from its spec: the section of [`mesh_section`] (the same quads the 3D
    /// mesh revolves) upgraded to Q9. With the axle, the axle's solid core (which the 3D mesh
    /// fills with an O-grid square) is added as a structured block down to the axis.
    pub fn from_wheel(spec: &WheelSpec, opts: WheelModelOptions) -> Result<AxisymModel> {
        let mut section = mesh_section(spec, None);
        let with_axle = spec.axle.is_some() && !opts.without_axle;
        if let (true, Some(axle)) = (with_axle, &spec.axle) {
            // Core block: eta in [0, 1/2] of the local axle radius, same stations as the ring,
            // rows four times the section element size (one row for the default wheel): the
            // quadratic elements carry the core's strain (about linear through the radius in
            // bending, uniform in extension), and rows of the section size would make this
            // block a quarter of the section's elements. Measured on the default wheel: every
            // mode below 10 kHz moves by less than 2e-5 (relative) against rows of size h,
            // with the same labels, and n = 0..12 solves 1.7x faster.
            let h = spec.mesh.element_size_mm;
            let r_max = axle.profile_mm.iter().fold(0.0f64, |m, p| m.max(p[1]));
            let k = ((0.5 * r_max / (4.0 * h)).round() as usize).max(1);
            let grid: Vec<Vec<[f64; 2]>> = section
                .axle_stations_mm
                .iter()
                .map(|&s| {
                    let r_axle = axle_radius_mm(&axle.profile_mm, s);
                    (0..=k)
                        .map(|i| [s, 0.5 * r_axle * i as f64 / k as f64])
                        .collect()
                })
                .collect();
            section.body.add_grid(&grid, part::AXLE);
        }
        let drop: &[u32] = if with_axle { &[] } else { &[part::AXLE] };
        let mesh = Q9Mesh::from_section(&section.body, drop);
        let tol = 1e-6; // m; section nodes lie on these lines to rounding (1e-7 mm merges)
        let clamped = match opts.clamp {
            WheelClamp::None => Vec::new(),
            WheelClamp::HubBore => mesh.nodes_at_r(
                spec.hub.bore_radius_mm * 1e-3,
                spec.hub.s_min_mm * 1e-3,
                spec.hub.s_max_mm * 1e-3,
                tol,
            ),
            WheelClamp::AxleEnds => {
                let axle = match (&spec.axle, with_axle) {
                    (Some(a), true) => a,
                    _ => {
                        return Err(Error::input(
                            "command line",
                            "--clamp",
                            "axle-ends needs a wheel file with an axle and no --without-axle",
                        ))
                    }
                };
                let p = &axle.profile_mm;
                let mut ids = mesh.nodes_at_z(p[0][0] * 1e-3, tol);
                ids.extend(mesh.nodes_at_z(p[p.len() - 1][0] * 1e-3, tol));
                ids
            }
        };
        if opts.clamp != WheelClamp::None && clamped.is_empty() {
            return Err(Error::Mesh(format!(
                "no section node lies on the clamped line ({:?})",
                opts.clamp
            )));
        }
        // Hub (bore to outer radius, at the web's centre there), web centre line, rim (up to
        // 5 mm below the tape circle, at the web's centre at the rim).
        let (hub_centre, _) = spec.web_at(0.0);
        let (rim_centre, _) = spec.web_at(1.0);
        let mut radial_path: Vec<[f64; 2]> = (0..10)
            .map(|i| {
                let r = spec.hub.bore_radius_mm
                    + (spec.hub.outer_radius_mm - spec.hub.bore_radius_mm) * i as f64 / 10.0;
                [r * 1e-3, hub_centre * 1e-3]
            })
            .collect();
        radial_path.extend((0..=40).map(|i| {
            let t = i as f64 / 40.0;
            let (c, _) = spec.web_at(t);
            let r = spec.hub.outer_radius_mm
                + t * (spec.rim_inner_radius_mm - spec.hub.outer_radius_mm);
            [r * 1e-3, c * 1e-3]
        }));
        let rim_top = spec.nominal_radius_mm - 5.0;
        radial_path.extend((1..=10).map(|i| {
            let r =
                spec.rim_inner_radius_mm + (rim_top - spec.rim_inner_radius_mm) * i as f64 / 10.0;
            [r * 1e-3, rim_centre * 1e-3]
        }));
        let axle_path = match (&spec.axle, with_axle) {
            (Some(a), true) => {
                let p = &a.profile_mm;
                let (z0, z1) = (p[0][0], p[p.len() - 1][0]);
                (0..=60)
                    .map(|i| {
                        let z = z0 + (z1 - z0) * i as f64 / 60.0;
                        [0.5 * axle_radius_mm(p, z) * 1e-3, z * 1e-3]
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        let m = spec.material;
        Ok(AxisymModel {
            mesh,
            material: Material {
                youngs_modulus_pa: m.youngs_modulus_pa,
                poisson_ratio: m.poisson_ratio,
                density_kg_per_m3: m.density_kg_per_m3,
            },
            clamped,
            radial_path,
            axle_path,
        })
    }

    /// An annular (r0 > 0) or solid (r0 = 0) disc / ring of rectangular section
    /// r in [r0, r1], z in [-t/2, t/2], `nr` x `nz` elements; radial path on the mid-plane.
    pub fn rectangle(
        r0: f64,
        r1: f64,
        thickness: f64,
        nr: usize,
        nz: usize,
        material: Material,
    ) -> AxisymModel {
        let mesh = Q9Mesh::rectangle(r0, r1, -0.5 * thickness, 0.5 * thickness, nr, nz);
        let radial_path = (0..=4 * nr)
            .map(|i| [r0 + (r1 - r0) * i as f64 / (4 * nr) as f64, 0.0])
            .collect();
        AxisymModel {
            mesh,
            material,
            clamped: Vec::new(),
            radial_path,
            axle_path: Vec::new(),
        }
    }
}

/// Solver options.
#[derive(Clone, Debug)]
pub struct AxisymOptions {
    /// Harmonics (nodal diameters) to solve.
    pub harmonics: Vec<u32>,
    /// Upper frequency (Hz): all modes below it are returned.
    pub fmax_hz: f64,
}

impl Default for AxisymOptions {
    fn default() -> Self {
        AxisymOptions {
            harmonics: (0..=12).collect(),
            fmax_hz: 10_000.0,
        }
    }
}

/// One mode of the axisymmetric model (`modes.json` entry; a superset of [`ModeRef`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AxisymMode {
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Family by kinetic energy share (rigid below [`RIGID_LIMIT_HZ`]).
    pub family: ModeFamily,
    /// Nodal circles along the radial path.
    pub nodal_circles: u32,
    /// Nodal diameters (= harmonic).
    pub nodal_diameters: u32,
    /// Fourier harmonic n.
    pub harmonic: u32,
    /// Relative residual ||K x - w^2 M x|| / ||K x|| (rigid modes: / (max K_ii ||x||)).
    pub residual: f64,
    /// 1 for n = 0, 2 for n >= 1 (the cos and sin companions).
    pub multiplicity: u32,
    /// Kinetic energy shares (radial, circumferential, axial), summing to 1.
    pub energy_share: [f64; 3],
    /// Share of the kinetic energy in the axle (0 without one).
    #[serde(default)]
    pub axle_energy_share: f64,
    /// Mode shape per section node (U_r, U_t, U_z), M-normalised; not written to JSON.
    #[serde(skip)]
    pub shape: Vec<[f64; 3]>,
}

impl AxisymMode {
    /// The label record the identification uses.
    pub fn mode_ref(&self) -> ModeRef {
        ModeRef {
            frequency_hz: self.frequency_hz,
            family: self.family,
            nodal_circles: self.nodal_circles,
            nodal_diameters: self.nodal_diameters,
        }
    }
    /// True for a rigid-body mode.
    pub fn is_rigid(&self) -> bool {
        self.family == ModeFamily::Rigid
    }
}

/// Per-harmonic statistics.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct HarmonicStats {
    /// Harmonic n.
    pub harmonic: u32,
    /// Free degrees of freedom.
    pub dofs: usize,
    /// Entries of the LDL^T factor.
    pub factor_nnz: usize,
    /// Sturm count below fmax (= modes returned).
    pub sturm_count: usize,
    /// Lanczos steps.
    pub lanczos_steps: usize,
    /// Wall time of the assembly of the values (s); the order, pattern and symbolic factor are
    /// built once per dof map before (included in the total of [`AxisymResult::seconds`]).
    pub assembly_seconds: f64,
    /// Wall time of the two factorisations, Lanczos runs and polish (s).
    pub eigen_seconds: f64,
    /// Wall time of assembly + solve + classification (s).
    pub seconds: f64,
}

/// Result of [`solve`].
#[derive(Clone, Debug)]
pub struct AxisymResult {
    /// Modes, sorted by frequency.
    pub modes: Vec<AxisymMode>,
    /// Per harmonic.
    pub harmonics: Vec<HarmonicStats>,
    /// Total wall time (s).
    pub seconds: f64,
}

/// Degree-of-freedom map: per node and component, the free dof and its coefficient.
type DofMap = Vec<[Option<(usize, f64)>; 3]>;

fn dof_map(model: &AxisymModel, harmonic: u32) -> (DofMap, usize) {
    let axis = model.mesh.axis_nodes();
    let mut clamped = vec![false; model.mesh.node_count()];
    for &c in &model.clamped {
        clamped[c] = true;
    }
    let mut next = 0usize;
    let mut fresh = || {
        next += 1;
        Some((next - 1, 1.0))
    };
    let map: DofMap = (0..model.mesh.node_count())
        .map(|i| {
            if clamped[i] {
                [None, None, None]
            } else if axis[i] {
                match harmonic {
                    0 => [None, None, fresh()],
                    1 => {
                        let r = fresh();
                        [r, r.map(|(g, _)| (g, -1.0)), None]
                    }
                    _ => [None, None, None],
                }
            } else {
                [fresh(), fresh(), fresh()]
            }
        })
        .collect();
    (map, next)
}

/// The entries of K_n and M_n in a fixed order (elements, then element rows and columns),
/// upper triangle in the free-dof numbering: `(i, j)` with i <= j. The order depends only on
/// the dof map, so harmonics with the same map share one [`eigen::Pattern`].
fn entry_pairs(model: &AxisymModel, map: &DofMap) -> Vec<(usize, usize)> {
    let mut pairs = Vec::with_capacity(model.mesh.elements.len() * 400);
    for conn in &model.mesh.elements {
        for a in 0..27 {
            let Some((ga, _)) = map[conn[a / 3]][a % 3] else {
                continue;
            };
            for b in 0..27 {
                let Some((gb, _)) = map[conn[b / 3]][b % 3] else {
                    continue;
                };
                if ga <= gb {
                    pairs.push((ga, gb));
                }
            }
        }
    }
    pairs
}

/// Values of the entries of [`entry_pairs`], same order, for harmonic n.
fn entry_values(model: &AxisymModel, map: &DofMap, harmonic: u32) -> Result<(Vec<f64>, Vec<f64>)> {
    let cap = model.mesh.elements.len() * 400;
    let (mut kv, mut mv) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
    for (e, conn) in model.mesh.elements.iter().enumerate() {
        let xy: [[f64; 2]; 9] = std::array::from_fn(|k| model.mesh.nodes[conn[k]]);
        let (ke, me) =
            element::element_matrices(&xy, harmonic, &model.material).ok_or_else(|| {
                Error::Mesh(format!(
                    "section element {e} is degenerate or folded (non-positive Jacobian or radius)"
                ))
            })?;
        for a in 0..27 {
            let Some((ga, ca)) = map[conn[a / 3]][a % 3] else {
                continue;
            };
            for b in 0..27 {
                let Some((gb, cb)) = map[conn[b / 3]][b % 3] else {
                    continue;
                };
                if ga <= gb {
                    kv.push(ca * cb * ke[a][b]);
                    mv.push(ca * cb * me[a][b]);
                }
            }
        }
    }
    Ok((kv, mv))
}

/// Dof map, dof count and shared pattern (AMD order, symbolic factor) of a harmonic.
fn harmonic_structure(
    model: &AxisymModel,
    harmonic: u32,
) -> Result<(DofMap, usize, std::sync::Arc<eigen::Pattern>)> {
    let (map, ndof) = dof_map(model, harmonic);
    if ndof == 0 {
        return Err(Error::Mesh(
            "the section has no free degree of freedom".into(),
        ));
    }
    // AMD on the dof graph (on this section's node graph, expanded to the dofs, it gave 5 %
    // more fill).
    let pairs = entry_pairs(model, &map);
    let perm_inv = eigen::amd_order(ndof, pairs.clone())?;
    let pattern = eigen::Pattern::new(ndof, &pairs, perm_inv)?;
    Ok((map, ndof, std::sync::Arc::new(pattern)))
}

/// Assemble K_n and M_n (with their own pattern).
pub fn assemble(
    model: &AxisymModel,
    harmonic: u32,
) -> Result<(eigen::PencilMatrices, DofMap, usize)> {
    let (map, ndof, pattern) = harmonic_structure(model, harmonic)?;
    let (kv, mv) = entry_values(model, &map, harmonic)?;
    Ok((
        eigen::PencilMatrices::from_values(pattern, &kv, &mv),
        map,
        ndof,
    ))
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Rigid-body motions of harmonic n as nodal (U_r, U_t, U_z) fields (exact null vectors of K
/// for a free body): n = 0 axial translation (U_z = 1) and rotation about the axis (U_t = r);
/// n = 1 translation across the axis (U_r = 1, U_t = -1: u_x = 1) and tilt about the
/// perpendicular axis (U_r = z, U_t = -z, U_z = -r); none for n >= 2.
fn rigid_motions(model: &AxisymModel, harmonic: u32) -> Vec<Vec<[f64; 3]>> {
    let nodes = &model.mesh.nodes;
    match harmonic {
        0 => vec![
            nodes.iter().map(|_| [0.0, 0.0, 1.0]).collect(),
            nodes.iter().map(|p| [0.0, p[0], 0.0]).collect(),
        ],
        1 => vec![
            nodes.iter().map(|_| [1.0, -1.0, 0.0]).collect(),
            nodes.iter().map(|p| [p[1], -p[1], -p[0]]).collect(),
        ],
        _ => Vec::new(),
    }
}

/// Solve one harmonic on a precomputed structure (dof map, count, pattern).
///
/// The phases share the section's numbering: the assembly of the harmonic's values, the solve
/// below `fmax_hz` (a free body's rigid motions given as known null vectors), and the
/// labelling of each mode.
fn solve_harmonic_with(
    model: &AxisymModel,
    harmonic: u32,
    fmax_hz: f64,
    structure: &(DofMap, usize, std::sync::Arc<eigen::Pattern>),
) -> Result<(Vec<AxisymMode>, HarmonicStats)> {
    let t0 = Instant::now();
    let (map, ndof) = (&structure.0, structure.1);
    let (kv, mv) = entry_values(model, map, harmonic)?;
    let pencil = eigen::PencilMatrices::from_values(structure.2.clone(), &kv, &mv);
    let assembly_seconds = t0.elapsed().as_secs_f64();
    let settings = eigen_settings(fmax_hz);
    let t_eig = Instant::now();
    let known = known_null_vectors(model, harmonic, map, ndof, &pencil);
    let res = eigen::solve_below(&pencil, &settings, &known)?;
    let eigen_seconds = t_eig.elapsed().as_secs_f64();
    let labels = ModeLabels::new(model, map, ndof, &pencil);
    let mut modes = Vec::with_capacity(res.values.len());
    let mut kx = vec![0.0; ndof];
    let mut mx = vec![0.0; ndof];
    for (lambda, x) in res.values.iter().zip(&res.vectors) {
        modes.push(labels.label(harmonic, *lambda, x, &mut kx, &mut mx)?);
    }
    let stats = HarmonicStats {
        harmonic,
        dofs: ndof,
        factor_nnz: pencil.factor_nnz(),
        sturm_count: res.sturm_count,
        lanczos_steps: res.lanczos_steps,
        assembly_seconds,
        eigen_seconds,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok((modes, stats))
}

/// The eigen solve's settings for all modes below `fmax_hz`.
fn eigen_settings(fmax_hz: f64) -> eigen::EigenSettings {
    let omega_max = std::f64::consts::TAU * fmax_hz;
    let lambda_max = omega_max * omega_max;
    eigen::EigenSettings {
        lambda_max,
        // Shift at -(0.2 fmax)^2 (in omega^2): below every eigenvalue (K - sigma M positive
        // definite even for a free body) and close enough to the band that its modes are the
        // dominant end of the transformed spectrum.
        sigma: -0.04 * lambda_max,
        // Transformed residual |beta s| <= 1e-12 theta: the accepted pairs then have relative
        // residuals in K, M well below MAX_RELATIVE_RESIDUAL (checked below, not assumed).
        ritz_tolerance: 1e-12,
    }
}

/// A free body's rigid motions of this harmonic as vectors of the (permuted) free dofs, the
/// null vectors the solve is told about; none for a clamped body.
fn known_null_vectors(
    model: &AxisymModel,
    harmonic: u32,
    map: &DofMap,
    ndof: usize,
    pencil: &eigen::PencilMatrices,
) -> Vec<Vec<f64>> {
    if model.clamped.is_empty() {
        rigid_motions(model, harmonic)
            .iter()
            .map(|field| {
                let mut x = vec![0.0; ndof];
                for (i, u) in field.iter().enumerate() {
                    for c in 0..3 {
                        if let Some((g, sign)) = map[i][c] {
                            // A dof shared by U_r and U_t (n = 1 on the axis) takes U_r.
                            if c == 0 || map[i][0].map(|d| d.0) != Some(g) {
                                x[g] = sign * u[c];
                            }
                        }
                    }
                }
                pencil.permute(&x)
            })
            .collect()
    } else {
        Vec::new()
    }
}

/// What labelling a harmonic's modes needs, in the pencil's (permuted) numbering: the residual
/// scale of rigid modes, the paths' nodes, the axle's dofs and each dof's component.
struct ModeLabels<'a> {
    pencil: &'a eigen::PencilMatrices,
    map: &'a DofMap,
    ndof: usize,
    /// The largest diagonal entry of K (the residual scale of a rigid mode).
    k_scale: f64,
    n_nodes: usize,
    /// Nodes along the axle (axle-family nodal circles).
    axle_path_nodes: Vec<usize>,
    /// Nodes along the wheel's radial path (nodal circles).
    wheel_path_nodes: Vec<usize>,
    /// Per permuted dof: on a node that only axle elements hold.
    in_axle: Vec<bool>,
    /// Per permuted dof: its component (0 radial, 1 circumferential, 2 axial).
    owner_perm: Vec<usize>,
}

impl<'a> ModeLabels<'a> {
    /// The labelling data of a harmonic with dof map `map` (`ndof` free dofs) and `pencil`.
    fn new(
        model: &AxisymModel,
        map: &'a DofMap,
        ndof: usize,
        pencil: &'a eigen::PencilMatrices,
    ) -> Self {
        let k_scale = pencil.max_k_diagonal();
        let n_nodes = model.mesh.node_count();
        let axle_path_nodes = path_nodes(model, &model.axle_path);
        let wheel_path_nodes = path_nodes(model, &model.radial_path);
        // Dofs of the nodes that only axle elements hold, in the permuted numbering.
        let axle_only = axle_only_nodes(model);
        let in_axle: Vec<bool> = {
            let mut flag = vec![0.0; ndof];
            for (i, node) in map.iter().enumerate() {
                if axle_only[i] {
                    for (g, _) in node.iter().flatten() {
                        flag[*g] = 1.0;
                    }
                }
            }
            pencil.permute(&flag).iter().map(|&f| f > 0.5).collect()
        };
        // Kinetic energy shares: x^T M x split by component (M couples only like components).
        // A dof shared by U_r and U_t (n = 1 axis node) counts as radial.
        let mut owner = vec![usize::MAX; ndof];
        for node in map.iter() {
            for (c, d) in node.iter().enumerate() {
                if let Some((g, _)) = d {
                    if owner[*g] == usize::MAX {
                        owner[*g] = c;
                    }
                }
            }
        }
        let owner_perm: Vec<usize> = {
            let as_f: Vec<f64> = owner.iter().map(|&c| c as f64).collect();
            pencil.permute(&as_f).iter().map(|&c| c as usize).collect()
        };
        ModeLabels {
            pencil,
            map,
            ndof,
            k_scale,
            n_nodes,
            axle_path_nodes,
            wheel_path_nodes,
            in_axle,
            owner_perm,
        }
    }

    /// The labelled mode of eigenpair (`lambda`, `x`) of `harmonic`: its residual (refused
    /// above [`MAX_RELATIVE_RESIDUAL`]), shape, energy shares, family and nodal circles. `kx`
    /// and `mx` are scratch vectors of the dof count, reused from mode to mode.
    fn label(
        &self,
        harmonic: u32,
        lambda: f64,
        x: &[f64],
        kx: &mut [f64],
        mx: &mut [f64],
    ) -> Result<AxisymMode> {
        let (pencil, map, ndof) = (self.pencil, self.map, self.ndof);
        pencil.k_mul(x, kx);
        pencil.m_mul(x, mx);
        let r: Vec<f64> = kx
            .iter()
            .zip(mx.iter())
            .map(|(k, m)| k - lambda * m)
            .collect();
        let freq = lambda.max(0.0).sqrt() / std::f64::consts::TAU;
        let rigid = freq < RIGID_LIMIT_HZ;
        let denom = if rigid {
            self.k_scale * norm(x)
        } else {
            norm(kx)
        };
        let residual = norm(&r) / denom.max(f64::MIN_POSITIVE);
        if residual > MAX_RELATIVE_RESIDUAL {
            return Err(Error::Numerical(format!(
                "axisymmetric solver: harmonic {harmonic}, mode at {freq:.3} Hz has relative \
                 residual {residual:.2e} > {MAX_RELATIVE_RESIDUAL:.0e}"
            )));
        }
        let xo = pencil.unpermute(x);
        let shape: Vec<[f64; 3]> = (0..self.n_nodes)
            .map(|i| std::array::from_fn(|c| map[i][c].map_or(0.0, |(g, s)| s * xo[g])))
            .collect();
        let mut share = pencil.component_energies(x, &self.owner_perm);
        let total: f64 = share.iter().sum::<f64>().max(f64::MIN_POSITIVE);
        share.iter_mut().for_each(|s| *s /= total);
        // x^T M x split over dofs as x_j (M x)_j: the parts sum to the total exactly.
        let (mut axle_e, mut all_e) = (0.0, 0.0);
        for j in 0..ndof {
            let e = x[j] * mx[j];
            all_e += e;
            if self.in_axle[j] {
                axle_e += e;
            }
        }
        let axle_energy_share = if all_e > 0.0 { axle_e / all_e } else { 0.0 };
        let family = mode_family(rigid, axle_energy_share, &share);
        let nodal_circles = self.nodal_circles(family, &shape);
        Ok(AxisymMode {
            frequency_hz: freq,
            family,
            nodal_circles,
            nodal_diameters: harmonic,
            harmonic,
            residual,
            multiplicity: if harmonic == 0 { 1 } else { 2 },
            energy_share: share,
            axle_energy_share,
            shape,
        })
    }

    /// Nodal circles of a mode of `family` with nodal `shape`: sign changes along the axle for
    /// the axle family; otherwise on the wheel's radial path, plus those along the axle where
    /// it moves enough.
    fn nodal_circles(&self, family: ModeFamily, shape: &[[f64; 3]]) -> u32 {
        // The axle's dominant component along the axle, from end to end through the hub.
        let mut e = [0.0f64; 3];
        for &i in &self.axle_path_nodes {
            for (c, ec) in e.iter_mut().enumerate() {
                *ec += shape[i][c] * shape[i][c];
            }
        }
        let axle_comp = (0..3).fold(0, |best, c| if e[c] > e[best] { c } else { best });
        let axle_samples: Vec<f64> = self
            .axle_path_nodes
            .iter()
            .map(|&i| shape[i][axle_comp])
            .collect();
        let comp = match family {
            ModeFamily::Radial => 0,
            ModeFamily::Circumferential => 1,
            _ => 2,
        };
        let wheel_samples: Vec<f64> = self
            .wheel_path_nodes
            .iter()
            .map(|&i| shape[i][comp])
            .collect();
        let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if family == ModeFamily::Axle {
            sign_changes(&axle_samples)
        } else {
            // Circles on the wheel, plus those along the axle where it moves at least 5 % as
            // much as the wheel does.
            let scale = peak(&wheel_samples).max(peak(&axle_samples));
            sign_changes_above(&wheel_samples, NODAL_SIGN_THRESHOLD * scale)
                + sign_changes_above(&axle_samples, NODAL_SIGN_THRESHOLD * scale)
        }
    }
}

/// The family of a mode: rigid below [`RIGID_LIMIT_HZ`], axle from [`AXLE_FAMILY_SHARE`] of
/// its kinetic energy in the axle, else the component with the largest energy `share`
/// (radial, circumferential, axial).
fn mode_family(rigid: bool, axle_energy_share: f64, share: &[f64; 3]) -> ModeFamily {
    if rigid {
        ModeFamily::Rigid
    } else if axle_energy_share >= AXLE_FAMILY_SHARE {
        ModeFamily::Axle
    } else if share[2] >= share[0] && share[2] >= share[1] {
        ModeFamily::Axial
    } else if share[0] >= share[1] {
        ModeFamily::Radial
    } else {
        ModeFamily::Circumferential
    }
}

/// Nodes that only axle elements hold (the hub-axle interface belongs to the wheel).
fn axle_only_nodes(model: &AxisymModel) -> Vec<bool> {
    let n = model.mesh.node_count();
    let (mut axle, mut other) = (vec![false; n], vec![false; n]);
    for (e, conn) in model.mesh.elements.iter().enumerate() {
        let flag = if model.mesh.part[e] == part::AXLE {
            &mut axle
        } else {
            &mut other
        };
        for &i in conn {
            flag[i] = true;
        }
    }
    (0..n).map(|i| axle[i] && !other[i]).collect()
}

/// The nearest mesh node to each point of a path (consecutive repeats removed).
fn path_nodes(model: &AxisymModel, path: &[[f64; 2]]) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::new();
    for p in path {
        let best = (0..model.mesh.node_count())
            .min_by(|&a, &b| {
                let da = dist2(model.mesh.nodes[a], *p);
                let db = dist2(model.mesh.nodes[b], *p);
                da.total_cmp(&db)
            })
            .unwrap_or(0);
        if out.last() != Some(&best) {
            out.push(best);
        }
    }
    out
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Sign changes of a sampled displacement, ignoring samples below
/// 5 % (`NODAL_SIGN_THRESHOLD`) of the largest magnitude.
pub fn sign_changes(samples: &[f64]) -> u32 {
    let peak = samples.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if peak == 0.0 {
        return 0;
    }
    sign_changes_above(samples, NODAL_SIGN_THRESHOLD * peak)
}

/// Sign changes of a sampled displacement, ignoring samples of magnitude below `threshold`.
pub fn sign_changes_above(samples: &[f64], threshold: f64) -> u32 {
    let mut last = 0.0f64;
    let mut count = 0;
    for &v in samples {
        if v.abs() < threshold || v == 0.0 {
            continue;
        }
        if last != 0.0 && v.signum() != last {
            count += 1;
        }
        last = v.signum();
    }
    count
}

/// Solve all requested harmonics (in parallel over harmonics) and sort the modes by frequency.
pub fn solve(model: &AxisymModel, opts: &AxisymOptions) -> Result<AxisymResult> {
    if !(opts.fmax_hz.is_finite() && opts.fmax_hz > 0.0) {
        return Err(Error::input(
            "command line",
            "--fmax-hz",
            format!("must be a positive frequency, got {}", opts.fmax_hz),
        ));
    }
    let t0 = Instant::now();
    // Harmonics with equal dof maps share a pattern: the axis conditions differ for n = 0,
    // n = 1 and n >= 2; a section off the axis has one map for all n.
    let on_axis = model.mesh.axis_nodes().iter().any(|&a| a);
    let class = |n: u32| if on_axis { n.min(2) } else { 0 };
    let mut classes: Vec<u32> = opts.harmonics.iter().map(|&n| class(n)).collect();
    classes.sort_unstable();
    classes.dedup();
    let structures: Vec<Result<(DofMap, usize, std::sync::Arc<eigen::Pattern>)>> = classes
        .par_iter()
        .map(|&c| harmonic_structure(model, c))
        .collect();
    let mut by_class = Vec::with_capacity(classes.len());
    for (c, s) in classes.iter().zip(structures) {
        by_class.push((*c, s?));
    }
    let per: Vec<Result<(Vec<AxisymMode>, HarmonicStats)>> = opts
        .harmonics
        .par_iter()
        .map(|&n| {
            let s = &by_class
                .iter()
                .find(|(c, _)| *c == class(n))
                .expect("every class was built")
                .1;
            solve_harmonic_with(model, n, opts.fmax_hz, s)
        })
        .collect();
    let mut modes = Vec::new();
    let mut harmonics = Vec::new();
    for r in per {
        let (m, s) = r?;
        modes.extend(m);
        harmonics.push(s);
    }
    modes.sort_by(|a, b| {
        a.frequency_hz
            .total_cmp(&b.frequency_hz)
            .then(a.harmonic.cmp(&b.harmonic))
    });
    Ok(AxisymResult {
        modes,
        harmonics,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// The modes of a wheel as the rolling model holds it, for labelling a run's peaks: every
/// harmonic of [`AxisymOptions::default`] below its upper frequency, the wheel clamped at
/// both axle end faces.
///
/// Why clamped there: in the rolling model those faces are one rigid body that cannot move
/// laterally (its lateral motion is prescribed) nor turn except about the axle, which is what
/// fixes the modes with 0 and 1 nodal diameters (the free wheelset's rigid and low axial modes
/// become the (0,0) axial mode at 229 Hz, which the demo cases' lateral vibration shows at
/// 227-234 Hz). Modes with 2 or more nodal diameters do not move the axle and are the same
/// either way.
pub fn rolling_wheel_modes(wheel: &WheelSpec) -> Result<AxisymResult> {
    let model = AxisymModel::from_wheel(
        wheel,
        WheelModelOptions {
            without_axle: false,
            clamp: WheelClamp::AxleEnds,
        },
    )?;
    solve(&model, &AxisymOptions::default())
}
