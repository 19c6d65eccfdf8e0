//! Wheel meshes against independent references: Pappus' theorem for the revolved volume, the
//! S1002 profile for the tread nodes, positive Jacobians over many parameter combinations, and
//! the explicit time step of the tread band.
use std::f64::consts::TAU;

use squeal::geometry::curve2d::polygon_properties;
use squeal::geometry::s1002;
use squeal::input::wheel::{body_outline_mm, WebShape, WheelSpec};
use squeal::mesh::quality::dilatational_wave_speed;
use squeal::mesh::wheel::{
    band_angles, wheel_mesh, FineStripSpec, RunningArcSpec, TreadBandSpec, WheelPlacement,
};
use squeal::mesh::{material, Mesh};

fn default_wheel() -> WheelSpec {
    squeal::input::read_json(std::path::Path::new("data/wheels/ns_intercity_920.json"))
        .expect("default wheel")
}

fn wheel_only(mut spec: WheelSpec, size_mm: f64, n: usize, n_inner: usize) -> Mesh {
    spec.axle = None;
    spec.mesh.element_size_mm = size_mm;
    spec.mesh.circumferential_divisions = n;
    spec.mesh.inner_circumferential_divisions = n_inner;
    spec.validate("test").expect("valid");
    wheel_mesh(&spec, None, &WheelPlacement::default())
}

/// Pappus: V = 2 pi A r_c for the exact section. A mesh of N straight-chord sectors holds
/// V sin(dtheta)/dtheta of each revolved area element (polygon of N sides inscribed in each
/// circle), so the chord factor is taken out and what is left is the section discretisation,
/// which must shrink under refinement.
#[test]
fn revolved_volume_matches_pappus_and_converges() {
    let spec = default_wheel();
    let outline: Vec<[f64; 2]> = body_outline_mm(&spec, 0.01);
    // polygon_properties works in (horizontal, vertical) = (S, r): centroid[1] is the radius.
    let (area_mm2, centroid, _, _) = polygon_properties(&outline);
    let pappus_m3 = TAU * area_mm2 * centroid[1] * 1e-9;
    let mut errors = Vec::new();
    for (size, n) in [(16.0, 64usize), (8.0, 128), (4.0, 256)] {
        let mesh = wheel_only(spec.clone(), size, n, n);
        let dtheta = TAU / n as f64;
        let chord_factor = dtheta.sin() / dtheta;
        let v = mesh.volume();
        let err = (v / (pappus_m3 * chord_factor) - 1.0).abs();
        errors.push(err);
        eprintln!("size {size} mm, N {n}: volume {v:.6e} m^3, Pappus {pappus_m3:.6e}, section error {err:.2e}");
    }
    // The section is meshed with straight edges on a curved tread: error of order h^2 / R_curv,
    // well under 0.5 % even at 16 mm; refinement must not make it worse.
    assert!(errors[0] < 5e-3, "{errors:?}");
    assert!(
        errors[2] <= errors[0] && errors[2] < 1e-3,
        "no convergence: {errors:?}"
    );
    // Plausible wheel mass: 350-420 kg for a 920 mm passenger wheel (docs/references.md, section 3).
    let mass = pappus_m3 * spec.material.density_kg_per_m3;
    assert!((340.0..=420.0).contains(&mass), "wheel mass {mass} kg");
}

