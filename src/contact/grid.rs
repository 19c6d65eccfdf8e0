//! The bucket grid of a contact pair's master faces: a uniform grid over the faces' (widened)
//! bounding boxes, each cell listing the faces whose box overlaps it, so that a slave's
//! candidate faces are those of its cell.

// Index loops mirror the cell arithmetic.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use crate::mesh::P3;

/// Uniform bucket grid over face bounding boxes.
#[derive(Default)]
pub(super) struct BucketGrid {
    origin: P3,
    cell_m: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
    /// Per face: its bounding box at the last build, widened by the rebuild distance and the
    /// penetration depth searched; a slave outside it cannot be over the face.
    pub(super) face_lo: Vec<P3>,
    pub(super) face_hi: Vec<P3>,
}

impl BucketGrid {
    /// Bins the face `boxes` (lowest, highest corner; already widened) in cells of about twice
    /// `small_face_m` (the tenth-percentile face size).
    pub(super) fn new(boxes: &[(P3, P3)], small_face_m: f64) -> BucketGrid {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (a, b) in boxes {
            for d in 0..3 {
                lo[d] = lo[d].min(a[d]);
                hi[d] = hi[d].max(b[d]);
            }
        }
        // Cells of about twice the small faces' size (where the faces are fine, at the patch,
        // a cell lists a few dozen; a coarse face is listed in each cell it spans), at most
        // ~4 M cells. Cells of twice the median (10 mm on the paper's rail, whose faces are
        // mostly coarse) listed about 400 of the 1 mm faces each.
        let mut cell = (2.0 * small_face_m).max(1e-6);
        let extent = [0, 1, 2].map(|d| (hi[d] - lo[d]).max(0.0));
        while extent
            .iter()
            .map(|e| (e / cell).ceil().max(1.0))
            .product::<f64>()
            > 4.0e6
        {
            cell *= 1.5;
        }
        let dims = [0, 1, 2].map(|d| ((extent[d] / cell).ceil() as usize).clamp(1, 1 << 20));
        let n_cells = dims[0] * dims[1] * dims[2];
        let cell_range = |a: f64, b: f64, d: usize| -> (usize, usize) {
            let i0 = (((a - lo[d]) / cell).floor().max(0.0) as usize).min(dims[d] - 1);
            let i1 = (((b - lo[d]) / cell).floor().max(0.0) as usize).min(dims[d] - 1);
            (i0, i1)
        };
        let mut counts = vec![0u32; n_cells + 1];
        let mut pairs: Vec<(usize, u32)> = Vec::new();
        for (k, (a, b)) in boxes.iter().enumerate() {
            let (x0, x1) = cell_range(a[0], b[0], 0);
            let (y0, y1) = cell_range(a[1], b[1], 1);
            let (z0, z1) = cell_range(a[2], b[2], 2);
            for z in z0..=z1 {
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let c = x + dims[0] * (y + dims[1] * z);
                        counts[c + 1] += 1;
                        pairs.push((c, k as u32));
                    }
                }
            }
        }
        for c in 0..n_cells {
            counts[c + 1] += counts[c];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; pairs.len()];
        for (c, k) in pairs {
            items[fill[c] as usize] = k;
            fill[c] += 1;
        }
        BucketGrid {
            origin: lo,
            cell_m: cell,
            dims,
            start: counts,
            items,
            face_lo: boxes.iter().map(|b| b.0).collect(),
            face_hi: boxes.iter().map(|b| b.1).collect(),
        }
    }

    fn cell_of(&self, x: P3) -> Option<[usize; 3]> {
        let mut c = [0usize; 3];
        for d in 0..3 {
            let f = ((x[d] - self.origin[d]) / self.cell_m).floor();
            if !(f >= 0.0) || f as usize >= self.dims[d] {
                return None;
            }
            c[d] = f as usize;
        }
        Some(c)
    }
    /// Whether `x` lies inside the (widened) box of some face: what the search tests first.
    pub(super) fn inside_some_box(&self, x: P3) -> bool {
        self.candidates(x).iter().any(|&f| {
            let (lo, hi) = (self.face_lo[f as usize], self.face_hi[f as usize]);
            (0..3).all(|d| x[d] >= lo[d] && x[d] <= hi[d])
        })
    }

    /// Whether `x` lies within `margin` (along every axis) of some face's box: the cells
    /// overlapping `x +- margin` are searched, so any face whose box a point within the margin
    /// falls into is seen (it is listed in that point's cell).
    pub(super) fn near_some_box(&self, x: P3, margin: f64) -> bool {
        // Rounding headroom: the region's move check uses `margin` itself.
        let m = margin * (1.0 + 1e-9) + 1e-12;
        let mut range = [(0usize, 0usize); 3];
        for d in 0..3 {
            let a = ((x[d] - m - self.origin[d]) / self.cell_m).floor();
            let b = ((x[d] + m - self.origin[d]) / self.cell_m).floor();
            if !(b >= 0.0) || a >= self.dims[d] as f64 {
                return false; // the whole neighbourhood is outside the grid
            }
            range[d] = (a.max(0.0) as usize, (b as usize).min(self.dims[d] - 1));
        }
        for z in range[2].0..=range[2].1 {
            for y in range[1].0..=range[1].1 {
                for xc in range[0].0..=range[0].1 {
                    let c = xc + self.dims[0] * (y + self.dims[1] * z);
                    let faces = &self.items[self.start[c] as usize..self.start[c + 1] as usize];
                    let near = faces.iter().any(|&f| {
                        let (lo, hi) = (self.face_lo[f as usize], self.face_hi[f as usize]);
                        (0..3).all(|d| x[d] >= lo[d] - m && x[d] <= hi[d] + m)
                    });
                    if near {
                        return true;
                    }
                }
            }
        }
        false
    }

    pub(super) fn candidates(&self, x: P3) -> &[u32] {
        match self.cell_of(x) {
            Some(c) => {
                let k = c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2]);
                &self.items[self.start[k] as usize..self.start[k + 1] as usize]
            }
            None => &[],
        }
    }
}
