//! What the rolling run measures at the contact besides the forces: where the contact sits on
//! both profiles, the lateral motion of tread and rail head under it, the micro-slip, and how
//! far the flange is from the rail.
//!
//! Every quantity is an average over the slave nodes in contact weighted by their normal force
//! `f_N,k` (for micro-slip this is the pressure-weighted mean, since every node's force is its
//! pressure times its tributary area):
//!
//! `q = sum_k f_N,k q_k / sum_k f_N,k`.
//!
//! - contact point on the wheel: the profile coordinate `S = (y_ref,k - y_tape) * 1000` mm of
//!   the slave nodes (their reference lateral position against the tape circle's, EN 13715);
//! - contact point on the rail: the lateral position `y` (mm) of the nodes' projections on the
//!   master faces in the reference configuration, in the inclined rail frame of
//!   [`crate::kalker::profiles`] (origin at the crown top of the upright section);
//! - contact angle: `atan2(-n_y, n_z)` of the master faces' unit normals, in degrees: positive
//!   when the normal leans towards the track centre (-y), as on the gauge side and the flange;
//! - lateral velocities of the tread (slaves) and of the rail head (the projections, from the
//!   face nodes' velocities with the projection weights), in the track frame;
//! - micro-slip: the tangential slip velocity `de / dt` of each node (m/s); divided by the
//!   rolling speed it is a local creepage;
//! - the lateral offset of the wheel against the rail at the contact, `u_y(slave) -
//!   u_y(projection)`: how far the tread has moved sideways on the rail since the preload,
//!   which with the profiles gives the flange clearance
//!   ([`crate::kalker::profiles::flange_contact_wheel_y_m`]).

use crate::contact::ContactPair;
use crate::explicit::solver::OutputFields;
use crate::mesh::P3;

/// Force-weighted contact kinematics of one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactKinematics {
    /// Wheel profile coordinate S of the contact (mm).
    pub wheel_s_mm: f64,
    /// Lateral position of the contact on the rail (mm).
    pub rail_y_mm: f64,
    /// Contact angle (degrees, positive towards the track centre).
    pub contact_angle_deg: f64,
    /// Lateral velocity of the tread at the contact (m/s).
    pub tread_lateral_velocity_m_per_s: f64,
    /// Lateral velocity of the rail head at the contact (m/s).
    pub rail_lateral_velocity_m_per_s: f64,
    /// Pressure-weighted lateral micro-slip velocity (m/s).
    pub lateral_microslip_m_per_s: f64,
    /// Pressure-weighted longitudinal micro-slip velocity (m/s).
    pub longitudinal_microslip_m_per_s: f64,
    /// Lateral displacement of the tread against the rail at the contact (m).
    pub lateral_offset_m: f64,
}

/// The kinematics of the slaves now in contact (None when nothing is in contact).
/// `tape_circle_y_m` is the reference lateral position of the wheel's tape circle;
/// `slave_yaw_shift_y_m` per slave how far the angle of attack moved its reference position
/// sideways (empty: none), taken off so that S and the lateral offset are the wheel's own.
pub fn contact_kinematics(
    pair: &ContactPair,
    reference: &[P3],
    output: &OutputFields,
    tape_circle_y_m: f64,
    slave_yaw_shift_y_m: &[f64],
) -> Option<ContactKinematics> {
    let mut total = 0.0;
    let mut sum = ContactKinematics::default();
    let (mut n_y, mut n_z) = (0.0, 0.0);
    for (k, st) in pair.state.iter().enumerate() {
        if !st.active || st.normal_force_n <= 0.0 {
            continue;
        }
        let w = st.normal_force_n;
        let slave = pair.slaves[k];
        let face = pair.faces[st.face as usize];
        let (mut master_ref_y, mut master_v_y, mut master_u_y) = (0.0, 0.0, 0.0);
        for (j, &m) in face.iter().enumerate() {
            master_ref_y += st.weights[j] * reference[m][1];
            master_v_y += st.weights[j] * output.velocity[m][1];
            master_u_y += st.weights[j] * output.displacement[m][1];
        }
        let shift = slave_yaw_shift_y_m.get(k).copied().unwrap_or(0.0);
        total += w;
        sum.wheel_s_mm += w * (reference[slave][1] - shift - tape_circle_y_m) * 1e3;
        sum.rail_y_mm += w * master_ref_y * 1e3;
        n_y += w * st.normal[1];
        n_z += w * st.normal[2];
        sum.tread_lateral_velocity_m_per_s += w * output.velocity[slave][1];
        sum.rail_lateral_velocity_m_per_s += w * master_v_y;
        sum.lateral_microslip_m_per_s += w * st.slip_velocity_m_per_s[1];
        sum.longitudinal_microslip_m_per_s += w * st.slip_velocity_m_per_s[0];
        sum.lateral_offset_m += w * (output.displacement[slave][1] + shift - master_u_y);
    }
    if total <= 0.0 {
        return None;
    }
    Some(ContactKinematics {
        wheel_s_mm: sum.wheel_s_mm / total,
        rail_y_mm: sum.rail_y_mm / total,
        contact_angle_deg: (-n_y).atan2(n_z).to_degrees(),
        tread_lateral_velocity_m_per_s: sum.tread_lateral_velocity_m_per_s / total,
        rail_lateral_velocity_m_per_s: sum.rail_lateral_velocity_m_per_s / total,
        lateral_microslip_m_per_s: sum.lateral_microslip_m_per_s / total,
        longitudinal_microslip_m_per_s: sum.longitudinal_microslip_m_per_s / total,
        lateral_offset_m: sum.lateral_offset_m / total,
    })
}

