//! A rolling case file (`data/cases/case*.json`): the model scenario it builds on (wheel +
//! track meshes), the track's discrete parts, the vehicle load, the rolling conditions, the
//! friction law, and what to write. Every field is validated with its name and allowed range.

// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use super::enforcement::Enforcement;
pub use super::lateral::{LateralMotion, LateralRamp, LateralTable};
pub use super::time_stepping::{MultiRateMode, TimeSteppingSpec};
use crate::friction::{FrictionLaw, SlipSpeed};

/// Leaves the default slip speed out of written cases (run.json), as before the field existed.
fn is_node_slip(s: &SlipSpeed) -> bool {
    *s == SlipSpeed::Node
}

/// Leaves the default enforcement out of written cases (run.json), as before the field existed.
fn is_penalty(e: &Enforcement) -> bool {
    *e == Enforcement::Penalty
}
use crate::input::Checker;
use crate::scenario::LoadedScenario;
use crate::{Error, Result};

/// A spring-damper's totals.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringDamper {
    /// Stiffness (N/m).
    pub stiffness_n_per_m: f64,
    /// Viscous damping (N s/m).
    pub damping_n_s_per_m: f64,
}

/// Rail pad: vertical stiffness and damping per pad (docs/references.md, section 3), and the shear
/// (longitudinal and lateral) stiffness as a fraction of the vertical one.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RailPad {
    /// Vertical stiffness per pad (N/m).
    pub stiffness_n_per_m: f64,
    /// Vertical damping per pad (N s/m).
    pub damping_n_s_per_m: f64,
    /// Shear stiffness and damping as a fraction of the vertical values.
    pub shear_fraction: f64,
}

use crate::material::Material;

/// Driving torque on the axle: a ramp from zero to `max_n_m` at `ramp_end_s`, then constant
/// (Yang & Li 2019).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TorqueSpec {
    /// Largest torque (N m).
    pub max_n_m: f64,
    /// End of the ramp (s).
    pub ramp_end_s: f64,
}

/// Prescribed longitudinal creepage (instead of the torque): the axle's forward speed is held at
/// the rolling speed V and its spin at `V (1 + xi(t)) / R` (R: loaded rolling radius measured
/// after the preload), with the creepage `xi` rising linearly from `start` at `start_s` to
/// `end` at `end_s`. A slow ramp traces the creep curve (creep force against creepage) in one
/// run; a driving wheel has `xi > 0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CreepageRamp {
    /// Creepage at `start_s` (dimensionless, e.g. 0.001 = 0.1 %).
    pub start: f64,
    /// Creepage at `end_s` and after.
    pub end: f64,
    /// Start of the ramp (s); free rolling before it.
    pub start_s: f64,
    /// End of the ramp (s).
    pub end_s: f64,
}

/// Curving: the half wheelset yawed about the vertical through the wheel centre by its angle
/// of attack, as the inner wheel of a leading wheelset in a tight curve (the outer wheel's
/// flange against its rail, the bogie holding the axle's lateral position). The axle turns
/// about its own yawed axis, the forward guide moves it along the rail at the rolling speed
/// and its lateral position is held, so the contact sees a steady lateral creepage of about
/// `sin(psi)` (Rudd 1976; Thompson, Railway Noise and Vibration, 2009, ch. 9).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvingSpec {
    /// Angle of attack psi (mrad). Positive: the wheel heads towards the track centre (its
    /// rolling direction `(cos psi, -sin psi, 0)`), so that, dragged along the rail, its
    /// contact slides towards the field side (eta > 0) and the rail's friction pushes it
    /// towards the track centre.
    pub angle_of_attack_mrad: f64,
}

/// Largest angle of attack accepted (mrad): 50 mrad (2.9 degrees) is beyond any wheelset in
/// a curve (a bogie of 2.5 m wheelbase in a 25 m tram curve runs at about 50 mrad).
pub const MAX_ANGLE_OF_ATTACK_MRAD: f64 = 50.0;

impl CurvingSpec {
    /// The angle of attack (rad).
    pub fn angle_of_attack_rad(&self) -> f64 {
        self.angle_of_attack_mrad * 1e-3
    }
}

