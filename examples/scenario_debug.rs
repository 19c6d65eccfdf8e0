fn main() -> squeal::Result<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "data/scenarios/demo.json".into());
    let sc = squeal::scenario::LoadedScenario::from_file(std::path::Path::new(&path))?;
    let t = std::time::Instant::now();
    let w = squeal::mesh::wheel::wheel_mesh(
        &sc.wheel,
        sc.scenario.tread_band.as_ref(),
        &sc.wheel_placement(),
    );
    println!("wheel {} el in {:?}", w.element_count(), t.elapsed());
    let t = std::time::Instant::now();
    let tr = squeal::mesh::track::track_mesh(&sc.track_layout());
    println!("track {} el in {:?}", tr.element_count(), t.elapsed());
    let t = std::time::Instant::now();
    let _ = w.boundary_faces();
    println!("wheel boundary faces {:?}", t.elapsed());
    Ok(())
}
