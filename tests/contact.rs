//! Penalty contact with friction against independent references: a block sliding on a fixed
//! plate decelerates at mu g with a friction force mu N (Coulomb), follows mu(v) with falling
//! friction, never exceeds the traction bound, and a pressed block carries its load.
use std::collections::BTreeMap;

use squeal::contact::{ContactPair, FrictionLaw, SlipSpeed};
use squeal::explicit::element::{ElasticMaterial, Formulation};
use squeal::explicit::model::Model;
use squeal::explicit::preload::{relax, PreloadOptions};
use squeal::explicit::{AuxForces, Curve, Solver};
use squeal::mesh::{Mesh, P3};

mod common;

use common::STEEL;
const G: f64 = 9.81;

fn bulk_modulus() -> f64 {
    STEEL.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * STEEL.poisson_ratio))
}

struct Setup {
    solver: Solver,
    pair: ContactPair,
    block: Vec<usize>,
    mass_kg: f64,
}

/// The block's bottom nodes against the plate's top faces, steel's bulk modulus.
fn steel_pair(
    mesh: &Mesh,
    slaves: Vec<usize>,
    faces: Vec<[usize; 4]>,
    penalty_scale: f64,
    friction: FrictionLaw,
) -> ContactPair {
    ContactPair::new(
        "block_on_plate",
        mesh,
        slaves,
        faces,
        penalty_scale,
        bulk_modulus(),
        friction,
    )
    .unwrap()
}

fn setup(friction: FrictionLaw, load_n: f64) -> Setup {
    let (mesh, slaves, faces, _) = common::sliding_block_on_plate();
    let pair = steel_pair(&mesh, slaves, faces, 0.1, friction);
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, STEEL), (2, STEEL)].into_iter().collect();
    let mut model = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
    model.gravity_m_per_s2 = [0.0, 0.0, -G];
    model.fix_set("plate", [true, true, true]).unwrap();
    if load_n > 0.0 {
        model
            .add_load("z1", [0.0, 0.0, 0.0], Curve::constant(0.0))
            .unwrap();
        let top_block: Vec<usize> = model
            .node_set("z1")
            .unwrap()
            .into_iter()
            .filter(|n| model.node_set("block").unwrap().contains(n))
            .collect();
        model.mesh.node_sets.insert("block_top".into(), top_block);
        model
            .add_load("block_top", [0.0, 0.0, -load_n], Curve::constant(1.0))
            .unwrap();
    }
    let block = model.node_set("block").unwrap();
    let mass_kg: f64 = block.iter().map(|&n| model.nodal_mass_kg[n]).sum();
    let bound = pair.time_step_bound_s(&model.nodal_mass_kg);
    model.register_time_step_bound("contact", bound);
    let solver = Solver::new(model, None).unwrap();
    Setup {
        solver,
        pair,
        block,
        mass_kg,
    }
}

fn block_velocity_x(s: &Solver, block: &[usize]) -> f64 {
    block.iter().map(|&n| s.v[n][0]).sum::<f64>() / block.len() as f64
}

