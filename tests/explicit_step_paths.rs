//! The time step's shortcuts against its general path, bit for bit: the short update of free
//! nodes on steps without output against the general update that output steps take; auxiliary
//! forces zeroed and read at the declared nodes only against the whole array (on a block and
//! on the tiny rolling case, with contact, springs, rigid bodies and ties); the phase clock
//! changes nothing and accounts for the step's wall time. And the error paths: a force outside
//! the declared nodes stops the step with the node named, a declared node outside the model is
//! refused.
#![allow(clippy::needless_range_loop)]
use std::collections::BTreeMap;

use squeal::explicit::element::{ElasticMaterial, Formulation};
use squeal::explicit::model::Model;
use squeal::explicit::phase_clock::{StepPhase, STEP_PHASES};
use squeal::explicit::{AuxForces, Curve, MotionKind, NoAux, Solver};
use squeal::mesh::{cuboid, P3};

const STEEL: ElasticMaterial = ElasticMaterial {
    density_kg_per_m3: 7850.0,
    youngs_modulus_pa: 210e9,
    poisson_ratio: 0.3,
};

/// A block with every kind of node the update treats apart: fixed (x0), prescribed (x1, z
/// velocity), loaded (y1), on ground springs (z0), free; gravity and mass damping on, so that
/// every term of the update is non-zero somewhere.
fn block() -> Solver {
    let mesh = cuboid([10, 4, 3], [0.1, 0.04, 0.03], 1);
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, STEEL)].into_iter().collect();
    let mut m = Model::from_mesh(mesh, &materials, Formulation::default(), "block").unwrap();
    m.gravity_m_per_s2 = [0.5, -1.0, -9.81];
    m.mass_damping_per_s = 40.0;
    m.fix_set("x0", [true, true, true]).unwrap();
    m.prescribe("x1", 2, MotionKind::Velocity, Curve::ramp(0.0, 2e-5, 0.3))
        .unwrap();
    m.add_load("y1", [300.0, 800.0, -500.0], Curve::ramp(0.0, 1e-5, 1.0))
        .unwrap();
    m.add_ground_springs("z0", [2e6, 0.0, 1e7], [0.0, 0.0, 1e3])
        .unwrap();
    Solver::new(m, None).unwrap()
}

/// A penalty floor under the block's top face (`z1`) pushing down where it rises above
/// `height_m`, and a drag on its y velocity: forces that depend on the state, on some nodes.
struct Lid {
    nodes: Vec<usize>,
    reference_z_m: Vec<f64>,
    height_m: f64,
    /// A node written outside the declaration (for the error path), if any.
    stray: Option<usize>,
}

impl Lid {
    fn on(s: &Solver) -> Lid {
        let nodes = s.model.mesh.node_sets["z1"].clone();
        let reference_z_m = nodes.iter().map(|&n| s.model.mesh.nodes[n][2]).collect();
        Lid {
            nodes,
            reference_z_m,
            height_m: 0.03 + 2e-7,
            stray: None,
        }
    }
}

impl AuxForces for Lid {
    fn add_forces(&mut self, _t: f64, _dt: f64, u: &[P3], v: &[P3], force: &mut [P3]) {
        for (k, &n) in self.nodes.iter().enumerate() {
            let above = self.reference_z_m[k] + u[n][2] - self.height_m;
            if above > 0.0 {
                force[n][2] -= 5e8 * above;
            }
            force[n][1] -= 20.0 * v[n][1];
        }
        if let Some(n) = self.stray {
            force[n][0] += 1.0;
        }
    }
    fn force_nodes(&self) -> Option<Vec<usize>> {
        Some(self.nodes.clone())
    }
}

fn bits(values: &[P3]) -> Vec<u64> {
    values.iter().flatten().map(|x| x.to_bits()).collect()
}

fn work_bits(s: &Solver) -> Vec<u64> {
    s.work.to_array().map(f64::to_bits).to_vec()
}

/// Steps the block `steps` times, output on every step or on none, with the lid's forces
/// declared or not.
fn run_block(steps: usize, output: bool, declare: bool) -> Solver {
    let mut s = block();
    let mut lid = Lid::on(&s);
    if declare {
        s.declare_aux_forces_of(&lid).unwrap();
    }
    for _ in 0..steps {
        s.step_with(&mut lid, output, false).unwrap();
    }
    s
}

/// Output steps take the general update for every node, plain steps the short one for free
/// nodes: the states and the work totals must agree bit for bit. (A short path that dropped the
/// mass damping, the gravity or the auxiliary force of a free node would move them apart.)
#[test]
fn plain_steps_advance_the_state_as_output_steps_do() {
    let plain = run_block(600, false, true);
    let output = run_block(600, true, true);
    assert!(plain.u.iter().any(|p| p[2] < -1e-7), "the block moves");
    assert!(plain.work.aux_j != 0.0 && plain.work.mass_damping_j > 0.0);
    assert_eq!(bits(&plain.u), bits(&output.u));
    assert_eq!(bits(&plain.v), bits(&output.v));
    assert_eq!(work_bits(&plain), work_bits(&output));
}

