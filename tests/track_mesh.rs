//! Track meshes: the extruded 54E1 rail against its catalogue section, the 1:40 inclination,
//! graded spacing, sleepers and the named node sets for pads and ballast.
use squeal::geometry::rail54e1;
use squeal::mesh::track::{rail_stations, sleeper_positions, track_mesh, RailZone, TrackLayout};
use squeal::mesh::{material, Mesh};
use squeal::scenario::LoadedScenario;

fn medium_layout() -> TrackLayout {
    LoadedScenario::from_file(std::path::Path::new("data/models/medium.json"))
        .expect("medium")
        .track_layout()
}

fn rail_volume(mesh: &Mesh) -> f64 {
    let v = mesh.volume_by_material();
    v[&material::RAIL] + v.get(&material::RAIL_BAND).copied().unwrap_or(0.0)
}

#[test]
fn rail_volume_is_section_area_times_length() {
    let mut layout = medium_layout();
    layout.length_m = 2.0;
    layout.solution_zone_start_m = 0.5;
    layout.solution_zone_length_m = 0.2;
    layout.first_sleeper_x_m = 0.3;
    let mut errors = Vec::new();
    for (rs, body) in [(6.0, 12.0), (3.0, 6.0), (1.5, 3.0)] {
        layout.running_surface_element_mm = rs;
        layout.section_element_mm = body;
        let mesh = track_mesh(&layout);
        let area_mm2 = rail_volume(&mesh) / layout.length_m * 1e6;
        let err = (area_mm2 - rail54e1::CATALOGUE_AREA_MM2).abs() / rail54e1::CATALOGUE_AREA_MM2;
        eprintln!("rail section {rs}/{body} mm: meshed area {area_mm2:.1} mm^2, error {err:.2e}");
        // Straight element edges on the convex arcs lose sagitta-sized slivers: < 1.5 % at the
        // coarsest setting (12 mm body: ~15 mm chords on the R13 gauge corner and the foot
        // fillets), shrinking with h.
        assert!(err < 1.5e-2, "area {area_mm2}");
        errors.push(err);
        let q = mesh.quality(6000.0);
        assert_eq!(q.inverted_elements, 0);
        assert!(
            q.min_scaled_jacobian > 0.2,
            "min scaled Jacobian {}",
            q.min_scaled_jacobian
        );
    }
    assert!(
        errors[2] < errors[0] && errors[2] < 2e-3,
        "no convergence: {errors:?}"
    );
}

#[test]
fn rail_is_inclined_one_in_forty_and_sets_are_where_they_belong() {
    let layout = medium_layout();
    let mesh = track_mesh(&layout);
    // The running surface nodes lie on the inclined crown: undo the rotation and compare with
    // the section's top surface.
    let (s, c) = rail54e1::INCLINATION_RAD.sin_cos();
    let running = mesh
        .node_set("rail_running_surface")
        .expect("running surface");
    assert!(!running.is_empty());
    let mut on_crown = 0;
    for &i in running {
        let [_, y, z] = mesh.nodes[i];
        let (ys, zs) = ((y * c + z * s) * 1e3, (-y * s + z * c) * 1e3);
        if let Some(zt) = rail54e1::top_surface_z_mm(ys) {
            // Tolerance: nodes sit on the 0.01 mm sampled outline.
            assert!(
                (zs - zt).abs() < 1e-3 || ys.abs() > 34.0,
                "node {i}: z {zs} vs crown {zt} at y {ys}"
            );
            on_crown += 1;
        }
    }
    assert!(on_crown > 100);
    // Foot bottom after rotation is tilted by 1:40: its lateral ends differ in height by
    // 140 mm / 40.
    let foot = mesh.node_set("rail_foot_bottom").expect("foot");
    let (mut lo, mut hi) = ((f64::INFINITY, 0.0), (f64::NEG_INFINITY, 0.0));
    for &i in foot {
        let [_, y, z] = mesh.nodes[i];
        if y < lo.0 {
            lo = (y, z);
        }
        if y > hi.0 {
            hi = (y, z);
        }
    }
    let slope = (hi.1 - lo.1) / (hi.0 - lo.0);
    assert!((slope - 1.0 / 40.0).abs() < 1e-3, "foot slope {slope}");
    // Rail ends at x = 0 and x = L.
    for &i in mesh.node_set("rail_end_start").expect("start") {
        assert_eq!(mesh.nodes[i][0], 0.0);
    }
    for &i in mesh.node_set("rail_end_finish").expect("finish") {
        assert!((mesh.nodes[i][0] - layout.length_m).abs() < 1e-12);
    }
    // One sleeper block of 2 x 3 x 2 = 12 elements per position, with pads over it.
    let sleepers = sleeper_positions(&layout);
    assert_eq!(sleepers.len(), 16);
    assert_eq!(
        mesh.material
            .iter()
            .filter(|&&m| m == material::SLEEPER)
            .count(),
        12 * sleepers.len()
    );
    for (k, &x) in sleepers.iter().enumerate() {
        let pad = mesh.node_set(&format!("rail_pad_{k}")).expect("pad");
        assert!(pad.len() >= 2, "pad {k} empty");
        assert!(pad
            .iter()
            .all(|&i| (mesh.nodes[i][0] - x).abs() <= 0.075 + 1e-12));
        let top = mesh.node_set(&format!("sleeper_top_{k}")).expect("top");
        let bottom = mesh
            .node_set(&format!("sleeper_bottom_{k}"))
            .expect("bottom");
        let z_top = mesh.nodes[top[0]][2];
        let z_bottom = mesh.nodes[bottom[0]][2];
        assert!((z_top - z_bottom - layout.sleeper_height_m).abs() < 1e-12);
        // Pad gap: sleeper top one pad thickness below the lowest rail foot node.
        let foot_min = foot
            .iter()
            .map(|&i| mesh.nodes[i][2])
            .fold(f64::INFINITY, f64::min);
        assert!((foot_min - z_top - layout.pad_thickness_m).abs() < 1e-12);
    }
    assert!(!mesh.surfaces["rail_top"].is_empty());
}

