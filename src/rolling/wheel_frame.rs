//! The wheel's own frame and its rigid motion, from which the vibration outputs are read: the
//! axle axis `a`, the vertical and the rolling direction `a x e_z`; the wheelset's centre, its
//! velocity and its spin about `a` from the hub nodes; and a node's deformation velocity, its
//! velocity less that rigid motion. Upright (`a = e_y`) every product reduces exactly to the
//! track's components.

use crate::explicit::solver::OutputFields;
use crate::mesh::P3;

/// `a . b`.
pub(super) fn dot3(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a x b`.
pub(super) fn cross3(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The wheel's frame, which moves with the wheelset but does not turn with its spin: the axle
/// axis `a` (lateral), the vertical `e_z` and the rolling direction `a x e_z` (longitudinal).
/// Upright (`a = e_y`) these are the track's y, z and x, and every product below reduces
/// exactly to the track components (multiplications by 0 and 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelFrame {
    /// The axle axis (unit vector).
    pub axis: P3,
    /// The rolling direction `a x e_z` (unit vector, horizontal).
    pub rolling: P3,
}

impl WheelFrame {
    /// The frame of a wheel turning about `axis` (a horizontal unit vector).
    pub fn new(axis: P3) -> WheelFrame {
        WheelFrame {
            axis,
            rolling: cross3(axis, [0.0, 0.0, 1.0]),
        }
    }

    /// Whether the axis is exactly the track's y (no angle of attack).
    pub fn is_upright(&self) -> bool {
        self.axis == [0.0, 1.0, 0.0]
    }

    /// A vector's lateral (along the axis), vertical and longitudinal components.
    pub fn components(&self, v: P3) -> [f64; 3] {
        [dot3(v, self.axis), v[2], dot3(v, self.rolling)]
    }
}

/// Rigid motion of the wheelset from the hub nodes: centre velocity (mean) and spin rate about
/// the axis `a`, `Omega = mean((r x (v - v_c)) . a / |r_perp|^2)` with `r_perp = r - (r . a) a`
/// the part of `r` across the axis.
pub(super) fn wheelset_motion(
    hub: &[usize],
    reference: &[P3],
    output: &OutputFields,
    axis: P3,
) -> (P3, P3, f64) {
    let n = hub.len().max(1) as f64;
    let mut c = [0.0; 3];
    let mut vc = [0.0; 3];
    for &h in hub {
        for i in 0..3 {
            c[i] += (reference[h][i] + output.displacement[h][i]) / n;
            vc[i] += output.velocity[h][i] / n;
        }
    }
    let mut omega = 0.0;
    for &h in hub {
        let r: P3 = [0, 1, 2].map(|i| reference[h][i] + output.displacement[h][i] - c[i]);
        let along = dot3(r, axis);
        let r_perp: P3 = [0, 1, 2].map(|i| r[i] - along * axis[i]);
        let dv: P3 = [0, 1, 2].map(|i| output.velocity[h][i] - vc[i]);
        let r2 = dot3(r_perp, r_perp);
        if r2 > 0.0 {
            omega += dot3(cross3(r_perp, dv), axis) / r2 / n;
        }
    }
    (c, vc, omega)
}

/// Velocity of node `nd` relative to the rigid motion (centre `c`, velocity `vc`, spin
/// `omega` about the axis `a`): `v - v_c - omega a x r`.
pub(super) fn deformation_velocity(
    nd: usize,
    reference: &[P3],
    output: &OutputFields,
    motion: (P3, P3, f64),
    axis: P3,
) -> P3 {
    let (c, vc, omega) = motion;
    let r = [0, 1, 2].map(|i| reference[nd][i] + output.displacement[nd][i] - c[i]);
    let spin = cross3(axis, r);
    let v = output.velocity[nd];
    [0, 1, 2].map(|i| v[i] - vc[i] - omega * spin[i])
}
