//! Hexahedral meshes: the `Mesh` type (nodes, 8-node hexahedra, materials, named node sets,
//! named surfaces, tied interfaces), generators (revolve, extrude, wheel, track), quality
//! checks and file writers/readers.

pub mod distribute;
pub mod gmsh;
pub mod hex;
pub mod insert;
pub mod pvd;
pub mod quality;
pub mod rail;
pub mod rail_insert;
pub mod section;
pub mod tie;
pub mod track;
pub mod tread_insert;
pub mod volume;
pub mod volume_io;
pub mod vtk_cells;
pub mod vtk_legacy;
pub mod vtu;
pub mod wheel;
mod wheel_zones;

use std::collections::{BTreeMap, HashMap};

pub use hex::P3;
pub use quality::QualityReport;
pub use tie::TiedInterface;

/// Material ids used by the generators.
pub mod material {
    /// Wheel body (rim, web, hub) steel.
    pub const WHEEL: u32 = 1;
    /// Axle steel.
    pub const AXLE: u32 = 2;
    /// Fine tread band of the wheel (same steel; separate id so it can be shown and tied).
    pub const TREAD_BAND: u32 = 3;
    /// Rail steel.
    pub const RAIL: u32 = 4;
    /// Concrete sleeper.
    pub const SLEEPER: u32 = 5;
    /// Fine running band of the rail crown (rail steel; tied to the rail head).
    pub const RAIL_BAND: u32 = 6;
}

/// A hexahedral mesh.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Node coordinates (m).
    pub nodes: Vec<P3>,
    /// 8-node hexahedra (VTK order), positively oriented.
    pub elements: Vec<[usize; 8]>,
    /// Material id per element.
    pub material: Vec<u32>,
    /// Named node sets (sorted, unique node ids).
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Named surfaces: quad faces with node order giving the outward normal (right-hand rule).
    pub surfaces: BTreeMap<String, Vec<[usize; 4]>>,
    /// Tied interfaces between non-matching parts.
    pub ties: Vec<TiedInterface>,
}