/// How the static preload is found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PreloadMethod {
    /// Newton's method on the static problem with a sparse Cholesky of the tangent
    /// ([`crate::explicit::statics`]), as the paper's implicit static solution. The default.
    #[default]
    Implicit,
    /// Dynamic relaxation ([`crate::explicit::preload`]): the fallback, for models whose
    /// factor does not fit in memory (the paper-resolution cases).
    DynamicRelaxation,
    /// Newton's method as `implicit`, each step solved by conjugate gradients with a two-level
    /// aggregation preconditioner ([`crate::linalg::iterative`]) instead of a Cholesky factor: memory
    /// linear in the model, for the models whose factor does not fit.
    ImplicitIterative,
}

/// Static preload: the method, and the settings of dynamic relaxation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreloadSpec {
    /// How the equilibrium is found (default: implicit). The other settings but `tolerance`
    /// and `load_tolerance` are dynamic relaxation's.
    #[serde(default)]
    pub method: PreloadMethod,
    /// Mass-proportional damping during relaxation (1/s). The slowest mode to settle is the
    /// wheelset sinking into its track (about 45 Hz with the preload's added inertia on the
    /// demo model): critical damping `2 omega` is about 570/s; 450/s (slightly underdamped)
    /// settled the demo model to a 1e-3 residual in 12 800 steps, where 750/s (overdamped:
    /// decay `omega^2 / alpha`) had not after 30 000. The 1 mm model's inertia scaling adds
    /// about 10 t, which brings that mode down to about 20 Hz (critical about 250/s): its cases
    /// use 230/s, which settled it in 39 500 steps, where 450/s was still 44 % short of the
    /// load after 12 000 and 150/s overshot.
    pub damping_per_s: f64,
    /// Relative residual to reach.
    pub tolerance: f64,
    /// Step limit; when reached the run goes on from the partly relaxed state, and `run.json`
    /// records the residual.
    pub max_steps: u64,
    /// Time step of the relaxation (s), reached by inertia scaling of the small elements, the
    /// springs' and the contact's nodes (gravity keeps the true masses, so the equilibrium is
    /// the same). None: the run's own step.
    #[serde(default)]
    pub time_step_s: Option<f64>,
    /// Largest relative difference between the vertical contact force and the static wheel
    /// load (wheelset and sprung weight) at which the preload counts as converged.
    #[serde(default = "default_load_tolerance")]
    pub load_tolerance: f64,
}

fn default_true() -> bool {
    true
}

/// 1 %: the bound on the normal force after preload (the demo cases settle to 0.65 %
/// within their step budget; the static Hertz check asks for 0.2 %).
fn default_load_tolerance() -> f64 {
    0.01
}

/// Output settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// History sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Times of contact-patch snapshots (s).
    #[serde(default)]
    pub patch_times_s: Vec<f64>,
    /// Times of VTU snapshots (s).
    #[serde(default)]
    pub vtu_times_s: Vec<f64>,
    /// Micro-slip speed above which a node counts as slipping (m/s).
    pub slip_threshold_m_per_s: f64,
    /// Checkpoint every this many steps (0 = never).
    pub checkpoint_every_steps: u64,
    /// A ring of rim nodes whose velocities are decomposed by nodal diameter into `ring.csv`
    /// (None: no ring).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ring: Option<RingSpec>,
}

/// The ring of rim nodes a run records (`ring.csv`, docs/curving.md): `nodes` equally spaced
/// nodes at one radius of the field-side rim face, their lateral, radial and circumferential
/// velocities in the wheel's turning frame decomposed into the harmonics `n = 0..=n_max`
/// around the circumference ([`crate::signal::ring`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingSpec {
    /// Nodes on the ring: at least `2 n_max + 1`, and a divisor of the wheel mesh's
    /// circumferential divisions (the ring takes every k-th node of one circle).
    pub nodes: usize,
    /// Highest nodal diameter recorded.
    pub n_max: usize,
}

/// Most nodes a ring may hold (the wheel meshes have at most a few hundred around).
pub const MAX_RING_NODES: usize = 4096;

