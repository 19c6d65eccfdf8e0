//! The model stage's rolling description of the tiny case against the case file it came from:
//! the supports carry exactly the case's totals, every pad joins a rail-foot node to a sleeper
//! top of its own sleeper, the sprung mass sits over the axle box at its static compression,
//! and the engine built from the description has the same nodes, springs and mass.

use std::path::Path;

use squeal::model::rolling::{describe, G_M_PER_S2};
use squeal::rolling::{build, load_case};

#[test]
fn rolling_description_carries_the_case_totals() {
    let loaded = load_case(Path::new("data/cases/case3-ci.json")).unwrap();
    let case = &loaded.case;
    let d = describe(&loaded).unwrap();
    let sleepers = d
        .mesh
        .node_sets
        .keys()
        .filter(|k| k.starts_with("sleeper_top_"))
        .count();
    assert!(sleepers > 0);
    let ground: Vec<_> = d
        .track_springs
        .iter()
        .filter(|s| s.node_b.is_none())
        .collect();
    let pads: Vec<_> = d
        .track_springs
        .iter()
        .filter(|s| s.node_b.is_some())
        .collect();
    // Shares of a total add back to the total up to rounding of a few hundred terms (1e-12).
    let ballast_total: f64 = ground.iter().map(|s| s.stiffness_n_per_m[2]).sum();
    let expected = sleepers as f64 * case.ballast.stiffness_n_per_m;
    assert!((ballast_total - expected).abs() <= 1e-12 * expected);
    assert!(ground
        .iter()
        .all(|s| s.stiffness_n_per_m[0] == 0.0 && s.stiffness_n_per_m[1] == 0.0));
    let pad_total: f64 = pads.iter().map(|s| s.stiffness_n_per_m[2]).sum();
    let expected = sleepers as f64 * case.rail_pad.stiffness_n_per_m;
    assert!((pad_total - expected).abs() <= 1e-12 * expected);
    for s in &pads {
        let k: usize = s.name.trim_start_matches("rail_pad_").parse().unwrap();
        let foot = d.mesh.node_set(&format!("rail_pad_{k}")).unwrap();
        let tops = d.mesh.node_set(&format!("sleeper_top_{k}")).unwrap();
        assert!(foot.contains(&s.node_a));
        assert!(tops.contains(&s.node_b.unwrap()));
        let shear = s.stiffness_n_per_m[0] / s.stiffness_n_per_m[2];
        assert!((shear - case.rail_pad.shear_fraction).abs() < 1e-12);
    }
    let sm = &d.sprung_mass;
    let b = d.mesh.nodes[sm.axle_box_node];
    assert!(d
        .mesh
        .node_set("axle_outer_end")
        .unwrap()
        .contains(&sm.axle_box_node));
    assert_eq!([sm.position_m[0], sm.position_m[1]], [b[0], b[1]]);
    let compression = case.sprung_mass_kg * G_M_PER_S2 / case.primary_suspension.stiffness_n_per_m;
    assert!((sm.static_compression_m - compression).abs() <= 1e-15);
    let ends = d.mesh.node_set(&d.axle.node_set).unwrap();
    let inner = d.mesh.node_set("axle_inner_end").unwrap().len();
    let outer = d.mesh.node_set("axle_outer_end").unwrap().len();
    assert_eq!(ends.len(), inner + outer);
    assert!(d.rim_and_hub.rim_nodes.contains(&d.rim_and_hub.rim_node));

    // The engine model built from the description: one extra node (the sprung mass), the
    // track springs plus the suspension, and the wheelset mass in the static load.
    let built = build(&loaded).unwrap();
    let model = &built.solver.model;
    assert_eq!(model.node_count(), d.mesh.nodes.len() + 1);
    assert_eq!(model.springs.len(), d.track_springs.len() + 1);
    assert_eq!(built.sprung_node, d.mesh.nodes.len());
    let wheelset_kg: f64 = d
        .wheelset_nodes
        .iter()
        .map(|&n| model.nodal_mass_kg[n])
        .sum();
    let load = (wheelset_kg + case.sprung_mass_kg) * G_M_PER_S2;
    assert!((built.info.static_wheel_load_n - load).abs() <= 1e-9 * load);
}
