//! Comparison of an FE contact-patch snapshot with Kalker's theory, as the paper does with
//! CONTACT: the FE normal and creep forces go in as prescribed forces, the creepages and
//! Kalker's adhesion/slip map come out, drawn beside the FE map on the same axes and scale,
//! each with its orientation angle.
//!
//! Orientation angle of a patch solution: the angle from the rolling direction (x) of the
//! principal axis of the adhesion region, from the second moments of the adhesion points
//! (`0.5 atan2(2 Ixy, Ixx - Iyy)`, area-weighted, about their centroid). Lateral creepage
//! turns the adhesion zone, and the angle grows with it (Yang & Li 2019).

use serde::{Deserialize, Serialize};

use super::hertz::HertzContact;
use super::inverse::{solve_force_prescribed, ForcePrescribedResult};
use super::rolling::{Method, RollingSolver};
use super::tangential::ElementState;
use super::Material;
use crate::{Error, Result};

/// One slave node of an FE contact patch.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatchPoint {
    /// Position in the patch, rolling direction (m), relative to the patch centre.
    pub x_m: f64,
    /// Lateral position in the patch (m).
    pub y_m: f64,
    /// Contact pressure (Pa).
    pub pressure_pa: f64,
    /// True where the node slips (by the stress criterion: shear at the traction bound).
    pub slip: bool,
}

/// An FE contact-patch snapshot (what the rolling-contact simulator writes per instant).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatchSnapshot {
    /// Time of the snapshot (s).
    pub time_s: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Longitudinal creep force on the wheel (N).
    pub force_x_n: f64,
    /// Lateral creep force on the wheel (N).
    pub force_y_n: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Lateral (y) component of the unit resultant normal force on the wheel: the sine of the
    /// contact angle. The wheel's spin `V / R` about its axle (y) projected on this normal
    /// gives the contact's spin creepage `phi = normal_lateral_fraction / R` (1/m), which
    /// `squeal kalker compare` uses when `--phi` is not given. Absent in snapshots from
    /// elsewhere (spin 0 then).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_lateral_fraction: Option<f64>,
    /// Patch points.
    pub points: Vec<PatchPoint>,
}

/// Result of the comparison.
#[derive(Clone, Debug, Serialize)]
pub struct SnapshotComparison {
    /// Kalker's force-prescribed solution (creepages, uniqueness, fields).
    pub kalker: ForcePrescribedResult,
    /// Orientation angle of the FE adhesion zone (degrees from x).
    pub fe_orientation_deg: Option<f64>,
    /// Orientation angle of Kalker's adhesion zone (degrees from x).
    pub kalker_orientation_deg: Option<f64>,
    /// Adhesion area fraction of the FE patch (by point count).
    pub fe_adhesion_fraction: f64,
    /// Adhesion area fraction of Kalker's patch.
    pub kalker_adhesion_fraction: f64,
}

/// Principal-axis angle (degrees, in (-90, 90]) of a weighted point cloud; None for fewer than
/// three points or an isotropic cloud.
pub fn orientation_deg(points: &[(f64, f64, f64)]) -> Option<f64> {
    let w: f64 = points.iter().map(|p| p.2).sum();
    if points.len() < 3 || w <= 0.0 {
        return None;
    }
    let cx = points.iter().map(|p| p.0 * p.2).sum::<f64>() / w;
    let cy = points.iter().map(|p| p.1 * p.2).sum::<f64>() / w;
    let (mut ixx, mut iyy, mut ixy) = (0.0, 0.0, 0.0);
    for &(x, y, m) in points {
        ixx += m * (x - cx) * (x - cx);
        iyy += m * (y - cy) * (y - cy);
        ixy += m * (x - cx) * (y - cy);
    }
    if (ixx - iyy).abs() + ixy.abs() < 1e-30 * (ixx + iyy).max(1e-300) {
        return None;
    }
    Some(0.5 * (2.0 * ixy).atan2(ixx - iyy).to_degrees())
}

