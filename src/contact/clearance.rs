//! How a contact pair's slave surface lies against its master before any load: the signed
//! distance of each slave over a master face, and the check that the bodies face each other
//! and touch (or nearly) before the preload.

use super::{distance_over_face, face_box, unit_normal, ContactPair};
use crate::mesh::P3;
use crate::{Error, Result};

/// How a slave surface lies against its master before any load
/// ([`ContactPair::clearance`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearance {
    /// Slaves over a master face within the search distance.
    pub slaves_near: usize,
    /// Of those, the ones clearly on the outer side of the face (`g` above 1 % of the search
    /// distance).
    pub slaves_outside: usize,
    /// And the ones clearly behind it (`g` below -1 % of the search distance).
    pub slaves_behind: usize,
    /// Smallest signed distance `g` among them (m; negative: penetrating); infinite if none.
    pub smallest_gap_m: f64,
}

impl ContactPair {
    /// How the slave nodes lie against the master surface before any load (reference
    /// positions): for each slave over a master face within `search_m` of it (on either side),
    /// the signed distance `g = (x_s - x_p) . n` along the face's outward normal.
    /// Slaves not over any face within `search_m` are left out.
    pub fn clearance(&self, search_m: f64) -> Clearance {
        let pos = |n: usize| self.reference[n];
        let mut gaps: Vec<f64> = Vec::new();
        // Face boxes widened by the search distance; a brute loop over the faces would be
        // slaves x faces (5e4 x 1e5 on the paper model), so the faces are binned by x-y cell.
        let boxes: Vec<(P3, P3)> = self
            .faces
            .iter()
            .map(|f| {
                let (lo, hi) = face_box(f.map(pos));
                (lo.map(|x| x - search_m), hi.map(|x| x + search_m))
            })
            .collect();
        let cell = (2.0 * self.median_face_size_m).max(search_m).max(1e-6);
        let mut bins: std::collections::HashMap<(i64, i64), Vec<usize>> =
            std::collections::HashMap::new();
        for (k, (lo, hi)) in boxes.iter().enumerate() {
            let (x0, x1) = ((lo[0] / cell).floor() as i64, (hi[0] / cell).floor() as i64);
            let (y0, y1) = ((lo[1] / cell).floor() as i64, (hi[1] / cell).floor() as i64);
            for x in x0..=x1 {
                for y in y0..=y1 {
                    bins.entry((x, y)).or_default().push(k);
                }
            }
        }
        for &s in &self.slaves {
            let xs = pos(s);
            let key = ((xs[0] / cell).floor() as i64, (xs[1] / cell).floor() as i64);
            let Some(candidates) = bins.get(&key) else {
                continue;
            };
            let mut nearest: Option<f64> = None;
            for &fi in candidates {
                let (lo, hi) = boxes[fi];
                if (0..3).any(|d| xs[d] < lo[d] || xs[d] > hi[d]) {
                    continue;
                }
                let p = self.faces[fi].map(pos);
                let (n, area) = unit_normal(&p);
                // Over the face (as in the contact search) and within the search distance.
                let Some((g, _)) = distance_over_face(&p, n, area, xs) else {
                    continue;
                };
                if g.abs() > search_m {
                    continue;
                }
                if nearest.is_none_or(|b| g.abs() < b.abs()) {
                    nearest = Some(g);
                }
            }
            if let Some(g) = nearest {
                gaps.push(g);
            }
        }
        // Beyond 1 % of the search distance, so that slaves flush with the master (g = 0 up to
        // rounding and faceting) count on neither side.
        let side = 0.01 * search_m;
        Clearance {
            slaves_near: gaps.len(),
            slaves_outside: gaps.iter().filter(|&&g| g > side).count(),
            slaves_behind: gaps.iter().filter(|&&g| g < -side).count(),
            smallest_gap_m: gaps.iter().copied().fold(f64::INFINITY, f64::min),
        }
    }

    /// Checks, before any load, that the slaves face the master surface from its outer side
    /// and come within `largest_gap_m` of it: errors name `field` (the input that places the
    /// bodies) and say which of the two failed.
    pub fn check_initial_clearance(
        &self,
        largest_gap_m: f64,
        source: &str,
        field: &str,
    ) -> Result<Clearance> {
        // Search a little beyond the allowed gap so that a gap just too large is measured and
        // named, not reported as "nothing near".
        let c = self.clearance(2.0 * largest_gap_m);
        if c.slaves_near == 0 {
            return Err(Error::input(
                source,
                field,
                format!(
                    "no slave node of `{}` lies over a master face within {:.3} mm: the \
                     initial gap must be at most {:.3} mm (or the surfaces miss each other)",
                    self.name,
                    2e3 * largest_gap_m,
                    1e3 * largest_gap_m
                ),
            ));
        }
        // A slave surface resting on the master has its neighbours outside the master (g > 0)
        // on the side the face normals point to; with the faces ordered inwards, or the slave
        // body placed inside the master, they come out negative.
        if c.slaves_behind > c.slaves_outside {
            return Err(Error::input(
                source,
                field,
                format!(
                    "the contact surfaces of `{}` do not face each other: {} of the {} slave \
                     nodes near the master surface lie behind it (against its outward normal)",
                    self.name, c.slaves_behind, c.slaves_near
                ),
            ));
        }
        if c.smallest_gap_m > largest_gap_m {
            return Err(Error::input(
                source,
                field,
                format!(
                    "the initial gap of `{}` measured on the meshes is {:.3} mm; at most {:.3} \
                     mm is allowed",
                    self.name,
                    1e3 * c.smallest_gap_m,
                    1e3 * largest_gap_m
                ),
            ));
        }
        Ok(c)
    }
}
