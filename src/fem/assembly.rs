//! Parallel sparse assembly of K and M with constraint elimination.
//!
//! Constraints are eliminated by a transformation `u = T u_r`: clamped nodes (all three dofs)
//! have no reduced dofs, a tied slave node is `u_s = sum_i w_i u_{m_i}` over its master face
//! nodes (resolved recursively if a master is itself a slave), every other node keeps its three
//! dofs. Then `K_r = Tᵀ K T`, `M_r = Tᵀ M T`, formed element by element by expanding each element
//! dof into its (reduced dof, weight) list, so T is never stored.
//!
//! Only the lower triangle (row >= column) of the reduced matrices is stored: it is what the
//! sparse Cholesky reads, what Matrix Market "symmetric" files hold, and half the memory.
//! Element matrices are computed in parallel (rayon); the triplet list is concatenated in
//! element order and summed by faer in a fixed order, so the result does not depend on the
//! thread count.

use std::collections::{BTreeMap, HashMap};

use faer::sparse::{SparseColMat, Triplet};
use rayon::prelude::*;

use super::hex8::ElasticMaterial;
use super::hex8_kind::{element_matrices_of_kind, Hex8Kind};
use super::{hex27, tet10, tet4};
use crate::mesh::volume::{VolumeElement, VolumeMesh};
use crate::mesh::{Mesh, TiedInterface};
use crate::{Error, Result};

/// Material per element material id.
pub type Materials = BTreeMap<u32, ElasticMaterial>;

/// Which mass matrix to assemble.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MassKind {
    /// Consistent (variationally consistent, 2x2x2 Gauss).
    Consistent,
    /// Row-sum lumped (diagonal).
    Lumped,
}

/// Constraints to eliminate.
#[derive(Clone, Debug, Default)]
pub struct Constraints {
    /// Names of node sets whose nodes are clamped (all three dofs zero).
    pub clamped_sets: Vec<String>,
    /// Apply the mesh's tied interfaces (`mesh.ties`).
    pub ties: bool,
}

/// Reduced K and M plus the map back to the full node displacements.
#[derive(Debug)]
pub struct Assembled {
    /// Reduced stiffness, lower triangle only.
    pub k: SparseColMat<usize, f64>,
    /// Reduced mass, lower triangle only.
    pub m: SparseColMat<usize, f64>,
    /// Per mesh node: (first reduced dof of a retained node, weight); empty for clamped nodes.
    pub expansion: Vec<Vec<(usize, f64)>>,
    /// Number of reduced dofs.
    pub n_reduced: usize,
}

impl Assembled {
    /// Full nodal displacements `u = T u_r` of a reduced vector.
    pub fn expand(&self, reduced: &[f64]) -> Vec<[f64; 3]> {
        self.expansion
            .iter()
            .map(|terms| {
                let mut u = [0.0; 3];
                for &(base, w) in terms {
                    for c in 0..3 {
                        u[c] += w * reduced[base + c];
                    }
                }
                u
            })
            .collect()
    }
}

/// Node-level expansion lists (see the module docs).
/// Per node: (first reduced dof, weight) terms.
type Expansion = Vec<Vec<(usize, f64)>>;

