//! 54E1 (UIC54) rail section (EN 13674-1) built from its arcs and lines.
//!
//! Section coordinates `[y, z]` in mm: origin at the top of the crown, z up (the rail lies in
//! z <= 0), symmetric about y = 0, upright (the 1:40 inclination is applied when the rail is
//! placed in the track, see [`INCLINATION_RAD`]). Dimensions from docs/references.md, section 2;
//! the fillet radii (R3, R8, R16, R20, R3, R2) are constructed as circles tangent to the
//! neighbouring curves.

use super::curve2d::{
    circle_circle, nearest, sample_chain, tangent_point_on_circle, Line, Segment, P2,
};

/// Rail inclination 1:40 towards the track centre, `atan(1/40)`.
pub const INCLINATION_RAD: f64 = 0.024994793618920;
/// Rail height (mm).
pub const HEIGHT_MM: f64 = 159.0;
/// Head width (mm).
pub const HEAD_WIDTH_MM: f64 = 70.0;
/// Foot width (mm).
pub const FOOT_WIDTH_MM: f64 = 140.0;
/// Crown radius (mm).
pub const CROWN_RADIUS_MM: f64 = 300.0;
/// Catalogue section properties (EN 13674-1) for tests: area (mm^2).
pub const CATALOGUE_AREA_MM2: f64 = 6977.0;
/// Catalogue second moment about the horizontal axis (mm^4).
pub const CATALOGUE_I_HORIZONTAL_MM4: f64 = 2337.9e4;
/// Catalogue second moment about the vertical axis (mm^4).
pub const CATALOGUE_I_VERTICAL_MM4: f64 = 419.1e4;

fn mirror(p: P2) -> P2 {
    [-p[0], p[1]]
}

/// The left half of the outline, from the crown top (0, 0) down the gauge side to the bottom
/// centre (0, -159), counter-clockwise (material on the left of the direction of travel).
pub fn left_half_segments() -> Vec<Segment> {
    let crown_centre = [0.0, -CROWN_RADIUS_MM];
    let y1 = -10.012;
    let p1 = [
        y1,
        -CROWN_RADIUS_MM + (CROWN_RADIUS_MM * CROWN_RADIUS_MM - y1 * y1).sqrt(),
    ];
    let r80_centre = [-7.342, -80.123];
    let p2 = [-24.8635, -2.065];
    let r13_centre = [-22.016, -14.749];
    let p3 = [-35.0, -14.1];

    // Straight pieces, directed along the counter-clockwise travel.
    let side_face = Line::through_with_slope(p3, -1.0, -20.0); // 1:20, going down
    let underside = Line::through_with_slope([0.0, -49.4], 1.0, -1.0 / 2.75); // towards the web
    let foot_top = Line::through_with_slope([0.0, -128.8], -1.0, -1.0 / 2.75); // towards the edge
    let foot_taper = Line::through_with_slope([-70.0, -148.0], -1.0, -0.1); // 1:10
    let foot_edge = Line::through_with_slope([-70.0, 0.0], 0.0, -1.0);
    let bottom = Line::through_with_slope([0.0, -HEIGHT_MM], 1.0, 0.0);

    // Convex corners: fillet centre inside the material (offset to the left).
    let convex =
        |a: &Line, b: &Line, r: f64| a.offset(r).intersect(&b.offset(r)).expect("non-parallel");
    // Concave corners: centre in the air (offset to the right).
    let concave =
        |a: &Line, b: &Line, r: f64| a.offset(-r).intersect(&b.offset(-r)).expect("non-parallel");

    let head_corner = convex(&side_face, &underside, 3.0);
    let r22_centre = [-30.664, -57.4];
    let r508_centre = [-516.0, -82.8];
    // R8: 8 from the underside (air side) and internally tangent to R22 (centres 22 - 8 apart).
    let r8_centre = nearest(
        &underside.offset(-8.0).intersect_circle(r22_centre, 14.0),
        [-12.0, -45.0],
    )
    .expect("R8 fillet");
    // R16: 16 from the foot top (air side) and internally tangent to R508.
    let r16_centre = nearest(
        &foot_top.offset(-16.0).intersect_circle(r508_centre, 492.0),
        [-20.0, -115.0],
    )
    .expect("R16 fillet");
    let r20_centre = concave(&foot_top, &foot_taper, 20.0);
    let foot_corner_top = convex(&foot_taper, &foot_edge, 3.0);
    let foot_corner_bottom = convex(&foot_edge, &bottom, 2.0);
    let _ = circle_circle; // (kept for other sections)

    let t_side_end = side_face.project(head_corner);
    let t_under_start = underside.project(head_corner);
    let t_under_end = underside.project(r8_centre);
    let t_r8_r22 = tangent_point_on_circle(r22_centre, 22.0, r8_centre);
    let t_r22_r508 = tangent_point_on_circle(r508_centre, 508.0, r22_centre);
    let t_r508_r16 = tangent_point_on_circle(r508_centre, 508.0, r16_centre);
    let t_foot_start = foot_top.project(r16_centre);
    let t_foot_end = foot_top.project(r20_centre);
    let t_taper_start = foot_taper.project(r20_centre);
    let t_taper_end = foot_taper.project(foot_corner_top);
    let t_edge_start = foot_edge.project(foot_corner_top);
    let t_edge_end = foot_edge.project(foot_corner_bottom);
    let t_bottom_start = bottom.project(foot_corner_bottom);

    vec![
        Segment::arc(crown_centre, [0.0, 0.0], p1, true),
        Segment::arc(r80_centre, p1, p2, true),
        Segment::arc(r13_centre, p2, p3, true),
        Segment::Line {
            start: p3,
            end: t_side_end,
        },
        Segment::arc(head_corner, t_side_end, t_under_start, true),
        Segment::Line {
            start: t_under_start,
            end: t_under_end,
        },
        Segment::arc(r8_centre, t_under_end, t_r8_r22, false),
        Segment::arc(r22_centre, t_r8_r22, t_r22_r508, false),
        Segment::arc(r508_centre, t_r22_r508, t_r508_r16, false),
        Segment::arc(r16_centre, t_r508_r16, t_foot_start, false),
        Segment::Line {
            start: t_foot_start,
            end: t_foot_end,
        },
        Segment::arc(r20_centre, t_foot_end, t_taper_start, false),
        Segment::Line {
            start: t_taper_start,
            end: t_taper_end,
        },
        Segment::arc(foot_corner_top, t_taper_end, t_edge_start, true),
        Segment::Line {
            start: t_edge_start,
            end: t_edge_end,
        },
        Segment::arc(foot_corner_bottom, t_edge_end, t_bottom_start, true),
        Segment::Line {
            start: t_bottom_start,
            end: [0.0, -HEIGHT_MM],
        },
    ]
}

