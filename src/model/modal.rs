//! The modal model: a body built from a wheel file (the hexahedral wheel mesh, with its half
//! axle when the file has one) or from an imported volume mesh (hex8, tet10, hex27), its
//! clamps, and the assembly of K and M with the clamps and ties eliminated. The modal stage
//! ([`crate::modal::pipeline`]) solves and classifies what these builders return; the command
//! line only calls them.

use std::collections::BTreeMap;

use crate::fem::axis::{fit_axis, AxisFit};
use crate::fem::{assemble, assemble_volume, Assembled, Constraints, Hex8Kind, MassKind};
use crate::input::wheel::WheelSpec;
use crate::material::Material;
use crate::mesh::volume::{self, BoxCondition, VolumeMesh};
use crate::mesh::wheel::{wheel_mesh, WheelPlacement};
use crate::mesh::{material, vtu, Mesh, P3};
use crate::{Error, Result};

/// What is held fixed.
#[derive(Clone, Debug, PartialEq)]
pub enum Clamp {
    /// Free-free (six rigid modes).
    None,
    /// The hub bore (a wheel without its axle: the wheel seat).
    HubBore,
    /// Both axle end faces.
    AxleEnds,
    /// Every node inside a box expression (`x<-1.09`, `r<0.1, y>=0.2`; metres).
    Box {
        /// The parsed conditions.
        conditions: Vec<BoxCondition>,
        /// The expression as given (for messages).
        text: String,
    },
}

impl Clamp {
    /// `none`, `hub-bore`, `axle-ends`, or a box expression; errors name `--clamp` and the
    /// allowed forms.
    pub fn parse(text: &str) -> Result<Clamp> {
        match text.trim().to_ascii_lowercase().as_str() {
            "none" => return Ok(Clamp::None),
            "hub-bore" => return Ok(Clamp::HubBore),
            "axle-ends" => return Ok(Clamp::AxleEnds),
            _ => {}
        }
        volume::parse_box_expression(text)
            .map(|conditions| Clamp::Box {
                conditions,
                text: text.to_string(),
            })
            .map_err(|e| {
                Error::input(
                    "command line",
                    "--clamp",
                    format!(
                        "{e}; allowed: none, hub-bore, axle-ends, or {}",
                        volume::BOX_EXPRESSION_FORM
                    ),
                )
            })
    }
}

/// The mesh a modal model was built on.
pub enum ModalMesh {
    /// A hexahedral wheel mesh (tied zones condensed).
    Hex(Mesh),
    /// A volume mesh (hex8, tet10, hex27).
    Volume(VolumeMesh),
}

/// A body ready to solve.
pub struct ModalModel {
    /// Its mesh.
    pub mesh: ModalMesh,
    /// K and M with the clamps and ties eliminated.
    pub assembled: Assembled,
    /// A point of the axis the modes are classified about (m).
    pub centre: P3,
    /// That axis (unit): y for a wheel file; for a mesh the fitted axis of revolution or the
    /// one asked for (`--axis`).
    pub axis: P3,
    /// The fit, when the axis of a mesh was fitted (`fem::axis`).
    pub axis_fit: Option<AxisFit>,
    /// One line on the mesh (nodes, elements, volume or sectors).
    pub summary: String,
    /// Nodes a box clamp holds, if the clamp was a box.
    pub box_clamped_nodes: Option<usize>,
}

pub(crate) fn empty_box(text: &str) -> Error {
    Error::input(
        "command line",
        "--clamp",
        format!(
            "no mesh node satisfies `{text}`: nothing would be clamped (coordinates are in metres)"
        ),
    )
}

/// A wheel file's body: the hexahedral wheel mesh (with its half axle when the file has one),
/// the wheel's steel, `clamp`, and the hexahedron `hex8`.
pub fn wheel_model(spec: &WheelSpec, clamp: &Clamp, hex8: Hex8Kind) -> Result<ModalModel> {
    let mut mesh = wheel_mesh(spec, None, &WheelPlacement::default());
    // Exact rigid modes through the tied web zones (see `Mesh::snap_tie_slaves`).
    mesh.snap_tie_slaves();
    let materials: BTreeMap<u32, Material> =
        [material::WHEEL, material::AXLE, material::TREAD_BAND]
            .into_iter()
            .map(|id| (id, spec.material))
            .collect();
    let mut box_clamped_nodes = None;
    let clamped_sets: Vec<String> = match clamp {
        Clamp::None => vec![],
        Clamp::HubBore => vec!["hub_bore".into()],
        Clamp::AxleEnds => vec!["axle_inner_end".into(), "axle_outer_end".into()],
        Clamp::Box { conditions, text } => {
            let ids = volume::select_nodes(&mesh.nodes, conditions);
            if ids.is_empty() {
                return Err(empty_box(text));
            }
            box_clamped_nodes = Some(ids.len());
            mesh.add_node_set("clamp_box", ids);
            vec!["clamp_box".into()]
        }
    };
    let assembled = assemble(
        &mesh,
        &materials,
        &Constraints {
            clamped_sets,
            ties: true,
        },
        MassKind::Consistent,
        hex8,
    )?;
    let summary = format!(
        "{} nodes, {} elements",
        mesh.node_count(),
        mesh.element_count()
    );
    Ok(ModalModel {
        mesh: ModalMesh::Hex(mesh),
        assembled,
        // The axis passes through the tape-circle centre (x = z = 0 by placement).
        centre: WheelPlacement::default().tape_circle_centre_m,
        axis: [0.0, 1.0, 0.0],
        axis_fit: None,
        summary,
        box_clamped_nodes,
    })
}

