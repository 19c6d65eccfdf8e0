//! Gmsh MSH 4.1 (ASCII) writer and reader.
//!
//! Written: one volume entity per material (physical group `material_<id>`), hexahedra as
//! element type 5 (8-node, same node order as VTK); each named surface as a surface entity of
//! quads (type 3) with a physical group of the same name, so boundary conditions can be set on
//! them in other tools. Read: nodes, 8-node hexahedra (type 5), 4-node tetrahedra (type 4) and
//! 10-node tetrahedra (type 11) with their entity tags; lower-dimensional elements are skipped.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use super::Mesh;
use crate::{Error, Result};

/// Write `mesh` as MSH 4.1 ASCII (refuses meshes with inverted elements).
pub fn write(mesh: &Mesh, path: &Path) -> Result<()> {
    mesh.quality(1.0).check_valid()?;
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    write_to(mesh, &mut w).map_err(|e| Error::io(path, e))
}

fn write_to(mesh: &Mesh, w: &mut impl Write) -> std::io::Result<()> {
    let mut by_material: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (e, &m) in mesh.material.iter().enumerate() {
        by_material.entry(m).or_default().push(e);
    }
    let surfaces: Vec<(&String, &Vec<[usize; 4]>)> = mesh
        .surfaces
        .iter()
        .filter(|(_, f)| !f.is_empty())
        .collect();
    writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    writeln!(w, "$PhysicalNames\n{}", by_material.len() + surfaces.len())?;
    for (k, (name, _)) in surfaces.iter().enumerate() {
        writeln!(w, "2 {} \"{}\"", k + 1, name)?;
    }
    for &m in by_material.keys() {
        writeln!(w, "3 {} \"material_{}\"", 1000 + m, m)?;
    }
    writeln!(w, "$EndPhysicalNames")?;
    // Entities with bounding boxes of the whole mesh (exact boxes are optional for readers).
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.nodes {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    writeln!(w, "$Entities\n0 0 {} {}", surfaces.len(), by_material.len())?;
    for k in 0..surfaces.len() {
        writeln!(
            w,
            "{} {} {} {} {} {} {} 1 {} 0",
            k + 1,
            lo[0],
            lo[1],
            lo[2],
            hi[0],
            hi[1],
            hi[2],
            k + 1
        )?;
    }
    for &m in by_material.keys() {
        writeln!(
            w,
            "{} {} {} {} {} {} {} 1 {} 0",
            m,
            lo[0],
            lo[1],
            lo[2],
            hi[0],
            hi[1],
            hi[2],
            1000 + m
        )?;
    }
    writeln!(w, "$EndEntities")?;
    let nn = mesh.nodes.len();
    writeln!(
        w,
        "$Nodes\n1 {nn} 1 {nn}\n3 {} 0 {nn}",
        by_material.keys().next().copied().unwrap_or(1)
    )?;
    for i in 1..=nn {
        writeln!(w, "{i}")?;
    }
    for p in &mesh.nodes {
        writeln!(w, "{:.17e} {:.17e} {:.17e}", p[0], p[1], p[2])?;
    }
    writeln!(w, "$EndNodes")?;
    let n_quads: usize = surfaces.iter().map(|(_, f)| f.len()).sum();
    let total = mesh.elements.len() + n_quads;
    writeln!(
        w,
        "$Elements\n{} {total} 1 {total}",
        by_material.len() + surfaces.len()
    )?;
    let mut tag = 1usize;
    for (k, (_, faces)) in surfaces.iter().enumerate() {
        writeln!(w, "2 {} 3 {}", k + 1, faces.len())?;
        for f in faces.iter() {
            writeln!(
                w,
                "{tag} {} {} {} {}",
                f[0] + 1,
                f[1] + 1,
                f[2] + 1,
                f[3] + 1
            )?;
            tag += 1;
        }
    }
    for (&m, elems) in &by_material {
        writeln!(w, "3 {m} 5 {}", elems.len())?;
        for &e in elems {
            let c = mesh.elements[e];
            writeln!(
                w,
                "{tag} {} {} {} {} {} {} {} {}",
                c[0] + 1,
                c[1] + 1,
                c[2] + 1,
                c[3] + 1,
                c[4] + 1,
                c[5] + 1,
                c[6] + 1,
                c[7] + 1
            )?;
            tag += 1;
        }
    }
    writeln!(w, "$EndElements")?;
    w.flush()
}

/// Contents of an MSH file: nodes, volume elements (hex8, tet4 or tet10) with their entity tag.
#[derive(Debug, Default)]
pub struct MshContents {
    /// Node coordinates, in file order.
    pub nodes: Vec<[f64; 3]>,
    /// Hexahedra (0-based node indices, VTK/Gmsh order) with entity tags.
    pub hexahedra: Vec<([usize; 8], i64)>,
    /// 10-node tetrahedra (0-based, Gmsh order) with entity tags.
    pub tetrahedra10: Vec<([usize; 10], i64)>,
    /// 4-node tetrahedra (0-based; Gmsh and VTK share the corner order) with entity tags.
    pub tetrahedra4: Vec<([usize; 4], i64)>,
    /// Quads of surface entities with entity tags.
    pub quads: Vec<([usize; 4], i64)>,
    /// Physical names: (dimension, tag) -> name.
    pub physical_names: BTreeMap<(i64, i64), String>,
}

struct Lines<'a> {
    iter: std::iter::Enumerate<std::str::Lines<'a>>,
    path: String,
    line_no: usize,
}

