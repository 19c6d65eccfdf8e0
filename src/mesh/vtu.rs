//! VTK XML unstructured grid (`.vtu`) writer and reader, for ParaView.
//!
//! Arrays are written inline as base64 binary (`format="binary"`, `header_type="UInt64"`:
//! an 8-byte little-endian byte count, then the data), which ParaView and VTK read natively and
//! which is ~4x smaller than ASCII. Cell data: `material`; point data: one UInt8 field
//! `set_<name>` per node set (1 = member), plus any extra point vectors (mode shapes,
//! displacements) the caller adds.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use super::volume::VolumeMesh;
use super::{Mesh, P3};
use crate::{Error, Result};

const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Standard base64 encoding (RFC 4648, with padding).
pub fn base64_encode(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = ((b[0] as u32) << 16) | ((b[1] as u32) << 8) | b[2] as u32;
        out.push(B64[(n >> 18) as usize & 63] as char);
        out.push(B64[(n >> 12) as usize & 63] as char);
        out.push(if chunk.len() > 1 {
            B64[(n >> 6) as usize & 63] as char
        } else {
            '='
        });
        out.push(if chunk.len() > 2 {
            B64[n as usize & 63] as char
        } else {
            '='
        });
    }
    out
}

/// Decode base64 (whitespace ignored); `None` on invalid input.
pub fn base64_decode(text: &str) -> Option<Vec<u8>> {
    let mut val = [255u8; 256];
    for (i, &c) in B64.iter().enumerate() {
        val[c as usize] = i as u8;
    }
    let clean: Vec<u8> = text.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    if !clean.len().is_multiple_of(4) {
        return None;
    }
    let mut out = Vec::with_capacity(clean.len() / 4 * 3);
    for q in clean.chunks(4) {
        let mut n = 0u32;
        let mut pad = 0;
        for &c in q {
            n <<= 6;
            if c == b'=' {
                pad += 1;
            } else if val[c as usize] == 255 {
                return None;
            } else {
                n |= val[c as usize] as u32;
            }
        }
        out.push((n >> 16) as u8);
        if pad < 2 {
            out.push((n >> 8) as u8);
        }
        if pad < 1 {
            out.push(n as u8);
        }
    }
    Some(out)
}

fn encode_block(data: &[u8]) -> String {
    let mut buf = Vec::with_capacity(8 + data.len());
    buf.extend_from_slice(&(data.len() as u64).to_le_bytes());
    buf.extend_from_slice(data);
    base64_encode(&buf)
}

/// A named per-node vector field (3 components), e.g. a mode shape.
pub struct PointVectorField<'a> {
    /// Field name.
    pub name: String,
    /// One vector per node.
    pub values: &'a [[f64; 3]],
}

/// Write `mesh` to `path` (refuses meshes with inverted elements).
pub fn write(mesh: &Mesh, path: &Path, extra_vectors: &[PointVectorField]) -> Result<()> {
    mesh.quality(1.0).check_valid()?;
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    write_to(mesh, &mut w, extra_vectors).map_err(|e| Error::io(path, e))
}

fn write_to(
    mesh: &Mesh,
    w: &mut impl Write,
    extra_vectors: &[PointVectorField],
) -> std::io::Result<()> {
    let cells: Vec<(&[usize], u8)> = mesh
        .elements
        .iter()
        .map(|c| (c.as_slice(), 12u8)) // VTK_HEXAHEDRON
        .collect();
    write_grid(
        w,
        &mesh.nodes,
        &mesh.node_sets,
        &mesh.material,
        &cells,
        extra_vectors,
    )
}

/// Write a mixed hex8 / tet10 [`VolumeMesh`] (hexahedra as VTK type 12, quadratic tetrahedra as
/// type 24, VTK node order) with per-node vector fields.
pub fn write_volume(
    mesh: &VolumeMesh,
    path: &Path,
    extra_vectors: &[PointVectorField],
) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    let cells: Vec<(&[usize], u8)> = mesh
        .elements
        .iter()
        .map(|c| (c.nodes(), c.vtk_type()))
        .collect();
    write_grid(
        &mut w,
        &mesh.nodes,
        &mesh.node_sets,
        &mesh.material,
        &cells,
        extra_vectors,
    )
    .map_err(|e| Error::io(path, e))
}