#[test]
fn stations_are_fine_in_the_solution_zone_and_graded_outside() {
    let layout = medium_layout();
    let x = rail_stations(&layout);
    let zone = (
        layout.solution_zone_start_m,
        layout.solution_zone_start_m + layout.solution_zone_length_m,
    );
    let mut max_ratio: f64 = 1.0;
    for w in x.windows(3) {
        let (a, b) = (w[1] - w[0], w[2] - w[1]);
        max_ratio = max_ratio.max(a / b).max(b / a);
        let mid = 0.5 * (w[0] + w[1]);
        if mid > zone.0 && mid < zone.1 {
            // The size function is exact inside the zone up to the 1/n rounding of the count.
            assert!(
                (a - layout.zone_element_length_m).abs() < 0.05 * layout.zone_element_length_m,
                "zone spacing {a}"
            );
        }
        assert!(
            a <= layout.far_element_length_m.min(0.5 * layout.pad_length_m) * 1.05,
            "spacing {a}"
        );
    }
    // Neighbouring elements differ by at most the growth ratio (plus rounding).
    assert!(
        max_ratio < layout.growth_ratio * 1.05,
        "max ratio {max_ratio}"
    );
    assert_eq!(x[0], 0.0);
    assert_eq!(*x.last().expect("stations"), layout.length_m);
}

/// A solution zone inside a medium running zone: the zone keeps its size, the running zone is
/// no coarser than its size, neighbours still differ by at most the growth ratio, and without
/// the running zone the same stretch is much coarser (so the checks can fail).
#[test]
fn stations_keep_the_running_zone_at_its_medium_size() {
    let mut layout = medium_layout();
    layout.solution_zone_start_m = 3.0;
    layout.solution_zone_length_m = 0.15;
    layout.zone_element_length_m = 1e-3;
    let running = RailZone {
        start_m: 2.4,
        length_m: 1.3,
        element_length_m: 6e-3,
    };
    let inside = |x: f64, a: f64, b: f64| x > a && x < b;
    let running_end = running.start_m + running.length_m;
    let zone_end = layout.solution_zone_start_m + layout.solution_zone_length_m;
    let largest_in_running = |x: &[f64]| {
        x.windows(2)
            .filter(|w| inside(0.5 * (w[0] + w[1]), running.start_m, running_end))
            .map(|w| w[1] - w[0])
            .fold(0.0, f64::max)
    };
    let without = rail_stations(&layout);
    assert!(
        largest_in_running(&without) > 5.0 * running.element_length_m,
        "without the running zone the stretch should be coarse: {}",
        largest_in_running(&without)
    );
    layout.running_zone = Some(running);
    let x = rail_stations(&layout);
    // The size function is exact up to the 1/n rounding of the interval count: 5 %.
    assert!(largest_in_running(&x) <= 1.05 * running.element_length_m);
    let mut max_ratio: f64 = 1.0;
    for w in x.windows(3) {
        let (a, b) = (w[1] - w[0], w[2] - w[1]);
        max_ratio = max_ratio.max(a / b).max(b / a);
        if inside(0.5 * (w[0] + w[1]), layout.solution_zone_start_m, zone_end) {
            assert!((a - 1e-3).abs() < 0.05e-3, "zone spacing {a}");
        }
    }
    assert!(max_ratio < layout.growth_ratio * 1.05, "ratio {max_ratio}");
    // Away from both zones the rail still grows to its far size.
    let largest = x.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    assert!(largest > 0.9 * layout.far_element_length_m.min(0.5 * layout.pad_length_m));
}

