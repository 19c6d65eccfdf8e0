//! No input makes a reader panic: seeded random mutations (bytes changed, ranges deleted or
//! repeated, files cut short) of valid small files in every format the toolkit reads (Gmsh
//! MSH, legacy VTK, VTU, CSV, case and model JSON, wheel JSON, universal files with every
//! dataset read, ASCII and binary); each reader must return
//! a value or an error, never panic.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// Mutations per file.
const MUTATIONS: usize = 300;

use squeal::random::XorShift64 as Rng;

/// One random edit of `bytes`.
fn mutate(bytes: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let n = out.len().max(1);
    match rng.below(6) {
        0 => {
            // A byte set to anything.
            let k = rng.below(n);
            if k < out.len() {
                out[k] = rng.next_u64() as u8;
            }
        }
        1 => {
            // A digit turned into another character that often matters to a parser.
            let k = rng.below(n);
            if k < out.len() {
                let characters = b"-.e9 \n\"{}[],0x";
                out[k] = characters[rng.below(characters.len())];
            }
        }
        2 => {
            let (a, len) = (rng.below(n), 1 + rng.below(64));
            let b = (a + len).min(out.len());
            if a < b {
                out.drain(a..b);
            }
        }
        3 => {
            let (a, len) = (rng.below(n), 1 + rng.below(64));
            let b = (a + len).min(out.len());
            if a < b {
                let piece = out[a..b].to_vec();
                let at = rng.below(out.len());
                out.splice(at..at, piece);
            }
        }
        4 => out.truncate(rng.below(n)),
        _ => {
            // A number made huge or negative.
            let k = rng.below(n);
            if k < out.len() {
                out.splice(k..k, b"-99999999999".iter().copied());
            }
        }
    }
    out
}

fn fixtures(dir: &Path) -> Vec<(PathBuf, &'static str)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = squeal::mesh::cuboid([2, 1, 1], [0.2, 0.1, 0.1], 1);
    let vtu = dir.join("m.vtu");
    squeal::mesh::vtu::write(&mesh, &vtu, &[]).unwrap();
    let msh = dir.join("m.msh");
    squeal::mesh::gmsh::write(&mesh, &msh).unwrap();
    let vtk = dir.join("m.vtk");
    std::fs::write(
        &vtk,
        "# vtk DataFile Version 3.0\ntet\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n\
         0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n",
    )
    .unwrap();
    let csv = dir.join("s.csv");
    std::fs::write(
        &csv,
        "time_s,x_m\n0,0\n0.001,1\n0.002,0\n0.003,-1\n0.004,0\n",
    )
    .unwrap();
    let case = dir.join("case.json");
    std::fs::copy(root.join("data/cases/case3-ci.json"), &case).unwrap();
    let model = dir.join("model.json");
    std::fs::copy(root.join("data/models/ci-tiny.json"), &model).unwrap();
    let wheel = dir.join("wheel.json");
    std::fs::copy(root.join("data/wheels/ns_intercity_920.json"), &wheel).unwrap();
    // Every dataset the UFF reader takes, small: the fixtures' units, nodes and mode shapes, and
    // the first FRF cut to 40 points, once ASCII and once binary.
    let fixture = |name: &str| std::fs::read(root.join("tests/fixtures/uff").join(name)).unwrap();
    let mut all = Vec::new();
    for name in [
        "units164.uff",
        "nodes15.uff",
        "nodes2411.uff",
        "modes55.uff",
    ] {
        all.extend(fixture(name));
    }
    let mut frf = squeal::testdata::uff::parse_uff(&fixture("frf_binary.uff"), "frf").unwrap();
    frf.functions.truncate(1);
    if let squeal::testdata::uff::FunctionValues::Complex(v) = &mut frf.functions[0].values {
        v.truncate(40);
    }
    all.extend(squeal::testdata::uff::write::to_bytes(&frf, false).unwrap());
    all.extend(squeal::testdata::uff::write::to_bytes(&frf, true).unwrap());
    let uff = dir.join("all.uff");
    std::fs::write(&uff, all).unwrap();
    // Issue 53: records as pyuff's `sample_test` files and Simcenter Testlab write them: a
    // dataset 164 whose temperature-mode field is blank, and the dataset 55 mode shapes with
    // negative values glued in fixed E13.5 columns (no blank before a minus sign).
    let units = String::from_utf8(fixture("units164.uff"))
        .unwrap()
        .replace("Meter (newton)         2", "Meter (newton)          ");
    let mut glued55: Vec<String> = String::from_utf8(fixture("modes55.uff"))
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    for k in 1..glued55.len() {
        let node: Option<usize> = glued55[k - 1].trim().parse().ok();
        let is_values = glued55[k].contains("e+") || glued55[k].contains("e-");
        if let (Some(node @ 1..=4), true, 10) = (node, is_values, glued55[k - 1].len()) {
            glued55[k] = [-0.125 * node as f64, -2.5e-3, -1.0 / node as f64]
                .iter()
                .map(|&v| squeal::testdata::uff::fields::format_real(v, 13, 6, 'E'))
                .collect();
        }
    }
    let fixed_width = dir.join("fixed_width.uff");
    std::fs::write(&fixed_width, units + &glued55.join("\n") + "\n").unwrap();
    // Unmutated, the file is one a reader must take (so the fuzzing starts from valid input).
    let read_back = squeal::testdata::uff::read_uff(&fixed_width).unwrap();
    assert_eq!(read_back.units.unwrap().temperature_mode, 0);
    assert!(!read_back.nodal_data.is_empty());
    let uff_binary = dir.join("pyuff_binary.uff");
    std::fs::copy(
        root.join("tests/fixtures/uff/frf_binary_pyuff.uff"),
        &uff_binary,
    )
    .unwrap();
    vec![
        (uff, "uff"),
        (fixed_width, "uff"),
        (uff_binary, "uff"),
        (vtu, "vtu"),
        (msh, "msh"),
        (vtk, "vtk"),
        (csv, "csv"),
        (case, "case"),
        (model, "model"),
        (wheel, "wheel"),
    ]
}

