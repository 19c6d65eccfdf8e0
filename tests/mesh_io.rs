//! Mesh files read back: the VTU and Gmsh MSH 4.1 writers against our own readers (counts,
//! coordinates, connectivity, material ids, node-set fields), and the refusal to write
//! inverted meshes.
use squeal::input::wheel::WheelSpec;
use squeal::mesh::wheel::{wheel_mesh, WheelPlacement};
use squeal::mesh::{gmsh, vtu, Mesh};

fn small_wheel() -> Mesh {
    let mut spec: WheelSpec =
        squeal::input::read_json(std::path::Path::new("data/wheels/ns_intercity_920.json"))
            .expect("wheel");
    spec.mesh.element_size_mm = 25.0;
    spec.mesh.circumferential_divisions = 32;
    spec.mesh.inner_circumferential_divisions = 16;
    wheel_mesh(&spec, None, &WheelPlacement::default())
}

/// Directory of one test (`tag` names it), unique within this process; the test removes it.
fn temp_dir(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("squeal-io-{tag}-{}", std::process::id()))
}

fn temp(tag: &str, name: &str) -> std::path::PathBuf {
    let dir = temp_dir(tag);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

#[test]
fn vtu_round_trip() {
    let mesh = small_wheel();
    let path = temp("vtu", "wheel.vtu");
    let shape: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|p| [p[0], 2.0 * p[1], -p[2]])
        .collect();
    vtu::write(
        &mesh,
        &path,
        &[vtu::PointVectorField {
            name: "shape".into(),
            values: &shape,
        }],
    )
    .expect("write");
    let back = vtu::read(&path).expect("read");
    assert_eq!(back.points.len(), mesh.nodes.len());
    assert_eq!(back.cells.len(), mesh.elements.len());
    // Binary f64: bit-exact.
    assert_eq!(back.points, mesh.nodes);
    for (c, e) in back.cells.iter().zip(&mesh.elements) {
        assert_eq!(c.as_slice(), e.as_slice());
    }
    assert!(back.cell_types.iter().all(|&t| t == 12));
    let mat: Vec<u32> = back.cell_data["material"]
        .iter()
        .map(|&v| v as u32)
        .collect();
    assert_eq!(mat, mesh.material);
    for (name, ids) in &mesh.node_sets {
        let field = &back.point_data[&format!("set_{name}")];
        assert_eq!(
            field.iter().filter(|&&v| v == 1.0).count(),
            ids.len(),
            "{name}"
        );
        assert!(ids.iter().all(|&i| field[i] == 1.0));
    }
    let s = &back.point_data["shape"];
    assert_eq!(s.len(), 3 * mesh.nodes.len());
    assert_eq!(s[4], 2.0 * mesh.nodes[1][1]);
    let _ = std::fs::remove_dir_all(temp_dir("vtu"));
}

#[test]
fn gmsh_round_trip() {
    let mesh = small_wheel();
    let path = temp("gmsh", "wheel.msh");
    gmsh::write(&mesh, &path).expect("write");
    let back = gmsh::read(&path).expect("read");
    assert_eq!(back.nodes.len(), mesh.nodes.len());
    assert_eq!(back.hexahedra.len(), mesh.elements.len());
    // %.17e round-trips f64 exactly.
    assert_eq!(back.nodes, mesh.nodes);
    let mut written: Vec<[usize; 8]> = back.hexahedra.iter().map(|(c, _)| *c).collect();
    let mut original = mesh.elements.clone();
    written.sort_unstable();
    original.sort_unstable();
    assert_eq!(written, original);
    // Entity tags are the material ids; surfaces come back as quads.
    for (c, tag) in &back.hexahedra {
        let e = mesh.elements.iter().position(|x| x == c).expect("element");
        assert_eq!(*tag as u32, mesh.material[e]);
    }
    assert_eq!(
        back.quads.len(),
        mesh.surfaces.values().map(|f| f.len()).sum::<usize>()
    );
    assert!(back.physical_names.values().any(|n| n == "tread"));
    let _ = std::fs::remove_dir_all(temp_dir("gmsh"));
}

#[test]
fn writers_refuse_inverted_meshes() {
    let mut mesh = small_wheel();
    // Mirror one element's numbering: all its corner Jacobians become negative.
    let c = mesh.elements[0];
    mesh.elements[0] = [c[4], c[5], c[6], c[7], c[0], c[1], c[2], c[3]];
    let q = mesh.quality(6000.0);
    assert_eq!(q.inverted_elements, 1);
    assert_eq!(q.first_inverted_element, Some(0));
    for name in ["bad.vtu", "bad.msh"] {
        let path = temp("inverted", name);
        let _ = std::fs::remove_file(&path);
        let err = if name.ends_with("vtu") {
            vtu::write(&mesh, &path, &[])
        } else {
            gmsh::write(&mesh, &path)
        };
        let msg = err.expect_err("must refuse").to_string();
        assert!(msg.contains("non-positive corner Jacobian"), "{msg}");
        assert!(!path.exists(), "no file may be written");
    }
    let _ = std::fs::remove_dir_all(temp_dir("inverted"));
}

#[test]
fn readers_report_malformed_files() {
    let path = temp("malformed", "broken.msh");
    std::fs::write(&path, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n").expect("write");
    let msg = gmsh::read(&path).expect_err("old format").to_string();
    assert!(
        msg.contains("MSH 4.1") && msg.contains("broken.msh"),
        "{msg}"
    );
    let path = temp("malformed", "broken.vtu");
    std::fs::write(&path, "<VTKFile><UnstructuredGrid><Piece><Points><DataArray type=\"Float64\" format=\"binary\">@@@@</DataArray></Points></Piece></UnstructuredGrid></VTKFile>").expect("write");
    let msg = vtu::read(&path).expect_err("bad base64").to_string();
    assert!(msg.contains("base64"), "{msg}");
    let _ = std::fs::remove_dir_all(temp_dir("malformed"));
}