impl Mesh {
    /// Moves every tie slave onto its master face (`x_s = sum w_i x_i`) and zeroes the recorded
    /// offsets. Then `u_s = sum w_i u_i` is exact for rigid motion (an affine combination of
    /// rigidly moving points moves rigidly): with an offset, a turned body would strain at the
    /// tie (the explicit engine) and a free body would lose its exact rigid modes (the modal
    /// solver). Offsets are a fraction of a millimetre on the default meshes.
    pub fn snap_tie_slaves(&mut self) {
        for t in &mut self.ties {
            for p in &mut t.pairs {
                let x: P3 = [0, 1, 2].map(|d| {
                    (0..4)
                        .map(|k| p.weights[k] * self.nodes[p.master[k]][d])
                        .sum::<f64>()
                });
                self.nodes[p.slave] = x;
                p.gap_m = 0.0;
            }
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }
    /// Number of elements.
    pub fn element_count(&self) -> usize {
        self.elements.len()
    }

    /// Coordinates of an element's nodes.
    pub fn element_coords(&self, e: usize) -> [P3; 8] {
        let c = &self.elements[e];
        std::array::from_fn(|k| self.nodes[c[k]])
    }

    /// Node set by name.
    pub fn node_set(&self, name: &str) -> Option<&[usize]> {
        self.node_sets.get(name).map(|v| v.as_slice())
    }

    /// Insert (or extend) a node set.
    pub fn add_node_set(&mut self, name: &str, ids: impl IntoIterator<Item = usize>) {
        let list = self.node_sets.entry(name.to_string()).or_default();
        list.extend(ids);
        list.sort_unstable();
        list.dedup();
    }

    /// Append another mesh (its node ids are shifted; sets with equal names are merged).
    pub fn append(&mut self, other: Mesh) {
        let offset = self.nodes.len();
        self.nodes.extend(other.nodes);
        self.elements
            .extend(other.elements.into_iter().map(|c| c.map(|n| n + offset)));
        self.material.extend(other.material);
        for (name, ids) in other.node_sets {
            self.add_node_set(&name, ids.into_iter().map(|n| n + offset));
        }
        for (name, faces) in other.surfaces {
            self.surfaces
                .entry(name)
                .or_default()
                .extend(faces.into_iter().map(|f| f.map(|n| n + offset)));
        }
        for tie in other.ties {
            self.ties.push(tie.shifted(offset));
        }
    }

    /// Make every element positively oriented (elements generated as mirror images are
    /// renumbered); elements with mixed-sign corners are left as they are for the quality check
    /// to report.
    pub fn orient_elements(&mut self) {
        for e in 0..self.elements.len() {
            let jac = hex::corner_jacobians(&self.element_coords(e));
            if jac.iter().all(|&j| j < 0.0) {
                self.elements[e] = hex::flip(self.elements[e]);
            }
        }
    }

    /// Fuse nodes closer than `tolerance` (m), renumbering elements, sets and surfaces.
    /// Returns the map old id -> new id.
    pub fn merge_coincident_nodes(&mut self, tolerance: f64) -> Vec<usize> {
        let cell = tolerance * 16.0;
        let key = |p: &P3| {
            (
                (p[0] / cell).floor() as i64,
                (p[1] / cell).floor() as i64,
                (p[2] / cell).floor() as i64,
            )
        };
        let mut buckets: HashMap<(i64, i64, i64), Vec<usize>> =
            HashMap::with_capacity(self.nodes.len());
        let mut new_id = vec![usize::MAX; self.nodes.len()];
        let mut kept: Vec<P3> = Vec::with_capacity(self.nodes.len());
        for (i, p) in self.nodes.iter().enumerate() {
            let (bx, by, bz) = key(p);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(list) = buckets.get(&(bx + dx, by + dy, bz + dz)) {
                            for &j in list {
                                let q = kept[j];
                                if (q[0] - p[0]).abs() <= tolerance
                                    && (q[1] - p[1]).abs() <= tolerance
                                    && (q[2] - p[2]).abs() <= tolerance
                                {
                                    found = Some(j);
                                    break 'search;
                                }
                            }
                        }
                    }
                }
            }
            new_id[i] = match found {
                Some(j) => j,
                None => {
                    kept.push(*p);
                    buckets
                        .entry((bx, by, bz))
                        .or_default()
                        .push(kept.len() - 1);
                    kept.len() - 1
                }
            };
        }
        self.nodes = kept;
        self.renumber(&new_id);
        new_id
    }

    fn renumber(&mut self, new_id: &[usize]) {
        for c in &mut self.elements {
            *c = c.map(|n| new_id[n]);
        }
        for ids in self.node_sets.values_mut() {
            for n in ids.iter_mut() {
                *n = new_id[*n];
            }
            ids.sort_unstable();
            ids.dedup();
        }
        for faces in self.surfaces.values_mut() {
            for f in faces.iter_mut() {
                *f = f.map(|n| new_id[n]);
            }
        }
        for tie in &mut self.ties {
            tie.renumber(new_id);
        }
    }

    /// Boundary faces (faces used by exactly one element), in outward order, with their owner.
    /// Faces are matched by their sorted node ids after a sort (no hashing: this runs on
    /// millions of faces).
    pub fn boundary_faces(&self) -> Vec<([usize; 4], usize)> {
        let mut all: Vec<([usize; 4], u32, u8)> = Vec::with_capacity(self.elements.len() * 6);
        for (e, conn) in self.elements.iter().enumerate() {
            for (k, f) in hex::FACES.iter().enumerate() {
                let mut sorted = f.map(|i| conn[i]);
                sorted.sort_unstable();
                all.push((sorted, e as u32, k as u8));
            }
        }
        all.sort_unstable();
        let mut out = Vec::new();
        let mut i = 0;
        while i < all.len() {
            let mut j = i + 1;
            while j < all.len() && all[j].0 == all[i].0 {
                j += 1;
            }
            if j == i + 1 {
                let (_, e, k) = all[i];
                let conn = self.elements[e as usize];
                out.push((hex::FACES[k as usize].map(|n| conn[n]), e as usize));
            }
            i = j;
        }
        out.sort_unstable_by_key(|v| (v.1, v.0));
        out
    }

    /// Define surface `name` as the boundary faces whose four nodes all belong to node set
    /// `set` (and, when given, whose owner element has material `only_material`).
    pub fn surface_from_node_set(
        &mut self,
        name: &str,
        set: &str,
        only_material: Option<u32>,
    ) -> usize {
        let Some(ids) = self.node_sets.get(set) else {
            return 0;
        };
        let mut member = vec![false; self.nodes.len()];
        for &n in ids {
            member[n] = true;
        }
        let faces: Vec<[usize; 4]> = self
            .boundary_faces()
            .into_iter()
            .filter(|(f, e)| {
                f.iter().all(|&n| member[n]) && only_material.is_none_or(|m| self.material[*e] == m)
            })
            .map(|(f, _)| f)
            .collect();
        let count = faces.len();
        self.surfaces.insert(name.to_string(), faces);
        count
    }

    /// Total volume (m^3).
    pub fn volume(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| hex::volume(&self.element_coords(e)))
            .sum()
    }

    /// Volume per material id.
    pub fn volume_by_material(&self) -> BTreeMap<u32, f64> {
        let mut out = BTreeMap::new();
        for e in 0..self.elements.len() {
            *out.entry(self.material[e]).or_insert(0.0) += hex::volume(&self.element_coords(e));
        }
        out
    }

    /// Quality report (see [`QualityReport`]).
    pub fn quality(&self, wave_speed_m_per_s: f64) -> QualityReport {
        QualityReport::of(self, wave_speed_m_per_s)
    }
}

/// A structured box `[0, lx] x [0, ly] x [0, lz]` (m) of `n[0] x n[1] x n[2]` hexahedra, material
/// `material_id`, with node sets `x0`, `x1`, `y0`, `y1`, `z0`, `z1` on its faces and `all`. Used by
/// tests (bars, plates, blocks with analytic answers) and the explicit benchmark.
pub fn cuboid(n: [usize; 3], size_m: [f64; 3], material_id: u32) -> Mesh {
    let [nx, ny, nz] = n;
    let id = |i: usize, j: usize, l: usize| i + (nx + 1) * (j + (ny + 1) * l);
    let mut mesh = Mesh::default();
    for l in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                mesh.nodes.push([
                    size_m[0] * i as f64 / nx as f64,
                    size_m[1] * j as f64 / ny as f64,
                    size_m[2] * l as f64 / nz as f64,
                ]);
            }
        }
    }
    for l in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                mesh.elements.push(hex::structured(i, j, l, id));
                mesh.material.push(material_id);
            }
        }
    }
    let count = mesh.nodes.len();
    let on = |axis: usize, value: usize| -> Vec<usize> {
        (0..count)
            .filter(|&k| {
                let ijk = [
                    k % (nx + 1),
                    (k / (nx + 1)) % (ny + 1),
                    k / ((nx + 1) * (ny + 1)),
                ];
                ijk[axis] == value
            })
            .collect()
    };
    for (axis, name, last) in [(0, "x", nx), (1, "y", ny), (2, "z", nz)] {
        mesh.add_node_set(&format!("{name}0"), on(axis, 0));
        mesh.add_node_set(&format!("{name}1"), on(axis, last));
    }
    mesh.add_node_set("all", 0..count);
    mesh
}
