//! Linear tetrahedra, the meshes people have: a cantilever meshed with linear tetrahedra
//! (each cube of a grid cut into six along its diagonal) against beam theory, kept linear
//! (`--element-order 1`: stiff, converging from above as the mesh is refined) and elevated to
//! straight-sided quadratic tetrahedra (the default: accurate on the coarse mesh).

use squeal::fem::Hex8Kind;
use squeal::material::Material;
use squeal::mesh::volume::{VolumeElement, VolumeMesh};
use squeal::modal::{solve, ModalOptions};
use squeal::model::modal::{mesh_model, Clamp};

const LENGTH_M: f64 = 0.4;
const SIDE_M: f64 = 0.02;

/// A beam `LENGTH_M` along x with a square `SIDE_M` section: `nx x ns x ns` cubes, each cut
/// into the six tetrahedra around its main diagonal (Kuhn's subdivision, conforming between
/// neighbouring cubes).
fn tet4_beam(nx: usize, ns: usize) -> VolumeMesh {
    let (hx, hs) = (LENGTH_M / nx as f64, SIDE_M / ns as f64);
    let id = |i: usize, j: usize, k: usize| (i * (ns + 1) + j) * (ns + 1) + k;
    let mut mesh = VolumeMesh::default();
    for i in 0..=nx {
        for j in 0..=ns {
            for k in 0..=ns {
                mesh.nodes
                    .push([i as f64 * hx, j as f64 * hs, k as f64 * hs]);
            }
        }
    }
    let permutations = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    for i in 0..nx {
        for j in 0..ns {
            for k in 0..ns {
                for p in permutations {
                    let mut corner = [i, j, k];
                    let mut tet = [id(i, j, k); 4];
                    for (step, &axis) in p.iter().enumerate() {
                        corner[axis] += 1;
                        tet[step + 1] = id(corner[0], corner[1], corner[2]);
                    }
                    let x = tet.map(|n| mesh.nodes[n]);
                    if squeal::fem::tet4::volume(&x) < 0.0 {
                        tet.swap(2, 3);
                    }
                    mesh.elements.push(VolumeElement::Tet4(tet));
                    mesh.material.push(1);
                }
            }
        }
    }
    mesh
}

fn first_frequency_hz(mesh: VolumeMesh) -> f64 {
    let clamp = Clamp::parse("x<0.0001").unwrap();
    let model = mesh_model(
        mesh,
        Material::STEEL,
        &clamp,
        Hex8Kind::Incompatible,
        Some(1),
    )
    .unwrap();
    let solution = solve(
        &model.assembled.k,
        &model.assembled.m,
        &ModalOptions {
            fmax_hz: 600.0,
            ..ModalOptions::default()
        },
    )
    .unwrap();
    solution.modes[0].frequency_hz
}

