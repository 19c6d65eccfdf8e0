//! Volume meshes from files: Gmsh MSH 4.1 (`.msh`), legacy VTK (`.vtk`) and VTK XML (`.vtu`)
//! into a [`VolumeMesh`], dispatched by extension. The format readers return plain contents
//! ([`super::gmsh`], [`super::vtk_cells::VtuContents`]); this module turns them into elements.

use std::path::Path;

use super::volume::{VolumeElement, VolumeMesh, GMSH_TO_VTK_TET10};
use super::vtk_cells::VtuContents;
use crate::{Error, Result};

/// Read a volume mesh: `.msh` (Gmsh 4.1 ASCII; material id = volume entity tag), `.vtk` (legacy
/// ASCII unstructured grid) or `.vtu` (VTK XML, ASCII or inline binary arrays). VTK material ids
/// come from the cell array `material`, `gmsh:physical`, `CellEntityIds` or `MaterialIds` (the
/// first present), else 1.
pub fn read(path: &Path) -> Result<VolumeMesh> {
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mut mesh = match ext.as_str() {
        "msh" => {
            let c = super::gmsh::read(path)?;
            let mut m = VolumeMesh {
                nodes: c.nodes,
                ..Default::default()
            };
            for (conn, entity) in c.hexahedra {
                m.elements.push(VolumeElement::Hex8(conn));
                m.material.push(entity.max(0) as u32);
            }
            for (conn, entity) in c.tetrahedra4 {
                m.elements.push(VolumeElement::Tet4(conn));
                m.material.push(entity.max(0) as u32);
            }
            for (conn, entity) in c.tetrahedra10 {
                let vtk = GMSH_TO_VTK_TET10.map(|k| conn[k]);
                m.elements.push(VolumeElement::Tet10(vtk));
                m.material.push(entity.max(0) as u32);
            }
            m
        }
        "vtk" => from_vtk_contents(&name, super::vtk_legacy::read(path)?)?,
        "vtu" => from_vtk_contents(&name, super::vtu::read(path)?)?,
        _ => {
            return Err(Error::input(
                &name,
                "--mesh",
                format!("unknown mesh file extension `.{ext}`: expected .msh (Gmsh 4.1 ASCII), .vtk (legacy VTK ASCII) or .vtu (VTK XML)"),
            ))
        }
    };
    mesh.validate_and_compact(&name)?;
    Ok(mesh)
}

/// VTK cell types that are not volume elements and are skipped (vertex, poly-vertex, line,
/// poly-line, triangle, triangle strip, polygon, pixel, quad, and their quadratic forms).
const SKIPPED_VTK_TYPES: [u8; 13] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 21, 22, 23, 28];

/// Convert VTK cells (types 12, 24 and 29) into a volume mesh; other volume cell types are errors.
pub fn from_vtk_contents(source: &str, c: VtuContents) -> Result<VolumeMesh> {
    let ids = ["material", "gmsh:physical", "CellEntityIds", "MaterialIds"]
        .iter()
        .find_map(|k| c.cell_data.get(*k).map(|v| (*k, v)));
    if let Some((key, v)) = ids {
        if v.len() != c.cells.len() {
            return Err(Error::input(
                source,
                format!("cell data `{key}`"),
                format!("{} values for {} cells", v.len(), c.cells.len()),
            ));
        }
    }
    let mut m = VolumeMesh {
        nodes: c.points,
        ..Default::default()
    };
    for (i, (cell, &ty)) in c.cells.iter().zip(&c.cell_types).enumerate() {
        let material = match ids {
            Some((key, v)) => {
                let x = v[i];
                if !(x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64) {
                    return Err(Error::input(
                        source,
                        format!("cell data `{key}`"),
                        format!("cell {i}: material id {x} is not a non-negative integer"),
                    ));
                }
                x as u32
            }
            None => 1,
        };
        let wrong_count = |n: usize| {
            Error::input(
                source,
                "cells",
                format!(
                    "cell {i} of type {ty} has {} nodes, expected {n}",
                    cell.len()
                ),
            )
        };
        match ty {
            12 => {
                let conn: [usize; 8] = cell.as_slice().try_into().map_err(|_| wrong_count(8))?;
                m.elements.push(VolumeElement::Hex8(conn));
                m.material.push(material);
            }
            24 => {
                let conn: [usize; 10] =
                    cell.as_slice().try_into().map_err(|_| wrong_count(10))?;
                m.elements.push(VolumeElement::Tet10(conn));
                m.material.push(material);
            }
            29 => {
                let conn: [usize; 27] =
                    cell.as_slice().try_into().map_err(|_| wrong_count(27))?;
                m.elements.push(VolumeElement::Hex27(conn));
                m.material.push(material);
            }
            10 => {
                let conn: [usize; 4] = cell.as_slice().try_into().map_err(|_| wrong_count(4))?;
                m.elements.push(VolumeElement::Tet4(conn));
                m.material.push(material);
            }
            t if SKIPPED_VTK_TYPES.contains(&t) => {}
            t => {
                return Err(Error::input(
                    source,
                    "cells",
                    format!("cell {i} has VTK cell type {t}, which is not supported: volume cells must be hexahedra (12), linear (10) or quadratic tetrahedra (24) or triquadratic hexahedra (29)"),
                ))
            }
        }
    }
    Ok(m)
}