#[test]
fn tread_and_bore_nodes_lie_on_their_surfaces() {
    let spec = default_wheel();
    let mesh = wheel_mesh(&spec, None, &WheelPlacement::default());
    let tread = mesh.node_set("tread").expect("tread set");
    assert!(tread.len() > 100);
    for &i in tread {
        let [x, y, z] = mesh.nodes[i];
        let r_mm = x.hypot(z) * 1e3;
        let s_mm = y * 1e3;
        // Nodes are placed on the profile exactly (to the 0.02 mm sampling of the flange
        // polyline, whose chords deviate by < 1e-4 mm from the arcs).
        if s_mm > s1002::S_FLANGE_BACK_MM + 1e-6 {
            assert!(
                (r_mm - spec.tread_radius_mm(s_mm)).abs() < 1e-3,
                "node {i} at S {s_mm} r {r_mm}"
            );
        }
    }
    for &i in mesh.node_set("hub_bore").expect("hub bore") {
        let [x, _, z] = mesh.nodes[i];
        assert!((x.hypot(z) * 1e3 - spec.hub.bore_radius_mm).abs() < 1e-6);
    }
    // Axle ends: flat faces at the first and last axle profile stations.
    let axle = spec.axle.as_ref().expect("axle");
    for (set, s) in [
        ("axle_inner_end", axle.profile_mm[0][0]),
        (
            "axle_outer_end",
            axle.profile_mm[axle.profile_mm.len() - 1][0],
        ),
    ] {
        let ids = mesh.node_set(set).expect(set);
        assert!(!ids.is_empty());
        assert!(
            ids.iter()
                .all(|&i| (mesh.nodes[i][1] * 1e3 - s).abs() < 1e-6),
            "{set}"
        );
    }
    // The tread surface faces point outwards (away from the axis).
    for f in &mesh.surfaces["tread"] {
        let p: Vec<[f64; 3]> = f.iter().map(|&i| mesh.nodes[i]).collect();
        let n = squeal::mesh::hex::face_normal(p[0], p[1], p[2], p[3]);
        let c = [
            0.25 * (p[0][0] + p[1][0] + p[2][0] + p[3][0]),
            0.0,
            0.25 * (p[0][2] + p[1][2] + p[2][2] + p[3][2]),
        ];
        assert!(
            n[0] * c[0] + n[2] * c[2] > 0.0 || n[1].abs() > (n[0].hypot(n[2])),
            "inward tread face"
        );
    }
}

#[test]
fn every_element_is_valid_over_many_parameter_sets() {
    let base = default_wheel();
    let mut count = 0;
    for shape in [WebShape::Straight, WebShape::Curved] {
        for (size, n, n_inner) in [(20.0, 32usize, 16usize), (12.0, 96, 40), (6.0, 160, 80)] {
            for axle in [true, false] {
                let mut spec = base.clone();
                spec.web.shape = shape;
                spec.mesh.element_size_mm = size;
                spec.mesh.circumferential_divisions = n;
                spec.mesh.inner_circumferential_divisions = n_inner;
                if !axle {
                    spec.axle = None;
                }
                spec.validate("test").expect("valid");
                let mesh = wheel_mesh(&spec, None, &WheelPlacement::default());
                let q = mesh.quality(6000.0);
                assert_eq!(q.inverted_elements, 0, "{shape:?} {size} {n} axle {axle}");
                assert!(
                    q.min_scaled_jacobian > 0.2,
                    "{shape:?} {size} {n}: {}",
                    q.min_scaled_jacobian
                );
                assert!(mesh.node_sets.values().all(|s| !s.is_empty()));
                count += 1;
            }
        }
    }
    assert_eq!(count, 12);
}

