fn main() -> squeal::Result<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/scenarios/demo.json".into());
    let sc = squeal::scenario::LoadedScenario::from_file(std::path::Path::new(&path))?;
    let t = std::time::Instant::now();
    let mesh = sc.model_mesh();
    println!("built in {:?}", t.elapsed());
    println!("{}", mesh.quality(6001.0).summary());
    for (k, v) in &mesh.node_sets {
        if !k.contains("_1")
            && !k.contains("_2")
            && !k.contains("_3")
            && !k.contains("_4")
            && !k.contains("_5")
            && !k.contains("_6")
            && !k.contains("_7")
            && !k.contains("_8")
            && !k.contains("_9")
        {
            println!("set {k}: {}", v.len());
        }
    }
    for (k, v) in &mesh.surfaces {
        println!("surface {k}: {}", v.len());
    }
    for t in &mesh.ties {
        println!(
            "tie {} pairs {} max gap {:.3} mm",
            t.name,
            t.pairs.len(),
            t.max_gap_m() * 1e3
        );
    }
    println!(
        "wheel centre {:?}",
        sc.wheel_placement().tape_circle_centre_m
    );
    Ok(())
}
