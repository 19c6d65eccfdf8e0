//! S1002 wheel on inclined 54E1 rail: the closures that [`super::geometry`] works with, the
//! contact point for a lateral wheel position, and the Hertz curvatures there.
//!
//! Frame: the upright rail section's origin (crown top) is at y = 0, z = 0 and the section is
//! inclined 1:40 towards the track centre (-y), as in the track mesh
//! ([`crate::mesh::track::place_rail_point`]). The wheel's tape circle sits at lateral position
//! `wheel_y_m`; the wheel radius at lateral y is `R + F(S)`, `S = (y - wheel_y) * 1000` mm.

use crate::geometry::{rail54e1, s1002};
use crate::{Error, Result};

/// Height (m) of the inclined 54E1 running surface at lateral position `y_m`, or None beyond
/// the head. The section coordinate whose rotated image lies at `y_m` is found by fixed-point
/// iteration (the rotation is only 1:40).
pub fn rail_top_height_m(y_m: f64) -> Option<f64> {
    let (s, c) = rail54e1::INCLINATION_RAD.sin_cos();
    let rotate = |ys_mm: f64, zs_mm: f64| {
        (
            (ys_mm * c - zs_mm * s) * 1e-3,
            (ys_mm * s + zs_mm * c) * 1e-3,
        )
    };
    let mut ys_mm = y_m * 1e3;
    for _ in 0..6 {
        let zs = rail54e1::top_surface_z_mm(ys_mm)?;
        let (y, _) = rotate(ys_mm, zs);
        ys_mm += (y_m - y) * 1e3;
    }
    let zs = rail54e1::top_surface_z_mm(ys_mm)?;
    Some(rotate(ys_mm, zs).1)
}

/// Wheel radius increment F (m) at lateral position `y_m` for a tape circle at `wheel_y_m`.
pub fn wheel_radius_offset_m(y_m: f64, wheel_y_m: f64) -> f64 {
    s1002::height_mm((y_m - wheel_y_m) * 1e3) * 1e-3
}

/// Lateral position (m) of the first point of contact of S1002 on 54E1 for the tape circle at
/// `wheel_y_m`: the closest approach, where `rail_top(y) + F(y)` is largest over the head (the
/// wheel is lowered onto the rail), searched on a 0.01 mm grid. None when no tread point lies
/// above the head.
pub fn first_contact_y_m(wheel_y_m: f64) -> Option<f64> {
    let mut best: Option<(f64, f64)> = None;
    let mut y = -0.036;
    while y <= 0.036 {
        if let Some(z) = rail_top_height_m(y) {
            let s_mm = (y - wheel_y_m) * 1e3;
            if (s1002::S_FLANGE_BACK_MM..=s1002::S_FIELD_FACE_MM).contains(&s_mm) {
                let v = z + wheel_radius_offset_m(y, wheel_y_m);
                if best.is_none_or(|b| v > b.1) {
                    best = Some((y, v));
                }
            }
        }
        y += 1e-5;
    }
    best.map(|b| b.0)
}

/// Contact angle (degrees) at lateral position `y_m` of the inclined rail top: the slope of the
/// running surface, `atan(dz/dy)` by a central difference over 0.2 mm, positive where the
/// surface falls towards the track centre (-y), so that the contact normal leans that way (the
/// gauge side and the flange). None beyond the head.
pub fn rail_contact_angle_deg(y_m: f64) -> Option<f64> {
    let h = 1e-4;
    let slope = (rail_top_height_m(y_m + h)? - rail_top_height_m(y_m - h)?) / (2.0 * h);
    Some(slope.atan().to_degrees())
}

/// Default point spacing of a profile table (mm): finer than the 1 mm contact-zone elements of
/// the `paper` meshes.
pub const DEFAULT_TABLE_STEP_MM: f64 = 0.5;
/// Default span of tape-circle positions (mm from the rail centre) of a contact scan: from
/// 30 mm towards the track centre to 24 mm towards the field side, short of flange contact.
pub const DEFAULT_CONTACT_SCAN_MM: (f64, f64) = (-30.0, 24.0);
/// Default element size (mm) of the rail section mesh on which the section's torsion constant,
/// shear centre and warping constant are solved.
pub const DEFAULT_SECTION_ELEMENT_MM: f64 = 1.0;

/// A contact angle from which the contact counts as flange contact (degrees): past the gauge
/// corner (the rail's R13 arc, 15-30 degrees in S1002 on 54E1) and onto the flange flank,
/// which stands at about 70 degrees.
pub const FLANGE_CONTACT_ANGLE_DEG: f64 = 45.0;

