//! The axis of revolution of an imported body, for labelling its modes (m, n).
//!
//! Method: the body's second moments about its volume centroid, `S = sum_i w_i (x_i - c)(x_i -
//! c)^T` with the nodal volume weights `w_i`. A body of revolution about the unit axis `a` has
//! `a` as an eigenvector of `S` and a double eigenvalue in the plane normal to it (the two
//! in-plane directions are alike). Of the three eigenvalues the axis is the one set apart: the
//! pair closest together is taken as the in-plane pair. Their relative difference is the
//! body's asymmetry, which a near-axisymmetric mesh keeps within a few per cent (the nodal
//! weights only approximate the volume's distribution); above [`ASYMMETRY_WARNING`] the labels
//! are descriptive only. A fitted axis within [`SNAP_RAD`] of a coordinate axis is snapped to it,
//! so that a mesh built along an axis is labelled about exactly that axis.
//!
//! The classifier works about the y axis (`modal::classify`); [`to_y_axis`] is the rotation
//! that takes the body's axis there, applied to the node positions and the mode shapes alike.

// Index loops mirror the tensor notation of the second moments.
#![allow(clippy::needless_range_loop)]

use nalgebra::{Matrix3, SymmetricEigen};

use crate::mesh::P3;

/// Relative difference of the two in-plane second moments above which the body is reported as
/// not near-axisymmetric. A revolved wheel mesh of 64 divisions has 1e-3 or less; 2 % is well
/// above a coarse wheel's faceting and below a body with a plainly different width and depth.
pub const ASYMMETRY_WARNING: f64 = 0.02;

/// A fitted axis is snapped to a coordinate axis within this angle (rad): 1 degree.
pub const SNAP_RAD: f64 = std::f64::consts::PI / 180.0;

/// The fitted axis of revolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisFit {
    /// Unit axis (its sign is that of its largest component, positive).
    pub axis: P3,
    /// `|s_1 - s_2| / ((s_1 + s_2) / 2)` of the two in-plane second moments.
    pub asymmetry: f64,
    /// The coordinate axis it was snapped to (0, 1, 2 for x, y, z), if any.
    pub snapped_to: Option<usize>,
}

/// The second moments `sum w (x - c)(x - c)^T` (m^5 with volume weights).
pub fn second_moments(points: &[P3], weights: &[f64], centre: P3) -> [[f64; 3]; 3] {
    let mut s = [[0.0; 3]; 3];
    for (p, &w) in points.iter().zip(weights) {
        let d = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += w * d[i] * d[j];
            }
        }
    }
    s
}

/// The axis of revolution of the body sampled by `points` with `weights` about `centre`.
pub fn fit_axis(points: &[P3], weights: &[f64], centre: P3) -> AxisFit {
    let s = second_moments(points, weights, centre);
    let eig = SymmetricEigen::new(Matrix3::from_fn(|i, j| s[i][j]));
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let value = |k: usize| eig.eigenvalues[order[k]];
    // The in-plane pair: the two closest eigenvalues; the axis is the third.
    let (axis_index, pair) = if value(1) - value(0) <= value(2) - value(1) {
        (order[2], (value(0), value(1)))
    } else {
        (order[0], (value(1), value(2)))
    };
    let mean = 0.5 * (pair.0 + pair.1);
    let asymmetry = if mean > 0.0 {
        (pair.1 - pair.0).abs() / mean
    } else {
        0.0
    };
    let v = eig.eigenvectors.column(axis_index);
    let mut axis = [v[0], v[1], v[2]];
    let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    axis = axis.map(|c| c / norm);
    let largest = (0..3)
        .max_by(|&a, &b| axis[a].abs().total_cmp(&axis[b].abs()))
        .unwrap_or(1);
    if axis[largest] < 0.0 {
        axis = axis.map(|c| -c);
    }
    let snapped_to = (axis[largest] >= SNAP_RAD.cos()).then_some(largest);
    if let Some(k) = snapped_to {
        axis = [0.0; 3];
        axis[k] = 1.0;
    }
    AxisFit {
        axis,
        asymmetry,
        snapped_to,
    }
}