/// The whole outline as segments, counter-clockwise, starting and ending at the crown top.
pub fn outline_segments() -> Vec<Segment> {
    let left = left_half_segments();
    let mut all = left.clone();
    // Right half: mirror image traversed backwards (orientation flips twice, so arcs keep `ccw`).
    for seg in left.iter().rev() {
        all.push(match seg {
            Segment::Line { start, end } => Segment::Line {
                start: mirror(*end),
                end: mirror(*start),
            },
            Segment::Arc {
                centre,
                radius,
                start,
                end,
                ccw,
            } => Segment::Arc {
                centre: mirror(*centre),
                radius: *radius,
                start: mirror(*end),
                end: mirror(*start),
                ccw: *ccw,
            },
        });
    }
    all
}

/// Outline polyline (closed, last point not repeated), points at most `max_step_mm` apart.
pub fn outline_points(max_step_mm: f64) -> Vec<P2> {
    let mut pts = sample_chain(&outline_segments(), max_step_mm);
    pts.pop();
    pts
}

/// Height of the running surface (crown arcs and gauge-corner arcs) at lateral position `y_mm`,
/// for |y| up to the head side; `None` beyond the head.
pub fn top_surface_z_mm(y_mm: f64) -> Option<f64> {
    let segs = left_half_segments();
    let y = -y_mm.abs();
    for seg in segs.iter().take(3) {
        if let Segment::Arc {
            centre,
            radius,
            start,
            end,
            ..
        } = seg
        {
            let (y_hi, y_lo) = (start[0].max(end[0]), start[0].min(end[0]));
            if y <= y_hi + 1e-12 && y >= y_lo - 1e-12 {
                let dy = y - centre[0];
                return Some(centre[1] + (radius * radius - dy * dy).max(0.0).sqrt());
            }
        }
    }
    None
}

/// Lateral half-width of the web at height `z_mm` (on the R508 arc), for checks.
pub fn web_half_width_mm(z_mm: f64) -> f64 {
    let dz = z_mm + 82.8;
    516.0 - (508.0f64 * 508.0 - dz * dz).sqrt()
}