/// Coulomb, mu = 0.3: after settling, a push to 1 m/s; the block decelerates at mu g and the
/// friction force is mu N; the tangential force never exceeds mu |f_N| at any node and step.
#[test]
fn sliding_block_decelerates_at_mu_g() {
    let mu = 0.3;
    let mut st = setup(FrictionLaw::Coulomb { mu }, 0.0);
    relax(&mut st.solver, &mut st.pair, contact_preload()).unwrap();
    let weight = st.mass_kg * G;
    let (normal, _, _) = st.pair.resultants();
    // Static: the contact carries the weight within 1 %.
    assert!(
        (normal[2] / weight - 1.0).abs() < 0.01,
        "normal {} vs weight {weight}",
        normal[2]
    );
    for &n in &st.block {
        st.solver.v[n][0] = 1.0;
    }
    let v0 = block_velocity_x(&st.solver, &st.block);
    let t_end = 0.1;
    let t0 = st.solver.time_s;
    // Time integrals of the friction and normal forces: the block chatters on its stiff
    // penalty springs (steps with no node in contact), so the ratio of the integrals is the
    // measured mean friction coefficient.
    let (mut friction_impulse, mut normal_impulse) = (0.0, 0.0);
    while st.solver.time_s - t0 < t_end {
        st.solver.step_with(&mut st.pair, false, false).unwrap();
        for s in &st.pair.state {
            if s.active {
                let ft = s
                    .tangential_force_n
                    .iter()
                    .map(|c| c * c)
                    .sum::<f64>()
                    .sqrt();
                assert!(
                    ft <= s.mu * s.normal_force_n * (1.0 + 1e-12),
                    "tangential force above the bound"
                );
            }
        }
        let (n, t, _) = st.pair.resultants();
        if st.solver.time_s - t0 > 0.01 {
            friction_impulse += -t[0];
            normal_impulse += n[2];
        }
    }
    let v1 = block_velocity_x(&st.solver, &st.block);
    let decel = (v0 - v1) / (st.solver.time_s - t0);
    // 2 %: the block rocks slightly on its penalty springs while it slides.
    assert!(
        (decel / (mu * G) - 1.0).abs() < 0.02,
        "deceleration {decel} vs mu g {}",
        mu * G
    );
    let mean_ratio = friction_impulse / normal_impulse;
    assert!(
        (mean_ratio / mu - 1.0).abs() < 0.01,
        "friction force / normal force {mean_ratio}"
    );
}

/// Falling friction (mu_s 0.5, mu_d 0.32, c 6 s/m): while the block slows down from 1 m/s the
/// measured force ratio follows mu(v) at the block's slip speed.
/// The same with the law read at the patch's sliding velocity (`SlipSpeed::Patch`): the block
/// slides as a whole, so the two must agree.
#[test]
fn falling_friction_follows_mu_of_v() {
    for slip_speed in [SlipSpeed::Node, SlipSpeed::Patch] {
        falling_friction_follows_mu_of_v_with(slip_speed);
    }
}

fn falling_friction_follows_mu_of_v_with(slip_speed: SlipSpeed) {
    let law = FrictionLaw::Falling {
        mu_static: 0.5,
        mu_dynamic: 0.32,
        decay_s_per_m: 6.0,
    };
    let mut st = setup(law, 0.0);
    st.pair.slip_speed = slip_speed;
    relax(&mut st.solver, &mut st.pair, contact_preload()).unwrap();
    for &n in &st.block {
        st.solver.v[n][0] = 1.0;
    }
    let t0 = st.solver.time_s;
    let mut checked = 0;
    let mut k = 0u64;
    while st.solver.time_s - t0 < 0.15 {
        st.solver.step_with(&mut st.pair, false, false).unwrap();
        k += 1;
        let (n, t, _) = st.pair.resultants();
        if st.solver.time_s - t0 > 0.01 && k.is_multiple_of(500) && n[2] > 0.0 {
            let v = block_velocity_x(&st.solver, &st.block);
            let expected = law.mu(v);
            let measured = -t[0] / n[2];
            // 2 %: node slip speeds differ slightly from the block's mean velocity as it rocks.
            assert!(
                (measured / expected - 1.0).abs() < 0.02,
                "{slip_speed:?}, v {v}: {measured} vs mu(v) {expected}"
            );
            checked += 1;
        }
    }
    assert!(checked > 5);
    // The law itself: mu(0) = mu_s, mu(inf) = mu_d.
    assert!((law.mu(0.0) - 0.5).abs() < 1e-15 && (law.mu(1e3) - 0.32).abs() < 1e-12);
}

