//! Lines and markers cut to a chart's plotting rectangle, so that nothing is drawn outside the
//! axes: plotters moves a point beyond an axis's range onto the edge, which draws lines along
//! the edge that are not in the data (a PSD beyond the frequencies shown became a vertical line
//! at the last one).

/// The parts of the polyline `pts` inside the rectangle `x` by `y`, each a polyline of its
/// own; a segment that crosses the edge ends on it. `log_y`: the y axis is logarithmic, and
/// segments (straight on the chart) are cut in ln y.
pub fn clip_polyline(
    pts: &[(f64, f64)],
    x: (f64, f64),
    y: (f64, f64),
    log_y: bool,
) -> Vec<Vec<(f64, f64)>> {
    let (to, from) = axis_maps(log_y);
    let (lo, hi) = ((x.0, to(y.0)), (x.1, to(y.1)));
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    if let [p] = pts {
        if inside(*p, x, y) {
            runs.push(vec![*p]);
        }
    }
    for w in pts.windows(2) {
        let (p, q) = ((w[0].0, to(w[0].1)), (w[1].0, to(w[1].1)));
        let at = |t: f64| (p.0 + t * (q.0 - p.0), from(p.1 + t * (q.1 - p.1)));
        match clip_segment(p, q, lo, hi) {
            Some((t0, t1)) => {
                if run.is_empty() || t0 > 0.0 {
                    if run.len() > 1 {
                        runs.push(std::mem::take(&mut run));
                    }
                    run = vec![if t0 > 0.0 { at(t0) } else { w[0] }];
                }
                run.push(if t1 < 1.0 { at(t1) } else { w[1] });
                if t1 < 1.0 {
                    runs.push(std::mem::take(&mut run));
                }
            }
            None => {
                if run.len() > 1 {
                    runs.push(std::mem::take(&mut run));
                }
                run.clear();
            }
        }
    }
    if run.len() > 1 {
        runs.push(run);
    }
    runs
}

/// Whether a marker at `p` lies in the rectangle `x` by `y` (to a billionth of its sides).
pub fn inside(p: (f64, f64), x: (f64, f64), y: (f64, f64)) -> bool {
    let within = |v: f64, (a, b): (f64, f64)| {
        let tol = 1e-9 * (b - a).abs();
        v >= a.min(b) - tol && v <= a.max(b) + tol
    };
    within(p.0, x) && within(p.1, y)
}

/// A map of axis values.
type AxisMap = fn(f64) -> f64;

/// The y axis's map to where segments are straight, and back.
fn axis_maps(log_y: bool) -> (AxisMap, AxisMap) {
    if log_y {
        (f64::ln, f64::exp)
    } else {
        (|v| v, |v| v)
    }
}

/// Liang-Barsky: the parameters (t0, t1) in [0, 1] of the part of the segment p-q inside the
/// rectangle lo-hi, or None where no part is.
fn clip_segment(
    p: (f64, f64),
    q: (f64, f64),
    lo: (f64, f64),
    hi: (f64, f64),
) -> Option<(f64, f64)> {
    let d = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (pk, qk) in [
        (-d.0, p.0 - lo.0),
        (d.0, hi.0 - p.0),
        (-d.1, p.1 - lo.1),
        (d.1, hi.1 - p.1),
    ] {
        if pk == 0.0 {
            if qk < 0.0 {
                return None;
            }
        } else {
            let r = qk / pk;
            if pk < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

#[cfg(test)]
mod tests {
    use super::clip_polyline;

    #[test]
    fn lines_are_cut_at_the_edges_of_the_plot() {
        let pts = [(0.0, 0.0), (1.0, 1.0), (3.0, 1.0), (4.0, 0.0), (5.0, 0.5)];
        // x from 0 to 2: the line leaves at x = 2 and does not come back.
        let runs = clip_polyline(&pts, (0.0, 2.0), (0.0, 1.0), false);
        assert_eq!(runs, vec![vec![(0.0, 0.0), (1.0, 1.0), (2.0, 1.0)]]);
        // y up to 0.5: two parts, each ending on the edge.
        let runs = clip_polyline(&pts, (0.0, 5.0), (0.0, 0.5), false);
        assert_eq!(
            runs,
            vec![
                vec![(0.0, 0.0), (0.5, 0.5)],
                vec![(3.5, 0.5), (4.0, 0.0), (5.0, 0.5)]
            ]
        );
        // A log axis cuts in ln y: from 1 to 100 over x 0..2, the edge y = 10 is at x = 1.
        let runs = clip_polyline(&[(0.0, 1.0), (2.0, 100.0)], (0.0, 2.0), (0.1, 10.0), true);
        assert_eq!(runs.len(), 1);
        assert!((runs[0][1].0 - 1.0).abs() < 1e-12 && (runs[0][1].1 - 10.0).abs() < 1e-9);
        // Wholly outside: nothing.
        assert!(clip_polyline(&pts, (6.0, 7.0), (0.0, 1.0), false).is_empty());
    }
}