/// A rolling case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RollingCase {
    /// Name (used for output folders).
    pub name: String,
    /// What the case is.
    pub description: String,
    /// The model scenario (meshes), relative to this file.
    pub model_scenario: String,
    /// Simulated time (s).
    pub end_time_s: f64,
    /// Initial rolling speed (km/h).
    pub speed_km_per_h: f64,
    /// Sprung mass share of car body and bogie on this wheel (kg).
    pub sprung_mass_kg: f64,
    /// Primary suspension (same values vertically, laterally and longitudinally).
    pub primary_suspension: SpringDamper,
    /// Rail pad, per sleeper.
    pub rail_pad: RailPad,
    /// Ballast, per sleeper, vertical.
    pub ballast: SpringDamper,
    /// Sleeper material (concrete).
    pub sleeper_material: Material,
    /// Driving torque.
    pub torque: TorqueSpec,
    /// Prescribed longitudinal creepage instead of the torque (which must then be zero).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub creepage: Option<CreepageRamp>,
    /// Hold the axle's forward speed at the rolling speed (the forward guide): the car body's
    /// inertia, which a half wheelset on its 1.15 MN/m suspension to a free sprung mass lacks
    /// (without it the driving torque surges the wheelset forward at the suspension's 6 Hz and
    /// spins the wheel up instead of pulling on the rail). The force that holds it is recorded
    /// as `forward_guide_force_n` in `histories.csv`. Default true.
    #[serde(default = "default_true")]
    pub hold_forward_speed: bool,
    /// Lateral motion of the axle ends (None: case 1, no lateral motion).
    pub lateral_motion: Option<LateralMotion>,
    /// Curving: the wheelset yawed by its angle of attack at a held lateral position (None:
    /// no yaw). Not with `lateral_motion`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curving: Option<CurvingSpec>,
    /// Friction law.
    pub friction: FrictionLaw,
    /// Which slip speed a falling friction law reads in the contact: `node` (each node's own,
    /// the default and the paper's) or `patch` (the patch's mean sliding velocity, one for all
    /// nodes; [`SlipSpeed`] says why). No effect on a constant coefficient.
    #[serde(default, skip_serializing_if = "is_node_slip")]
    pub friction_slip_speed: SlipSpeed,
    /// How the rolling run enforces the contact: `penalty` (the default and the paper's) or
    /// `exact` (forward-increment Lagrange multipliers, `contact::exact`: no penetration and
    /// no penalty compliance). The static preload is the penalty's either way, so
    /// `penalty_scale` still sets it.
    #[serde(default, skip_serializing_if = "is_penalty")]
    pub contact_enforcement: Enforcement,
    /// Penalty scale factor `s` in `k = s K A^2 / V`.
    pub penalty_scale: f64,
    /// A penalty per unit area (mm): each slave's stiffness `s K A_s / L` from its tributary
    /// area `A_s` and this length `L`, instead of the master face's `s K A^2 / V` (absent). Why:
    /// per unit area the face's penalty is `s K / h` with `h` the master element's depth, so a
    /// refined insert is stiffer than the band around it and the normal force jumps where the
    /// wheel rolls onto it; with one `L` the contact's compliance is the same on both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub penalty_length_mm: Option<f64>,
    /// Rayleigh mass-proportional damping of the run (1/s).
    #[serde(default)]
    pub mass_damping_per_s: f64,
    /// Hold the sleepers' cut at the track centre laterally: the half track's plane of
    /// symmetry, which a full sleeper under a symmetric axle load has. Default false, the
    /// paper's model (Yang & Li 2019: sleeper supports constrained laterally and longitudinally,
    /// ballast vertical): there a half sleeper, held laterally only at its bottom face, tilts
    /// about the track axis as a rigid body under the off-centre wheel load, and the tilt moves
    /// the rail seat sideways (0.2 mm under the passing wheel on the demo track). With the cut
    /// held, the tilt has to bend the sleeper (data/runs/LOG.md, "What `paper` case 3 showed").
    #[serde(default)]
    pub track_centre_symmetry: bool,
    /// Static preload.
    pub preload: PreloadSpec,
    /// Single rate or multi-rate stepping of the rolling run (absent: automatic, docs/rolling.md).
    #[serde(default)]
    pub time_stepping: TimeSteppingSpec,
    /// Output.
    pub output: OutputSpec,
}

/// A case with its model scenario loaded.
pub struct LoadedCase {
    /// The case.
    pub case: RollingCase,
    /// Its model scenario.
    pub scenario: LoadedScenario,
    /// Where the case came from.
    pub source: PathBuf,
}

impl RollingCase {
    /// Checks every field; errors name the file and the field with the allowed range. One
    /// check per field, in the file's order, grouped by the part of the case they describe.
    pub fn validate(&self, source: &str) -> Result<()> {
        let c = Checker {
            source_name: source,
        };
        self.validate_vehicle_and_track(&c)?;
        self.validate_drive(&c)?;
        if let Some(l) = &self.lateral_motion {
            l.validate(source, "lateral_motion", self.end_time_s)?;
        }
        self.validate_curving(&c)?;
        self.friction.validate(source, "friction")?;
        self.validate_numerics(&c)?;
        self.time_stepping.validate(source)?;
        self.validate_output(&c)
    }

