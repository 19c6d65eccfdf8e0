//! Hammer-test data: the loader's error paths (file, line, column), the pairing of measured and
//! FE modes by family and indices, and the comparison chart.
use squeal::analysis::identify::{ModeFamily, ModeRef};
use squeal::report::modal_chart::write_modal_chart;
use squeal::testdata::hammer::{compare, read_hammer_csv};

/// Directory of one test (`tag` names it), unique within this process; the test removes it.
fn temp_dir(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("squeal-hammer-{tag}-{}", std::process::id()))
}

fn temp_file(tag: &str, name: &str, text: &str) -> std::path::PathBuf {
    let dir = temp_dir(tag);
    std::fs::create_dir_all(&dir).expect("dir");
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

const HEADER: &str = "family,nodal_circles,nodal_diameters,frequency_hz,damping_ratio,source\n";

#[test]
fn shipped_example_is_synthetic_and_loads() {
    let modes =
        read_hammer_csv(std::path::Path::new("data/hammer/synthetic_example.csv")).expect("load");
    assert_eq!(modes.len(), 5);
    assert!(
        modes.iter().all(|m| m.source.starts_with("synthetic")),
        "shipped data must say it is synthetic"
    );
    assert_eq!(modes[0].damping_ratio, Some(0.0005));
    assert_eq!(modes[2].damping_ratio, None);
}

#[test]
fn malformed_rows_name_file_line_and_column() {
    let cases = [
        (
            "freq.csv",
            format!("{HEADER}axial,0,3,abc,,s\n"),
            "line 2, column 4 (frequency_hz)",
        ),
        (
            "family.csv",
            format!("{HEADER}axial,0,3,1000,,s\nbending,0,2,400,,s\n"),
            "line 3, column 1 (family)",
        ),
        (
            "count.csv",
            format!("{HEADER}axial,-1,3,1000,,s\n"),
            "line 2, column 2 (nodal_circles)",
        ),
        (
            "damping.csv",
            format!("{HEADER}axial,0,3,1000,1.5,s\n"),
            "line 2, column 5 (damping_ratio)",
        ),
        (
            "source.csv",
            format!("{HEADER}axial,0,3,1000,,\n"),
            "line 2, column 6 (source)",
        ),
        (
            "header.csv",
            "family,n,m,f\naxial,0,3,1000\n".to_string(),
            "line 1",
        ),
        ("short.csv", format!("{HEADER}axial,0,3\n"), "line 2"),
        ("empty.csv", HEADER.to_string(), "no measured modes"),
    ];
    for (name, text, needle) in cases {
        let path = temp_file("malformed", name, &text);
        let e = read_hammer_csv(&path).expect_err(name);
        let msg = e.to_string();
        assert!(msg.contains(name) && msg.contains(needle), "{name}: {msg}");
        assert_eq!(e.exit_code(), 2);
    }
    let _ = std::fs::remove_dir_all(temp_dir("malformed"));
}

#[test]
fn measured_modes_pair_with_fe_modes_of_the_same_label() {
    let measured =
        read_hammer_csv(std::path::Path::new("data/hammer/synthetic_example.csv")).expect("load");
    let fe = vec![
        ModeRef {
            frequency_hz: 0.0,
            family: ModeFamily::Rigid,
            nodal_circles: 0,
            nodal_diameters: 0,
        },
        ModeRef {
            frequency_hz: 410.0,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 2,
        },
        ModeRef {
            frequency_hz: 410.5,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 2,
        },
        ModeRef {
            frequency_hz: 1080.0,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 3,
        },
        ModeRef {
            frequency_hz: 1990.0,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 4,
        },
        ModeRef {
            frequency_hz: 1720.0,
            family: ModeFamily::Radial,
            nodal_circles: 0,
            nodal_diameters: 2,
        },
        ModeRef {
            frequency_hz: 2500.0,
            family: ModeFamily::Circumferential,
            nodal_circles: 0,
            nodal_diameters: 1,
        },
    ];
    let c = compare(&measured, &fe);
    assert_eq!(c.pairs.len(), 4);
    let p = c
        .pairs
        .iter()
        .find(|p| p.measured.nodal_diameters == 3)
        .expect("(0,3)");
    assert!((p.error_percent - 100.0 * (1080.0 - 1060.0) / 1060.0).abs() < 1e-12);
    // The (0,2) pair uses the lower member of the repeated FE pair; the other member is not
    // listed as unmatched.
    let p2 = c
        .pairs
        .iter()
        .find(|p| p.measured.family == ModeFamily::Axial && p.measured.nodal_diameters == 2)
        .expect("(0,2)");
    assert_eq!(p2.fe_frequency_hz, 410.0);
    assert_eq!(
        c.unmatched_measured.len(),
        1,
        "the (1,0) axial mode has no FE partner"
    );
    assert_eq!(
        c.unmatched_fe.len(),
        1,
        "the circumferential mode has no measured partner"
    );
    assert_eq!(c.unmatched_fe[0].family, ModeFamily::Circumferential);
    let md = c.to_markdown();
    assert!(
        md.contains("| Axial | (0,3) | 1060.0 | 1080.0 | +1.89 |"),
        "{md}"
    );
    let dir = temp_dir("chart");
    write_modal_chart(
        &fe,
        Some(&measured),
        Some(&dir.join("m.png")),
        Some(&dir.join("m.svg")),
    )
    .expect("chart");
    let svg = std::fs::read_to_string(dir.join("m.svg")).expect("svg");
    assert!(svg.contains("measured") && svg.contains("FE") && svg.contains("nodal diameters"));
    let _ = std::fs::remove_dir_all(&dir);
}
