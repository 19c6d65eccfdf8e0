use squeal::geometry::wheel::WheelSpec;
fn main() {
    let spec: WheelSpec =
        squeal::input::read_json(std::path::Path::new("data/wheels/ns_intercity_920.json"))
            .unwrap();
    let sec = squeal::mesh::wheel::mesh_section(&spec, None);
    let m = &sec.body;
    for (qi, q) in m.quads.iter().enumerate() {
        let a = m.signed_area(*q);
        let mut worst = f64::INFINITY;
        for k in 0..4 {
            let p = m.nodes[q[k]];
            let b = m.nodes[q[(k + 1) % 4]];
            let c = m.nodes[q[(k + 3) % 4]];
            let cr = (b[0] - p[0]) * (c[1] - p[1]) - (b[1] - p[1]) * (c[0] - p[0]);
            worst = worst
                .min(cr / ((b[0] - p[0]).hypot(b[1] - p[1]) * (c[0] - p[0]).hypot(c[1] - p[1])));
        }
        if worst < 0.2 {
            println!(
                "quad {qi} area {a:.2} worst {worst:.3} nodes {:?}",
                q.map(|i| m.nodes[i])
            );
        }
    }
    println!("min {}", m.min_corner_cross());
}