fn expansions(
    n: usize,
    node_sets: &BTreeMap<String, Vec<usize>>,
    ties: &[TiedInterface],
    constraints: &Constraints,
) -> Result<(Expansion, usize)> {
    let mut clamped = vec![false; n];
    for name in &constraints.clamped_sets {
        let ids = node_sets.get(name).ok_or_else(|| {
            let known: Vec<&str> = node_sets.keys().map(|s| s.as_str()).collect();
            Error::input(
                "command line",
                "clamp",
                format!(
                    "node set `{name}` does not exist; the mesh has: {}",
                    known.join(", ")
                ),
            )
        })?;
        if ids.is_empty() {
            return Err(Error::Mesh(format!("clamped node set `{name}` is empty")));
        }
        for &i in ids {
            clamped[i] = true;
        }
    }
    let mut slave: HashMap<usize, Vec<(usize, f64)>> = HashMap::new();
    if constraints.ties {
        for tie in ties {
            for p in &tie.pairs {
                slave.entry(p.slave).or_insert_with(|| {
                    p.master
                        .iter()
                        .copied()
                        .zip(p.weights.iter().copied())
                        .collect()
                });
            }
        }
    }
    let mut base = vec![usize::MAX; n];
    let mut count = 0;
    for i in 0..n {
        if !clamped[i] && !slave.contains_key(&i) {
            base[i] = count;
            count += 3;
        }
    }
    fn resolve(
        i: usize,
        depth: usize,
        clamped: &[bool],
        slave: &HashMap<usize, Vec<(usize, f64)>>,
        base: &[usize],
        out: &mut Vec<(usize, f64)>,
        w: f64,
    ) -> Result<()> {
        if clamped[i] {
            return Ok(());
        }
        if let Some(masters) = slave.get(&i) {
            if depth > 8 {
                return Err(Error::Mesh(format!("tie chain through node {i} is cyclic")));
            }
            for &(m, wm) in masters {
                resolve(m, depth + 1, clamped, slave, base, out, w * wm)?;
            }
            return Ok(());
        }
        out.push((base[i], w));
        Ok(())
    }
    let mut exp = Vec::with_capacity(n);
    for i in 0..n {
        let mut terms = Vec::new();
        resolve(i, 0, &clamped, &slave, &base, &mut terms, 1.0)?;
        // merge repeated bases (a slave reaching the same master twice), drop zero weights
        terms.sort_by_key(|t| t.0);
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(terms.len());
        for (b, w) in terms {
            match merged.last_mut() {
                Some(last) if last.0 == b => last.1 += w,
                _ => merged.push((b, w)),
            }
        }
        merged.retain(|t| t.1 != 0.0);
        exp.push(merged);
    }
    Ok((exp, count))
}

/// Assemble reduced K and M (lower triangles) of `mesh` with `materials` under `constraints`,
/// with the `hex8` element stiffness.
pub fn assemble(
    mesh: &Mesh,
    materials: &Materials,
    constraints: &Constraints,
    mass: MassKind,
    hex8: Hex8Kind,
) -> Result<Assembled> {
    check_materials(&mesh.material, materials)?;
    let (expansion, n_reduced) =
        expansions(mesh.node_count(), &mesh.node_sets, &mesh.ties, constraints)?;
    let lumped = mass == MassKind::Lumped;
    let (k, m) = assemble_elements(
        mesh.element_count(),
        &expansion,
        n_reduced,
        |e, buf: &mut ElementBuffer| {
            let x = mesh.element_coords(e);
            let mat = &materials[&mesh.material[e]];
            let em = element_matrices_of_kind(hex8, &x, mat, lumped).ok_or_else(|| inverted(e))?;
            buf.set(
                &mesh.elements[e],
                em.k.iter().flatten(),
                em.m.iter().flatten(),
            );
            Ok(())
        },
    )?;
    Ok(Assembled {
        k,
        m,
        expansion,
        n_reduced,
    })
}

/// Assemble reduced K and M (lower triangles) of a mixed hex8 / tet10 [`VolumeMesh`]
/// (`constraints.ties` is ignored: a volume mesh has no tied interfaces), with the `hex8`
/// element stiffness for the hexahedra (tet10 elements are unaffected).
pub fn assemble_volume(
    mesh: &VolumeMesh,
    materials: &Materials,
    constraints: &Constraints,
    mass: MassKind,
    hex8: Hex8Kind,
) -> Result<Assembled> {
    check_materials(&mesh.material, materials)?;
    let (expansion, n_reduced) = expansions(mesh.nodes.len(), &mesh.node_sets, &[], constraints)?;
    let lumped = mass == MassKind::Lumped;
    let (k, m) = assemble_elements(
        mesh.elements.len(),
        &expansion,
        n_reduced,
        |e, buf: &mut ElementBuffer| {
            let mat = &materials[&mesh.material[e]];
            match &mesh.elements[e] {
                VolumeElement::Hex8(c) => {
                    let x = c.map(|n| mesh.nodes[n]);
                    let em = element_matrices_of_kind(hex8, &x, mat, lumped)
                        .ok_or_else(|| inverted(e))?;
                    buf.set(c, em.k.iter().flatten(), em.m.iter().flatten());
                }
                VolumeElement::Tet10(c) => {
                    let x = c.map(|n| mesh.nodes[n]);
                    let em = tet10::element_matrices(&x, mat, lumped).ok_or_else(|| inverted(e))?;
                    buf.set(c, em.k.iter().flatten(), em.m.iter().flatten());
                }
                VolumeElement::Tet4(c) => {
                    let x = c.map(|n| mesh.nodes[n]);
                    let em = tet4::element_matrices(&x, mat, lumped).ok_or_else(|| inverted(e))?;
                    buf.set(c, em.k.iter().flatten(), em.m.iter().flatten());
                }
                VolumeElement::Hex27(c) => {
                    let x = c.map(|n| mesh.nodes[n]);
                    let em = hex27::element_matrices(&x, mat, lumped).ok_or_else(|| inverted(e))?;
                    buf.set(c, em.k.iter(), em.m.iter());
                }
            }
            Ok(())
        },
    )?;
    Ok(Assembled {
        k,
        m,
        expansion,
        n_reduced,
    })
}

