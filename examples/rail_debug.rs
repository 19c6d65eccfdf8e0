fn main() {
    for h in [1.0, 4.0] {
        let m = &squeal::mesh::rail::rail_section(squeal::mesh::rail::RailSectionSizes {
            running_surface_mm: h,
            body_mm: 2.0 * h,
        })
        .body;
        println!(
            "h {h}: quads {} area {:.2} min cross {:.3}",
            m.quads.len(),
            m.area(),
            m.min_corner_cross()
        );
        let mut v: Vec<(f64, usize)> = m
            .quads
            .iter()
            .enumerate()
            .map(|(qi, q)| {
                let a = m.signed_area(*q);
                let emax = (0..4)
                    .map(|k| {
                        let p = m.nodes[q[k]];
                        let r = m.nodes[q[(k + 1) % 4]];
                        (p[0] - r[0]).hypot(p[1] - r[1])
                    })
                    .fold(0.0, f64::max);
                (a / emax, qi)
            })
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut parts = [0.0f64; 3];
        for q in &m.quads {
            let zc = q.iter().map(|&i| m.nodes[i][1]).sum::<f64>() / 4.0;
            let k = if zc > -52.0 {
                0
            } else if zc > -125.0 {
                1
            } else {
                2
            };
            parts[k] += m.signed_area(*q);
        }
        println!("  head/web/foot areas {:?}", parts);
        for (l, qi) in v.iter().take(4) {
            println!(
                "  L {l:.3} quad {qi} nodes {:?}",
                m.quads[*qi].map(|i| [
                    (m.nodes[i][0] * 10.0).round() / 10.0,
                    (m.nodes[i][1] * 10.0).round() / 10.0
                ])
            );
        }
    }
}
#[allow(dead_code)]
fn regions() {}