#[test]
fn model_mesh_places_the_wheel_on_the_rail() {
    let loaded =
        LoadedScenario::from_file(std::path::Path::new("data/models/medium.json")).expect("medium");
    let mesh = loaded.model_mesh();
    assert_eq!(mesh.quality(6000.0).inverted_elements, 0);
    // Closest wheel tread node to the rail is at the initial gap (0 mm): the lowest tread node
    // above the rail head (|y| < 30 mm; the flange hangs lower, beside the head) near
    // x = x_wheel sits on the crown, to within the sagitta and lateral spacing of the band
    // nodes (< 1 mm), and none lies below it.
    let xw = loaded.scenario.wheel_position.x_m;
    let tread = mesh.node_set("wheel_tread").expect("tread");
    let layout = loaded.track_layout();
    let rail_top_at = |y: f64| -> Option<f64> {
        // Section coordinate whose inclined image lies at lateral position y (one fixed-point
        // correction suffices: the inclination is 1:40 and the crown is within 3 mm of z = 0).
        let mut ys = y * 1e3;
        for _ in 0..3 {
            let zt = rail54e1::top_surface_z_mm(ys)?;
            let [yp, _] = squeal::mesh::track::place_rail_point(&layout, ys, zt);
            ys += (y - yp) * 1e3;
        }
        let zt = rail54e1::top_surface_z_mm(ys)?;
        Some(squeal::mesh::track::place_rail_point(&layout, ys, zt)[1])
    };
    let mut min_gap = f64::INFINITY;
    let zc = loaded.wheel_placement().tape_circle_centre_m[2];
    for p in tread
        .iter()
        .map(|&i| mesh.nodes[i])
        .filter(|p| (p[0] - xw).abs() < 0.02 && p[1].abs() < 0.03)
    {
        // Height the node would have at the bottom of the wheel (same radius, angle 0).
        let bottom_z = zc - (p[0] - xw).hypot(p[2] - zc);
        if let Some(zr) = rail_top_at(p[1]) {
            min_gap = min_gap.min(bottom_z - zr);
        }
    }
    // Band nodes 4 mm apart laterally on a conformal tread: the closest one is within a few
    // hundredths of a mm of the exact contact point's height; none penetrates.
    assert!((-1e-6..0.2e-3).contains(&min_gap), "min gap {min_gap} m");
    for name in ["wheel_tread", "rail_top"] {
        assert!(!mesh.surfaces[name].is_empty(), "{name}");
    }
}

/// With a running band (running surface finer than the section body), the rail's smallest
/// element is a band element of the intended size: the explicit time step is set by the contact
/// zone (within 20 %), not by the head's O-grid core.
#[test]
fn running_band_keeps_the_time_step_of_the_contact_zone() {
    let mut layout = medium_layout();
    layout.length_m = 1.2;
    layout.first_sleeper_x_m = 0.3;
    layout.solution_zone_start_m = 0.5;
    layout.solution_zone_length_m = 0.15;
    for (fine, body) in [(2.0, 6.0), (1.0, 4.0)] {
        layout.running_surface_element_mm = fine;
        layout.section_element_mm = body;
        layout.zone_element_length_m = fine * 1e-3;
        let mesh = track_mesh(&layout);
        let q = mesh.quality(6000.0);
        let ratio = q.min_characteristic_length_m / (fine * 1e-3);
        eprintln!(
            "running surface {fine} mm / body {body} mm: smallest {:.3} mm (ratio {ratio:.2})",
            q.min_characteristic_length_m * 1e3
        );
        assert!((0.8..=1.2).contains(&ratio), "ratio {ratio}");
        let tie = mesh
            .ties
            .iter()
            .find(|t| t.name == "rail_running_band")
            .expect("tie");
        assert!(!tie.pairs.is_empty());
        // The band's interface lies on the body's interface faces (offsets are chord sagittas).
        assert!(tie.max_gap_m() < 0.1e-3, "gap {}", tie.max_gap_m());
        for p in &tie.pairs {
            assert!((p.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }
}