/// A block pressed with 2 kN: after preload the contact's normal force equals load + weight
/// within 1 %.
#[test]
fn pressed_block_carries_its_load() {
    let load = 2000.0;
    let mut st = setup(FrictionLaw::Coulomb { mu: 0.3 }, load);
    relax(&mut st.solver, &mut st.pair, contact_preload()).unwrap();
    let (normal, _, _) = st.pair.resultants();
    let expected = load + st.mass_kg * G;
    assert!(
        (normal[2] / expected - 1.0).abs() < 0.01,
        "{} vs {expected}",
        normal[2]
    );
    // Penetration stays a small fraction of the element size (25 mm): below 1 %.
    let deepest = st
        .pair
        .state
        .iter()
        .map(|s| s.penetration_m)
        .fold(0.0, f64::max);
    assert!(deepest < 0.01 * 0.025, "penetration {deepest} m");
    // Snapshot files.
    let dir = std::env::temp_dir().join(format!("squeal_patch_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let reference: Vec<P3> = st.solver.model.mesh.nodes.clone();
    let json =
        squeal::contact::patch::write_snapshot(&st.pair, &reference, &st.solver.u, 0.0, 0.01, &dir)
            .unwrap();
    let snap: squeal::kalker::snapshot::PatchSnapshot = squeal::input::read_json(&json).unwrap();
    assert_eq!(snap.points.len(), 9);
    assert!((snap.normal_force_n / expected - 1.0).abs() < 0.01);
    let _ = std::fs::remove_dir_all(&dir);
    // Checkpoint state round trip.
    let saved = st.pair.checkpoint_state();
    st.pair.restore_state(&saved).unwrap();
    assert!(st.pair.restore_state(&saved[1..]).is_err());
}

#[test]
fn bad_friction_and_penalty_are_rejected_with_the_field() {
    let (mesh, slaves, faces, _) = common::sliding_block_on_plate();
    let bad = FrictionLaw::Falling {
        mu_static: 0.3,
        mu_dynamic: 0.5,
        decay_s_per_m: 6.0,
    };
    let e = ContactPair::new(
        "c",
        &mesh,
        slaves.clone(),
        faces.clone(),
        0.1,
        bulk_modulus(),
        bad,
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("contact.friction.mu_dynamic"), "{e}");
    assert_eq!(e.exit_code(), 2);
    let e = ContactPair::new(
        "c",
        &mesh,
        slaves.clone(),
        faces.clone(),
        0.1,
        bulk_modulus(),
        FrictionLaw::Coulomb { mu: 2.5 },
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("contact.friction.mu"), "{e}");
    let e = ContactPair::new(
        "c",
        &mesh,
        slaves,
        faces,
        -1.0,
        bulk_modulus(),
        FrictionLaw::Coulomb { mu: 0.3 },
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("penalty_scale"), "{e}");
}

/// Preload with a fixed damping near critical for the block bouncing on its contact (the
/// adaptive estimate is dominated by the penalty springs; see `PreloadOptions`).
fn contact_preload() -> PreloadOptions {
    PreloadOptions {
        fixed_damping_per_s: Some(2000.0),
        ..Default::default()
    }
}

/// The bucket grid follows its master surface: the plate carried 0.1 m along x (five faces,
/// twenty times the rebuild distance of a quarter face) with the block on it, 0.1 mm into it.
/// Every block-bottom slave must find its face at the new place, with the penalty force
/// `k x 0.1 mm` (k: the uniform face stiffness); a grid left at the old place finds none of
/// them. Then a further 0.5 mm (a tenth of the rebuild distance: no rebuild) finds them too.
#[test]
fn contact_search_follows_a_carried_master_surface() {
    let (mesh, slaves, faces, offset) = common::sliding_block_on_plate();
    let mut pair = ContactPair::new(
        "block_on_plate",
        &mesh,
        slaves.clone(),
        faces,
        0.1,
        bulk_modulus(),
        FrictionLaw::Coulomb { mu: 0.3 },
    )
    .unwrap();
    let k = pair.face_stiffness_n_per_m[0];
    assert!(pair
        .face_stiffness_n_per_m
        .iter()
        .all(|&x| (x / k - 1.0).abs() < 1e-9));
    let depth = 1e-4;
    for shift_m in [0.1, 0.1005] {
        let n = mesh.nodes.len();
        let mut u: Vec<P3> = vec![[shift_m, 0.0, 0.0]; n];
        // Slaves (block bottom, resting on the plate top) pressed into the plate.
        for &s in &slaves {
            u[s][2] = -depth;
        }
        let v = vec![[0.0; 3]; n];
        let mut force = vec![[0.0; 3]; n];
        pair.add_forces(0.0, 1e-7, &u, &v, &mut force);
        let in_contact = pair.state.iter().filter(|s| s.active).count();
        assert_eq!(in_contact, slaves.len(), "shift {shift_m} m");
        let (normal, _, _) = pair.resultants();
        let expected = k * depth * slaves.len() as f64;
        // The faces are flat and the slaves over their interiors or edges: the gap is the
        // depth to rounding.
        assert!(
            (normal[2] / expected - 1.0).abs() < 1e-9,
            "shift {shift_m} m: {} N vs {expected} N",
            normal[2]
        );
        let on_block: f64 = (offset..n).map(|i| force[i][2]).sum();
        assert!((on_block / expected - 1.0).abs() < 1e-9);
    }
}

/// The plate's 20 x 20 x 20 mm elements give every master face `k = s K A^2 / V = s K 0.02 m`;
/// with slave masses 1..9 kg and a step of 0.1 ms the median cap is `5 kg / (1e-4 s)^2`, so the
/// largest scale the step carries is `s_max = 5e8 / (K 0.02 m)` (0.1429 for steel). Just above
/// it the scale is refused naming the field; just below it is accepted.
#[test]
fn penalty_scale_above_what_the_step_carries_is_refused() {
    let (mesh, slaves, faces, _) = common::sliding_block_on_plate();
    let pair_with = |scale: f64| {
        let mut pair = steel_pair(
            &mesh,
            slaves.clone(),
            faces.clone(),
            scale,
            FrictionLaw::Coulomb { mu: 0.3 },
        );
        let mut mass_kg = vec![0.0; mesh.nodes.len()];
        for (k, &n) in slaves.iter().enumerate() {
            mass_kg[n] = 1.0 + k as f64;
        }
        pair.cap_stiffness_for_step(&mass_kg, 1e-4);
        pair
    };
    let (area_m2, volume_m3) = (0.02 * 0.02, 0.02 * 0.02 * 0.02);
    let face_k_per_scale = bulk_modulus() * area_m2 * area_m2 / volume_m3;
    let expected = 5.0 / (1e-4 * 1e-4) / face_k_per_scale;
    let largest = pair_with(0.1).largest_penalty_scale();
    // Same formula by two routes: only rounding differs.
    assert!(
        (largest - expected).abs() < 1e-9 * expected,
        "{largest} against {expected}"
    );
    // The limit does not depend on the scale it is computed from (k is linear in s).
    let from_other = pair_with(0.01).largest_penalty_scale();
    assert!((from_other - expected).abs() < 1e-9 * expected);
    let e = pair_with(1.01 * expected)
        .check_penalty_scale_against_step("case.json", "penalty_scale")
        .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("case.json") && text.contains("penalty_scale") && text.contains("0.143"),
        "{text}"
    );
    assert_eq!(e.exit_code(), 2);
    pair_with(0.99 * expected)
        .check_penalty_scale_against_step("case.json", "penalty_scale")
        .unwrap();
}

/// The block lifted by `lift_m` above the plate, as a contact pair (faces reversed if asked).
fn lifted_pair(lift_m: f64, reversed: bool) -> ContactPair {
    let (mut mesh, slaves, faces, offset) = common::sliding_block_on_plate();
    for p in &mut mesh.nodes[offset..] {
        p[2] += lift_m;
    }
    let faces = if reversed {
        faces.iter().map(|f| [f[0], f[3], f[2], f[1]]).collect()
    } else {
        faces
    };
    steel_pair(&mesh, slaves, faces, 0.1, FrictionLaw::Coulomb { mu: 0.3 })
}

/// Before any load the clearance is measured on the meshes: the block's nine bottom nodes at
/// the lift (exact: flat faces), on the plate's outer side; a lift beyond the allowed gap, a
/// block out of reach and faces ordered inwards are each refused naming the field.
#[test]
fn initial_clearance_measures_the_gap_and_the_facing() {
    let field = "wheel_position.initial_gap_mm";
    let flush = lifted_pair(0.0, false)
        .check_initial_clearance(1e-3, "s.json", field)
        .unwrap();
    assert_eq!(flush.slaves_near, 9);
    assert!(flush.smallest_gap_m.abs() < 1e-12, "{flush:?}");
    let c = lifted_pair(0.5e-3, false)
        .check_initial_clearance(1e-3, "s.json", field)
        .unwrap();
    assert_eq!(
        (c.slaves_near, c.slaves_outside, c.slaves_behind),
        (9, 9, 0)
    );
    assert!((c.smallest_gap_m - 0.5e-3).abs() < 1e-12, "{c:?}");
    for (lift_m, reversed, words) in [
        (1.5e-3, false, "measured on the meshes is 1.500 mm"),
        (3e-3, false, "no slave node"),
        (0.5e-3, true, "do not face each other: 9 of the 9"),
    ] {
        let e = lifted_pair(lift_m, reversed)
            .check_initial_clearance(1e-3, "s.json", field)
            .unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains(field) && text.contains("s.json") && text.contains(words),
            "lift {lift_m}, reversed {reversed}: {text}"
        );
        assert_eq!(e.exit_code(), 2);
    }
}

