//! Legacy VTK (`.vtk`) reader: ASCII `DATASET UNSTRUCTURED_GRID`, file versions 2.0 to 5.1
//! (`CELLS` as `n k i0 .. ik-1` lines, or the 5.x `OFFSETS` / `CONNECTIVITY` arrays),
//! `CELL_TYPES`, and `CELL_DATA` scalars / field arrays (kept by name, as f64). Point data and
//! metadata are skipped. BINARY files are refused with a message.
//!
//! Every error names the file and the line.

use std::path::Path;

use super::vtk_cells::VtuContents;
use crate::{Error, Result};

struct Tokens<'a> {
    /// (1-based line, token)
    tokens: Vec<(usize, &'a str)>,
    /// Blank line numbers (METADATA blocks end at one).
    blank: Vec<usize>,
    at: usize,
    path: &'a str,
    last_line: usize,
}

impl<'a> Tokens<'a> {
    fn err(&self, line: usize, msg: impl Into<String>) -> Error {
        Error::input(self.path, format!("line {line}"), msg)
    }
    fn next(&mut self, what: &str) -> Result<(usize, &'a str)> {
        match self.tokens.get(self.at) {
            Some(&t) => {
                self.at += 1;
                Ok(t)
            }
            None => Err(self.err(
                self.last_line + 1,
                format!("unexpected end of file while reading {what} (truncated file?)"),
            )),
        }
    }
    fn peek(&self) -> Option<(usize, &'a str)> {
        self.tokens.get(self.at).copied()
    }
    fn count(&mut self, what: &str) -> Result<usize> {
        let (l, t) = self.next(what)?;
        t.parse::<usize>().map_err(|_| {
            self.err(
                l,
                format!("expected {what} (a non-negative integer), got `{t}`"),
            )
        })
    }
    fn number(&mut self, what: &str) -> Result<f64> {
        let (l, t) = self.next(what)?;
        t.parse::<f64>()
            .map_err(|_| self.err(l, format!("expected {what} (a number), got `{t}`")))
    }
    fn index(&mut self, what: &str, n_points: usize) -> Result<usize> {
        let (l, t) = self.next(what)?;
        let v: i64 = t
            .parse()
            .map_err(|_| self.err(l, format!("expected {what} (an integer), got `{t}`")))?;
        if v < 0 || v as u64 >= n_points as u64 {
            return Err(self.err(
                l,
                format!(
                    "{what} {v} is out of range: there are {n_points} points (0-based indices)"
                ),
            ));
        }
        Ok(v as usize)
    }
    /// Bounded capacity for a count read from the file (a corrupt count must not allocate).
    fn cap(&self, n: usize) -> usize {
        n.min(self.tokens.len() - self.at)
    }
}

/// Read a legacy ASCII `.vtk` unstructured grid.
pub fn read(path: &Path) -> Result<VtuContents> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::InvalidData => Error::input(
            &name,
            "line 3",
            "the file is not text (BINARY legacy VTK is not supported: save as ASCII)",
        ),
        _ => Error::reading(path, e),
    })?;
    parse(&name, &text)
}

/// Parses a legacy VTK file's text (`name` for messages): the header, the dataset line, then
/// one pass over the file's sections in the order the format gives them (points, cells, cell
/// types, data), each section read by its own phase and each error naming its line; last, the
/// checks that the sections a mesh needs were all there.
fn parse(name: &str, text: &str) -> Result<VtuContents> {
    let lines: Vec<&str> = text.lines().collect();
    check_header(name, &lines)?;
    let mut t = tokenize(name, &lines);
    read_dataset(&mut t)?;
    let mut out = VtuContents::default();
    let mut n_cells_declared: Option<usize> = None;
    // (CELL_DATA or POINT_DATA, count) of the attribute section being read
    let mut section: Option<(bool, usize)> = None;
    while let Some((line, kw)) = t.peek() {
        t.at += 1;
        match kw.to_ascii_uppercase().as_str() {
            "POINTS" => read_points(&mut t, &mut out)?,
            "CELLS" => {
                read_cells(&mut t, line, &mut out)?;
                n_cells_declared = Some(out.cells.len());
            }
            "CELL_TYPES" => read_cell_types(&mut t, line, n_cells_declared, &mut out)?,
            "CELL_DATA" => {
                section = Some((true, t.count("the number of cell values")?));
            }
            "POINT_DATA" => {
                section = Some((false, t.count("the number of point values")?));
            }
            "SCALARS"
            | "VECTORS"
            | "NORMALS"
            | "TENSORS"
            | "COLOR_SCALARS"
            | "TEXTURE_COORDINATES" => read_attribute(&mut t, line, kw, section, &mut out)?,
            "FIELD" => read_field(&mut t, line, section, &mut out)?,
            "LOOKUP_TABLE" => skip_lookup_table(&mut t)?,
            "METADATA" => skip_metadata(&mut t, line),
            other => {
                return Err(t.err(
                    line,
                    format!(
                        "unexpected keyword `{kw}`{}",
                        if other.parse::<f64>().is_ok() {
                            " (a number: more values than the section header declares?)"
                        } else {
                            ""
                        }
                    ),
                ))
            }
        }
    }
    check_complete(name, &out, n_cells_declared)?;
    Ok(out)
}