/// With the fine tread band, the smallest element of the wheel is
/// the band's, so the critical time step is that of the intended contact-zone size (within
/// 20 %), even though the hub radius is ~0.2 of the tread radius.
#[test]
fn tread_band_keeps_the_time_step_of_the_contact_zone() {
    let spec = default_wheel();
    let c_l = dilatational_wave_speed(
        spec.material.youngs_modulus_pa,
        spec.material.poisson_ratio,
        spec.material.density_kg_per_m3,
    );
    for band_mm in [3.0, 2.0] {
        let band = TreadBandSpec {
            element_size_mm: band_mm,
            arc_centre_deg: 0.0,
            arc_width_deg: 30.0,
            growth_ratio: 1.15,
            running_arc: None,
            fine_strip: None,
            insert: None,
        };
        let mesh = wheel_mesh(&spec, Some(&band), &WheelPlacement::default());
        let q = mesh.quality(c_l);
        let intended = band_mm * 1e-3 / c_l;
        let ratio = q.critical_time_step_s / intended;
        eprintln!(
            "band {band_mm} mm: dt {:.1} ns vs intended {:.1} ns (ratio {ratio:.3})",
            q.critical_time_step_s * 1e9,
            intended * 1e9
        );
        assert!((0.8..=1.2).contains(&ratio), "ratio {ratio}");
        assert_eq!(
            mesh.material[q.min_characteristic_length_element],
            material::TREAD_BAND
        );
        // Every band interface node is tied, weights form a partition of unity, and the
        // geometric offsets are chord sagittas (well under a body element size).
        let tie = mesh
            .ties
            .iter()
            .find(|t| t.name == "tread_band")
            .expect("band tie");
        assert_eq!(
            tie.pairs.len(),
            mesh.node_set("band_interface").expect("set").len()
        );
        for p in &tie.pairs {
            assert!((p.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            assert!(p
                .weights
                .iter()
                .all(|&w| (-1e-12..=1.0 + 1e-12).contains(&w)));
        }
        assert!(tie.max_gap_m() < 0.5e-3, "gap {}", tie.max_gap_m());
        // Fine arc: the band's circumferential spacing at the arc centre is the band size.
        // One band column near the tape circle (columns are band_mm apart laterally).
        let tread_nodes: Vec<&[f64; 3]> = mesh
            .node_set("tread")
            .expect("tread")
            .iter()
            .map(|&i| &mesh.nodes[i])
            .collect();
        let column_y = tread_nodes
            .iter()
            .map(|p| p[1])
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .expect("tread nodes");
        let arc_nodes: Vec<&&[f64; 3]> = tread_nodes
            .iter()
            .filter(|p| (p[1] - column_y).abs() < 1e-9)
            .collect();
        let mut angles: Vec<f64> = arc_nodes
            .iter()
            .map(|p| p[0].atan2(-p[2]))
            .filter(|a| a.abs() < 0.1)
            .collect();
        angles.sort_by(|a, b| a.total_cmp(b));
        let spacing_mm = angles
            .windows(2)
            .map(|w| (w[1] - w[0]) * 460.0)
            .fold(0.0, f64::max);
        assert!(
            (spacing_mm - band_mm).abs() < 0.1 * band_mm,
            "arc spacing {spacing_mm}"
        );
    }
}

/// The tread band's circumferential spacing with a running arc: 1 mm on the fine arc, at most
/// the running size on the rest of the running arc (which straddles the bottom point, as in
/// the `paper` model), the body's spacing far away, and no jump above the growth ratio. Without
/// the running arc the same stretch is much coarser (so the checks can fail).
#[test]
fn running_arc_keeps_the_rolled_tread_at_its_medium_size() {
    let radius_mm = 460.0;
    let body_divisions = 160; // 18 mm at the tread
    let mut band = TreadBandSpec {
        element_size_mm: 1.0,
        arc_centre_deg: 66.4,
        arc_width_deg: 30.0,
        growth_ratio: 1.15,
        running_arc: None,
        fine_strip: None,
        insert: None,
    };
    let running = RunningArcSpec {
        element_size_mm: 6.0,
        arc_centre_deg: 72.5,
        arc_width_deg: 155.0,
    };
    // Spacing (mm) and mid-angle (degrees, in (-180, 180]) of every band interval.
    let intervals = |band: &TreadBandSpec| -> Vec<(f64, f64)> {
        let a = band_angles(band, radius_mm, body_divisions);
        let n = a.len();
        (0..n)
            .map(|k| {
                let (a0, a1) = (a[k], if k + 1 < n { a[k + 1] } else { a[0] + TAU });
                let mid = (0.5 * (a0 + a1)).to_degrees().rem_euclid(360.0);
                let mid = if mid > 180.0 { mid - 360.0 } else { mid };
                ((a1 - a0) * radius_mm, mid)
            })
            .collect()
    };
    let in_arc = |mid: f64, centre: f64, width: f64| (mid - centre).abs() < 0.5 * width;
    let largest_running = |iv: &[(f64, f64)]| {
        iv.iter()
            .filter(|(_, m)| in_arc(*m, running.arc_centre_deg, running.arc_width_deg))
            .map(|(h, _)| *h)
            .fold(0.0, f64::max)
    };
    let without = intervals(&band);
    assert!(largest_running(&without) > 2.5 * running.element_size_mm);
    band.running_arc = Some(running.clone());
    let with = intervals(&band);
    // The size function is exact up to the 1/n rounding of the interval count: 5 %.
    assert!(
        largest_running(&with) <= 1.05 * running.element_size_mm,
        "largest on the running arc {}",
        largest_running(&with)
    );
    for (k, (h, mid)) in with.iter().enumerate() {
        if in_arc(*mid, band.arc_centre_deg, band.arc_width_deg) {
            assert!((h - 1.0).abs() < 0.05, "fine arc spacing {h} at {mid} deg");
        }
        let next = with[(k + 1) % with.len()].0;
        assert!(
            next / h < 1.15 * 1.05 && h / next < 1.15 * 1.05,
            "jump {h} -> {next} at {mid} deg"
        );
    }
    let largest = with.iter().map(|(h, _)| *h).fold(0.0, f64::max);
    let body_mm = TAU * radius_mm / body_divisions as f64;
    assert!(
        (largest - body_mm).abs() < 0.05 * body_mm,
        "largest {largest}"
    );
}

/// The web-zone tie joins a coarse inner zone to a finer outer zone: hub elements keep a
/// circumferential size near the tread's instead of shrinking with the radius.
#[test]
fn inner_zone_keeps_hub_elements_large() {
    let spec = default_wheel();
    let mesh = wheel_mesh(&spec, None, &WheelPlacement::default());
    let tie = mesh
        .ties
        .iter()
        .find(|t| t.name == "web_zones")
        .expect("zone tie");
    assert!(!tie.pairs.is_empty());
    let bore = mesh.node_set("hub_bore").expect("bore");
    // Distinct angles around the bore: the inner zone's division count.
    let mut angles: Vec<i64> = bore
        .iter()
        .map(|&i| (mesh.nodes[i][0].atan2(-mesh.nodes[i][2]) * 1e6).round() as i64)
        .collect();
    angles.sort_unstable();
    angles.dedup();
    assert_eq!(angles.len(), spec.mesh.inner_circumferential_divisions);
}

/// A fine strip (`TreadBandSpec::fine_strip`): the band's tread nodes are the band's size apart
/// across the strip and its nodes the band's size apart under the strip's surface, down to the
/// strip's depth; away from the strip the spacing grows by at most the growth ratio (10 % for
/// the 1/n rounding of the size function) up to the body's size; the band holds far fewer
/// elements than one fine everywhere, and the time step stays that of the band's size (the
/// strip does not undercut it). A strip outside the band is refused naming the field.
#[test]
fn a_fine_strip_keeps_the_contact_path_fine_and_thins_the_band() {
    let spec = default_wheel();
    let c_l = dilatational_wave_speed(
        spec.material.youngs_modulus_pa,
        spec.material.poisson_ratio,
        spec.material.density_kg_per_m3,
    );
    let (band_mm, growth) = (2.0, 1.3);
    let uniform = TreadBandSpec {
        element_size_mm: band_mm,
        arc_centre_deg: 0.0,
        arc_width_deg: 30.0,
        growth_ratio: growth,
        running_arc: None,
        fine_strip: None,
        insert: None,
    };
    let strip_spec = FineStripSpec {
        s_min_mm: -15.0,
        s_max_mm: 15.0,
        depth_mm: 4.0,
    };
    let strip = TreadBandSpec {
        fine_strip: Some(strip_spec.clone()),
        insert: None,
        ..uniform.clone()
    };
    strip.validate("model.json", "tread_band", &spec).unwrap();
    let placement = WheelPlacement::default();
    let mesh_uniform = wheel_mesh(&spec, Some(&uniform), &placement);
    let mesh = wheel_mesh(&spec, Some(&strip), &placement);
    let band_elements = |m: &Mesh| {
        m.material
            .iter()
            .filter(|&&k| k == material::TREAD_BAND)
            .count()
    };
    let (n_uniform, n_strip) = (band_elements(&mesh_uniform), band_elements(&mesh));
    let (q_uniform, q_strip) = (mesh_uniform.quality(c_l), mesh.quality(c_l));
    println!(
        "band elements: uniform {n_uniform}, strip {n_strip}; critical step {:.1} / {:.1} ns",
        q_uniform.critical_time_step_s * 1e9,
        q_strip.critical_time_step_s * 1e9
    );
    // Measured 25 064 of 46 272 (0.54): a 30 mm strip of a band about 80 mm across and one
    // body row deep.
    assert!(
        (n_strip as f64) < 0.6 * n_uniform as f64,
        "{n_strip} of {n_uniform}"
    );
    let dt_ratio = q_strip.critical_time_step_s / q_uniform.critical_time_step_s;
    assert!(
        (0.9..=1.1).contains(&dt_ratio),
        "time step ratio {dt_ratio}"
    );
    // The band's nodes in the plane of the arc centre (x = 0, under the axle).
    let mut band_nodes = vec![false; mesh.nodes.len()];
    for (e, nodes) in mesh.elements.iter().enumerate() {
        if mesh.material[e] == material::TREAD_BAND {
            nodes.iter().for_each(|&n| band_nodes[n] = true);
        }
    }
    // Relative to the wheel centre (x, S, z), in the band's node plane nearest the bottom.
    let centre = placement.tape_circle_centre_m;
    let relative = |n: usize| [0, 1, 2].map(|d| mesh.nodes[n][d] - centre[d]);
    let angle = |p: [f64; 3]| p[0].atan2(-p[2]);
    let plane = (0..mesh.nodes.len())
        .filter(|&n| band_nodes[n])
        .map(|n| angle(relative(n)))
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap();
    let in_plane: Vec<[f64; 3]> = (0..mesh.nodes.len())
        .filter(|&n| band_nodes[n] && (angle(relative(n)) - plane).abs() < 1e-9)
        .map(|n| {
            let p = relative(n);
            // (x, S, -radius): the radius in the plane.
            [0.0, p[1], -(p[0] * p[0] + p[2] * p[2]).sqrt()]
        })
        .collect();
    assert!(
        in_plane.len() > 100,
        "{} nodes in the plane",
        in_plane.len()
    );
    // Across the tread: the top node of every column (the largest radius at that y).
    let mut columns: Vec<(f64, f64)> = Vec::new(); // (y mm, top radius mm)
    for p in &in_plane {
        let (y, r) = (p[1] * 1e3, -p[2] * 1e3);
        match columns.iter_mut().find(|c| (c.0 - y).abs() < 1e-6) {
            Some(c) => c.1 = c.1.max(r),
            None => columns.push((y, r)),
        }
    }
    columns.sort_by(|a, b| a.0.total_cmp(&b.0));
    let spacings: Vec<(f64, f64)> = columns
        .windows(2)
        .map(|w| (0.5 * (w[0].0 + w[1].0), w[1].0 - w[0].0))
        .collect();
    let body_mm = spec.mesh.element_size_mm;
    for (k, &(mid, h)) in spacings.iter().enumerate() {
        // y is S here (the default placement puts the tape circle at y = 0).
        if mid > strip_spec.s_min_mm + band_mm && mid < strip_spec.s_max_mm - band_mm {
            assert!(
                (h / band_mm - 1.0).abs() < 0.1,
                "spacing {h} mm at S = {mid} mm"
            );
        }
        assert!(h <= 1.1 * body_mm, "spacing {h} mm at S = {mid} mm");
        if let Some(&(_, next)) = spacings.get(k + 1) {
            let jump = (next / h).max(h / next);
            assert!(
                jump <= 1.1 * growth,
                "jump {h} -> {next} mm at S = {mid} mm"
            );
        }
    }
    assert!(
        spacings.iter().any(|&(_, h)| h > 2.0 * band_mm),
        "no growth"
    );
    // Down the column nearest the tape circle: the band's size to the strip's depth.
    let y0 = columns
        .iter()
        .map(|c| c.0)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap();
    let mut radii: Vec<f64> = in_plane
        .iter()
        .filter(|p| (p[1] * 1e3 - y0).abs() < 1e-6)
        .map(|p| -p[2] * 1e3)
        .collect();
    radii.sort_by(|a, b| b.total_cmp(a));
    let top = radii[0];
    for w in radii.windows(2) {
        let (depth, h) = (top - w[0], w[0] - w[1]);
        if depth + h <= strip_spec.depth_mm + 1e-6 {
            assert!(
                (h / band_mm - 1.0).abs() < 0.1,
                "radial {h} mm at depth {depth} mm"
            );
        }
    }
    assert!(radii[0] - radii[1] < radii[radii.len() - 2] - radii[radii.len() - 1]);
    // A strip beyond the band's end is refused, naming the field.
    let beyond = TreadBandSpec {
        fine_strip: Some(FineStripSpec {
            s_max_mm: 90.0,
            ..strip_spec
        }),
        ..uniform
    };
    let e = beyond
        .validate("model.json", "tread_band", &spec)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("model.json") && e.contains("tread_band.fine_strip.s_max_mm"),
        "{e}"
    );
}
