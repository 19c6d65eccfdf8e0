//! Build the default wheel mesh and print its quality summary.
use squeal::geometry::wheel::WheelSpec;
use squeal::mesh::wheel::{wheel_mesh, TreadBandSpec, WheelPlacement};

fn main() -> squeal::Result<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/wheels/ns_intercity_920.json".into());
    let spec: WheelSpec = squeal::input::read_json(std::path::Path::new(&path))?;
    spec.validate(&path)?;
    let t = std::time::Instant::now();
    let mesh = wheel_mesh(&spec, None, &WheelPlacement::default());
    println!(
        "plain: {:?}\n{}",
        t.elapsed(),
        mesh.quality(6001.0).summary()
    );
    let band = TreadBandSpec {
        element_size_mm: 2.0,
        arc_centre_deg: 0.0,
        arc_width_deg: 20.0,
        growth_ratio: 1.15,
        running_arc: None,
    };
    let t = std::time::Instant::now();
    let mesh = wheel_mesh(&spec, Some(&band), &WheelPlacement::default());
    println!(
        "band: {:?}\n{}",
        t.elapsed(),
        mesh.quality(6001.0).summary()
    );
    println!(
        "tie pairs {} max gap {:.4} mm",
        mesh.ties[0].pairs.len(),
        mesh.ties[0].max_gap_m() * 1e3
    );
    for (k, v) in &mesh.node_sets {
        println!("set {k}: {}", v.len());
    }
    for (k, v) in &mesh.surfaces {
        println!("surface {k}: {}", v.len());
    }
    Ok(())
}