#[test]
fn linear_tet_cantilever_against_beam_theory_in_both_orders() {
    let steel = Material::STEEL;
    // Euler-Bernoulli: f1 = 1.8751² / (2 pi L²) sqrt(E I / (rho A)), I / A = h² / 12.
    let euler_bernoulli = 1.8751f64.powi(2) / (2.0 * std::f64::consts::PI * LENGTH_M.powi(2))
        * (steel.youngs_modulus_pa * SIDE_M.powi(2) / (12.0 * steel.density_kg_per_m3)).sqrt();
    // Timoshenko: shear and rotary inertia lower f1 by about lambda² (r / L)² (1 + E / (k G)) / 2
    // = 0.15 % at L / h = 20 (r² = h² / 12, k = 5/6).
    let r2 = SIDE_M.powi(2) / 12.0 / LENGTH_M.powi(2);
    let shear = 1.0 + steel.youngs_modulus_pa / (5.0 / 6.0 * steel.shear_modulus_pa());
    let timoshenko = euler_bernoulli * (1.0 - 0.5 * 1.8751f64.powi(2) * r2 * shear);
    let mut linear = Vec::new();
    for (nx, ns) in [(20, 1), (40, 2), (80, 4)] {
        let f = first_frequency_hz(tet4_beam(nx, ns));
        println!(
            "linear tets, {nx} x {ns} x {ns} cubes: f1 {f:.2} Hz ({:+.1} % against Timoshenko {timoshenko:.2} Hz)",
            100.0 * (f / timoshenko - 1.0)
        );
        linear.push(f);
    }
    let mut elevated_mesh = tet4_beam(20, 1);
    let count = elevated_mesh.elevate_linear_tets();
    assert_eq!(count, 20 * 6);
    assert!(elevated_mesh
        .elements
        .iter()
        .all(|e| matches!(e, VolumeElement::Tet10(_))));
    let quadratic = first_frequency_hz(elevated_mesh);
    println!(
        "elevated to tet10, 20 x 1 x 1 cubes: f1 {quadratic:.2} Hz ({:+.2} %)",
        100.0 * (quadratic / timoshenko - 1.0)
    );
    // Conforming elements with a consistent mass bound the eigenvalues from above, and the
    // error of the constant-strain element falls as the mesh is refined.
    for pair in linear.windows(2) {
        assert!(pair[1] < pair[0], "no convergence: {linear:?}");
    }
    assert!(linear.iter().all(|&f| f > timoshenko));
    // The coarse linear mesh locks (tens of per cent high); the elevated one bends: within 3 %
    // (the clamped end face also stops the Poisson contraction there, a slight stiffening).
    assert!(linear[0] / timoshenko - 1.0 > 0.2, "{}", linear[0]);
    assert!((quadratic / timoshenko - 1.0).abs() < 0.03, "{quadratic}");
}

/// From the command line: a VTU of linear tetrahedra is read, elevated by default (said on
/// stdout) or kept linear with `--element-order 1` (a warning on stderr), and gives the same
/// frequencies as the library above.
#[test]
fn modes_reads_linear_tets_and_states_the_element_order() {
    let dir = std::env::temp_dir().join(format!("squeal_linear_tets_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("beam.vtu");
    squeal::mesh::vtu::write_volume(&tet4_beam(20, 1), &file, &[]).unwrap();
    let run = |order: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(["modes", "--clamp", "x<0.0001", "--fmax-hz", "400", "--mesh"])
            .arg(&file)
            .args(["--element-order", order, "--out"])
            .arg(dir.join(format!("order{order}")))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let modes: Vec<squeal::analysis::identify::ModeRef> = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("order{order}/modes.json"))).unwrap(),
        )
        .unwrap();
        (
            String::from_utf8_lossy(&out.stdout).to_string(),
            String::from_utf8_lossy(&out.stderr).to_string(),
            modes[0].frequency_hz,
        )
    };
    let (stdout, _, quadratic) = run("2");
    assert!(
        stdout.contains("120 linear tetrahedra elevated"),
        "{stdout}"
    );
    let (_, stderr, linear) = run("1");
    assert!(stderr.contains("kept linear"), "{stderr}");
    // The same meshes as the library test: tet10 near 105 Hz, linear near 198 Hz.
    assert!(
        (quadratic
            - first_frequency_hz({
                let mut m = tet4_beam(20, 1);
                m.elevate_linear_tets();
                m
            }))
        .abs()
            < 1e-6 * quadratic
    );
    assert!(linear > 1.5 * quadratic);
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["modes", "--element-order", "3", "--mesh"])
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A Gmsh MSH 4.1 file of one linear tetrahedron (element type 4) reads as one tet4 of volume
/// 1/6 (before this, type 4 was skipped and the mesh came out empty).
#[test]
fn gmsh_linear_tetrahedra_are_read() {
    let dir = std::env::temp_dir().join(format!("squeal_gmsh_tet4_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("one.msh");
    std::fs::write(
        &file,
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n\
         0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n\
         $EndElements\n",
    )
    .unwrap();
    let mesh = squeal::mesh::volume_io::read(&file).unwrap();
    assert_eq!(mesh.elements.len(), 1);
    let VolumeElement::Tet4(c) = mesh.elements[0] else {
        panic!("not a tet4: {:?}", mesh.elements[0]);
    };
    let volume = squeal::fem::tet4::volume(&c.map(|n| mesh.nodes[n]));
    assert!((volume - 1.0 / 6.0).abs() < 1e-15);
    let _ = std::fs::remove_dir_all(&dir);
}
