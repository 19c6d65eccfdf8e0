//! No heap allocation inside the time loop: a counting global allocator around steps of a model
//! with every kind of part (elements, springs, loads, ties, a rigid body, prescribed motion,
//! damping), on one and on two threads; then with a frictional contact pair in the loop, and
//! with multi-rate stepping.
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};

use squeal::contact::{ContactPair, Enforcement, FrictionLaw};
use squeal::explicit::element::{ElasticMaterial, Formulation};
use squeal::explicit::model::Model;
use squeal::explicit::{AuxForces, Curve, MotionKind, NoAux, Solver};
use squeal::mesh::cuboid;

mod common;

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Set on the stepping pool's threads while steps are counted: allocations by other threads
    /// of the process (the test harness's, on a loaded machine) are not the time loop's.
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

fn count() {
    // `try_with`: a thread being torn down has no thread-locals left; it is not stepping.
    if COUNTING.try_with(Cell::get).unwrap_or(false) {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn the_time_step_does_not_allocate() {
    let steel = ElasticMaterial {
        density_kg_per_m3: 7850.0,
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, steel)].into_iter().collect();
    let mesh = cuboid([40, 10, 10], [0.4, 0.1, 0.1], 1);
    let mut m = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
    m.gravity_m_per_s2 = [0.0, 0.0, -9.81];
    m.mass_damping_per_s = 5.0;
    m.stiffness_damping_s = 1e-8;
    m.add_ground_springs("z0", [1e6, 1e6, 1e8], [10.0, 10.0, 100.0])
        .unwrap();
    m.add_load("x1", [0.0, 100.0, -1000.0], Curve::ramp(0.0, 1e-5, 1.0))
        .unwrap();
    m.prescribe(
        "y0",
        1,
        MotionKind::Displacement,
        Curve::ramp(0.0, 1e-3, 1e-5),
    )
    .unwrap();
    let rb = m.add_rigid_body("x0").unwrap();
    m.rigid_bodies[rb].torque = Some(squeal::explicit::model::TorqueLoad {
        axis: [0.0, 1.0, 0.0],
        curve_n_m: Curve::ramp(0.0, 1e-4, 100.0),
    });
    for threads in [1, 2] {
        assert_steps_do_not_allocate(&m, threads, &mut NoAux, "", None);
    }
    // The contact module in the loop too (in the same test: the counter is global): a block of
    // 441 slave nodes (two parallel chunks) pressed by gravity on a fixed plate, with friction.
    let (mesh, slaves, faces, _) = common::block_on_plate(
        [12, 12, 1],
        [0.3, 0.3, 0.02],
        [20, 20, 1],
        [0.1, 0.1, 0.01],
        [0.1, 0.1],
        1,
    );
    let bulk_pa = 210e9 / (3.0 * (1.0 - 2.0 * 0.3));
    // One pair per thread count and enforcement (a pair carries its friction state): penalty,
    // then exact (contact/exact.rs: its search, constraints and solve run on buffers of the
    // pair's size).
    let mut pairs: Vec<ContactPair> = [Enforcement::Penalty, Enforcement::Penalty]
        .into_iter()
        .chain([Enforcement::Exact, Enforcement::Exact])
        .map(|enforcement| {
            let mut pair = ContactPair::new(
                "block_on_plate",
                &mesh,
                slaves.clone(),
                faces.clone(),
                0.1,
                bulk_pa,
                FrictionLaw::Coulomb { mu: 0.3 },
            )
            .unwrap();
            pair.enforcement = enforcement;
            pair
        })
        .collect();
    let mut m = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
    m.gravity_m_per_s2 = [0.0, 0.0, -9.81];
    m.fix_set("plate", [true, true, true]).unwrap();
    let bound = pairs[0].time_step_bound_s(&m.nodal_mass_kg);
    m.register_time_step_bound("contact", bound);
    for (threads, contact) in [1, 2, 1, 2].into_iter().zip(pairs.iter_mut()) {
        let label = format!("contact ({}) ", contact.enforcement.word());
        assert_steps_do_not_allocate(&m, threads, contact, &label, None);
        // The block did touch the plate (else the contact loop did no work).
        assert!(
            contact.state.iter().any(|st| st.active),
            "no slave in contact"
        );
    }
    // Multi-rate stepping: a bar whose elements grow fourfold along it (two levels), on
    // springs at one end, under gravity.
    let mut mesh = cuboid([48, 2, 2], [48.0, 0.02, 0.02], 1);
    for p in mesh.nodes.iter_mut() {
        p[0] = if p[0] <= 24.0 {
            p[0] * 0.005
        } else {
            0.12 + (p[0] - 24.0) * 0.02
        };
    }
    let mut m = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
    m.gravity_m_per_s2 = [0.0, 0.0, -9.81];
    m.add_ground_springs("x0", [1e6, 1e6, 1e6], [10.0, 10.0, 10.0])
        .unwrap();
    for threads in [1, 2] {
        assert_steps_do_not_allocate(&m, threads, &mut NoAux, "multi-rate ", Some(8));
    }
}

/// Steps a solver of `m` on a pool of `threads` threads with `aux` in the loop (multi-rate with
/// at most `levels` levels when given): three steps to warm up (rayon's registry, first touch
/// of buffers), then 50 counted steps (every fifth with output) must not allocate.
fn assert_steps_do_not_allocate<A: AuxForces + Send>(
    m: &Model,
    threads: usize,
    aux: &mut A,
    what: &str,
    levels: Option<usize>,
) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    // Every worker must have started before counting: a thread that starts late (on a loaded
    // machine) sets up its job queues inside the counted steps (measured: 1-3 allocations in
    // rayon_core::registry::main_loop, none in our code).
    pool.broadcast(|_| ());
    let mut s = pool.install(|| {
        let mut s = Solver::new(m.clone(), None).unwrap();
        if let Some(levels) = levels {
            // Coarse levels at their elements' own stable step, so that this small model has
            // an interface (the allocation-free path does not depend on the level rule).
            let scheme = squeal::explicit::levels::LevelScheme::binary(levels)
                .with_coarse_courant(squeal::explicit::levels::COURANT_FACTOR);
            let p = s.enable_multi_rate_with(scheme, &[]).unwrap();
            assert!(p.counts.len() >= 2, "{:?}", p.counts);
        }
        for _ in 0..3 {
            s.step_with(aux, true, false).unwrap();
        }
        s
    });
    // Count on the pool's threads only; the steps themselves run on them.
    pool.broadcast(|_| COUNTING.with(|c| c.set(true)));
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    pool.install(|| {
        for k in 0..50 {
            s.step_with(aux, k % 5 == 0, false).unwrap();
        }
    });
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    pool.broadcast(|_| COUNTING.with(|c| c.set(false)));
    assert_eq!(
        after - before,
        0,
        "{} allocations in 50 {what}steps on {threads} thread(s)",
        after - before
    );
}
