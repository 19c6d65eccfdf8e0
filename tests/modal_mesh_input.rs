//! Modal input from general volume meshes: the tet10 element (patch, rigid modes, mass,
//! quadrature), mesh readers (Gmsh, legacy VTK, VTU) and their error paths, tet10 against hex8
//! on the same block, Matrix Market round trip and `squeal bench modal` against `squeal modes`.

use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;
use std::process::Command;

use squeal::fem::assembly::{read_matrix_market, write_matrix_market};
use squeal::fem::tet10::{self, element_matrices, rule_degree5, straight};
use squeal::fem::{
    assemble, assemble_volume, Constraints, ElasticMaterial, Hex8Kind, MassKind, Materials,
};
use squeal::mesh::cuboid;
use squeal::mesh::volume::{self, VolumeElement, VolumeMesh};
use squeal::modal::{solve, ModalOptions};

/// Directory of one test (`tag` names it), unique within this process; the test removes it.
fn tmp_dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("squeal_mesh_input_{tag}_{}", std::process::id()))
}

fn tmp(tag: &str, name: &str) -> PathBuf {
    let d = tmp_dir(tag);
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// A general (not right-angled) straight-sided tetrahedron.
fn corners() -> [[f64; 3]; 4] {
    [
        [0.1, 0.0, 0.05],
        [1.2, 0.1, 0.0],
        [0.2, 0.9, 0.1],
        [0.3, 0.2, 1.1],
    ]
}

fn tet_volume(c: &[[f64; 3]; 4]) -> f64 {
    let a = [0, 1, 2].map(|d| c[1][d] - c[0][d]);
    let b = [0, 1, 2].map(|d| c[2][d] - c[0][d]);
    let e = [0, 1, 2].map(|d| c[3][d] - c[0][d]);
    (a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0])
        + a[2] * (b[0] * e[1] - b[1] * e[0]))
        / 6.0
}

#[test]
fn degree5_rule_integrates_quintic_monomials_exactly() {
    // Reference: int over the unit simplex of L0^a L1^b L2^c L3^d = a! b! c! d! / (a+b+c+d+3)!
    let fact = |n: u32| (1..=n).map(|k| k as f64).product::<f64>();
    let rule = rule_degree5();
    assert_eq!(rule.len(), 14);
    for a in 0..=5u32 {
        for b in 0..=5 - a {
            for c in 0..=5 - a - b {
                for d in 0..=5 - a - b - c {
                    let exact = fact(a) * fact(b) * fact(c) * fact(d) / fact(a + b + c + d + 3);
                    let q: f64 = rule
                        .iter()
                        .map(|(x, w)| {
                            let l = [1.0 - x[0] - x[1] - x[2], x[0], x[1], x[2]];
                            w * l[0].powi(a as i32)
                                * l[1].powi(b as i32)
                                * l[2].powi(c as i32)
                                * l[3].powi(d as i32)
                        })
                        .sum();
                    // the tabulated points/weights have 16 digits: 1e-13 relative is rounding
                    assert!(
                        (q - exact).abs() <= 1e-13 * exact.max(1e-3),
                        "({a},{b},{c},{d}): {q} vs {exact}"
                    );
                }
            }
        }
    }
}

