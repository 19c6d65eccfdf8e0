//! How the wheelset is driven once rolling: the loaded rolling radius, the forward guide that
//! holds the axle at the rolling speed, and the prescribed-creepage drive.

use super::build::RollingModel;
use crate::explicit::Curve;
use crate::mesh::P3;
use crate::model::case;
use crate::Result;

/// Holds the axle at the rolling speed and spins it at `V cos(psi) (1 + xi(t)) / R` (see
/// [`case::CreepageRamp`]; psi the angle of attack, whose wheel rolls freely at `V cos(psi) /
/// R`): forward speed and spin are prescribed on the axle body from now on.
pub(super) fn prescribe_creepage(
    m: &mut RollingModel,
    ramp: &case::CreepageRamp,
    speed_m_per_s: f64,
    radius_m: f64,
    angle_of_attack_rad: f64,
) -> Result<()> {
    let t0 = m.solver.time_s;
    let end = m.solver.time_s.max(ramp.end_s) + 1.0;
    let rolling_speed = speed_m_per_s * angle_of_attack_rad.cos();
    let spin = |xi: f64| rolling_speed * (1.0 + xi) / radius_m;
    let mut times = vec![t0];
    let mut values = vec![spin(0.0)];
    if ramp.start_s > t0 {
        times.push(ramp.start_s);
        values.push(spin(0.0));
    }
    times.push(ramp.start_s.max(t0) + 1e-9);
    values.push(spin(ramp.start));
    times.push(ramp.end_s);
    values.push(spin(ramp.end));
    times.push(end);
    values.push(spin(ramp.end));
    let spin_curve = Curve::new(times, values, "creepage")?;
    hold_forward_speed(m, speed_m_per_s)?;
    let body = &mut m.solver.model.rigid_bodies[m.axle_body];
    body.prescribed_spin_rad_per_s = Some(spin_curve);
    body.torque = None;
    Ok(())
}

/// The forward guide: from now on the axle body's centre moves along x at the rolling speed
/// (see [`RollingCase::hold_forward_speed`]); the force that holds it is the body's reaction.
///
/// The engine takes the body's velocity from the curve's slope alone, so a run resumed from a
/// checkpoint gets the same guide from a curve laid from its own start.
pub(super) fn hold_forward_speed(m: &mut RollingModel, speed_m_per_s: f64) -> Result<()> {
    let t0 = m.solver.time_s;
    // Longer than any case (end_time_s <= 1 s): the curve holds its last value after its end.
    let end = t0 + 2.0;
    let axle = m.axle_body;
    let centre_x = m.solver.rigid[axle].centre_m[0] - m.solver.rigid[axle].centre0_m[0];
    let forward = Curve::new(
        vec![t0, end],
        vec![centre_x, centre_x + speed_m_per_s * (end - t0)],
        "hold_forward_speed",
    )?;
    m.solver.model.rigid_bodies[axle].prescribed_translation_m[0] = Some(forward);
    Ok(())
}

/// Current wheel centre (mean of the hub bore nodes) and the force-weighted distance from it to
/// the loaded contact nodes (the nominal radius when nothing is in contact).
pub(super) fn loaded_centre_and_radius(m: &RollingModel) -> (P3, f64) {
    let nodes = &m.solver.model.mesh.nodes;
    let u = &m.solver.u;
    let hub = &m.contact.hub_nodes;
    let mut c = [0.0; 3];
    for &h in hub {
        for i in 0..3 {
            c[i] += (nodes[h][i] + u[h][i]) / hub.len() as f64;
        }
    }
    let axis = m.solver.model.rigid_bodies[m.axle_body]
        .rotation_axis
        .unwrap_or([0.0, 1.0, 0.0]);
    let (mut weighted, mut total) = (0.0, 0.0);
    for (k, st) in m.contact.pair.state.iter().enumerate() {
        if st.active {
            let n = m.contact.pair.slaves[k];
            // The distance from the axis: the part of r across it.
            let r: P3 = [0, 1, 2].map(|i| nodes[n][i] + u[n][i] - c[i]);
            let along = r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2];
            let [dx, dy, dz] = [0, 1, 2].map(|i| r[i] - along * axis[i]);
            weighted += st.normal_force_n * (dx * dx + dy * dy + dz * dz).sqrt();
            total += st.normal_force_n;
        }
    }
    let radius = if total > 0.0 {
        weighted / total
    } else {
        m.info.rolling_radius_m
    };
    (c, radius)
}
