//! Cross-section properties (`squeal::fem::section_properties`) against closed forms:
//! the rectangle's torsion series (with the convergence rate), thin-walled theory for the shear
//! centre and warping constant of a channel and an I-section, invariance under a rigid motion
//! of the mesh, and the 54E1 rail against its catalogue values.

use squeal::fem::section_properties::{
    rectangle_torsion_constant, section_properties, SectionProperties,
};
use squeal::geometry::curve2d::P2;
use squeal::mesh::rail::{rail_section, RailSectionSizes};
use squeal::mesh::section::SectionMesh;

/// A structured mesh of the rectangle [y0, y1] x [z0, z1] added to `mesh`.
fn add_rectangle(mesh: &mut SectionMesh, y: [f64; 2], z: [f64; 2], n: [usize; 2]) {
    let grid: Vec<Vec<P2>> = (0..=n[0])
        .map(|i| {
            (0..=n[1])
                .map(|j| {
                    [
                        y[0] + (y[1] - y[0]) * i as f64 / n[0] as f64,
                        z[0] + (z[1] - z[0]) * j as f64 / n[1] as f64,
                    ]
                })
                .collect()
        })
        .collect();
    mesh.add_grid(&grid, 1);
}

fn rectangle(a: f64, b: f64, n: [usize; 2]) -> SectionProperties {
    let mut mesh = SectionMesh::new(1e-9);
    add_rectangle(&mut mesh, [0.0, a], [0.0, b], n);
    section_properties(&mesh).unwrap()
}