    /// Run length, speed, masses, suspension, rail pads, ballast and sleepers.
    fn validate_vehicle_and_track(&self, c: &Checker) -> Result<()> {
        c.above_at_most("end_time_s", self.end_time_s, 0.0, 1.0)?;
        c.within("speed_km_per_h", self.speed_km_per_h, 0.0, 500.0)?;
        c.positive("sprung_mass_kg", self.sprung_mass_kg)?;
        let s = &self.primary_suspension;
        c.positive("primary_suspension.stiffness_n_per_m", s.stiffness_n_per_m)?;
        c.non_negative("primary_suspension.damping_n_s_per_m", s.damping_n_s_per_m)?;
        let p = &self.rail_pad;
        c.positive("rail_pad.stiffness_n_per_m", p.stiffness_n_per_m)?;
        c.non_negative("rail_pad.damping_n_s_per_m", p.damping_n_s_per_m)?;
        c.within("rail_pad.shear_fraction", p.shear_fraction, 0.0, 1.0)?;
        let b = &self.ballast;
        c.positive("ballast.stiffness_n_per_m", b.stiffness_n_per_m)?;
        c.non_negative("ballast.damping_n_s_per_m", b.damping_n_s_per_m)?;
        let m = &self.sleeper_material;
        c.positive("sleeper_material.youngs_modulus_pa", m.youngs_modulus_pa)?;
        c.positive("sleeper_material.density_kg_per_m3", m.density_kg_per_m3)?;
        // An isotropic solid needs -1 < nu < 0.5 for a positive definite elasticity.
        c.within_open("sleeper_material.poisson_ratio", m.poisson_ratio, -1.0, 0.5)
    }

    /// The driving torque, or the prescribed creepage that replaces it.
    fn validate_drive(&self, c: &Checker) -> Result<()> {
        c.non_negative("torque.max_n_m", self.torque.max_n_m)?;
        if let Some(cr) = &self.creepage {
            c.require(self.hold_forward_speed, "hold_forward_speed", || {
                "a prescribed creepage holds the axle at the rolling speed: set \
                 hold_forward_speed to true (or leave it out), or remove creepage"
                    .into()
            })?;
            c.require(self.torque.max_n_m == 0.0, "creepage", || {
                "a prescribed creepage replaces the driving torque: set torque.max_n_m to 0".into()
            })?;
            // 10 % is far into full sliding; 0.001 is 0.1 %.
            c.within("creepage.start", cr.start, -0.1, 0.1)?;
            c.within("creepage.end", cr.end, -0.1, 0.1)?;
            c.require(
                cr.start_s >= 0.0 && cr.end_s > cr.start_s && cr.end_s <= self.end_time_s,
                "creepage.end_s",
                || {
                    format!(
                        "needs 0 <= start_s < end_s <= end_time_s (got {} .. {} s, end_time_s {} s)",
                        cr.start_s, cr.end_s, self.end_time_s
                    )
                },
            )?;
        }
        c.positive("torque.ramp_end_s", self.torque.ramp_end_s)
    }

    /// The angle of attack, and what it cannot be combined with.
    fn validate_curving(&self, c: &Checker) -> Result<()> {
        let Some(curving) = &self.curving else {
            return Ok(());
        };
        let limit = MAX_ANGLE_OF_ATTACK_MRAD;
        c.within(
            "curving.angle_of_attack_mrad",
            curving.angle_of_attack_mrad,
            -limit,
            limit,
        )?;
        c.require(self.lateral_motion.is_none(), "curving", || {
            "a yawed wheelset holds its lateral position: a case must have either \
             lateral_motion or curving, not both"
                .into()
        })?;
        c.require(self.hold_forward_speed, "hold_forward_speed", || {
            "a yawed wheelset is guided along the rail: set hold_forward_speed to true (or \
             leave it out), or remove curving"
                .into()
        })
    }

    /// The angle of attack (rad; 0 without curving).
    pub fn angle_of_attack_rad(&self) -> f64 {
        self.curving.map_or(0.0, |c| c.angle_of_attack_rad())
    }