/// The smallest tape-circle position at or above `from_wheel_y_m` (m) at which S1002 on 54E1
/// first touches with a contact angle of [`FLANGE_CONTACT_ANGLE_DEG`] or more: the wheel moving
/// towards +y (field side) brings its flange to the rail's gauge face. Scanned in 0.05 mm steps
/// up to 30 mm; None if no flange contact is found there.
pub fn flange_contact_wheel_y_m(from_wheel_y_m: f64) -> Option<f64> {
    let mut wheel_y = from_wheel_y_m;
    while wheel_y <= 0.03 {
        if let Some(angle) = first_contact_y_m(wheel_y).and_then(rail_contact_angle_deg) {
            if angle >= FLANGE_CONTACT_ANGLE_DEG {
                return Some(wheel_y);
            }
        }
        wheel_y += 5e-5;
    }
    None
}

/// The contact point and Hertz curvatures of S1002 (tape-circle radius `wheel_radius_m`) on
/// 54E1 at 1:40 for the wheel's tape circle at `wheel_y_m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileContact {
    /// Lateral position of the first point of contact (m).
    pub contact_y_m: f64,
    /// Wheel profile coordinate S at the contact point (mm).
    pub contact_s_mm: f64,
    /// Curvature of the gap along x (1/m): `1 / (2 R(y0))`.
    pub curvature_x_per_m: f64,
    /// Curvature of the gap along y (1/m).
    pub curvature_y_per_m: f64,
}

/// Find the first point of contact (where wheel and rail are closest when the wheel is lowered)
/// and the Hertz curvatures there (central differences over 0.5 mm). Near a junction of the
/// crown's arcs (R300|R80 at |y| = 10.0 mm, R80|R13 at 24.9 mm) the curvature jumps and the
/// contact is not Hertzian: the value is then an average over the step, and the exact
/// half-space solver on [`super::geometry::profile_gap`] is the right tool. Errors when the wheel position puts the tread off the rail
/// head or the contact is not Hertzian there (conformal to within the curvature step).
pub fn s1002_on_54e1(wheel_y_m: f64, wheel_radius_m: f64) -> Result<ProfileContact> {
    if wheel_y_m.is_nan() || wheel_y_m.abs() > 0.03 {
        return Err(Error::input(
            "command line",
            "--wheel-y-m",
            format!("the tape circle must be within 30 mm of the rail centre, got {wheel_y_m} m"),
        ));
    }
    let y0 = first_contact_y_m(wheel_y_m).ok_or_else(|| {
        Error::input(
            "command line",
            "--wheel-y-m",
            "no tread point above the rail head",
        )
    })?;
    let rail = |y: f64| rail_top_height_m(y).unwrap_or(f64::NAN);
    let (a, b) = super::geometry::curvatures_at(
        wheel_radius_m,
        |y| wheel_radius_offset_m(y, wheel_y_m),
        rail,
        y0,
        5e-4,
    )?;
    Ok(ProfileContact {
        contact_y_m: y0,
        contact_s_mm: (y0 - wheel_y_m) * 1e3,
        curvature_x_per_m: a,
        curvature_y_per_m: b,
    })
}

/// One row of the undeformed gap across the rail head (m).
#[derive(Clone, Copy, Debug)]
pub struct GapRow {
    /// Lateral position (m).
    pub y_m: f64,
    /// Gap to the first point of contact: `g(y) = max(h) - h(y)` (m).
    pub gap_m: f64,
    /// Rail top height (inclined 54E1) (m).
    pub rail_height_m: f64,
    /// Wheel radius increment (S1002) at y (m).
    pub wheel_radius_increment_m: f64,
}

/// The undeformed gap of S1002 on the inclined 54E1 across the head at x = 0, for the tape
/// circle at `wheel_y_m`: `g(y) = max(h) - h(y)`, `h = rail height + wheel radius increment`
/// (the gap Kalker's `--profile-gap` solves on), from -35 to 35 mm every `step_m`, where the
/// rail has a top. Returns the first contact and the rows: the check of a meshed contact
/// against the profiles.
pub fn undeformed_gap_across_head(
    wheel_y_m: f64,
    wheel_radius_m: f64,
    step_m: f64,
) -> Result<(ProfileContact, Vec<GapRow>)> {
    let contact = s1002_on_54e1(wheel_y_m, wheel_radius_m)?;
    let height = |y: f64| rail_top_height_m(y).map(|z| z + wheel_radius_offset_m(y, wheel_y_m));
    let top = height(contact.contact_y_m).unwrap_or(f64::NAN);
    let count = (0.070 / step_m).floor() as usize;
    let rows = (0..=count)
        .map(|i| -0.035 + i as f64 * step_m)
        .filter_map(|y| {
            let h = height(y)?;
            Some(GapRow {
                y_m: y,
                gap_m: top - h,
                rail_height_m: rail_top_height_m(y)?,
                wheel_radius_increment_m: wheel_radius_offset_m(y, wheel_y_m),
            })
        })
        .collect();
    Ok((contact, rows))
}