/// The region of interest searches only the slaves near the master surface, and gives the
/// full search's result bit for bit: a tall block (50 x 50 x 80 mm, every node a slave, so its
/// upper nodes lie far above the plate) lifted 30 mm and thrown at the plate (1 m/s along it,
/// 1 m/s down), so that slaves enter the faces' boxes from outside; run once with the full
/// search and once with the region, its guard checked every step. The block slides several
/// margins, so the region is rebuilt along the way.
#[test]
fn region_of_interest_search_matches_the_full_search_step_by_step() {
    use squeal::contact::ContactSearch;
    let run = |search: ContactSearch| {
        let (mesh, _, faces, offset) = common::block_on_plate(
            [30, 10, 1],
            [0.6, 0.2, 0.02],
            [2, 2, 4],
            [0.05, 0.05, 0.08],
            [0.1, 0.075],
            2,
        );
        let mut mesh = mesh;
        for p in &mut mesh.nodes[offset..] {
            p[2] += 0.03;
        }
        let slaves: Vec<usize> = (offset..mesh.nodes.len()).collect();
        let mut pair = steel_pair(&mesh, slaves, faces, 0.1, FrictionLaw::Coulomb { mu: 0.3 });
        pair.search = search;
        pair.verify_region_every_steps = 1;
        let materials: BTreeMap<u32, ElasticMaterial> =
            [(1, STEEL), (2, STEEL)].into_iter().collect();
        let mut model = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
        model.gravity_m_per_s2 = [0.0, 0.0, -G];
        model.fix_set("plate", [true, true, true]).unwrap();
        let block = model.node_set("block").unwrap();
        let bound = pair.time_step_bound_s(&model.nodal_mass_kg);
        model.register_time_step_bound("contact", bound);
        let mut solver = Solver::new(model, None).unwrap();
        for &n in &block {
            solver.v[n] = [1.0, 0.0, -1.0];
        }
        let mut history = Vec::new();
        let mut smallest_region = usize::MAX;
        while solver.time_s < 0.06 {
            solver.step_with(&mut pair, false, false).unwrap();
            smallest_region = smallest_region.min(pair.searched_slaves());
            history.push(pair.state.clone());
        }
        (
            history,
            solver.u.clone(),
            pair.region_rebuilds(),
            smallest_region,
            pair.slaves.len(),
        )
    };
    let (full, u_full, _, _, slaves) = run(ContactSearch::Full);
    let (region, u_region, rebuilds, smallest, _) = run(ContactSearch::Region);
    println!(
        "{} steps, {rebuilds} region rebuilds, at least {smallest} of {slaves} slaves searched",
        full.len()
    );
    // The first build and at least two after the block slid a margin (20 mm) each.
    assert!(rebuilds >= 3, "the region was built {rebuilds} times");
    assert!(
        smallest < slaves / 2,
        "the upper nodes stay out of the region"
    );
    assert_eq!(full.len(), region.len());
    for (step, (a, b)) in full.iter().zip(&region).enumerate() {
        assert!(a == b, "slave states differ at step {step}");
    }
    // The thrown block hits the plate (and bounces off it): the comparison covers contact.
    let touching = full.iter().filter(|s| s.iter().any(|s| s.active)).count();
    assert!(touching > 0, "the block never touched the plate");
    assert!(u_full == u_region, "displacements differ");
}

