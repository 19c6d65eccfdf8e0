//! Plane curves made of lines and circular arcs, the building blocks of rail and wheel
//! sections, plus the fillet constructions (circle tangent to two curves) the 54E1 drawing uses.
//! Coordinates are `[horizontal, vertical]` in whatever unit the caller uses (mm for profiles).

use nalgebra::Vector2;

/// A point or vector in the plane, as stored in sections and meshes.
pub type P2 = [f64; 2];

/// The constructions below compute with nalgebra's `Vector2`; `P2` is converted at the
/// boundary (both are two contiguous `f64`, so the conversion is free).
fn vector(p: P2) -> Vector2<f64> {
    Vector2::from(p)
}

/// Euclidean length, by `hypot` (no overflow or underflow in the squares).
fn length(v: Vector2<f64>) -> f64 {
    v.x.hypot(v.y)
}

/// `v` scaled to unit length.
fn unit(v: Vector2<f64>) -> Vector2<f64> {
    v * (1.0 / length(v))
}

/// Euclidean length.
pub fn norm(a: P2) -> f64 {
    length(vector(a))
}

/// An infinite line through `point` with unit `direction`.
#[derive(Clone, Copy, Debug)]
pub struct Line {
    /// A point on the line.
    pub point: P2,
    /// Unit direction.
    pub direction: P2,
}

impl Line {
    /// Line through `point` with slope `dz/dy` given as `rise / run`.
    pub fn through_with_slope(point: P2, run: f64, rise: f64) -> Self {
        Line {
            point,
            direction: unit(Vector2::new(run, rise)).into(),
        }
    }
    /// Unit normal to the left of the direction.
    pub fn left_normal(&self) -> P2 {
        [-self.direction[1], self.direction[0]]
    }
    /// The line moved by `distance` along its left normal (negative: to the right).
    pub fn offset(&self, distance: f64) -> Line {
        Line {
            point: (vector(self.point) + vector(self.left_normal()) * distance).into(),
            direction: self.direction,
        }
    }
    /// Orthogonal projection of `p` on the line.
    pub fn project(&self, p: P2) -> P2 {
        let direction = vector(self.direction);
        let t = (vector(p) - vector(self.point)).dot(&direction);
        (vector(self.point) + direction * t).into()
    }
    /// Intersection with another line (None if parallel).
    pub fn intersect(&self, other: &Line) -> Option<P2> {
        let (direction, other_direction) = (vector(self.direction), vector(other.direction));
        let d = direction.perp(&other_direction);
        if d.abs() < 1e-14 {
            return None;
        }
        let w = vector(other.point) - vector(self.point);
        let t = w.perp(&other_direction) / d;
        Some((vector(self.point) + direction * t).into())
    }
    /// Intersections with a circle (0, 1 or 2 points).
    pub fn intersect_circle(&self, centre: P2, radius: f64) -> Vec<P2> {
        let (point, direction) = (vector(self.point), vector(self.direction));
        let w = point - vector(centre);
        let b = w.dot(&direction);
        let c = w.norm_squared() - radius * radius;
        let disc = b * b - c;
        if disc < 0.0 {
            return vec![];
        }
        let root = disc.sqrt();
        vec![
            (point + direction * (-b - root)).into(),
            (point + direction * (-b + root)).into(),
        ]
    }
}

/// Intersections of two circles.
pub fn circle_circle(c1: P2, r1: f64, c2: P2, r2: f64) -> Vec<P2> {
    let d_vec = vector(c2) - vector(c1);
    let d = length(d_vec);
    if d < 1e-14 || d > r1 + r2 || d < (r1 - r2).abs() {
        return vec![];
    }
    let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let e = d_vec * (1.0 / d);
    let mid = vector(c1) + e * a;
    let perp = Vector2::new(-e.y, e.x);
    vec![(mid + perp * h).into(), (mid - perp * h).into()]
}

/// The candidate nearest to `near`.
pub fn nearest(candidates: &[P2], near: P2) -> Option<P2> {
    candidates.iter().copied().min_by(|a, b| {
        let distance = |p: &P2| length(vector(*p) - vector(near));
        distance(a).total_cmp(&distance(b))
    })
}

/// Point where a circle centred at `centre_from` touches a circle centred at `centre_to` of
/// radius `radius_to` (tangency lies on the line of centres).
pub fn tangent_point_on_circle(centre_to: P2, radius_to: f64, towards: P2) -> P2 {
    let centre = vector(centre_to);
    (centre + unit(vector(towards) - centre) * radius_to).into()
}

