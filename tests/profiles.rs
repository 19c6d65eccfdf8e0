//! Profiles against the standards' published dimensions (docs/references.md, sections 1-2).
use squeal::geometry::{curve2d::polygon_properties, rail54e1, s1002};

/// Value and slope continuity at all 7 breakpoints of S1002. The published coefficients are
/// rounded to ~10 significant digits, which leaves jumps of order 1e-5 mm; docs/references.md quotes ~1e-4 (measured worst: 1.2e-4 mm at S = -35, section C|D).
#[test]
fn s1002_is_continuous_in_value_and_slope() {
    let h = 1e-6;
    for &s in &s1002::BREAKPOINTS_MM {
        let left = s1002::standard_height_mm(s - 1e-9);
        let right = s1002::standard_height_mm(s + 1e-9);
        assert!(
            (left - right).abs() < 2e-4,
            "value jump {} at S = {s}",
            left - right
        );
        let slope_left =
            (s1002::standard_height_mm(s - 1e-9) - s1002::standard_height_mm(s - 1e-9 - h)) / h;
        let slope_right =
            (s1002::standard_height_mm(s + 1e-9 + h) - s1002::standard_height_mm(s + 1e-9)) / h;
        // Slope check at 1e-3 (mm/mm): the arcs are steep near breakpoints F|E|D, so the
        // one-sided difference itself carries ~h * F'' error.
        assert!(
            (slope_left - slope_right).abs() < 2e-3,
            "slope jump {slope_left} vs {slope_right} at S = {s}"
        );
    }
}

#[test]
fn s1002_flange_dimensions_match_the_standard() {
    // EN 13715 nominal S1002: flange height 28 mm, flange thickness 32.5 mm, qR 10.8 mm.
    assert!((s1002::flange_height_mm() - 28.0).abs() < 1e-6);
    assert!(
        (s1002::flange_thickness_mm() - 32.5).abs() < 0.05,
        "Sd = {}",
        s1002::flange_thickness_mm()
    );
    assert!(
        (s1002::qr_mm() - 10.8).abs() < 0.05,
        "qR = {}",
        s1002::qr_mm()
    );
    // Tape circle at S = 0 has F = 0; the field side is the 1:15 line of section A.
    assert!(s1002::standard_height_mm(0.0).abs() < 1e-12);
    let slope = s1002::standard_height_mm(50.0) - s1002::standard_height_mm(49.0);
    assert!((slope + 1.0 / 15.0).abs() < 1e-6);
    // Section H is vertical at the flange back: F rises steeply just inside S = -70.
    let rise = s1002::standard_height_mm(-69.99) - s1002::standard_height_mm(-70.0);
    assert!(rise > 0.5, "section H must start vertical, rise {rise}");
    // Chamfer ends the 135 mm rim at S = 65.
    assert!((s1002::S_FIELD_FACE_MM - s1002::S_FLANGE_BACK_MM - 135.0).abs() < 1e-12);
}

/// Section properties of 54E1 against the EN 13674-1 catalogue within 0.5 % (the issue's
/// tolerance; the drawing's rounded coordinates alone account for ~0.1 %).
#[test]
fn rail_54e1_section_properties_match_catalogue() {
    let pts = rail54e1::outline_points(0.02);
    let (area, centroid, i_horizontal, i_vertical) = polygon_properties(&pts);
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(
        rel(area, rail54e1::CATALOGUE_AREA_MM2) < 0.005,
        "area {area}"
    );
    assert!(
        rel(i_horizontal, rail54e1::CATALOGUE_I_HORIZONTAL_MM4) < 0.005,
        "I_horizontal {i_horizontal}"
    );
    assert!(
        rel(i_vertical, rail54e1::CATALOGUE_I_VERTICAL_MM4) < 0.005,
        "I_vertical {i_vertical}"
    );
    assert!(
        centroid[0].abs() < 1e-6,
        "symmetric section, cy = {}",
        centroid[0]
    );
    eprintln!(
        "54E1: area {area:.2} mm2, I_h {i_horizontal:.4e}, I_v {i_vertical:.4e} mm4, cz {:.2} mm",
        centroid[1]
    );
    // Mass per metre with steel 7850 kg/m^3: catalogue 54.77 kg/m.
    let mass_kg_per_m = area * 1e-6 * 7850.0;
    assert!(
        (mass_kg_per_m - 54.77).abs() / 54.77 < 0.005,
        "mass {mass_kg_per_m}"
    );
}

#[test]
fn rail_54e1_main_dimensions() {
    let pts = rail54e1::outline_points(0.05);
    let y_min = pts.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
    let z_min = pts.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let z_max = pts.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    assert!((z_max - z_min - 159.0).abs() < 1e-9, "height");
    assert!((-2.0 * y_min - 140.0).abs() < 1e-9, "foot width");
    // Head width: widest point above z = -40 (head), 70 mm at the top of the side face plus
    // the 1:20 flare below it.
    let head_top =
        squeal::geometry::curve2d::sample_chain(&rail54e1::left_half_segments()[..3], 0.01);
    let head_half = head_top.iter().map(|p| -p[0]).fold(0.0, f64::max);
    assert!(
        (2.0 * head_half - 70.0).abs() < 1e-6,
        "head width {}",
        2.0 * head_half
    );
    // Web thickness 16 mm at z = -82.8.
    assert!((2.0 * rail54e1::web_half_width_mm(-82.8) - 16.0).abs() < 1e-9);
    // Outline is a simple closed curve: consecutive points close together.
    for w in pts.windows(2) {
        assert!(((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt() < 0.051);
    }
}