fn write_grid(
    w: &mut impl Write,
    nodes: &[P3],
    node_sets: &BTreeMap<String, Vec<usize>>,
    material: &[u32],
    cells: &[(&[usize], u8)],
    extra_vectors: &[PointVectorField],
) -> std::io::Result<()> {
    let (nn, ne) = (nodes.len(), cells.len());
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(
        w,
        "<UnstructuredGrid>\n<Piece NumberOfPoints=\"{nn}\" NumberOfCells=\"{ne}\">"
    )?;
    writeln!(w, "<PointData>")?;
    for (name, ids) in node_sets {
        let mut flag = vec![0u8; nn];
        for &i in ids {
            flag[i] = 1;
        }
        writeln!(
            w,
            "<DataArray type=\"UInt8\" Name=\"set_{name}\" format=\"binary\">{}</DataArray>",
            encode_block(&flag)
        )?;
    }
    for field in extra_vectors {
        let bytes: Vec<u8> = field
            .values
            .iter()
            .flat_map(|v| v.iter().flat_map(|c| c.to_le_bytes()))
            .collect();
        writeln!(w, "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" format=\"binary\">{}</DataArray>", field.name, encode_block(&bytes))?;
    }
    writeln!(w, "</PointData>\n<CellData>")?;
    let mat: Vec<u8> = material
        .iter()
        .flat_map(|&m| (m as i32).to_le_bytes())
        .collect();
    writeln!(
        w,
        "<DataArray type=\"Int32\" Name=\"material\" format=\"binary\">{}</DataArray>",
        encode_block(&mat)
    )?;
    writeln!(w, "</CellData>\n<Points>")?;
    let pts: Vec<u8> = nodes
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    writeln!(
        w,
        "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">{}</DataArray>",
        encode_block(&pts)
    )?;
    writeln!(w, "</Points>\n<Cells>")?;
    let conn: Vec<u8> = cells
        .iter()
        .flat_map(|c| c.0.iter().flat_map(|&n| (n as i64).to_le_bytes()))
        .collect();
    writeln!(
        w,
        "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"binary\">{}</DataArray>",
        encode_block(&conn)
    )?;
    let offsets: Vec<u8> = cells
        .iter()
        .scan(0i64, |end, c| {
            *end += c.0.len() as i64;
            Some(*end)
        })
        .flat_map(|o| o.to_le_bytes())
        .collect();
    writeln!(
        w,
        "<DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\">{}</DataArray>",
        encode_block(&offsets)
    )?;
    let types: Vec<u8> = cells.iter().map(|c| c.1).collect();
    writeln!(
        w,
        "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">{}</DataArray>",
        encode_block(&types)
    )?;
    writeln!(w, "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>")?;
    w.flush()
}

pub use super::vtk_cells::VtuContents;

fn bad(path: &str, what: impl Into<String>) -> Error {
    Error::input(path, "(vtu)", what.into())
}