/// The first three lines: the `# vtk DataFile Version` header (else this is not a legacy VTK
/// file) and the format line, which must say ASCII (BINARY is refused with its own message).
fn check_header(name: &str, lines: &[&str]) -> Result<()> {
    let bad = |line: usize, msg: String| Error::input(name, format!("line {line}"), msg);
    let header = lines.first().map(|l| l.trim()).unwrap_or("");
    if !header.starts_with("# vtk DataFile Version") {
        return Err(bad(
            1,
            format!(
                "expected `# vtk DataFile Version x.y`, got `{header}` (not a legacy VTK file)"
            ),
        ));
    }
    let format = lines.get(2).map(|l| l.trim()).unwrap_or("");
    match format.to_ascii_uppercase().as_str() {
        "ASCII" => {}
        "BINARY" => {
            return Err(bad(
                3,
                "BINARY legacy VTK is not supported: save the file as ASCII".into(),
            ))
        }
        _ => return Err(bad(3, format!("expected ASCII or BINARY, got `{format}`"))),
    }
    Ok(())
}

/// The tokens of the lines after the header (with their 1-based line numbers) and the blank
/// lines, where METADATA blocks end.
fn tokenize<'a>(name: &'a str, lines: &[&'a str]) -> Tokens<'a> {
    let mut t = Tokens {
        tokens: Vec::new(),
        blank: Vec::new(),
        at: 0,
        path: name,
        last_line: lines.len(),
    };
    for (i, l) in lines.iter().enumerate().skip(3) {
        if l.trim().is_empty() {
            t.blank.push(i + 1);
        }
        for tok in l.split_whitespace() {
            t.tokens.push((i + 1, tok));
        }
    }
    t
}

/// The `DATASET UNSTRUCTURED_GRID` line: the only dataset type read.
fn read_dataset(t: &mut Tokens<'_>) -> Result<()> {
    let (l, kw) = t.next("DATASET")?;
    let (l2, ds) = t.next("the dataset type")?;
    if !kw.eq_ignore_ascii_case("DATASET") {
        return Err(t.err(
            l,
            format!("expected `DATASET UNSTRUCTURED_GRID`, got `{kw}`"),
        ));
    }
    if !ds.eq_ignore_ascii_case("UNSTRUCTURED_GRID") {
        return Err(t.err(
            l2,
            format!("dataset `{ds}` is not supported: only UNSTRUCTURED_GRID"),
        ));
    }
    Ok(())
}

/// A `POINTS n type` section: n points of three coordinates.
fn read_points(t: &mut Tokens<'_>, out: &mut VtuContents) -> Result<()> {
    let n = t.count("the number of points")?;
    t.next("the point data type")?;
    out.points = Vec::with_capacity(t.cap(n));
    for _ in 0..n {
        let x = t.number("a point coordinate")?;
        let y = t.number("a point coordinate")?;
        let z = t.number("a point coordinate")?;
        out.points.push([x, y, z]);
    }
    Ok(())
}

/// A `CELLS n size` section (header on `line`), after the points its indices refer to: the
/// 5.x `OFFSETS` / `CONNECTIVITY` arrays or the older `k i0 .. ik-1` lists.
fn read_cells(t: &mut Tokens<'_>, line: usize, out: &mut VtuContents) -> Result<()> {
    let n = t.count("the number of cells")?;
    let size = t.count("the cell list size")?;
    if out.points.is_empty() {
        return Err(t.err(line, "CELLS before POINTS (or no points)"));
    }
    if matches!(t.peek(), Some((_, k)) if k.eq_ignore_ascii_case("OFFSETS")) {
        read_cells_offsets(t, line, n, size, out)
    } else {
        read_cells_lists(t, line, n, size, out)
    }
}

/// Cells of a 5.x file: `n` offsets (cells + 1) and `size` connectivity entries, each cell the
/// entries between two offsets.
fn read_cells_offsets(
    t: &mut Tokens<'_>,
    line: usize,
    n: usize,
    size: usize,
    out: &mut VtuContents,
) -> Result<()> {
    let np = out.points.len();
    // version 5.x: n = offsets count (cells + 1), size = connectivity length
    t.next("OFFSETS")?;
    t.next("the offsets type")?;
    let mut offsets = Vec::with_capacity(t.cap(n));
    for _ in 0..n {
        offsets.push(t.count("a cell offset")?);
    }
    let (lc, kc) = t.next("CONNECTIVITY")?;
    if !kc.eq_ignore_ascii_case("CONNECTIVITY") {
        return Err(t.err(lc, format!("expected CONNECTIVITY, got `{kc}`")));
    }
    t.next("the connectivity type")?;
    let mut conn = Vec::with_capacity(t.cap(size));
    for _ in 0..size {
        conn.push(t.index("a cell point index", np)?);
    }
    for w in offsets.windows(2) {
        if w[0] > w[1] || w[1] > conn.len() {
            return Err(t.err(
                line,
                format!(
                    "cell offsets {} .. {} out of range (connectivity has {} entries)",
                    w[0],
                    w[1],
                    conn.len()
                ),
            ));
        }
        out.cells.push(conn[w[0]..w[1]].to_vec());
    }
    Ok(())
}

/// Cells of a file before 5.x: `n` lists `k i0 .. ik-1`, which together must fill exactly the
/// declared `size`.
fn read_cells_lists(
    t: &mut Tokens<'_>,
    line: usize,
    n: usize,
    size: usize,
    out: &mut VtuContents,
) -> Result<()> {
    let np = out.points.len();
    let mut used = 0;
    for _ in 0..n {
        let (lk, _) = t.peek().unwrap_or((t.last_line + 1, ""));
        let k = t.count("the node count of a cell")?;
        used += k + 1;
        if used > size {
            return Err(t.err(
                lk,
                format!("cell list is longer than the declared size {size}"),
            ));
        }
        let mut cell = Vec::with_capacity(t.cap(k));
        for _ in 0..k {
            cell.push(t.index("a cell point index", np)?);
        }
        out.cells.push(cell);
    }
    if used != size {
        return Err(t.err(
            line,
            format!("cell list size is {used}, but the header declares {size}"),
        ));
    }
    Ok(())
}

/// A `CELL_TYPES n` section (header on `line`): one VTK type per cell of the CELLS section.
fn read_cell_types(
    t: &mut Tokens<'_>,
    line: usize,
    n_cells_declared: Option<usize>,
    out: &mut VtuContents,
) -> Result<()> {
    let n = t.count("the number of cell types")?;
    if Some(n) != n_cells_declared {
        return Err(t.err(
            line,
            format!(
                "CELL_TYPES has {n} entries but CELLS has {}",
                n_cells_declared.map_or("no".into(), |c| c.to_string())
            ),
        ));
    }
    for _ in 0..n {
        let (lt, tok) = t.next("a cell type")?;
        let ty: u8 = tok
            .parse()
            .map_err(|_| t.err(lt, format!("`{tok}` is not a VTK cell type")))?;
        out.cell_types.push(ty);
    }
    Ok(())
}

/// One attribute array (`SCALARS`, `VECTORS`, `NORMALS`, `TENSORS`, `COLOR_SCALARS`,
/// `TEXTURE_COORDINATES`; keyword `kw` on `line`) of the current CELL_DATA / POINT_DATA
/// `section`, kept by name.
fn read_attribute(
    t: &mut Tokens<'_>,
    line: usize,
    kw: &str,
    section: Option<(bool, usize)>,
    out: &mut VtuContents,
) -> Result<()> {
    let Some((cell, n)) = section else {
        return Err(t.err(line, format!("{kw} outside CELL_DATA / POINT_DATA")));
    };
    let (_, aname) = t.next("the array name")?;
    let ncomp = attribute_components(t, line, &kw.to_ascii_uppercase())?;
    read_array(t, n * ncomp, cell, aname, out)
}

/// `count` values of the array `name`, kept with the cell or the point data.
fn read_array(
    t: &mut Tokens<'_>,
    count: usize,
    cell: bool,
    name: &str,
    out: &mut VtuContents,
) -> Result<()> {
    let mut vals = Vec::with_capacity(t.cap(count));
    for _ in 0..count {
        vals.push(t.number("a data value")?);
    }
    if cell {
        out.cell_data.insert(name.to_string(), vals);
    } else {
        out.point_data.insert(name.to_string(), vals);
    }
    Ok(())
}

/// The rest of an attribute's header line (keyword `upper`, on `line`) and its component
/// count: SCALARS' optional count (and lookup table line), 3 for vectors and normals, 9 for
/// tensors, the given count for colours and texture coordinates.
fn attribute_components(t: &mut Tokens<'_>, line: usize, upper: &str) -> Result<usize> {
    Ok(match upper {
        "SCALARS" => {
            t.next("the data type")?;
            // optional component count on the SCALARS line, then (usually) a
            // LOOKUP_TABLE line
            let mut nc = 1;
            if let Some((l, v)) = t.peek() {
                if l == line {
                    nc = v
                        .parse::<usize>()
                        .ok()
                        .filter(|c| (1..=4).contains(c))
                        .ok_or_else(|| {
                            t.err(
                                l,
                                format!("SCALARS component count must be 1 to 4, got `{v}`"),
                            )
                        })?;
                    t.at += 1;
                }
            }
            if matches!(t.peek(), Some((_, k)) if k.eq_ignore_ascii_case("LOOKUP_TABLE")) {
                t.at += 2;
            }
            nc
        }
        "VECTORS" | "NORMALS" => {
            t.next("the data type")?;
            3
        }
        "TENSORS" => {
            t.next("the data type")?;
            9
        }
        "COLOR_SCALARS" | "TEXTURE_COORDINATES" => {
            let c = t.count("the component count")?;
            if upper == "TEXTURE_COORDINATES" {
                t.next("the data type")?;
            }
            c
        }
        _ => 1,
    })
}

/// A `FIELD name k` section (on `line`) of the current CELL_DATA / POINT_DATA `section`: k
/// named arrays of components x tuples values, kept by name.
fn read_field(
    t: &mut Tokens<'_>,
    line: usize,
    section: Option<(bool, usize)>,
    out: &mut VtuContents,
) -> Result<()> {
    let Some((cell, _)) = section else {
        return Err(t.err(line, "FIELD outside CELL_DATA / POINT_DATA"));
    };
    t.next("the field name")?;
    let arrays = t.count("the number of field arrays")?;
    for _ in 0..arrays {
        let (_, aname) = t.next("the array name")?;
        let nc = t.count("the component count")?;
        let nt = t.count("the tuple count")?;
        t.next("the data type")?;
        read_array(t, nc.saturating_mul(nt), cell, aname, out)?;
    }
    Ok(())
}

/// A `LOOKUP_TABLE name n` section: n RGBA entries, read (so they are checked) and dropped.
fn skip_lookup_table(t: &mut Tokens<'_>) -> Result<()> {
    t.next("the table name")?;
    let n = t.count("the table size")?;
    for _ in 0..4 * n {
        t.number("a table value")?;
    }
    Ok(())
}

/// A METADATA block (keyword on `line`): skipped up to the next blank line, or to the end of
/// the file when none follows.
fn skip_metadata(t: &mut Tokens<'_>, line: usize) {
    // skip to the next blank line
    let end = t.blank.iter().copied().find(|&b| b > line);
    match end {
        Some(b) => {
            while matches!(t.peek(), Some((l, _)) if l < b) {
                t.at += 1;
            }
        }
        None => t.at = t.tokens.len(),
    }
}

/// After the pass: a mesh needs points, a CELLS section and one cell type per cell.
fn check_complete(name: &str, out: &VtuContents, n_cells_declared: Option<usize>) -> Result<()> {
    if out.points.is_empty() {
        return Err(Error::input(name, "POINTS", "no points in the file"));
    }
    if n_cells_declared.is_none() {
        return Err(Error::input(name, "CELLS", "no CELLS section in the file"));
    }
    if out.cell_types.len() != out.cells.len() {
        return Err(Error::input(
            name,
            "CELL_TYPES",
            format!(
                "{} cell types for {} cells (missing CELL_TYPES section?)",
                out.cell_types.len(),
                out.cells.len()
            ),
        ));
    }
    Ok(())
}
