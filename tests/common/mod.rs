//! Scenes and helpers shared by more than one test file.

// Each test file uses some of them.
#![allow(dead_code)]
use squeal::explicit::element::ElasticMaterial;
use squeal::mesh::{cuboid, Mesh};

/// Steel for the contact scenes.
pub const STEEL: ElasticMaterial = ElasticMaterial {
    density_kg_per_m3: 7850.0,
    youngs_modulus_pa: 210e9,
    poisson_ratio: 0.3,
};

/// The contact tests' scene of [`block_on_plate`]: a 0.6 x 0.2 m x 20 mm plate (30 x 10 x 1)
/// and a 50 x 50 x 20 mm block (2 x 2 x 1, material 2) resting on it at x = 0.1 m.
pub fn sliding_block_on_plate() -> (Mesh, Vec<usize>, Vec<[usize; 4]>, usize) {
    block_on_plate(
        [30, 10, 1],
        [0.6, 0.2, 0.02],
        [2, 2, 1],
        [0.05, 0.05, 0.02],
        [0.1, 0.075],
        2,
    )
}

/// A plate (`plate_divisions` elements over `plate_size_m`, material 1, its bottom at z = 0) with
/// a block (`block_divisions` over `block_size_m`, material `block_material`) resting on its top
/// with the block's corner at `block_corner_m` (x, y). Node sets "plate" and "block" are added.
/// Returns the mesh, the block's bottom nodes (contact slaves), the plate's top faces (contact
/// masters, outward) and the block's first node index.
pub fn block_on_plate(
    plate_divisions: [usize; 3],
    plate_size_m: [f64; 3],
    block_divisions: [usize; 3],
    block_size_m: [f64; 3],
    block_corner_m: [f64; 2],
    block_material: u32,
) -> (Mesh, Vec<usize>, Vec<[usize; 4]>, usize) {
    let plate = cuboid(plate_divisions, plate_size_m, 1);
    let top: std::collections::HashSet<usize> = plate.node_sets["z1"].iter().copied().collect();
    let mut block = cuboid(block_divisions, block_size_m, block_material);
    for p in &mut block.nodes {
        p[0] += block_corner_m[0];
        p[1] += block_corner_m[1];
        p[2] += plate_size_m[2];
    }
    let mut mesh = plate;
    let offset = mesh.nodes.len();
    let block_bottom: Vec<usize> = block.node_sets["z0"].iter().map(|n| n + offset).collect();
    let block_all: Vec<usize> = (offset..offset + block.nodes.len()).collect();
    mesh.append(block);
    mesh.node_sets.insert("block".into(), block_all);
    mesh.node_sets.insert("plate".into(), (0..offset).collect());
    let faces: Vec<[usize; 4]> = mesh
        .boundary_faces()
        .into_iter()
        .map(|(f, _)| f)
        .filter(|f| f.iter().all(|n| top.contains(n)))
        .collect();
    (mesh, block_bottom, faces, offset)
}

/// The plate-and-block scene of [`block_on_plate`] (plate 2 x 2 x 1 over 0.1 x 0.1 x 0.05 m,
/// block `block_divisions` over 0.1 x 0.1 x 0.02 m covering it) with the block tied to the
/// plate, its bottom nodes the slaves. Returns the mesh, the slaves, the block's first node and
/// the plate's bottom nodes (the support).
#[allow(dead_code)] // used by the engine's test files, not by every file that includes this one
pub fn tied_block_on_plate(block_divisions: [usize; 3]) -> (Mesh, Vec<usize>, usize, Vec<usize>) {
    let (mut mesh, slaves, faces, offset) = block_on_plate(
        [2, 2, 1],
        [0.1, 0.1, 0.05],
        block_divisions,
        [0.1, 0.1, 0.02],
        [0.0, 0.0],
        1,
    );
    let tie = squeal::mesh::tie::build("block_tie", &mesh.nodes, &slaves, &faces);
    assert_eq!(tie.pairs.len(), slaves.len());
    mesh.ties.push(tie);
    let base: Vec<usize> = mesh.node_sets["z0"]
        .iter()
        .copied()
        .filter(|&n| n < offset)
        .collect();
    (mesh, slaves, offset, base)
}

/// `f` run on a rayon pool of `threads` threads (the thread-count independence tests).
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// Runs the `squeal` binary with `args`, then `--out out`; panics with its stderr unless it
/// succeeds.
pub fn run_squeal(args: &[&str], out: &std::path::Path) -> std::process::Output {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// The modes a `squeal` command (`axisym` or `modes`, with `args`) writes into `out`, read
/// back from its `modes.json`.
pub fn squeal_modes(
    args: &[&str],
    out: &std::path::Path,
) -> Vec<squeal::analysis::identify::ModeRef> {
    run_squeal(args, out);
    squeal::modal::mode::read_modes_json(&out.join("modes.json")).unwrap()
}