fn inverted(e: usize) -> Error {
    Error::Mesh(format!(
        "element {e} is inverted or degenerate (det J <= 0): the Jacobian must be positive \
         everywhere (check the element's node order against the VTK/Gmsh convention)"
    ))
}

fn check_materials(ids: &[u32], materials: &Materials) -> Result<()> {
    for (e, id) in ids.iter().enumerate() {
        if !materials.contains_key(id) {
            return Err(Error::Mesh(format!(
                "element {e} has material id {id} but no material was given for it (known ids: {:?})",
                materials.keys().collect::<Vec<_>>()
            )));
        }
    }
    Ok(())
}

/// One element's node list and dense row-major `3n x 3n` K and M, reused across elements.
#[derive(Default)]
struct ElementBuffer {
    conn: Vec<usize>,
    k: Vec<f64>,
    m: Vec<f64>,
}

impl ElementBuffer {
    fn set<'a>(
        &mut self,
        conn: &[usize],
        k: impl Iterator<Item = &'a f64>,
        m: impl Iterator<Item = &'a f64>,
    ) {
        self.conn.clear();
        self.conn.extend_from_slice(conn);
        self.k.clear();
        self.k.extend(k);
        self.m.clear();
        self.m.extend(m);
    }
}

type SparsePair = (SparseColMat<usize, f64>, SparseColMat<usize, f64>);