/// A channel: web of height `h` (outer) and thickness `t` along z at y in [0, t], flanges of
/// width `b` (outer) from the web towards +y; `per_t` elements across a thickness.
fn channel(h: f64, b: f64, t: f64, per_t: usize) -> SectionMesh {
    let e = t / per_t as f64;
    let count = |len: f64| (len / e).round() as usize;
    let mut mesh = SectionMesh::new(1e-9);
    add_rectangle(&mut mesh, [0.0, t], [-h / 2.0, h / 2.0], [per_t, count(h)]);
    add_rectangle(
        &mut mesh,
        [t, b],
        [h / 2.0 - t, h / 2.0],
        [count(b - t), per_t],
    );
    add_rectangle(
        &mut mesh,
        [t, b],
        [-h / 2.0, -h / 2.0 + t],
        [count(b - t), per_t],
    );
    mesh
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn rectangle_torsion_converges_to_the_series_from_above_at_second_order() {
    for (a, b) in [(1.0, 1.0), (2.0, 1.0), (5.0, 1.0)] {
        let exact = rectangle_torsion_constant(a, b);
        let mut errors = Vec::new();
        for refine in [4usize, 8, 16, 32] {
            let n = [refine * (a / b) as usize, refine];
            let p = rectangle(a, b, n);
            // Bilinear quads with 2 x 2 Gauss points integrate a rectangle's area and second
            // moments exactly: only rounding.
            assert!(rel(p.area, a * b) < 1e-12);
            assert!(rel(p.second_moment_yy, a * b.powi(3) / 12.0) < 1e-12);
            assert!(rel(p.second_moment_zz, b * a.powi(3) / 12.0) < 1e-12);
            // Symmetric: the shear centre is the centroid.
            for k in 0..2 {
                assert!((p.shear_centre[k] - p.centroid[k]).abs() < 1e-9 * a);
            }
            errors.push((p.torsion_constant - exact) / exact);
        }
        println!("{a} x {b}: J relative errors {errors:?}");
        for w in errors.windows(2) {
            // The discrete warping is too stiff: J from above.
            assert!(w[0] > 0.0 && w[1] > 0.0, "{errors:?}");
            // Second order: a halving of h divides the error by about 4 (measured 3.9-4.0).
            let ratio = w[0] / w[1];
            assert!((3.5..4.5).contains(&ratio), "ratio {ratio}, {errors:?}");
        }
        // 32 elements across: within 0.2 % (measured 0.04-0.1 %).
        assert!(errors[3] < 2e-3);
    }
}

/// Thin-walled theory for a channel with equal thicknesses (centreline dimensions h' = h - t
/// between the flanges, b' = b - t / 2 from the web): the shear centre lies outside the web at
/// `e = 3 b'^2 / (6 b' + h')` from its centreline, and `I_w = t b'^3 h'^2 (3 b' + 2 h') /
/// (12 (6 b' + h'))` (Pilkey 2002, table of thin-walled sections; Timoshenko & Gere, Theory of
/// Elastic Stability, 1961, section 5.3).
#[test]
fn channel_shear_centre_and_warping_constant_against_thin_walled_theory() {
    let (h, b) = (100.0, 50.0);
    let mut previous_error = f64::INFINITY;
    for t in [4.0, 2.0, 1.0] {
        let p = section_properties(&channel(h, b, t, 4)).unwrap();
        let (hc, bc) = (h - t, b - t / 2.0);
        let e = 3.0 * bc * bc / (6.0 * bc + hc);
        let y_s = t / 2.0 - e;
        let iw = t * bc.powi(3) * hc * hc * (3.0 * bc + 2.0 * hc) / (12.0 * (6.0 * bc + hc));
        let shear_error = (p.shear_centre[0] - y_s).abs() / e;
        let warping_error = rel(p.warping_constant, iw);
        println!(
            "t = {t}: shear centre y {:.4} (thin-walled {y_s:.4}, error {:.2} % of e), z {:.2e}; \
             I_w {:.5e} (thin-walled {iw:.5e}, {:.2} %)",
            p.shear_centre[0],
            100.0 * shear_error,
            p.shear_centre[1],
            p.warping_constant,
            100.0 * warping_error,
        );
        // Symmetric about z = 0.
        assert!(p.shear_centre[1].abs() < 1e-9 * h);
        // Thin-walled theory is exact only as t / b -> 0; its error is of order t / b (4-8 %
        // of e at t = 2-4 mm). The solid section's must fall as the walls thin and be small
        // at t / b = 1 / 50.
        assert!(shear_error < previous_error);
        previous_error = shear_error;
        if t == 1.0 {
            assert!(shear_error < 0.02, "{shear_error}");
            assert!(warping_error < 0.03, "{warping_error}");
        }
    }
}

/// A doubly symmetric I-section: the shear centre is the centroid, and thin-walled theory
/// gives `I_w = t_f b^3 h'^2 / 24` (h' between the flange centrelines: the flanges' lateral
/// bending, Timoshenko & Gere 1961, section 5.3).
#[test]
fn i_section_warping_constant_against_thin_walled_theory() {
    let (h, b, t) = (100.0, 60.0, 1.0);
    let mut mesh = SectionMesh::new(1e-9);
    let per = 4usize;
    let e = t / per as f64;
    let count = |len: f64| (len / e).round() as usize;
    add_rectangle(
        &mut mesh,
        [-t / 2.0, t / 2.0],
        [-h / 2.0 + t, h / 2.0 - t],
        [per, count(h - 2.0 * t)],
    );
    for z0 in [h / 2.0 - t, -h / 2.0] {
        add_rectangle(
            &mut mesh,
            [-b / 2.0, b / 2.0],
            [z0, z0 + t],
            [count(b), per],
        );
    }
    let p = section_properties(&mesh).unwrap();
    let hc = h - t;
    let iw = t * b.powi(3) * hc * hc / 24.0;
    println!(
        "I-section: I_w {:.5e} against {iw:.5e} ({:.2} %), shear centre {:?}",
        p.warping_constant,
        100.0 * rel(p.warping_constant, iw),
        p.shear_centre
    );
    assert!(p.shear_centre[0].abs() < 1e-9 * h && p.shear_centre[1].abs() < 1e-9 * h);
    // Thin-walled: error of order (t / h)^2 with t / b = 1 / 60; measured 0.1 %.
    assert!(rel(p.warping_constant, iw) < 0.01);
}

/// Properties of the same channel moved by a rotation and a translation: J, I_w and the
/// principal moments stay; the centroid and the shear centre move with the section. The
/// rotated section has a product moment, which the shear-centre formula must handle.
#[test]
fn a_rigid_motion_of_the_mesh_moves_the_shear_centre_with_it() {
    let base = channel(100.0, 50.0, 2.0, 2);
    let p0 = section_properties(&base).unwrap();
    let (s, c) = 0.7f64.sin_cos();
    let shift = [30.0, -12.0];
    let motion = |p: P2| {
        [
            c * p[0] - s * p[1] + shift[0],
            s * p[0] + c * p[1] + shift[1],
        ]
    };
    let mut moved = base.clone();
    moved.nodes.iter_mut().for_each(|p| *p = motion(*p));
    let p1 = section_properties(&moved).unwrap();
    assert!(p1.product_moment_yz.abs() > 0.1 * p1.second_moment_yy);
    for (a, b) in [
        (p1.area, p0.area),
        (p1.torsion_constant, p0.torsion_constant),
        (p1.warping_constant, p0.warping_constant),
        (
            p1.second_moment_yy + p1.second_moment_zz,
            p0.second_moment_yy + p0.second_moment_zz,
        ),
    ] {
        // Only rounding differs.
        assert!(rel(a, b) < 1e-9, "{a} {b}");
    }
    let expected = motion(p0.shear_centre);
    for k in 0..2 {
        assert!(
            (p1.shear_centre[k] - expected[k]).abs() < 1e-8 * 100.0,
            "{:?} {expected:?}",
            p1.shear_centre
        );
    }
}

/// The 54E1 section mesh: area and second moments against EN 13674-1, and the torsion
/// properties converged in the mesh size.
#[test]
fn rail_54e1_section_properties() {
    use squeal::geometry::rail54e1;
    let props = |h: f64| {
        section_properties(
            &rail_section(RailSectionSizes {
                running_surface_mm: h,
                body_mm: h,
                band_rows_at_least: 1,
            })
            .body,
        )
        .unwrap()
    };
    let (coarse, fine) = (props(2.0), props(1.0));
    println!(
        "54E1, 1 mm mesh: area {:.1} mm^2, centroid {:.2} mm below the crown, I_yy {:.1} cm^4, \
         I_zz {:.1} cm^4, J {:.1} cm^4 (2 mm mesh {:.1}), shear centre {:.2} mm below the crown \
         (2 mm mesh {:.2}), I_w {:.1} cm^6",
        fine.area,
        -fine.centroid[1],
        fine.second_moment_yy * 1e-4,
        fine.second_moment_zz * 1e-4,
        fine.torsion_constant * 1e-4,
        coarse.torsion_constant * 1e-4,
        -fine.shear_centre[1],
        -coarse.shear_centre[1],
        fine.warping_constant * 1e-6,
    );
    // The outline is EN 13674-1's drawing; the catalogue's figures are rounded and its drawing
    // has small radii the outline approximates: within 1 %.
    assert!(rel(fine.area, rail54e1::CATALOGUE_AREA_MM2) < 0.01);
    assert!(rel(fine.second_moment_yy, rail54e1::CATALOGUE_I_HORIZONTAL_MM4) < 0.01);
    assert!(rel(fine.second_moment_zz, rail54e1::CATALOGUE_I_VERTICAL_MM4) < 0.01);
    // Symmetric about the vertical axis (the mesh is symmetric only to its smoothing's
    // rounding of node positions).
    println!(
        "lateral offsets: centroid {:.2e} mm, shear centre {:.2e} mm",
        fine.centroid[0], fine.shear_centre[0]
    );
    assert!(fine.shear_centre[0].abs() < 0.05 && fine.centroid[0].abs() < 0.05);
    // Mesh convergence, second order: 2 mm and 1 mm within 1 %.
    assert!(rel(coarse.torsion_constant, fine.torsion_constant) < 0.01);
    assert!((coarse.shear_centre[1] - fine.shear_centre[1]).abs() < 0.5);
    // A rail's shear centre lies between the centroid and the foot (AREMA's 119 RE: 22 % of
    // the height above the base, the neutral axis at 46 %).
    assert!(fine.shear_centre[1] < fine.centroid[1]);
    assert!(fine.shear_centre[1] > -rail54e1::HEIGHT_MM);
    // The rail beam's constants (stability::rail::RailSection::UIC54) are these values,
    // rounded to the digits printed above.
    let r = squeal::stability::rail::RailSection::UIC54;
    for (constant, computed) in [
        (r.torsion_constant_m4, fine.torsion_constant * 1e-12),
        (r.warping_constant_m6, fine.warping_constant * 1e-18),
        (r.centroid_below_crown_m, -fine.centroid[1] * 1e-3),
        (r.shear_centre_below_crown_m, -fine.shear_centre[1] * 1e-3),
    ] {
        assert!(
            rel(constant, computed) < 1e-3,
            "{constant} against {computed}"
        );
    }
}