#[test]
fn tet10_patch_rigid_modes_and_mass() {
    let c = corners();
    let x = straight(c);
    let mat = ElasticMaterial::steel();
    let em = element_matrices(&x, &mat, false).unwrap();
    let v = tet_volume(&c);
    assert!((em.volume - v).abs() < 1e-14 * v);
    let kmax = em.k.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
    // rigid translations and rotations: K u = 0 (to round-off of the largest entry)
    for mode in 0..6 {
        let u: Vec<f64> = (0..30)
            .map(|dof| {
                let (a, comp) = (dof / 3, dof % 3);
                let p = x[a];
                if mode < 3 {
                    (comp == mode) as u8 as f64
                } else {
                    // omega x p with omega = e_(mode-3)
                    let w = mode - 3;
                    let r = [[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]];
                    r[w][comp]
                }
            })
            .collect();
        for i in 0..30 {
            let f: f64 = (0..30).map(|j| em.k[i][j] * u[j]).sum();
            assert!(f.abs() < 1e-12 * kmax, "mode {mode} dof {i}: {f}");
        }
    }
    // patch test: a linear field u = G x has constant strain; the element's strain energy
    // u^T K u / 2 must equal V eps^T D eps / 2 exactly (the 4-point rule is exact here).
    let g = [
        [1e-3, 2e-4, -3e-4],
        [5e-4, -2e-3, 1e-4],
        [-1e-4, 3e-4, 1.5e-3],
    ];
    let u: Vec<f64> = (0..30)
        .map(|dof| {
            let (a, comp) = (dof / 3, dof % 3);
            (0..3).map(|k| g[comp][k] * x[a][k]).sum()
        })
        .collect();
    let eps = [
        g[0][0],
        g[1][1],
        g[2][2],
        g[0][1] + g[1][0],
        g[1][2] + g[2][1],
        g[2][0] + g[0][2],
    ];
    let d = mat.d_matrix();
    let exact: f64 = (0..6)
        .map(|i| (0..6).map(|j| eps[i] * d[i][j] * eps[j]).sum::<f64>())
        .sum::<f64>()
        * v;
    let fem: f64 = (0..30)
        .map(|i| (0..30).map(|j| u[i] * em.k[i][j] * u[j]).sum::<f64>())
        .sum();
    // exact integration: round-off only (30x30 sums of O(1) terms)
    assert!((fem - exact).abs() < 1e-10 * exact, "{fem} vs {exact}");
    // consistent mass: total translational mass rho V; HRZ lumped: rho V, corners rho V / 36,
    // mid-edge nodes 4 rho V / 27 (closed form for a straight tet10, see the module docs)
    let m = mat.density_kg_per_m3 * v;
    let total: f64 = (0..10)
        .flat_map(|a| (0..10).map(move |b| (a, b)))
        .map(|(a, b)| em.m[3 * a][3 * b])
        .sum();
    assert!((total - m).abs() < 1e-12 * m);
    let lm = element_matrices(&x, &mat, true).unwrap();
    for a in 0..10 {
        let want = if a < 4 { m / 36.0 } else { 4.0 * m / 27.0 };
        assert!((lm.m[3 * a][3 * a] - want).abs() < 1e-12 * m, "node {a}");
    }
    // an inverted element is refused
    let mut bad = c;
    bad.swap(1, 2);
    assert!(element_matrices(&straight(bad), &mat, false).is_none());
}

/// Structured tet10 mesh of a box: each hex of an n-grid split into 6 tetrahedra around its
/// 0-6 diagonal, mid-edge nodes shared.
fn tet10_box(n: [usize; 3], size: [f64; 3]) -> VolumeMesh {
    let hex = cuboid(n, size, 1);
    let mut nodes = hex.nodes.clone();
    let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
    let mut elements = Vec::new();
    for c in &hex.elements {
        for t in [
            [0, 1, 2, 6],
            [0, 2, 3, 6],
            [0, 3, 7, 6],
            [0, 7, 4, 6],
            [0, 4, 5, 6],
            [0, 5, 1, 6],
        ] {
            let mut k = t.map(|i| c[i]);
            if tet_volume(&k.map(|i| nodes[i])) < 0.0 {
                k.swap(1, 2);
            }
            let mut conn = [0usize; 10];
            conn[..4].copy_from_slice(&k);
            for (e, &[i, j]) in tet10::EDGES.iter().enumerate() {
                let key = (k[i].min(k[j]), k[i].max(k[j]));
                let id = *mid.entry(key).or_insert_with(|| {
                    let p = [0, 1, 2].map(|d| 0.5 * (nodes[key.0][d] + nodes[key.1][d]));
                    nodes.push(p);
                    nodes.len() - 1
                });
                conn[4 + e] = id;
            }
            elements.push(VolumeElement::Tet10(conn));
        }
    }
    VolumeMesh {
        nodes,
        material: vec![1; elements.len()],
        elements,
        node_sets: BTreeMap::new(),
    }
}