/// An imported volume mesh of one `material`: named clamps are refused (they name wheel node
/// sets), a box clamp must hold some node. The modes are labelled about `axis` (0, 1, 2: x, y,
/// z) through the volume centroid, or, with None, about the fitted axis of revolution.
pub fn mesh_model(
    mut mesh: VolumeMesh,
    material: Material,
    clamp: &Clamp,
    hex8: Hex8Kind,
    axis: Option<usize>,
) -> Result<ModalModel> {
    let mut box_clamped_nodes = None;
    let clamped_sets = match clamp {
        Clamp::None => vec![],
        Clamp::Box { conditions, text } => {
            let ids = volume::select_nodes(&mesh.nodes, conditions);
            if ids.is_empty() {
                let (lo, hi) = mesh.bounds();
                return Err(Error::input(
                    "command line",
                    "--clamp",
                    format!(
                        "no mesh node satisfies `{text}`; the mesh spans x {:.4}..{:.4}, y {:.4}..{:.4}, z {:.4}..{:.4} m",
                        lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
                    ),
                ));
            }
            box_clamped_nodes = Some(ids.len());
            mesh.set_node_set("clamp_box", ids);
            vec!["clamp_box".to_string()]
        }
        named => {
            return Err(Error::input(
                "command line",
                "--clamp",
                format!(
                    "`{}` names wheel node sets and needs --wheel; with --mesh use none or {}",
                    match named {
                        Clamp::HubBore => "HubBore",
                        _ => "AxleEnds",
                    },
                    volume::BOX_EXPRESSION_FORM
                ),
            ))
        }
    };
    let count = |vtk_type: u8| {
        mesh.elements
            .iter()
            .filter(|e| e.vtk_type() == vtk_type)
            .count()
    };
    let summary = format!(
        "{} nodes, {} elements ({} hex8, {} tet10, {} tet4, {} hex27), volume {:.6e} m³",
        mesh.nodes.len(),
        mesh.elements.len(),
        count(12),
        count(24),
        count(10),
        count(29),
        crate::fem::measure::volume(&mesh),
    );
    // Classified about an axis through the volume centroid: the fitted axis of revolution
    // unless one was asked for; for a body that is not near-axisymmetric the labels are only
    // descriptive.
    let centre = crate::fem::measure::centroid(&mesh);
    let fit = fit_axis(
        &mesh.nodes,
        &crate::fem::measure::nodal_weights(&mesh),
        centre,
    );
    let mut model = volume_model(
        mesh,
        material,
        clamped_sets,
        centre,
        summary,
        box_clamped_nodes,
        hex8,
    )?;
    match axis {
        Some(k) => {
            model.axis = [0.0; 3];
            model.axis[k] = 1.0;
        }
        None => model.axis = fit.axis,
    }
    model.axis_fit = Some(fit);
    Ok(model)
}

/// The common end of the volume-mesh builders: one material, the clamped sets, assembly.
pub fn volume_model(
    mesh: VolumeMesh,
    material: Material,
    clamped_sets: Vec<String>,
    centre: P3,
    summary: String,
    box_clamped_nodes: Option<usize>,
    hex8: Hex8Kind,
) -> Result<ModalModel> {
    let materials: BTreeMap<u32, Material> =
        mesh.material.iter().map(|&id| (id, material)).collect();
    let assembled = assemble_volume(
        &mesh,
        &materials,
        &Constraints {
            clamped_sets,
            ties: false,
        },
        MassKind::Consistent,
        hex8,
    )?;
    Ok(ModalModel {
        mesh: ModalMesh::Volume(mesh),
        assembled,
        centre,
        axis: [0.0, 1.0, 0.0],
        axis_fit: None,
        summary,
        box_clamped_nodes,
    })
}

impl ModalModel {
    /// Node coordinates of the mesh (m), in the order of the mode shapes' values.
    pub fn node_positions_m(&self) -> &[P3] {
        match &self.mesh {
            ModalMesh::Hex(mesh) => &mesh.nodes,
            ModalMesh::Volume(mesh) => &mesh.nodes,
        }
    }

    /// Writes the mesh with point vector fields (the mode shapes) as VTU.
    pub fn write_vtu(
        &self,
        path: &std::path::Path,
        fields: &[vtu::PointVectorField],
    ) -> Result<()> {
        match &self.mesh {
            ModalMesh::Hex(mesh) => vtu::write(mesh, path, fields),
            ModalMesh::Volume(mesh) => vtu::write_volume(mesh, path, fields),
        }
    }
}