impl<'a> Lines<'a> {
    fn next_line(&mut self) -> Result<&'a str> {
        for (i, l) in self.iter.by_ref() {
            self.line_no = i + 1;
            let t = l.trim();
            if !t.is_empty() {
                return Ok(t);
            }
        }
        Err(Error::input(
            &self.path,
            format!("line {}", self.line_no + 1),
            "unexpected end of file",
        ))
    }
    fn numbers<T: std::str::FromStr>(&mut self, expect: usize) -> Result<Vec<T>> {
        let line = self.next_line()?;
        let vals: std::result::Result<Vec<T>, _> =
            line.split_whitespace().map(|t| t.parse::<T>()).collect();
        match vals {
            Ok(v) if v.len() >= expect => Ok(v),
            _ => Err(Error::input(
                &self.path,
                format!("line {}", self.line_no),
                format!("expected {expect} numbers, got `{line}`"),
            )),
        }
    }
}

/// Read an MSH 4.1 ASCII file.
pub fn read(path: &Path) -> Result<MshContents> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::reading(path, e))?;
    let name = path.display().to_string();
    let mut lines = Lines {
        iter: text.lines().enumerate(),
        path: name.clone(),
        line_no: 0,
    };
    let mut out = MshContents::default();
    let mut tag_to_index: BTreeMap<usize, usize> = BTreeMap::new();
    let mut raw_elements: Vec<(i64, i64, Vec<usize>)> = Vec::new();
    while let Ok(line) = lines.next_line() {
        match line {
            "$MeshFormat" => {
                let l = lines.next_line()?;
                let version = l.split_whitespace().next().unwrap_or("");
                let file_type = l.split_whitespace().nth(1).unwrap_or("");
                if !version.starts_with("4.1") || file_type != "0" {
                    return Err(Error::input(
                        &name,
                        format!("line {}", lines.line_no),
                        format!("only MSH 4.1 ASCII is supported, found `{l}`"),
                    ));
                }
            }
            "$PhysicalNames" => {
                let n: Vec<usize> = lines.numbers(1)?;
                for _ in 0..n[0] {
                    let l = lines.next_line()?;
                    let mut parts = l.splitn(3, ' ');
                    let dim = parts.next().and_then(|v| v.parse().ok()).unwrap_or(-1);
                    let tag = parts.next().and_then(|v| v.parse().ok()).unwrap_or(-1);
                    out.physical_names.insert(
                        (dim, tag),
                        parts.next().unwrap_or("").trim_matches('"').to_string(),
                    );
                }
            }
            "$Nodes" => {
                let head: Vec<usize> = lines.numbers(4)?;
                for _ in 0..head[0] {
                    let block: Vec<i64> = lines.numbers(4)?;
                    let count = block[3] as usize;
                    let parametric = block[2] != 0;
                    let mut tags = Vec::with_capacity(count);
                    for _ in 0..count {
                        tags.push(lines.numbers::<usize>(1)?[0]);
                    }
                    for t in tags {
                        let c: Vec<f64> = lines.numbers(3)?;
                        let _ = parametric;
                        tag_to_index.insert(t, out.nodes.len());
                        out.nodes.push([c[0], c[1], c[2]]);
                    }
                }
            }
            "$Elements" => {
                let head: Vec<usize> = lines.numbers(4)?;
                for _ in 0..head[0] {
                    let block: Vec<i64> = lines.numbers(4)?;
                    let (entity, etype, count) = (block[1], block[2], block[3] as usize);
                    for _ in 0..count {
                        let v: Vec<usize> = lines.numbers(1)?;
                        raw_elements.push((etype, entity, v[1..].to_vec()));
                    }
                }
            }
            _ => {}
        }
    }
    let map = |tags: &[usize]| -> Result<Vec<usize>> {
        tags.iter()
            .map(|t| {
                tag_to_index.get(t).copied().ok_or_else(|| {
                    Error::input(
                        &name,
                        "$Elements",
                        format!("element refers to unknown node {t}"),
                    )
                })
            })
            .collect()
    };
    for (etype, entity, tags) in raw_elements {
        match etype {
            5 if tags.len() == 8 => out
                .hexahedra
                .push((map(&tags)?.try_into().unwrap_or([0; 8]), entity)),
            11 if tags.len() == 10 => out
                .tetrahedra10
                .push((map(&tags)?.try_into().unwrap_or([0; 10]), entity)),
            4 if tags.len() == 4 => out
                .tetrahedra4
                .push((map(&tags)?.try_into().unwrap_or([0; 4]), entity)),
            3 if tags.len() == 4 => out
                .quads
                .push((map(&tags)?.try_into().unwrap_or([0; 4]), entity)),
            _ => {}
        }
    }
    Ok(out)
}