/// A penalty per unit area (`ContactPair::use_area_penalty`, the cases' `penalty_length_mm`):
/// a block pressed uniformly `g` into the plate carries `s K A g / L` over its bottom area `A`
/// whatever its mesh (2 x 2 or 6 x 6 elements), where the faces' `s K A_f^2 / V` give a force
/// that grows with the number of slave nodes (by 49 / 9 here). Exact to rounding: the
/// tributary areas sum to the block's bottom, and every slave is `g` deep.
#[test]
fn an_area_penalty_carries_the_same_pressure_on_any_mesh() {
    let (s, length_m, depth) = (0.1, 0.005, 1e-5);
    let mut totals = Vec::new();
    for divisions in [2, 6] {
        let (mesh, slaves, faces, _) = common::block_on_plate(
            [30, 10, 1],
            [0.6, 0.2, 0.02],
            [divisions, divisions, 1],
            [0.05, 0.05, 0.02],
            [0.1, 0.075],
            2,
        );
        let mut u: Vec<P3> = vec![[0.0; 3]; mesh.nodes.len()];
        for &n in &slaves {
            u[n][2] = -depth;
        }
        let v = vec![[0.0; 3]; mesh.nodes.len()];
        let mut by_law = Vec::new();
        for area_law in [false, true] {
            let mut pair = steel_pair(
                &mesh,
                slaves.clone(),
                faces.clone(),
                s,
                FrictionLaw::Coulomb { mu: 0.3 },
            );
            if area_law {
                pair.use_area_penalty(bulk_modulus(), length_m);
            }
            let mut force = vec![[0.0; 3]; mesh.nodes.len()];
            pair.add_forces(0.0, 1e-7, &u, &v, &mut force);
            by_law.push(pair.resultants().0[2]);
        }
        totals.push(by_law);
    }
    let expected = s * bulk_modulus() * 0.05 * 0.05 * depth / length_m;
    for by_law in &totals {
        assert!(
            (by_law[1] / expected - 1.0).abs() < 1e-9,
            "{} vs {expected}",
            by_law[1]
        );
    }
    let growth = totals[1][0] / totals[0][0];
    assert!(
        (growth - 49.0 / 9.0).abs() < 1e-6,
        "segment penalty: {growth}"
    );
}