/// The rotation matrix `R` with `R axis = e_y` (Rodrigues' formula about `axis x e_y`; a half
/// turn about x when `axis` is `-e_y`). `axis` must be a unit vector.
pub fn to_y_axis(axis: P3) -> [[f64; 3]; 3] {
    // k = a x y, sin = |k|, cos = a . y.
    let k = [-axis[2], 0.0, axis[0]];
    let cos = axis[1];
    let sin = (k[0] * k[0] + k[2] * k[2]).sqrt();
    if sin < 1e-15 {
        return if cos > 0.0 {
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        } else {
            [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
        };
    }
    let u = k.map(|c| c / sin);
    // R = cos I + sin [u]x + (1 - cos) u u^T.
    let cross = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]];
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = sin * cross[i][j] + (1.0 - cos) * u[i] * u[j];
        }
        r[i][i] += cos;
    }
    r
}

/// `R v`.
pub fn rotate(r: &[[f64; 3]; 3], v: P3) -> P3 {
    [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of a ring of `n` around the unit axis `axis` (radius 0.5, two layers 0.1 apart
    /// along it), with unit weights.
    fn ring(axis: P3, n: usize) -> Vec<P3> {
        // Two unit vectors normal to the axis.
        let helper = if axis[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let cross = |a: P3, b: P3| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let e1 = cross(axis, helper);
        let l = (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]).sqrt();
        let e1 = e1.map(|c| c / l);
        let e2 = cross(axis, e1);
        let mut out = Vec::new();
        for layer in [-0.05, 0.05] {
            for k in 0..n {
                let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                out.push(
                    [0, 1, 2].map(|d| 0.5 * (t.cos() * e1[d] + t.sin() * e2[d]) + layer * axis[d]),
                );
            }
        }
        out
    }

    #[test]
    fn the_axis_of_a_ring_is_found_and_snapped_to_a_coordinate_axis() {
        for (k, axis) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            let p = ring(axis, 64);
            let fit = fit_axis(&p, &vec![1.0; p.len()], [0.0; 3]);
            assert_eq!(fit.snapped_to, Some(k));
            assert_eq!(fit.axis, axis);
            // A ring of 64 equally spaced points: its in-plane moments are equal to rounding.
            assert!(fit.asymmetry < 1e-12, "{}", fit.asymmetry);
        }
    }

    #[test]
    fn an_oblique_axis_is_found_and_rotated_onto_y() {
        let a = [0.48, 0.6, 0.64];
        let p = ring(a, 48);
        let fit = fit_axis(&p, &vec![1.0; p.len()], [0.0; 3]);
        assert_eq!(fit.snapped_to, None);
        for d in 0..3 {
            assert!((fit.axis[d] - a[d]).abs() < 1e-12, "{:?}", fit.axis);
        }
        let r = to_y_axis(fit.axis);
        let y = rotate(&r, fit.axis);
        assert!((y[0]).abs() < 1e-12 && (y[1] - 1.0).abs() < 1e-12 && y[2].abs() < 1e-12);
        // R is a rotation: orthonormal rows, determinant 1.
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
                assert!((dot - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
            - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
            + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        assert!((det - 1.0).abs() < 1e-12);
        // -y goes to +y by a half turn.
        let r = to_y_axis([0.0, -1.0, 0.0]);
        assert_eq!(rotate(&r, [0.0, -1.0, 0.0]), [0.0, 1.0, 0.0]);
    }

    #[test]
    fn a_box_of_unequal_width_and_depth_is_reported_as_asymmetric() {
        // Corners of a 0.1 x 0.3 x 1.0 box: the long side is set apart, the other two differ
        // by a factor of 9 in their second moments.
        let mut p = Vec::new();
        for x in [-0.05, 0.05] {
            for y in [-0.15, 0.15] {
                for z in [-0.5, 0.5] {
                    p.push([x, y, z]);
                }
            }
        }
        let fit = fit_axis(&p, &vec![1.0; p.len()], [0.0; 3]);
        assert_eq!(fit.snapped_to, Some(2));
        // (0.15^2 - 0.05^2) / ((0.15^2 + 0.05^2) / 2) = 1.6.
        assert!((fit.asymmetry - 1.6).abs() < 1e-12, "{}", fit.asymmetry);
        assert!(fit.asymmetry > ASYMMETRY_WARNING);
    }
}
