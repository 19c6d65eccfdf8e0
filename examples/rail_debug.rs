fn main() {
    for h in [1.0, 4.0] {
        let m = squeal::mesh::rail::rail_section(squeal::mesh::rail::RailSectionSizes {
            running_surface_mm: h,
            body_mm: 2.0 * h,
        });
        println!(
            "h {h}: quads {} area {:.2} min cross {:.3}",
            m.quads.len(),
            m.area(),
            m.min_corner_cross()
        );
        for (qi, q) in m.quads.iter().enumerate() {
            let mut worst = f64::INFINITY;
            for k in 0..4 {
                let p = m.nodes[q[k]];
                let b = m.nodes[q[(k + 1) % 4]];
                let c = m.nodes[q[(k + 3) % 4]];
                let cr = (b[0] - p[0]) * (c[1] - p[1]) - (b[1] - p[1]) * (c[0] - p[0]);
                worst = worst.min(
                    cr / ((b[0] - p[0]).hypot(b[1] - p[1]) * (c[0] - p[0]).hypot(c[1] - p[1])),
                );
            }
            if worst < 0.15 {
                println!(
                    "  quad {qi} worst {worst:.3} nodes {:?}",
                    q.map(|i| [
                        (m.nodes[i][0] * 10.0).round() / 10.0,
                        (m.nodes[i][1] * 10.0).round() / 10.0
                    ])
                );
            }
        }
    }
}
