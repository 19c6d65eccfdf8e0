//! The 3D modal pipeline that `squeal modes` runs on a model built by [`crate::model::modal`]
//! (or on the axisymmetric solver's section revolved into quadratic sectors, built here because
//! it needs that solver's section mesh): the band solve ([`super::solve`]) and the
//! classification of the modes ([`super::classify`]).
//!
//! The command line only parses, prints and writes; everything here returns plain data.

use crate::fem::axis::{rotate, to_y_axis};
use crate::fem::Hex8Kind;
use crate::input::wheel::WheelSpec;
use crate::mesh::volume;
use crate::mesh::P3;
use crate::modal::axisym::revolve::revolve_hex27;
use crate::modal::axisym::{AxisymModel, WheelClamp, WheelModelOptions};
use crate::model::modal::{empty_box, volume_model, Clamp, ModalMesh, ModalModel};
use crate::{Error, Result};

use super::classify::{axle_only_nodes_of, classify_modes, classify_modes_points, ModeRecord};
use super::{solve, ModalOptions, ModalSolution};

/// The solved band.
pub struct ModalRun {
    /// The eigen solution (frequencies, residuals, counts, timings).
    pub solution: ModalSolution,
    /// Per mode: (frequency Hz, residual, rigid, shape per node).
    pub shapes: Vec<(f64, f64, bool, Vec<P3>)>,
    /// The classified modes (sin/cos pairs merged).
    pub records: Vec<ModeRecord>,
}

/// A wheel file's section meshed as the axisymmetric solver meshes it (Q9), revolved into
/// `sectors` quadratic (hex27) sectors: the same cross-section discretisation as `squeal
/// axisym`, differing only by the circumferential interpolation.
pub fn revolved_model(
    spec: &WheelSpec,
    clamp: &Clamp,
    sectors: usize,
    hex8: Hex8Kind,
) -> Result<ModalModel> {
    if !(3..=512).contains(&sectors) {
        return Err(Error::input(
            "command line",
            "--revolved-sectors",
            format!("{sectors} is outside the allowed range 3..=512"),
        ));
    }
    let wheel_clamp = match clamp {
        Clamp::HubBore => WheelClamp::HubBore,
        Clamp::AxleEnds => WheelClamp::AxleEnds,
        _ => WheelClamp::None,
    };
    let section = AxisymModel::from_wheel(
        spec,
        WheelModelOptions {
            without_axle: false,
            clamp: wheel_clamp,
        },
    )?;
    let mut mesh = revolve_hex27(&section.mesh, sectors, &[("clamp", &section.clamped)]);
    let mut box_clamped_nodes = None;
    let clamped_sets = match clamp {
        Clamp::None => vec![],
        Clamp::Box { conditions, text } => {
            let ids = volume::select_nodes(&mesh.nodes, conditions);
            if ids.is_empty() {
                return Err(empty_box(text));
            }
            box_clamped_nodes = Some(ids.len());
            mesh.set_node_set("clamp_box", ids);
            vec!["clamp_box".to_string()]
        }
        _ => vec!["clamp".to_string()],
    };
    let summary = format!(
        "Q9 section of {} elements revolved into {} sectors: {} nodes, {} hex27",
        section.mesh.elements.len(),
        sectors,
        mesh.nodes.len(),
        mesh.elements.len(),
    );
    // The axis of revolution is the y axis through the origin (see `revolve_hex27`).
    volume_model(
        mesh,
        spec.material,
        clamped_sets,
        [0.0; 3],
        summary,
        box_clamped_nodes,
        hex8,
    )
}

/// Every mode below `fmax_hz` (in `slices` spectrum slices), classified.
pub fn solve_and_classify(model: &ModalModel, fmax_hz: f64, slices: usize) -> Result<ModalRun> {
    let asm = &model.assembled;
    let solution = solve(
        &asm.k,
        &asm.m,
        &ModalOptions {
            fmax_hz,
            // Tie slaves are snapped onto their faces, so the free wheel's rigid modes are exact
            // (below 1e-2 Hz); its first flexible mode is hundreds of Hz.
            rigid_below_hz: 1.0,
            slices,
            ..Default::default()
        },
    )?;
    let shapes: Vec<(f64, f64, bool, Vec<P3>)> = solution
        .modes
        .iter()
        .map(|m| (m.frequency_hz, m.residual, m.rigid, asm.expand(&m.vector)))
        .collect();
    let mut records = match &model.mesh {
        ModalMesh::Hex(mesh) => classify_modes(mesh, model.centre, &shapes),
        ModalMesh::Volume(mesh) => {
            let axle = axle_only_nodes_of(
                mesh.nodes.len(),
                mesh.elements
                    .iter()
                    .zip(&mesh.material)
                    .map(|(e, &m)| (e.nodes(), m)),
            );
            let weights = crate::fem::measure::nodal_weights(mesh);
            if model.axis == [0.0, 1.0, 0.0] {
                classify_modes_points(&mesh.nodes, &weights, &axle, model.centre, &shapes)
            } else {
                // The classifier works about y: the positions (about the centre) and the
                // shapes turned so that the model's axis is y.
                let r = to_y_axis(model.axis);
                let c = model.centre;
                let points: Vec<P3> = mesh
                    .nodes
                    .iter()
                    .map(|p| rotate(&r, [p[0] - c[0], p[1] - c[1], p[2] - c[2]]))
                    .collect();
                let turned: Vec<(f64, f64, bool, Vec<P3>)> = shapes
                    .iter()
                    .map(|(f, res, rigid, u)| {
                        (*f, *res, *rigid, u.iter().map(|v| rotate(&r, *v)).collect())
                    })
                    .collect();
                classify_modes_points(&points, &weights, &axle, [0.0; 3], &turned)
            }
        }
    };
    for record in &mut records {
        record.residual_floor = record
            .members
            .iter()
            .map(|&k| solution.modes[k].residual_floor)
            .fold(0.0, f64::max);
    }
    Ok(ModalRun {
        solution,
        shapes,
        records,
    })
}