/// Auxiliary forces zeroed and read at the declared nodes only give the very run that zeroes and
/// reads the whole array, and the set holds the declared, spring and load nodes and no other.
#[test]
fn declared_aux_nodes_give_the_full_arrays_run() {
    let narrowed = run_block(600, false, true);
    let full = run_block(600, false, false);
    assert_eq!(bits(&narrowed.u), bits(&full.u));
    assert_eq!(bits(&narrowed.v), bits(&full.v));
    assert_eq!(work_bits(&narrowed), work_bits(&full));
    assert!(full.aux_force_nodes().is_none());
    let set = narrowed.aux_force_nodes().expect("declared");
    let sets = &narrowed.model.mesh.node_sets;
    let mut expected: Vec<u32> = ["z1", "y1", "z0"]
        .iter()
        .flat_map(|name| sets[*name].iter().map(|&n| n as u32))
        .collect();
    expected.sort_unstable();
    expected.dedup();
    assert_eq!(set, expected.as_slice());
    assert!(
        set.len() < narrowed.u.len(),
        "the set is a part of the model"
    );
}

/// The tiny rolling case (contact, suspension springs, rigid axle, tied zones): the model as
/// built declares the contact's nodes; stepping it so and with the declaration widened to every
/// node gives the same states bit for bit, on plain and output steps.
#[test]
fn tiny_rolling_case_with_declared_contact_nodes_steps_as_with_the_full_array() {
    let loaded =
        squeal::rolling::load_case(std::path::Path::new("data/cases/case3-ci.json")).unwrap();
    let run = |widen: bool| {
        let mut m = squeal::rolling::build(&loaded).unwrap();
        if widen {
            m.solver.declare_aux_force_nodes(None).unwrap();
        } else {
            let set = m.solver.aux_force_nodes().expect("the build declares");
            assert!(set.len() < m.solver.u.len());
        }
        // The wheel, released at its static position without the preload, meets the rail
        // after about 1700 steps (1.1 ms).
        for k in 0..2400 {
            m.solver
                .step_with(&mut m.contact, k % 7 == 0, k % 35 == 0)
                .unwrap();
        }
        let (normal, _, _) = m.contact.pair.resultants();
        (m.solver.u.clone(), m.solver.v.clone(), normal)
    };
    let (u_a, v_a, normal_a) = run(false);
    let (u_b, v_b, normal_b) = run(true);
    assert!(
        normal_a[2] > 1e3,
        "the wheel presses on the rail: {normal_a:?}"
    );
    assert_eq!(bits(&u_a), bits(&u_b));
    assert_eq!(bits(&v_a), bits(&v_b));
    assert_eq!(bits(&[normal_a]), bits(&[normal_b]));
}

/// A force written outside the declared nodes would never be zeroed: the next energy report
/// stops the step and names the node.
#[test]
fn aux_force_outside_the_declared_nodes_stops_the_step() {
    let mut s = block();
    let mut lid = Lid::on(&s);
    s.declare_aux_forces_of(&lid).unwrap();
    let stray = (0..s.u.len())
        .find(|&n| {
            s.aux_force_nodes()
                .unwrap()
                .binary_search(&(n as u32))
                .is_err()
        })
        .unwrap();
    lid.stray = Some(stray);
    s.step_with(&mut lid, false, false).unwrap();
    assert_eq!(s.aux_forces_outside_declared(), Some(stray));
    let e = s.step_with(&mut lid, false, true).unwrap_err().to_string();
    assert!(e.contains(&format!("node {stray}")), "{e}");
    assert!(e.contains("force_nodes"), "{e}");
}

#[test]
fn declaring_a_node_outside_the_model_is_refused() {
    let mut s = block();
    let n = s.u.len();
    let e = s
        .declare_aux_force_nodes(Some(&[0, n + 3]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("force_nodes"), "{e}");
    assert!(e.contains(&format!("node {}", n + 3)), "{e}");
    assert!(e.contains(&format!("0 to {}", n - 1)), "{e}");
    // Nothing was narrowed.
    assert!(s.aux_force_nodes().is_none());
    // NoAux declares no node of its own: the set is the springs' and loads'.
    s.declare_aux_forces_of(&NoAux).unwrap();
    assert!(s.aux_force_nodes().unwrap().len() < n);
}

/// The phase clock changes no result, and its phases add up to the wall time of the steps
/// (the first lap starts when the clock is switched on; the steps do nothing else).
#[test]
fn phase_clock_accounts_for_the_steps_and_changes_nothing() {
    let plain = run_block(300, false, true);
    let mut s = block();
    let mut lid = Lid::on(&s);
    s.declare_aux_forces_of(&lid).unwrap();
    let started = std::time::Instant::now();
    s.time_phases(true);
    for _ in 0..300 {
        s.step_with(&mut lid, false, false).unwrap();
    }
    let wall_s = started.elapsed().as_secs_f64();
    assert_eq!(bits(&plain.u), bits(&s.u));
    let clock = s.phase_clock().expect("on");
    let total = clock.total_seconds();
    // The clock misses only the instants between `started` and its start, and after its last
    // lap: microseconds against the steps' milliseconds.
    assert!(
        total <= wall_s && total > 0.95 * wall_s,
        "{total} s of {wall_s} s"
    );
    for p in STEP_PHASES {
        assert!(clock.seconds(p) >= 0.0, "{}", p.name());
    }
    assert!(clock.seconds(StepPhase::Elements) > 0.0);
    assert!(clock.seconds(StepPhase::NodeUpdate) > 0.0);
    s.time_phases(false);
    assert!(s.phase_clock().is_none());
}