fn steel() -> Materials {
    [(1, ElasticMaterial::steel())].into_iter().collect()
}

fn flexible(
    k: &faer::sparse::SparseColMat<usize, f64>,
    m: &faer::sparse::SparseColMat<usize, f64>,
    fmax: f64,
) -> Vec<f64> {
    let sol = solve(
        k,
        m,
        &ModalOptions {
            fmax_hz: fmax,
            rigid_below_hz: 1.0,
            // The mode just below fmax reaches only ~1e-8..1e-7 relative residual on these
            // blocks (seen at 9, 11 and 12 kHz bands); a Rayleigh-quotient frequency with
            // residual r is accurate to O(r²), far below the 1 % compared here.
            residual_tolerance: 1e-6,
            ..Default::default()
        },
    )
    .unwrap();
    sol.modes
        .iter()
        .filter(|m| !m.rigid)
        .map(|m| m.frequency_hz)
        .collect()
}

#[test]
fn tet10_and_hex8_agree_on_a_free_block() {
    // Free-free steel block 0.5 x 0.3 x 0.2 m: first ten flexible modes (~3-9 kHz).
    let size = [0.5, 0.3, 0.2];
    let fmax = 9_000.0;
    let tet = tet10_box([10, 6, 4], size);
    let a = assemble_volume(
        &tet,
        &steel(),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let ft = flexible(&a.k, &a.m, fmax);
    // hex8 at two sizes, Richardson-extrapolated (full-integration hex8 is over-stiff, error
    // O(h²) from bending/shear locking): f_ext = f_h/2 + (f_h/2 - f_h) / 3
    let hc = assemble(
        &cuboid([10, 6, 4], size, 1),
        &steel(),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let fc = flexible(&hc.k, &hc.m, fmax * 1.2);
    let hf = assemble(
        &cuboid([20, 12, 8], size, 1),
        &steel(),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let ff = flexible(&hf.k, &hf.m, fmax);
    assert!(
        ft.len() >= 10 && fc.len() >= 10 && ff.len() >= 10,
        "{ft:?} {fc:?} {ff:?}"
    );
    for i in 0..10 {
        let ext = ff[i] + (ff[i] - fc[i]) / 3.0;
        eprintln!(
            "mode {i}: tet10 {:.2} hex8 coarse {:.2} fine {:.2} extrapolated {:.2}  tet10/fine-1 {:.4} tet10/ext-1 {:.4}",
            ft[i], fc[i], ff[i], ext, ft[i] / ff[i] - 1.0, ft[i] / ext - 1.0
        );
        // The issue's criterion, 1 %: tet10 against hex8 converged by Richardson extrapolation
        // (hex8 at h = 25 mm is still 0.2-1.2 % stiff here, locking in bending; tet10 and the
        // extrapolation agree to 0.3 %).
        assert!(
            (ft[i] / ext - 1.0).abs() < 0.01,
            "mode {i}: tet10 {} hex8 extrapolated {ext}",
            ft[i]
        );
        // and directly against the fine hex8 mesh: within its own O(h²) error, 2 %, and below it
        // (hex8 converges from above)
        assert!(
            ft[i] < ff[i] && ft[i] / ff[i] > 0.98,
            "mode {i}: tet10 {} hex8 {}",
            ft[i],
            ff[i]
        );
    }
}

fn write(path: &PathBuf, text: &str) {
    std::fs::write(path, text).unwrap();
}

/// One straight tet10 in VTK order as text rows.
fn tet_points() -> Vec<[f64; 3]> {
    straight(corners()).to_vec()
}

#[test]
fn readers_agree_and_convert_gmsh_order() {
    let p = tet_points();
    let v = tet_volume(&corners());
    // legacy VTK
    let mut vtk = String::from(
        "# vtk DataFile Version 3.0\ntest\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 11 double\n",
    );
    for q in &p {
        vtk.push_str(&format!("{} {} {}\n", q[0], q[1], q[2]));
    }
    vtk.push_str("9 9 9\n"); // an unused point: dropped on reading
    vtk.push_str("CELLS 2 14\n10 0 1 2 3 4 5 6 7 8 9\n2 0 1\nCELL_TYPES 2\n24\n3\nCELL_DATA 2\nSCALARS material int 1\nLOOKUP_TABLE default\n7 7\n");
    let fv = tmp("readers", "one.vtk");
    write(&fv, &vtk);
    let m = squeal::mesh::volume_io::read(&fv).unwrap();
    assert_eq!(m.nodes.len(), 10);
    assert_eq!(m.elements.len(), 1);
    assert_eq!(m.material, vec![7]);
    // straight tet volume: the degree-5 rule is exact (round-off)
    assert!((squeal::fem::measure::volume(&m) - v).abs() < 1e-13);
    // VTU ascii
    let pts: String = p
        .iter()
        .map(|q| format!("{} {} {} ", q[0], q[1], q[2]))
        .collect();
    let vtu = format!(
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="10" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">{pts}</DataArray></Points>
<Cells>
<DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3 4 5 6 7 8 9</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">10</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">24</DataArray>
</Cells></Piece></UnstructuredGrid></VTKFile>
"#
    );
    let fu = tmp("readers", "one.vtu");
    write(&fu, &vtu);
    let mu = squeal::mesh::volume_io::read(&fu).unwrap();
    assert_eq!(mu.elements, m.elements);
    assert_eq!(mu.nodes, m.nodes);
    // Gmsh 4.1: node tags 1..10; element lists Gmsh order, i.e. nodes 8 and 9 swapped
    let mut msh =
        String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n3 5 0 10\n");
    for i in 1..=10 {
        msh.push_str(&format!("{i}\n"));
    }
    for q in &p {
        msh.push_str(&format!("{} {} {}\n", q[0], q[1], q[2]));
    }
    msh.push_str("$EndNodes\n$Elements\n1 1 1 1\n3 5 11 1\n1 1 2 3 4 5 6 7 8 10 9\n$EndElements\n");
    let fg = tmp("readers", "one.msh");
    write(&fg, &msh);
    let mg = squeal::mesh::volume_io::read(&fg).unwrap();
    assert_eq!(
        mg.elements, m.elements,
        "Gmsh 2-3/1-3 edge nodes must be swapped"
    );
    assert_eq!(mg.material, vec![5]);
    // the converted VTK node 8 lies on edge 1-3, node 9 on edge 2-3
    if let VolumeElement::Tet10(c) = &mg.elements[0] {
        let mid =
            |i: usize, j: usize| [0, 1, 2].map(|d| 0.5 * (mg.nodes[c[i]][d] + mg.nodes[c[j]][d]));
        assert_eq!(mg.nodes[c[8]], mid(1, 3));
        assert_eq!(mg.nodes[c[9]], mid(2, 3));
    }
    // box selection
    let conds = volume::parse_box_expression("x<0.5, z <= 0.6 & r>0").unwrap();
    assert_eq!(conds.len(), 3);
    assert!(volume::parse_box_expression("q<1").is_err());
    assert!(volume::parse_box_expression("x=1").is_err());
    assert!(volume::parse_box_expression("x<abc").is_err());
    assert!(volume::parse_box_expression("").is_err());
    let _ = std::fs::remove_dir_all(tmp_dir("readers"));
}

fn read_err(name: &str, text: &str) -> String {
    let f = tmp("errors", name);
    write(&f, text);
    let e = squeal::mesh::volume_io::read(&f).expect_err("must fail");
    assert_eq!(e.exit_code(), 2, "{e}");
    e.to_string()
}

#[test]
fn reader_errors_name_file_line_and_problem() {
    let head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 float\n0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1\n";
    // truncated
    let e = read_err("trunc.vtk", &format!("{head}CELLS 1 9\n8 0 1 2 3"));
    assert!(e.contains("trunc.vtk") && e.contains("end of file"), "{e}");
    // unknown cell type (13 = wedge)
    let e = read_err(
        "wedge.vtk",
        &format!("{head}CELLS 1 7\n6 0 1 2 4 5 6\nCELL_TYPES 1\n13\n"),
    );
    assert!(e.contains("cell type 13"), "{e}");
    // index out of range, with the line
    let e = read_err(
        "range.vtk",
        &format!("{head}CELLS 1 9\n8 0 1 2 3 4 5 6 8\nCELL_TYPES 1\n12\n"),
    );
    assert!(e.contains("line 8") && e.contains("out of range"), "{e}");
    // binary legacy
    let e = read_err("bin.vtk", "# vtk DataFile Version 3.0\nt\nBINARY\n");
    assert!(e.contains("save the file as ASCII"), "{e}");
    // vtu: index out of range, appended data
    let e = read_err(
        "range.vtu",
        r#"<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece>
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3 4 5 6 7 8 12</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">10</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">24</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>"#,
    );
    assert!(
        e.contains("refers to point 4") || e.contains("out of range"),
        "{e}"
    );
    let e = read_err(
        "app.vtu",
        r#"<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece>
<Points><DataArray type="Float64" NumberOfComponents="3" format="appended" offset="0"></DataArray></Points></Piece></UnstructuredGrid></VTKFile>"#,
    );
    assert!(e.contains("appended"), "{e}");
    // gmsh truncated, unknown node
    let e = read_err(
        "t.msh",
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n3 1 0 2\n1\n",
    );
    assert!(e.contains("t.msh") && e.contains("end of file"), "{e}");
    let e = read_err("u.xyz", "");
    assert!(e.contains("extension"), "{e}");
    let _ = std::fs::remove_dir_all(tmp_dir("errors"));
}

#[test]
fn matrix_market_round_trip_is_exact() {
    let a = assemble(
        &cuboid([3, 2, 2], [0.3, 0.2, 0.2], 1),
        &steel(),
        &Constraints {
            clamped_sets: vec!["x0".into()],
            ties: false,
        },
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    for (mat, name) in [(&a.k, "K.mtx"), (&a.m, "M.mtx")] {
        let f = tmp("mtx", name);
        write_matrix_market(mat, &f).unwrap();
        let b = read_matrix_market(&f).unwrap();
        // 17 significant digits round-trip every f64 exactly
        assert_eq!(b.symbolic().col_ptr(), mat.symbolic().col_ptr());
        assert_eq!(b.symbolic().row_idx(), mat.symbolic().row_idx());
        assert_eq!(b.val(), mat.val());
    }
    let f = tmp("mtx", "bad.mtx");
    write(
        &f,
        "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1.0\n3 1 2.0\n",
    );
    let e = read_matrix_market(&f).unwrap_err().to_string();
    assert!(e.contains("bad.mtx") && e.contains("line 4"), "{e}");
    write(
        &f,
        "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1.0\n2 1 2.0\n",
    );
    let e = read_matrix_market(&f).unwrap_err().to_string();
    assert!(e.contains("truncated"), "{e}");
    let _ = std::fs::remove_dir_all(tmp_dir("mtx"));
}

#[test]
fn bench_modal_matches_modes_on_exported_wheel_and_mesh_cli_runs() {
    let out = tmp("bench", "wheel");
    let mtx = tmp("bench", "mtx");
    let st = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "modes",
            "--wheel",
            "data/wheels/ns_intercity_920.json",
            "--element-size-mm",
            "40",
            "--fmax-hz",
            "1200",
            "--out",
        ])
        .arg(&out)
        .arg("--export-mtx")
        .arg(&mtx)
        .status()
        .unwrap();
    assert!(st.success());
    let bench = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["bench", "modal", "--fmax-hz", "1200", "--mtx"])
        .arg(&mtx)
        .output()
        .unwrap();
    assert!(bench.status.success());
    // An impossible block size or slice count is refused, naming the option and its range,
    // exit code 2.
    for (option, value, range) in [("--block-size", "0", "1..=64"), ("--slices", "0", "1..=32")] {
        let refused = Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(["bench", "modal", option, value, "--mtx"])
            .arg(&mtx)
            .output()
            .unwrap();
        let message = String::from_utf8_lossy(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "{message}");
        assert!(
            message.contains(option) && message.contains(range),
            "{message}"
        );
    }
    let text = String::from_utf8_lossy(&bench.stdout);
    let freqs: Vec<f64> = text
        .lines()
        .filter_map(|l| l.split("frequency_hz=").nth(1))
        .map(|r| r.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    let last = text.lines().last().unwrap();
    assert!(
        last.starts_with("seconds=") && last.ends_with(&format!("modes={}", freqs.len())),
        "{last}"
    );
    let detail: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("modes_detail.json")).unwrap())
            .unwrap();
    let records = detail.as_array().unwrap();
    let members: usize = records
        .iter()
        .map(|r| r["members"].as_array().unwrap().len())
        .sum();
    assert_eq!(members, freqs.len());
    for r in records {
        if r["rigid"].as_bool().unwrap() {
            continue;
        }
        let ms: Vec<usize> = r["members"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as usize)
            .collect();
        let f = ms.iter().map(|&k| freqs[k]).sum::<f64>() / ms.len() as f64;
        let g = r["frequency_hz"].as_f64().unwrap();
        // same matrices (exact round trip) and solver: only the order of parallel reductions
        // differs, far below 1e-9 relative
        assert!((f - g).abs() < 1e-9 * g, "{f} vs {g}");
    }
    // --mesh with a tet10 block clamped at one end: runs, writes the files; bad clamp is exit 2
    let tet = tet10_box([4, 2, 2], [0.4, 0.1, 0.1]);
    let vf = tmp("bench", "block.vtu");
    squeal::mesh::vtu::write_volume(&tet, &vf, &[]).unwrap();
    let mout = tmp("bench", "block_out");
    let st = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["modes", "--fmax-hz", "3000", "--clamp", "x<0.001", "--mesh"])
        .arg(&vf)
        .arg("--out")
        .arg(&mout)
        .status()
        .unwrap();
    assert!(st.success());
    for f in ["modes.json", "modes.csv", "modes.vtu"] {
        assert!(mout.join(f).exists(), "{f}");
    }
    let back = squeal::mesh::vtu::read(&mout.join("modes.vtu")).unwrap();
    assert_eq!(back.cell_types, vec![24; tet.elements.len()]);
    let csv = std::fs::read_to_string(mout.join("modes.csv")).unwrap();
    // clamped-free steel bar 0.4 x 0.1 x 0.1: first bending, Euler-Bernoulli
    // 1.875² / (2 pi L²) sqrt(E I / (rho A)) = 522 Hz; at L/h = 4 shear deformation and rotary
    // inertia (Timoshenko) lower it by several %, the coarse mesh raises it slightly: 15 %
    let f1: f64 = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    assert!((f1 / 522.0 - 1.0).abs() < 0.15, "{f1}");
    for bad in ["x<<1", "w<1", "x<1,,", "hub-bore"] {
        let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(["modes", "--clamp", bad, "--mesh"])
            .arg(&vf)
            .arg("--out")
            .arg(&mout)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains("--clamp"),
            "{bad}"
        );
    }
    let _ = std::fs::remove_dir_all(tmp_dir("bench"));
}

