//! Geometry of the 8-node hexahedron (VTK node order: 0-3 counter-clockwise on the bottom face
//! seen from the top, 4-7 above them).

use nalgebra::Vector3;

/// A point in space.
pub type P3 = [f64; 3];

/// Faces with outward normals (right-hand rule) for a positively oriented hexahedron.
pub const FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// The three edge neighbours of each corner, ordered so that their edge vectors form a
/// right-handed triple for a positively oriented element.
pub const CORNER_NEIGHBOURS: [[usize; 3]; 8] = [
    [1, 3, 4],
    [2, 0, 5],
    [3, 1, 6],
    [0, 2, 7],
    [7, 5, 0],
    [4, 6, 1],
    [5, 7, 2],
    [6, 4, 3],
];

/// The 12 edges.
pub const EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// Hexahedron geometry computes with nalgebra's `Vector3`; `P3` (three contiguous `f64`, the
/// storage of every node array) converts to it for free.
fn vector(p: P3) -> Vector3<f64> {
    Vector3::from(p)
}

/// Edge vector `to - from`.
fn edge(from: P3, to: P3) -> Vector3<f64> {
    vector(to) - vector(from)
}

/// Natural coordinates of the eight nodes of a hexahedron in the mesh's (VTK) node order.
pub const NODE_NATURAL: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Corner Jacobian determinants (triple products of the three corner edges); all positive for
/// a valid, positively oriented element.
pub fn corner_jacobians(x: &[P3; 8]) -> [f64; 8] {
    let mut out = [0.0; 8];
    for (c, nb) in CORNER_NEIGHBOURS.iter().enumerate() {
        let e1 = edge(x[c], x[nb[0]]);
        let e2 = edge(x[c], x[nb[1]]);
        let e3 = edge(x[c], x[nb[2]]);
        out[c] = e1.dot(&e2.cross(&e3));
    }
    out
}

/// Smallest scaled corner Jacobian: triple product over the product of the edge lengths
/// (1 for a perfect cube, <= 0 for an inverted corner).
pub fn min_scaled_jacobian(x: &[P3; 8]) -> f64 {
    let mut worst = f64::INFINITY;
    for (c, nb) in CORNER_NEIGHBOURS.iter().enumerate() {
        let e1 = edge(x[c], x[nb[0]]);
        let e2 = edge(x[c], x[nb[1]]);
        let e3 = edge(x[c], x[nb[2]]);
        let scale = (e1.norm() * e2.norm() * e3.norm()).max(1e-300);
        worst = worst.min(e1.dot(&e2.cross(&e3)) / scale);
    }
    worst
}

/// Volume by splitting the (possibly non-planar) hexahedron into the 6 tetrahedra around the
/// 0-6 diagonal; exact for trilinear elements with planar faces and second-order accurate
/// otherwise.
pub fn volume(x: &[P3; 8]) -> f64 {
    const TETS: [[usize; 4]; 6] = [
        [0, 1, 2, 6],
        [0, 2, 3, 6],
        [0, 3, 7, 6],
        [0, 7, 4, 6],
        [0, 4, 5, 6],
        [0, 5, 1, 6],
    ];
    let mut v = 0.0;
    for t in TETS {
        let base = x[t[0]];
        v += edge(base, x[t[1]]).dot(&edge(base, x[t[2]]).cross(&edge(base, x[t[3]]))) / 6.0;
    }
    v
}

/// Area of a (possibly warped) quad face: half the norm of the cross product of its diagonals.
pub fn face_area(a: P3, b: P3, c: P3, d: P3) -> f64 {
    0.5 * edge(a, c).cross(&edge(b, d)).norm()
}

/// Outward normal (not normalised; length = face area) of a face given in outward order.
pub fn face_normal(a: P3, b: P3, c: P3, d: P3) -> P3 {
    (edge(a, c).cross(&edge(b, d)) * 0.5).into()
}

/// Characteristic length for the explicit time step, `L = V / A_max` (volume over the largest
/// face area), the choice of LS-DYNA's default solid time-step estimate.
pub fn characteristic_length(x: &[P3; 8]) -> f64 {
    let mut a_max: f64 = 0.0;
    for f in FACES {
        a_max = a_max.max(face_area(x[f[0]], x[f[1]], x[f[2]], x[f[3]]));
    }
    volume(x) / a_max.max(1e-300)
}

/// Shortest and longest edge.
pub fn edge_range(x: &[P3; 8]) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi: f64 = 0.0;
    for e in EDGES {
        let l = edge(x[e[0]], x[e[1]]).norm();
        lo = lo.min(l);
        hi = hi.max(l);
    }
    (lo, hi)
}

/// Reorder an element whose corner Jacobians are all negative (mirror-image numbering) so that
/// it becomes positively oriented: swap the bottom and top faces.
pub fn flip(conn: [usize; 8]) -> [usize; 8] {
    [
        conn[4], conn[5], conn[6], conn[7], conn[0], conn[1], conn[2], conn[3],
    ]
}

/// The hexahedron swept by a quad (counter-clockwise nodes `quad`) from layer `k` to `k + 1`,
/// where `node(id, k)` numbers the copy of section node `id` in layer `k` (revolve, extrude).
pub fn swept(quad: [usize; 4], k: usize, node: impl Fn(usize, usize) -> usize) -> [usize; 8] {
    [
        node(quad[0], k),
        node(quad[1], k),
        node(quad[2], k),
        node(quad[3], k),
        node(quad[0], k + 1),
        node(quad[1], k + 1),
        node(quad[2], k + 1),
        node(quad[3], k + 1),
    ]
}

/// Cell `(i, j, l)` of a structured block whose node `(i, j, l)` has id `id(i, j, l)`.
pub fn structured(
    i: usize,
    j: usize,
    l: usize,
    id: impl Fn(usize, usize, usize) -> usize,
) -> [usize; 8] {
    [
        id(i, j, l),
        id(i + 1, j, l),
        id(i + 1, j + 1, l),
        id(i, j + 1, l),
        id(i, j, l + 1),
        id(i + 1, j, l + 1),
        id(i + 1, j + 1, l + 1),
        id(i, j + 1, l + 1),
    ]
}