/// Compare an FE snapshot with Kalker's theory for the given contact (curvatures from the
/// profiles or the crown radii) and method. The FE forces are prescribed together with the
/// spin creepage `spin_per_m` (1/m; for a wheel rolling at a contact angle `gamma` about
/// `sin(gamma) / R`), and Kalker returns the longitudinal and lateral creepages. With spin left
/// at zero, a lateral force that the FE contact's spin produces is read as lateral creepage.
pub fn compare_snapshot(
    snapshot: &PatchSnapshot,
    hertz_curvatures_per_m: (f64, f64),
    material: Material,
    method: Method,
    elements_per_axis: usize,
    spin_per_m: f64,
) -> Result<SnapshotComparison> {
    require_points(snapshot, "snapshot")?;
    let hertz = HertzContact::from_curvatures(
        hertz_curvatures_per_m.0,
        hertz_curvatures_per_m.1,
        snapshot.normal_force_n,
        material,
    )?;
    let solver = RollingSolver::new(&hertz, snapshot.mu, method, elements_per_axis)?;
    compare_with_solver(
        snapshot,
        &solver,
        (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
        spin_per_m,
    )
}

/// Compare an FE snapshot with Kalker's exact half-space solution on the undeformed gap of the
/// S1002 wheel (tape-circle radius `wheel_radius_m`) on the 1:40 54E1 rail with the tape
/// circle at `wheel_y_m` (CONTACT's non-Hertzian mode). Where the contact straddles a junction
/// of the crown's arcs, or two points of the profiles come close, the patch is not elliptic, as
/// the FE patch is not.
///
/// Grid: it must hold every point the bodies' approach can close, not only the first point of
/// contact (near a two-point contact the second point is centimetres away). Along y it spans,
/// with a 10 % margin, the lateral range where the undeformed gap at x = 0,
/// `g(y) = max(h) - h(y)` with `h = rail height + wheel radius increment`, is below twice the
/// Hertz approach `delta` at the first point of contact; along x, `|x| <= sqrt(4 R delta)`
/// (the wheel circle's gap `x^2 / 2R` at `2 delta`). It is widened (up to three times) while
/// the pressure still reaches its edge. The creepages returned are about the first point of
/// contact (with spin, xi depends on the origin).
pub fn compare_snapshot_on_profiles(
    snapshot: &PatchSnapshot,
    wheel_y_m: f64,
    wheel_radius_m: f64,
    material: Material,
    elements_per_axis: usize,
    spin_per_m: f64,
) -> Result<SnapshotComparison> {
    require_points(snapshot, "snapshot")?;
    if !(16..=400).contains(&elements_per_axis) {
        return Err(Error::input(
            "command line",
            "--grid",
            format!("must be in 16..=400 elements per axis, got {elements_per_axis}"),
        ));
    }
    let contact = super::profiles::s1002_on_54e1(wheel_y_m, wheel_radius_m)?;
    let hertz = HertzContact::from_curvatures(
        contact.curvature_x_per_m,
        contact.curvature_y_per_m,
        snapshot.normal_force_n,
        material,
    )?;
    let rail = |y: f64| super::profiles::rail_top_height_m(y).unwrap_or(f64::NAN);
    let wheel = |y: f64| super::profiles::wheel_radius_offset_m(y, wheel_y_m);
    // Lateral range that an approach of 2 delta closes (the same scan as the contact point's).
    let height = |y: f64| rail(y) + wheel(y);
    let top = height(contact.contact_y_m);
    let closing = 2.0 * hertz.approach_m;
    let (mut y_lo, mut y_hi) = (contact.contact_y_m, contact.contact_y_m);
    let mut y = -0.036;
    while y <= 0.036 {
        let s_mm = (y - wheel_y_m) * 1e3;
        let on_tread = (crate::geometry::s1002::S_FLANGE_BACK_MM
            ..=crate::geometry::s1002::S_FIELD_FACE_MM)
            .contains(&s_mm);
        let h = height(y);
        if on_tread && h.is_finite() && top - h < closing {
            y_lo = y_lo.min(y);
            y_hi = y_hi.max(y);
        }
        y += 1e-5;
    }
    let centre_y_m = 0.5 * (y_lo + y_hi);
    let mut half_y_m = 1.1 * (0.5 * (y_hi - y_lo)).max(hertz.semi_axis_b_m);
    let mut half_x_m = 1.1 * (4.0 * wheel_radius_m * hertz.approach_m).sqrt();
    // The creepages' origin is the first point of contact, as in the Hertz case and in
    // CONTACT; the grid's is its centre, `offset` to the side of it. With spin the rigid slip
    // `xi - phi y` is the same field in both when `xi_grid = xi_contact + phi offset`.
    let offset_y_m = contact.contact_y_m - centre_y_m;
    for _ in 0..3 {
        let grid = super::halfspace::Grid::centered(
            half_x_m,
            half_y_m,
            elements_per_axis,
            elements_per_axis,
        );
        let gap_m = super::geometry::profile_gap(
            &grid,
            wheel_radius_m,
            wheel,
            rail,
            centre_y_m,
            super::geometry::WheelCircle::Exact,
        )?;
        let solver = RollingSolver::exact_from_gap(
            grid,
            &gap_m,
            snapshot.normal_force_n,
            material,
            snapshot.mu,
        )?;
        let touches_edge = solver.normal_solution().is_some_and(|(g, normal)| {
            (0..g.nx).any(|i| {
                normal.pressure_pa[g.index(i, 0)] > 0.0
                    || normal.pressure_pa[g.index(i, g.ny - 1)] > 0.0
            }) || (0..g.ny).any(|j| {
                normal.pressure_pa[g.index(0, j)] > 0.0
                    || normal.pressure_pa[g.index(g.nx - 1, j)] > 0.0
            })
        });
        if !touches_edge {
            let mut cmp = compare_with_solver(
                snapshot,
                &solver,
                (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
                spin_per_m,
            )?;
            let xi_contact = cmp.kalker.creepages.xi - spin_per_m * offset_y_m;
            cmp.kalker.creepages.xi = xi_contact;
            cmp.kalker.solution.creepages.xi = xi_contact;
            return Ok(cmp);
        }
        half_x_m *= 1.5;
        half_y_m *= 1.5;
    }
    Err(Error::input(
        "command line",
        "--wheel-y-m",
        format!(
            "the contact patch at this wheel position reaches beyond the grid ({:.1} x {:.1} mm)",
            2e3 * half_x_m / 1.5,
            2e3 * half_y_m / 1.5
        ),
    ))
}

/// An FE snapshot without a contact point that carries pressure has nothing to compare (a
/// comparison of zero points would otherwise come out as a result).
pub fn require_points(snapshot: &PatchSnapshot, source: &str) -> Result<()> {
    if snapshot.points.is_empty() {
        return Err(Error::input(
            source,
            "points",
            "the FE patch has no contact points",
        ));
    }
    if !snapshot.points.iter().any(|p| p.pressure_pa > 0.0) {
        return Err(Error::input(
            source,
            "points[].pressure_pa",
            format!(
                "none of the FE patch's {} points carries pressure (every pressure_pa is at or \
                 below 0): at least one must be positive for a contact to compare",
                snapshot.points.len()
            ),
        ));
    }
    Ok(())
}

/// Force-prescribed solve on `solver` and the comparison of the two adhesion zones.
fn compare_with_solver(
    snapshot: &PatchSnapshot,
    solver: &RollingSolver,
    semi_axes_m: (f64, f64),
    spin_per_m: f64,
) -> Result<SnapshotComparison> {
    let kalker = solve_force_prescribed(
        solver,
        semi_axes_m,
        snapshot.force_x_n,
        snapshot.force_y_n,
        spin_per_m,
    )?;
    let fe_adhesion: Vec<(f64, f64, f64)> = snapshot
        .points
        .iter()
        .filter(|p| !p.slip && p.pressure_pa > 0.0)
        .map(|p| (p.x_m, p.y_m, 1.0))
        .collect();
    let s = &kalker.solution;
    let k_adhesion: Vec<(f64, f64, f64)> = (0..s.x_m.len())
        .filter(|&k| s.state[k] == ElementState::Adhesion)
        .map(|k| (s.x_m[k], s.y_m[k], s.area_m2[k]))
        .collect();
    let loaded = snapshot
        .points
        .iter()
        .filter(|p| p.pressure_pa > 0.0)
        .count()
        .max(1);
    Ok(SnapshotComparison {
        fe_orientation_deg: orientation_deg(&fe_adhesion),
        kalker_orientation_deg: orientation_deg(&k_adhesion),
        fe_adhesion_fraction: fe_adhesion.len() as f64 / loaded as f64,
        kalker_adhesion_fraction: s.adhesion_area_fraction(),
        kalker,
    })
}