/// The (family, nodal circles, nodal diameters) and frequency of every flexible mode in a
/// `modes` output folder.
fn labels(dir: &std::path::Path) -> Vec<(String, u64, u64, f64)> {
    let modes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("modes.json")).unwrap()).unwrap();
    modes
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["family"] != "rigid")
        .map(|m| {
            (
                m["family"].as_str().unwrap().to_string(),
                m["nodal_circles"].as_u64().unwrap(),
                m["nodal_diameters"].as_u64().unwrap(),
                m["frequency_hz"].as_f64().unwrap(),
            )
        })
        .collect()
}

/// Issue 53, item 16: a body whose axis of revolution is x is labelled as the same body along
/// y. The wheel revolved in 16 hex27 sectors (no tied zones, so the exported mesh is the
/// model), read back and turned a quarter turn about z (its axis y onto x): `modes --mesh`
/// fits the axis and gives the unturned mesh's labels at its frequencies; with `--axis y` the
/// turned wheel gets other labels (the old behaviour: labels like (0,23)).
#[test]
fn a_mesh_turned_onto_the_x_axis_keeps_its_mode_labels() {
    let run = |args: &[&str], out: &std::path::Path| -> String {
        let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(args)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr)
    };
    let wheel = tmp("axis", "wheel");
    run(
        &[
            "modes",
            "--wheel",
            "data/wheels/ns_intercity_920.json",
            "--element-size-mm",
            "40",
            "--revolved-sectors",
            "16",
            "--fmax-hz",
            "1500",
        ],
        &wheel,
    );
    let mut mesh = squeal::mesh::volume_io::read(&wheel.join("modes.vtu")).unwrap();
    let straight = tmp("axis", "straight.vtu");
    squeal::mesh::vtu::write_volume(&mesh, &straight, &[]).unwrap();
    // A quarter turn about z: (x, y, z) -> (y, -x, z) takes the y axis onto x.
    for p in mesh.nodes.iter_mut() {
        *p = [p[1], -p[0], p[2]];
    }
    let turned = tmp("axis", "turned.vtu");
    squeal::mesh::vtu::write_volume(&mesh, &turned, &[]).unwrap();
    let (a, b, c) = (tmp("axis", "a"), tmp("axis", "b"), tmp("axis", "c"));
    let said_a = run(
        &[
            "modes",
            "--fmax-hz",
            "1500",
            "--mesh",
            straight.to_str().unwrap(),
        ],
        &a,
    );
    let said_b = run(
        &[
            "modes",
            "--fmax-hz",
            "1500",
            "--mesh",
            turned.to_str().unwrap(),
        ],
        &b,
    );
    run(
        &[
            "modes",
            "--fmax-hz",
            "1500",
            "--axis",
            "y",
            "--mesh",
            turned.to_str().unwrap(),
        ],
        &c,
    );
    assert!(
        said_a.contains("about the y axis") && said_b.contains("about the x axis"),
        "{said_b}"
    );
    assert!(!said_b.contains("not near-axisymmetric"), "{said_b}");
    let (la, lb, lc) = (labels(&a), labels(&b), labels(&c));
    assert!(la.len() >= 6, "{la:?}");
    assert_eq!(la.len(), lb.len());
    for (x, y) in la.iter().zip(&lb) {
        assert_eq!((&x.0, x.1, x.2), (&y.0, y.1, y.2), "{x:?} against {y:?}");
        // The same matrices up to the order of the coordinates: 1e-6 relative.
        assert!((x.3 / y.3 - 1.0).abs() < 1e-6, "{x:?} against {y:?}");
    }
    assert!(
        la.iter()
            .zip(&lc)
            .any(|(x, y)| (&x.0, x.1, x.2) != (&y.0, y.1, y.2)),
        "labelled about the wrong axis, the turned wheel kept every label"
    );
    // A wheel file's axis is y: --axis is refused with --wheel.
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "modes",
            "--wheel",
            "data/wheels/ns_intercity_920.json",
            "--axis",
            "x",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--axis"));
}