    /// Contact penalty, damping and the static preload's settings.
    fn validate_numerics(&self, c: &Checker) -> Result<()> {
        c.above_at_most("penalty_scale", self.penalty_scale, 0.0, 100.0)?;
        if let Some(l) = self.penalty_length_mm {
            c.within("penalty_length_mm", l, 0.1, 100.0)?;
        }
        c.non_negative("mass_damping_per_s", self.mass_damping_per_s)?;
        let p = &self.preload;
        c.positive("preload.damping_per_s", p.damping_per_s)?;
        c.within_open("preload.tolerance", p.tolerance, 0.0, 1.0)?;
        c.within_open("preload.load_tolerance", p.load_tolerance, 0.0, 1.0)?;
        c.require(
            (2..=100_000_000).contains(&p.max_steps),
            "preload.max_steps",
            || format!("must be in 2..=100000000, got {}", p.max_steps),
        )?;
        if let Some(dt) = p.time_step_s {
            c.above_at_most("preload.time_step_s", dt, 0.0, 1e-4)?;
        }
        Ok(())
    }

    /// Sampling, snapshot and VTU times, and the slip threshold of the patch maps.
    fn validate_output(&self, c: &Checker) -> Result<()> {
        let o = &self.output;
        c.within("output.sample_rate_hz", o.sample_rate_hz, 100.0, 1e7)?;
        for (name, times) in [
            ("output.patch_times_s", &o.patch_times_s),
            ("output.vtu_times_s", &o.vtu_times_s),
        ] {
            for (k, t) in times.iter().enumerate() {
                c.within(&format!("{name}[{k}]"), *t, 0.0, self.end_time_s)?;
            }
        }
        c.positive("output.slip_threshold_m_per_s", o.slip_threshold_m_per_s)?;
        if let Some(ring) = &o.ring {
            c.require(
                (3..=MAX_RING_NODES).contains(&ring.nodes),
                "output.ring.nodes",
                || format!("must be in 3..={MAX_RING_NODES}, got {}", ring.nodes),
            )?;
            c.require(ring.nodes > 2 * ring.n_max, "output.ring.nodes", || {
                format!(
                    "a ring resolving n = 0..={} needs at least 2 n_max + 1 = {} nodes (the \
                     aliasing bound, docs/curving.md), got {}",
                    ring.n_max,
                    2 * ring.n_max + 1,
                    ring.nodes
                )
            })?;
        }
        Ok(())
    }

    /// Rolling speed (m/s).
    pub fn speed_m_per_s(&self) -> f64 {
        self.speed_km_per_h / 3.6
    }
}

/// The default-run case (`data/cases/case3-demo-inserts.json`), embedded: paper case 3 on the
/// demo meshes with 2 mm inserts, so that the report's patches are resolved (issue 24 item 6).
pub const EMBEDDED_DEFAULT_CASE: &str = include_str!("../../data/cases/case3-demo-inserts.json");

/// The embedded default-run case: paper case 3 on the demo meshes with 2 mm inserts (the model
/// is the embedded default scenario, `data/models/demo-inserts.json`).
pub fn embedded_default_case() -> Result<LoadedCase> {
    let source = "embedded default case (data/cases/case3-demo-inserts.json)";
    let case: RollingCase = crate::input::parse_json(EMBEDDED_DEFAULT_CASE, source)?;
    case.validate(source)?;
    let scenario = LoadedScenario::from_texts(
        crate::scenario::EMBEDDED_DEFAULT_SCENARIO,
        crate::scenario::EMBEDDED_DEFAULT_WHEEL,
        crate::scenario::EMBEDDED_DEFAULT_SCENARIO_SOURCE,
    )?;
    Ok(LoadedCase {
        case,
        scenario,
        source: PathBuf::from(source),
    })
}

/// Reads and validates a case and the model scenario it names.
pub fn load_case(path: &Path) -> Result<LoadedCase> {
    let source = path.display().to_string();
    let (text, value) = crate::input::read_json_kind(path)?;
    if value.get("model_scenario").is_none() && value.get("wheel_file").is_some() {
        return Err(Error::input(
            &source,
            "model_scenario",
            "this is a model scenario (wheel and track meshes, data/models/), not a rolling \
             case: expected a case file (data/cases/) that names it in `model_scenario`; \
             `squeal mesh --model` takes a model scenario as it is",
        ));
    }
    let case: RollingCase = crate::input::parse_json(&text, &source)?;
    case.validate(&source)?;
    let scenario_path = path
        .parent()
        .unwrap_or(Path::new("."))
        .join(&case.model_scenario);
    if !scenario_path.exists() {
        return Err(Error::input(
            &source,
            "model_scenario",
            format!("file {} does not exist", scenario_path.display()),
        ));
    }
    let scenario = LoadedScenario::from_file(&scenario_path)?;
    Ok(LoadedCase {
        case,
        scenario,
        source: path.to_path_buf(),
    })
}
