//! Mesh generation throughput: `cargo bench --bench mesh`.
//! Builds the `paper` scenario (1 mm tread arc and rail zone) and a ~1-million-element variant
//! of it (wider fine arc and longer fine rail zone), prints elements per second.
//! Target: a 1-million-element wheel + track mesh in under 10 s on the
//! 2-core reference machine.
use squeal::scenario::LoadedScenario;

fn build(label: &str, loaded: &LoadedScenario) {
    let mut best = f64::INFINITY;
    let mut elements = 0;
    for _ in 0..3 {
        let t = std::time::Instant::now();
        let mesh = loaded.model_mesh();
        best = best.min(t.elapsed().as_secs_f64());
        elements = mesh.element_count();
    }
    println!(
        "{label}: {elements} elements, best of 3: {best:.2} s, {:.0} elements/s (threads: {})",
        elements as f64 / best,
        rayon::current_num_threads()
    );
}

fn main() {
    let paper = LoadedScenario::from_file(std::path::Path::new("data/models/paper.json"))
        .expect("paper scenario");
    build("paper", &paper);
    let mut big = paper.clone();
    if let Some(band) = big.scenario.tread_band.as_mut() {
        band.arc_width_deg = 120.0;
    }
    big.scenario.track.solution_zone.length_m = 0.9;
    big.validate().expect("valid variant");
    build("paper, 120-degree arc, 0.9 m zone", &big);
}
