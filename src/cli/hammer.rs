//! `--hammer FILE` of `squeal modes` and `squeal axisym`: a hammer-test CSV (labelled modes,
//! data/hammer/) or a universal file (FRFs analysed by LSCF, or mode shapes), compared with the
//! FE modes and written into the output folder.

use std::fmt::Write as _;
use std::path::Path;

use squeal::mesh::P3;
use squeal::modal::mode::ModeRef;
use squeal::report::ema_charts::{write_mac_chart, write_stabilisation_chart};
use squeal::testdata::ema::fe_comparison::compare_with_fe;
use squeal::testdata::ema::pairing::FeShape;
use squeal::testdata::ema::uff_modes::{
    nearest_node, sample_fe_shape, test_from_uff, DEFAULT_MAX_ORDER,
};
use squeal::testdata::hammer::{compare, read_hammer_csv, MeasuredMode};
use squeal::{Error, Result};

/// FE mode shapes on the mesh: node positions (m) and, per FE mode (same order as the refs),
/// the displacement of every node of each member (two for a doublet).
pub struct FeShapesOnMesh<'a> {
    /// Mesh node coordinates (m).
    pub nodes_m: &'a [P3],
    /// `members[j]`: the shapes of FE mode j.
    pub members: Vec<Vec<&'a [P3]>>,
}

/// Whether `path` is a universal file (by its extension).
pub fn is_universal_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "uff" | "unv"))
}

/// Compares the hammer test at `path` with the FE modes `refs` (and their shapes when given),
/// writes the comparison into `dir` and returns the measured modes for the modal chart.
pub fn compare_hammer(
    path: &Path,
    refs: &[ModeRef],
    shapes: Option<&FeShapesOnMesh>,
    fmax_hz: f64,
    dir: &Path,
) -> Result<Vec<MeasuredMode>> {
    let write = |name: &str, text: &str| -> Result<()> {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
    };
    if !is_universal_file(path) {
        let measured = read_hammer_csv(path)?;
        let cmp = compare(&measured, refs);
        write("comparison.md", &cmp.to_markdown())?;
        write("comparison.csv", &cmp.to_csv())?;
        println!("{}", cmp.to_markdown());
        return Ok(measured);
    }
    let name = path.display().to_string();
    let file = squeal::testdata::uff::read_uff(path)?;
    let test = test_from_uff(&file, &name, fmax_hz, DEFAULT_MAX_ORDER)?;
    println!(
        "{name}: {} test modes ({}) at {} DOFs",
        test.modes.len(),
        if test.estimate.is_some() {
            "LSCF on its FRFs"
        } else {
            "its datasets 55"
        },
        test.dofs.len()
    );
    // FE shapes at the test DOFs, when the file places every DOF's node.
    let sampled: Option<Vec<FeShape>> = match (shapes, &test.dof_positions_m) {
        (Some(fe), Some(positions)) => {
            let farthest = positions
                .iter()
                .map(|p| nearest_node(fe.nodes_m, *p).1)
                .fold(0.0, f64::max);
            println!(
                "test points mapped to the nearest mesh nodes (farthest {:.1} mm away)",
                farthest * 1e3
            );
            Some(
                fe.members
                    .iter()
                    .map(|members| {
                        members
                            .iter()
                            .map(|shape| sample_fe_shape(fe.nodes_m, shape, &test.dofs, positions))
                            .collect()
                    })
                    .collect(),
            )
        }
        (Some(_), None) => {
            println!(
                "the file does not give every test node's coordinates (datasets 15 / 2411): \
                 modes paired by frequency only"
            );
            None
        }
        (None, _) => {
            println!("no FE shapes here: modes paired by frequency only");
            None
        }
    };
    let cmp = compare_with_fe(&test, &name, refs, sampled.as_deref());
    write("comparison.md", &cmp.table.to_markdown())?;
    write("comparison.csv", &cmp.table.to_csv())?;
    println!("{}", cmp.table.to_markdown());
    let mut csv = String::from(
        "test_mode,test_frequency_hz,damping_ratio,method,fe_mode,fe_frequency_hz,error_percent,mac\n",
    );
    for p in &cmp.pairs {
        let t = &test.modes[p.test_index];
        let _ = writeln!(
            csv,
            "{},{:.6},{:.6e},{},{},{:.6},{:.4},{}",
            p.test_index + 1,
            t.frequency_hz,
            t.damping_ratio,
            t.method.name(),
            p.fe_index + 1,
            p.fe_frequency_hz,
            p.error_percent,
            p.mac.map_or(String::new(), |m| format!("{m:.6}"))
        );
    }
    write("test_pairs.csv", &csv)?;
    if let Some(mac) = &cmp.mac {
        let mut text = String::from("test_mode");
        for j in 0..refs.len() {
            let _ = write!(text, ",fe_{}", j + 1);
        }
        text.push('\n');
        for (i, row) in mac.iter().enumerate() {
            let _ = write!(text, "{}", i + 1);
            for v in row {
                let _ = write!(text, ",{v:.6}");
            }
            text.push('\n');
        }
        write("mac.csv", &text)?;
        let test_f: Vec<f64> = test.modes.iter().map(|m| m.frequency_hz).collect();
        let fe_f: Vec<f64> = refs.iter().map(|m| m.frequency_hz).collect();
        write_mac_chart(
            mac,
            &test_f,
            &fe_f,
            Some(&dir.join("mac.png")),
            Some(&dir.join("mac.svg")),
        )?;
    }
    if let (Some(estimate), Some(set)) = (&test.estimate, &test.frf) {
        let max = estimate.orders.last().copied().unwrap_or(2);
        write_stabilisation_chart(
            &estimate.diagram,
            max,
            &estimate.modes,
            &set.frequency_hz,
            &set.mean_magnitude(),
            Some(&dir.join("stabilisation.png")),
            Some(&dir.join("stabilisation.svg")),
        )?;
    }
    Ok(cmp.measured)
}