/// The scatter loop shared by every element kind: `element(e, buffer)` fills the buffer with
/// element `e`'s nodes and matrices; each element dof is expanded into its (reduced dof,
/// weight) list and the lower-triangle triplets are summed by faer.
fn assemble_elements<F>(
    n_elements: usize,
    expansion: &Expansion,
    n_reduced: usize,
    element: F,
) -> Result<SparsePair>
where
    F: Fn(usize, &mut ElementBuffer) -> Result<()> + Sync,
{
    if n_reduced == 0 {
        return Err(Error::Mesh(
            "every node is constrained: no degrees of freedom left".into(),
        ));
    }
    type Trip = Triplet<usize, usize, f64>;
    let chunks: Vec<Result<(Vec<Trip>, Vec<Trip>)>> = (0..n_elements)
        .collect::<Vec<_>>()
        .par_chunks(256)
        .map(|chunk| {
            let mut tk = Vec::new();
            let mut tm = Vec::new();
            let mut buf = ElementBuffer::default();
            for &e in chunk {
                element(e, &mut buf)?;
                let conn = &buf.conn;
                let nd = 3 * conn.len();
                for a in 0..conn.len() {
                    for b in 0..conn.len() {
                        for &(ra, wa) in &expansion[conn[a]] {
                            for &(rb, wb) in &expansion[conn[b]] {
                                let w = wa * wb;
                                for ca in 0..3 {
                                    for cb in 0..3 {
                                        let (i, j) = (ra + ca, rb + cb);
                                        if i < j {
                                            continue;
                                        }
                                        let at = (3 * a + ca) * nd + 3 * b + cb;
                                        let kv = buf.k[at];
                                        if kv != 0.0 {
                                            tk.push(Triplet::new(i, j, w * kv));
                                        }
                                        let mv = buf.m[at];
                                        if mv != 0.0 {
                                            tm.push(Triplet::new(i, j, w * mv));
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
            Ok((tk, tm))
        })
        .collect();
    let mut tk = Vec::new();
    let mut tm = Vec::new();
    for c in chunks {
        let (a, b) = c?;
        tk.extend(a);
        tm.extend(b);
    }
    let build = |t: &[Trip]| {
        SparseColMat::<usize, f64>::try_new_from_triplets(n_reduced, n_reduced, t)
            .map_err(|e| Error::Numerical(format!("sparse matrix creation failed: {e:?}")))
    };
    let k = build(&tk)?;
    drop(tk);
    let m = build(&tm)?;
    Ok((k, m))
}

/// `y = A x` for a symmetric matrix stored as its lower triangle.
pub fn sym_lower_matvec(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    y.iter_mut().for_each(|v| *v = 0.0);
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let val = a.val();
    for j in 0..a.ncols() {
        let xj = x[j];
        let mut acc = 0.0;
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            let v = val[p];
            y[i] += v * xj;
            if i != j {
                acc += v * x[i];
            }
        }
        y[j] += acc;
    }
}

/// Write a symmetric matrix (lower triangle) as Matrix Market coordinate real symmetric, 1-based,
/// full precision.
pub fn write_matrix_market(a: &SparseColMat<usize, f64>, path: &std::path::Path) -> Result<()> {
    use std::io::Write;
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let val = a.val();
    let io = |e| Error::io(path, e);
    writeln!(w, "%%MatrixMarket matrix coordinate real symmetric").map_err(io)?;
    writeln!(w, "% written by squeal (lower triangle, 1-based)").map_err(io)?;
    writeln!(w, "{} {} {}", a.nrows(), a.ncols(), val.len()).map_err(io)?;
    for j in 0..a.ncols() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            writeln!(w, "{} {} {:.17e}", row_idx[p] + 1, j + 1, val[p]).map_err(io)?;
        }
    }
    w.flush().map_err(io)
}

/// Read a Matrix Market `coordinate real symmetric` file (as [`write_matrix_market`] writes) into
/// a lower-triangle sparse matrix. Entries above the diagonal are mirrored into the lower
/// triangle; duplicates are summed. Errors name the file and line.
pub fn read_matrix_market(path: &std::path::Path) -> Result<SparseColMat<usize, f64>> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::reading(path, e))?;
    let bad = |line: usize, msg: String| Error::input(&name, format!("line {line}"), msg);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let (_, header) = lines
        .next()
        .ok_or_else(|| bad(1, "empty file (expected a Matrix Market header)".into()))?;
    let h: Vec<String> = header
        .split_whitespace()
        .map(|t| t.to_ascii_lowercase())
        .collect();
    if h.len() != 5 || h[0] != "%%matrixmarket" || h[1] != "matrix" || h[2] != "coordinate" {
        return Err(bad(
            1,
            format!("expected `%%MatrixMarket matrix coordinate real symmetric`, got `{header}`"),
        ));
    }
    if h[3] != "real" || h[4] != "symmetric" {
        return Err(bad(
            1,
            format!(
                "only `real symmetric` matrices are supported, got `{} {}`",
                h[3], h[4]
            ),
        ));
    }
    let mut data = lines.filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    let (ls, size) = data
        .next()
        .ok_or_else(|| bad(2, "missing the size line `rows cols entries`".into()))?;
    let dims: Vec<usize> = size
        .split_whitespace()
        .map(|t| t.parse::<usize>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad(ls, format!("expected `rows cols entries`, got `{size}`")))?;
    if dims.len() != 3 || dims[0] != dims[1] || dims[0] == 0 {
        return Err(bad(
            ls,
            format!("expected a non-empty square matrix `n n entries`, got `{size}`"),
        ));
    }
    let (n, nnz) = (dims[0], dims[2]);
    let mut trips = Vec::with_capacity(nnz.min(text.len() / 6 + 1));
    for (l, line) in data {
        let mut it = line.split_whitespace();
        let parsed = (|| {
            let i: usize = it.next()?.parse().ok()?;
            let j: usize = it.next()?.parse().ok()?;
            let v: f64 = it.next()?.parse().ok()?;
            it.next().is_none().then_some((i, j, v))
        })();
        let (i, j, v) =
            parsed.ok_or_else(|| bad(l, format!("expected `row col value`, got `{line}`")))?;
        if i == 0 || j == 0 || i > n || j > n {
            return Err(bad(
                l,
                format!("index ({i}, {j}) outside the 1-based range 1..={n}"),
            ));
        }
        if !v.is_finite() {
            return Err(bad(l, format!("non-finite value {v}")));
        }
        if trips.len() == nnz {
            return Err(bad(
                l,
                format!("more entries than the {nnz} the size line declares"),
            ));
        }
        let (r, c) = if i >= j {
            (i - 1, j - 1)
        } else {
            (j - 1, i - 1)
        };
        trips.push(Triplet::new(r, c, v));
    }
    if trips.len() != nnz {
        return Err(Error::input(
            &name,
            "entries",
            format!(
                "{} entries, but the size line declares {nnz} (truncated file?)",
                trips.len()
            ),
        ));
    }
    SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trips)
        .map_err(|e| Error::Numerical(format!("{name}: sparse matrix creation failed: {e:?}")))
}