/// Running extremes of the contact point over a run, for `run.json`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ContactPointRecord {
    /// Contact point when rolling starts (after the preload): wheel S (mm).
    pub initial_wheel_s_mm: f64,
    /// Rail y (mm) when rolling starts.
    pub initial_rail_y_mm: f64,
    /// Contact angle when rolling starts (degrees).
    pub initial_contact_angle_deg: f64,
    /// Smallest and largest wheel S over the run (mm).
    pub wheel_s_range_mm: [f64; 2],
    /// Smallest and largest rail y over the run (mm).
    pub rail_y_range_mm: [f64; 2],
    /// Smallest and largest contact angle over the run (degrees).
    pub contact_angle_range_deg: [f64; 2],
    /// Tape-circle position at which S1002 on 54E1 first touches with the flange (contact
    /// angle of [`crate::kalker::profiles::FLANGE_CONTACT_ANGLE_DEG`] or more), from the
    /// profiles (mm).
    pub flange_contact_wheel_y_mm: f64,
    /// Flange clearance (mm) when rolling starts, and its smallest value over the run:
    /// `flange_contact_wheel_y - (tape_circle_y + lateral offset at the contact)`.
    pub initial_flange_clearance_mm: f64,
    /// Smallest flange clearance over the run (mm).
    pub smallest_flange_clearance_mm: f64,
}

impl ContactPointRecord {
    /// A record that starts at `k` with the profiles' flange position.
    pub fn start(k: &ContactKinematics, clearance_mm: f64, flange_contact_wheel_y_mm: f64) -> Self {
        ContactPointRecord {
            initial_wheel_s_mm: k.wheel_s_mm,
            initial_rail_y_mm: k.rail_y_mm,
            initial_contact_angle_deg: k.contact_angle_deg,
            wheel_s_range_mm: [k.wheel_s_mm; 2],
            rail_y_range_mm: [k.rail_y_mm; 2],
            contact_angle_range_deg: [k.contact_angle_deg; 2],
            flange_contact_wheel_y_mm,
            initial_flange_clearance_mm: clearance_mm,
            smallest_flange_clearance_mm: clearance_mm,
        }
    }

    /// Widens the ranges with one sample.
    pub fn update(&mut self, k: &ContactKinematics, clearance_mm: f64) {
        let widen = |r: &mut [f64; 2], x: f64| {
            r[0] = r[0].min(x);
            r[1] = r[1].max(x);
        };
        widen(&mut self.wheel_s_range_mm, k.wheel_s_mm);
        widen(&mut self.rail_y_range_mm, k.rail_y_mm);
        widen(&mut self.contact_angle_range_deg, k.contact_angle_deg);
        self.smallest_flange_clearance_mm = self.smallest_flange_clearance_mm.min(clearance_mm);
    }
}