/// Reads `path` as `kind`; only whether it panics matters.
fn read(path: &Path, kind: &str) {
    match kind {
        "vtu" | "msh" | "vtk" => {
            let _ = squeal::mesh::volume_io::read(path);
        }
        "csv" => {
            let _ = squeal::signal::TimeSeries::from_csv(path, "x_m");
            let _ = squeal::table::Table::read(path);
        }
        "uff" => {
            let _ = squeal::testdata::uff::read_uff(path);
        }
        "case" => {
            let _ = squeal::model::case::load_case(path);
        }
        "model" => {
            let _ = squeal::scenario::LoadedScenario::from_file(path);
        }
        _ => {
            if let Ok(w) = squeal::input::read_json::<squeal::input::wheel::WheelSpec>(path) {
                let _ = w.validate("fuzz");
            }
        }
    }
}

#[test]
fn mutated_inputs_never_panic_a_reader() {
    let dir = std::env::temp_dir().join(format!("squeal_fuzz_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    let mut panics = Vec::new();
    let files = fixtures(&dir);
    // Panics are caught and counted, not printed one by one.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    for (path, kind) in files {
        let original = std::fs::read(&path).unwrap();
        // The unmutated file reads without panicking too (and the model loads).
        for k in 0..MUTATIONS {
            let bytes = if k == 0 {
                original.clone()
            } else {
                mutate(&original, &mut rng)
            };
            std::fs::write(&path, &bytes).unwrap();
            if catch_unwind(AssertUnwindSafe(|| read(&path, kind))).is_err() {
                let keep = dir.join(format!("panic_{kind}_{k}"));
                let _ = std::fs::write(&keep, &bytes);
                panics.push(format!("{kind} mutation {k} (kept as {})", keep.display()));
            }
        }
        std::fs::write(&path, &original).unwrap();
    }
    std::panic::set_hook(hook);
    assert!(
        panics.is_empty(),
        "readers panicked:\n{}",
        panics.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