/// Decode one DataArray's payload (binary with UInt64 header, or ascii) into f64 values.
fn decode_array(path: &str, attrs: &str, body: &str) -> Result<Vec<f64>> {
    let attr = |key: &str| -> Option<String> {
        let pat = format!("{key}=\"");
        attrs.find(&pat).map(|i| {
            let rest = &attrs[i + pat.len()..];
            rest[..rest.find('"').unwrap_or(rest.len())].to_string()
        })
    };
    let ty = attr("type").ok_or_else(|| bad(path, "DataArray without type"))?;
    let format = attr("format").unwrap_or_else(|| "ascii".into());
    if format == "ascii" {
        return body
            .split_whitespace()
            .map(|t| {
                t.parse::<f64>()
                    .map_err(|_| bad(path, format!("bad number `{t}`")))
            })
            .collect();
    }
    if format == "appended" {
        return Err(bad(
            path,
            "appended data (format=\"appended\") is not supported: save the file with ASCII data arrays (ParaView: Data Mode = Ascii)",
        ));
    }
    if format != "binary" {
        return Err(bad(
            path,
            format!("unsupported DataArray format `{format}` (ascii or binary)"),
        ));
    }
    let raw = base64_decode(body).ok_or_else(|| bad(path, "invalid base64 data"))?;
    if raw.len() < 8 {
        return Err(bad(path, "binary block shorter than its header"));
    }
    let len = u64::from_le_bytes(raw[..8].try_into().unwrap_or([0; 8])) as usize;
    let data = raw
        .get(8..8 + len)
        .ok_or_else(|| bad(path, "binary block shorter than its byte count"))?;
    let vals: Vec<f64> = match ty.as_str() {
        "Float64" => data
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect(),
        "Float32" => data
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap_or([0; 4])) as f64)
            .collect(),
        "Int64" => data
            .chunks_exact(8)
            .map(|c| i64::from_le_bytes(c.try_into().unwrap_or([0; 8])) as f64)
            .collect(),
        "Int32" => data
            .chunks_exact(4)
            .map(|c| i32::from_le_bytes(c.try_into().unwrap_or([0; 4])) as f64)
            .collect(),
        "UInt8" => data.iter().map(|&b| b as f64).collect(),
        other => return Err(bad(path, format!("unsupported DataArray type `{other}`"))),
    };
    Ok(vals)
}

/// Read a `.vtu` file written by this toolkit or by other tools (inline ascii or base64 binary
/// arrays with a UInt64 header; appended data is not supported).
pub fn read(path: &Path) -> Result<VtuContents> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::reading(path, e))?;
    let mut out = VtuContents::default();
    let mut section = "";
    let mut pos = 0;
    let (mut conn, mut offsets) = (Vec::new(), Vec::new());
    while let Some(start) = text[pos..].find('<') {
        let start = pos + start;
        let end = start
            + text[start..]
                .find('>')
                .ok_or_else(|| bad(&name, "unterminated tag"))?;
        let tag = &text[start + 1..end];
        pos = end + 1;
        for s in ["PointData", "CellData", "Points", "Cells"] {
            if tag.starts_with(s) {
                section = s;
            }
        }
        if tag.starts_with("DataArray") {
            let close = pos
                + text[pos..]
                    .find("</DataArray>")
                    .ok_or_else(|| bad(&name, "DataArray not closed"))?;
            let vals = decode_array(&name, tag, &text[pos..close])?;
            pos = close;
            let aname = tag.find("Name=\"").map(|i| {
                let r = &tag[i + 6..];
                r[..r.find('"').unwrap_or(0)].to_string()
            });
            match (section, aname.as_deref()) {
                ("Points", _) => {
                    out.points = vals.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
                }
                ("Cells", Some("connectivity")) => {
                    conn = vals.iter().map(|&v| v as usize).collect()
                }
                ("Cells", Some("offsets")) => offsets = vals.iter().map(|&v| v as usize).collect(),
                ("Cells", Some("types")) => {
                    out.cell_types = vals.iter().map(|&v| v as u8).collect()
                }
                ("PointData", Some(n)) => {
                    out.point_data.insert(n.to_string(), vals);
                }
                ("CellData", Some(n)) => {
                    out.cell_data.insert(n.to_string(), vals);
                }
                _ => {}
            }
        }
    }
    let mut prev = 0;
    for &o in &offsets {
        if o < prev || o > conn.len() {
            return Err(bad(&name, "cell offsets out of range"));
        }
        out.cells.push(conn[prev..o].to_vec());
        prev = o;
    }
    if out.cells.len() != out.cell_types.len() {
        return Err(bad(&name, "cell count differs between offsets and types"));
    }
    Ok(out)
}