/// One piece of a section outline.
#[derive(Clone, Debug)]
pub enum Segment {
    /// Straight line from `start` to `end`.
    Line {
        /// First point.
        start: P2,
        /// Last point.
        end: P2,
    },
    /// Circular arc around `centre`, from `start` to `end`, turning counter-clockwise when
    /// `ccw` is true.
    Arc {
        /// Centre.
        centre: P2,
        /// Radius.
        radius: f64,
        /// First point (on the circle).
        start: P2,
        /// Last point (on the circle).
        end: P2,
        /// Turning direction.
        ccw: bool,
    },
}

impl Segment {
    /// Arc helper taking start/end points on the circle.
    pub fn arc(centre: P2, start: P2, end: P2, ccw: bool) -> Self {
        Segment::Arc {
            centre,
            radius: length(vector(start) - vector(centre)),
            start,
            end,
            ccw,
        }
    }

    fn arc_angles(&self) -> Option<(f64, f64)> {
        match self {
            Segment::Arc {
                centre,
                start,
                end,
                ccw,
                ..
            } => {
                let a0 = (start[1] - centre[1]).atan2(start[0] - centre[0]);
                let mut a1 = (end[1] - centre[1]).atan2(end[0] - centre[0]);
                if *ccw {
                    while a1 < a0 {
                        a1 += std::f64::consts::TAU;
                    }
                } else {
                    while a1 > a0 {
                        a1 -= std::f64::consts::TAU;
                    }
                }
                Some((a0, a1))
            }
            Segment::Line { .. } => None,
        }
    }

    /// Length of the segment.
    pub fn length(&self) -> f64 {
        match self {
            Segment::Line { start, end } => length(vector(*end) - vector(*start)),
            Segment::Arc { radius, .. } => {
                let (a0, a1) = self.arc_angles().unwrap_or((0.0, 0.0));
                radius * (a1 - a0).abs()
            }
        }
    }

    /// Point at fraction `t` in [0, 1] of the length.
    pub fn point_at(&self, t: f64) -> P2 {
        match self {
            Segment::Line { start, end } => {
                (vector(*start) + (vector(*end) - vector(*start)) * t).into()
            }
            Segment::Arc { centre, radius, .. } => {
                let (a0, a1) = self.arc_angles().unwrap_or((0.0, 0.0));
                let a = a0 + t * (a1 - a0);
                [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
            }
        }
    }

    /// End point.
    pub fn end(&self) -> P2 {
        match self {
            Segment::Line { end, .. } | Segment::Arc { end, .. } => *end,
        }
    }
    /// Start point.
    pub fn start(&self) -> P2 {
        match self {
            Segment::Line { start, .. } | Segment::Arc { start, .. } => *start,
        }
    }
}

/// Sample a chain of segments into a polyline with points no further apart than `max_step`
/// (the first point of each segment is included once; the last point of the chain closes it).
pub fn sample_chain(segments: &[Segment], max_step: f64) -> Vec<P2> {
    let mut points = Vec::new();
    for seg in segments {
        let n = ((seg.length() / max_step).ceil() as usize).max(1);
        for i in 0..n {
            points.push(seg.point_at(i as f64 / n as f64));
        }
    }
    if let Some(last) = segments.last() {
        points.push(last.end());
    }
    points
}

/// Area, centroid and second moments of a closed polygon (counter-clockwise positive), by
/// Green's theorem. Returns `(area, [cy, cz], i_yy_about_centroid, i_zz_about_centroid)` where
/// `i_yy = integral of (z - cz)^2` (bending about the horizontal axis) and
/// `i_zz = integral of (y - cy)^2` (about the vertical axis).
pub fn polygon_properties(points: &[P2]) -> (f64, P2, f64, f64) {
    let n = points.len();
    let (mut a2, mut sy, mut sz, mut szz, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        let [y0, z0] = points[i];
        let [y1, z1] = points[(i + 1) % n];
        let cross = y0 * z1 - y1 * z0;
        a2 += cross;
        sy += (y0 + y1) * cross;
        sz += (z0 + z1) * cross;
        syy += (y0 * y0 + y0 * y1 + y1 * y1) * cross;
        szz += (z0 * z0 + z0 * z1 + z1 * z1) * cross;
    }
    let area = 0.5 * a2;
    let cy = sy / (6.0 * area);
    let cz = sz / (6.0 * area);
    let i_about_origin_z = szz / 12.0;
    let i_about_origin_y = syy / 12.0;
    (
        area,
        [cy, cz],
        i_about_origin_z - area * cz * cz,
        i_about_origin_y - area * cy * cy,
    )
}