/// The patch's sliding velocity (`SlipSpeed::Patch`) against its definition, by hand: a
/// 3 x 3-node block bottom pressed 10 um into the plate with a penalty per unit area (so the
/// corner, edge and centre slaves carry normal forces in the ratio 1 : 2 : 4), each slave
/// slipping at its own velocity. After one step the patch velocity is `sum N_i v_i / sum N_i`
/// (to rounding); in the next step every slave's coefficient is `mu` at that velocity's
/// magnitude under `Patch`, and at its own speed under `Node`. The velocity travels with the
/// checkpoint; a checkpoint of the earlier layout (slaves only) restores it as zero.
#[test]
fn the_patch_slip_speed_is_the_normal_force_weighted_mean_velocity() {
    let law = FrictionLaw::Falling {
        mu_static: 0.5,
        mu_dynamic: 0.32,
        decay_s_per_m: 6.0,
    };
    let (mesh, slaves, faces, _) = common::block_on_plate(
        [30, 10, 1],
        [0.6, 0.2, 0.02],
        [2, 2, 1],
        [0.05, 0.05, 0.02],
        [0.1, 0.075],
        2,
    );
    let mut u: Vec<P3> = vec![[0.0; 3]; mesh.nodes.len()];
    let mut v: Vec<P3> = vec![[0.0; 3]; mesh.nodes.len()];
    for (i, &n) in slaves.iter().enumerate() {
        u[n][2] = -1e-5;
        v[n] = [0.02 + 0.05 * i as f64, 0.01 * i as f64, 0.0];
    }
    for slip_speed in [SlipSpeed::Node, SlipSpeed::Patch] {
        let mut pair = steel_pair(&mesh, slaves.clone(), faces.clone(), 0.1, law);
        pair.use_area_penalty(bulk_modulus(), 0.005);
        pair.slip_speed = slip_speed;
        let mut force = vec![[0.0; 3]; mesh.nodes.len()];
        pair.add_forces(0.0, 1e-7, &u, &v, &mut force);
        let (mut weighted, mut normal_sum) = ([0.0; 3], 0.0);
        for (st, &n) in pair.state.iter().zip(&slaves) {
            assert!(st.active);
            for d in 0..3 {
                weighted[d] += st.normal_force_n * v[n][d];
            }
            normal_sum += st.normal_force_n;
        }
        let largest = pair
            .state
            .iter()
            .map(|s| s.normal_force_n)
            .fold(0.0, f64::max);
        let smallest = pair
            .state
            .iter()
            .map(|s| s.normal_force_n)
            .fold(f64::INFINITY, f64::min);
        assert!(
            (largest / smallest - 4.0).abs() < 1e-9,
            "{largest} / {smallest}"
        );
        let mean = weighted.map(|c| c / normal_sum);
        let patch = pair.patch_slip_velocity_m_per_s();
        for d in 0..3 {
            assert!((patch[d] - mean[d]).abs() < 1e-14, "{patch:?} vs {mean:?}");
        }
        pair.add_forces(0.0, 1e-7, &u, &v, &mut force);
        let patch_speed = (mean[0] * mean[0] + mean[1] * mean[1]).sqrt();
        for (st, &n) in pair.state.iter().zip(&slaves) {
            let own_speed = (v[n][0] * v[n][0] + v[n][1] * v[n][1]).sqrt();
            let expected = match slip_speed {
                SlipSpeed::Node => law.mu(own_speed),
                SlipSpeed::Patch => law.mu(patch_speed),
            };
            assert!(
                (st.mu - expected).abs() < 1e-14,
                "{slip_speed:?}: {} vs {expected}",
                st.mu
            );
        }
        // Checkpoint round trip, and the earlier layout.
        let saved = pair.checkpoint_state();
        let mut fresh = steel_pair(&mesh, slaves.clone(), faces.clone(), 0.1, law);
        fresh.restore_state(&saved).unwrap();
        assert_eq!(
            fresh.patch_slip_velocity_m_per_s(),
            pair.patch_slip_velocity_m_per_s()
        );
        fresh.restore_state(&saved[..4 * slaves.len()]).unwrap();
        assert_eq!(fresh.patch_slip_velocity_m_per_s(), [0.0; 3]);
        assert!(fresh.restore_state(&saved[..4 * slaves.len() - 1]).is_err());
    }
}
