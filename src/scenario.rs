//! Model scenario files (`data/models/*.json`): which wheel, how it is meshed, the track and where
//! the wheel stands on it. Paths inside a scenario are relative to the scenario file. Every
//! field is checked; errors name the file, the field and the allowed range.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::geometry::{rail54e1, s1002};
use crate::input::wheel::{WheelMeshSpec, WheelSpec};
use crate::input::{parse_json, read_json, Checker};
use crate::mesh::track::{track_mesh, RailZone, TrackLayout};
use crate::mesh::wheel::{wheel_mesh, TreadBandSpec, WheelPlacement};
use crate::mesh::Mesh;
use crate::{Error, Result};

/// Rail settings.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RailSpec {
    /// Section element size at the running surface (mm).
    pub running_surface_element_mm: f64,
    /// Section element size in web and foot (mm).
    pub section_element_mm: f64,
    /// Largest element length along the track (mm).
    pub far_element_length_mm: f64,
    /// Growth ratio of the element length away from the solution zone.
    pub growth_ratio: f64,
}

/// The finely meshed stretch of rail.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolutionZoneSpec {
    /// Start along the track (m).
    pub start_m: f64,
    /// Length (m).
    pub length_m: f64,
    /// Element length along the track inside the zone (mm).
    pub element_length_mm: f64,
}

impl SolutionZoneSpec {
    /// Check a rail zone named `name` (`solution_zone`, `running_zone`): positive length,
    /// element length in `[min_element_mm, max_element_mm]`, inside the track.
    fn validate(
        &self,
        c: &Checker,
        name: &str,
        min_element_mm: f64,
        max_element_mm: f64,
        track_length_m: f64,
    ) -> Result<()> {
        c.positive(&format!("track.{name}.length_m"), self.length_m)?;
        c.within(
            &format!("track.{name}.element_length_mm"),
            self.element_length_mm,
            min_element_mm,
            max_element_mm,
        )?;
        let end_m = self.start_m + self.length_m;
        c.require(
            self.start_m >= 0.0 && end_m <= track_length_m,
            &format!("track.{name}.start_m"),
            || {
                format!(
                    "the {} [{}, {}] m must lie inside the track [0, {}] m",
                    name.replace('_', " "),
                    self.start_m,
                    end_m,
                    track_length_m
                )
            },
        )
    }
}

/// Sleeper blocks and rail pads.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SleeperSpec {
    /// Width along the track (m).
    pub width_m: f64,
    /// Height (m).
    pub height_m: f64,
    /// Length from the track centre to the sleeper end (m) (half sleeper: half track).
    pub half_length_m: f64,
    /// Element divisions along x, y, z (about 12 elements per sleeper).
    pub divisions: [usize; 3],
    /// Rail pad thickness (mm).
    pub pad_thickness_mm: f64,
    /// Rail pad length along the track (mm).
    pub pad_length_mm: f64,
}

/// Track settings.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSpec {
    /// Track length (m).
    pub length_m: f64,
    /// Sleeper spacing (m).
    pub sleeper_spacing_m: f64,
    /// Position of the first sleeper centre (m).
    pub first_sleeper_x_m: f64,
    /// Rail.
    pub rail: RailSpec,
    /// Solution zone.
    pub solution_zone: SolutionZoneSpec,
    /// A medium-size stretch over the whole rolling path, containing or beside the solution
    /// zone (absent: the rail grows from the solution zone to the far size).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub running_zone: Option<SolutionZoneSpec>,
    /// A finer block tied into the rail's running band where contact patches are resolved
    /// (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rail_insert: Option<crate::mesh::track::RailInsertSpec>,
    /// Sleepers and pads.
    pub sleeper: SleeperSpec,
}

/// Where the wheel stands.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WheelPositionSpec {
    /// Axle position along the track (m).
    pub x_m: f64,
    /// Lateral position of the tape circle relative to the rail section origin (crown top of
    /// the upright rail) (mm); positive towards the field side.
    pub tape_circle_y_mm: f64,
    /// Initial vertical gap between wheel and rail at the closest point (mm).
    pub initial_gap_mm: f64,
}

/// A scenario.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Name (used for output folders).
    pub name: String,
    /// What the scenario is for and where its numbers come from.
    #[serde(default)]
    pub description: String,
    /// Wheel file, relative to the scenario file.
    pub wheel_file: String,
    /// Overrides the wheel file's mesh settings.
    #[serde(default)]
    pub wheel_mesh: Option<WheelMeshSpec>,
    /// Fine tread band (absent: the wheel body's own mesh is in contact).
    #[serde(default)]
    pub tread_band: Option<TreadBandSpec>,
    /// Wheel position.
    pub wheel_position: WheelPositionSpec,
    /// Track.
    pub track: TrackSpec,
}

/// Lateral distance from the rail section origin to the track centre (m): gauge 1435 mm
/// between gauge faces plus half the 70 mm head, `-(717.5 + 35) mm` (EN 13674-1, 54E1).
pub const TRACK_CENTRE_FROM_RAIL_Y_M: f64 = -0.7525;

/// A scenario with its wheel loaded and checked.
#[derive(Clone, Debug)]
pub struct LoadedScenario {
    /// The scenario.
    pub scenario: Scenario,
    /// The wheel (with the scenario's mesh override applied).
    pub wheel: WheelSpec,
    /// Where the scenario came from (file path or "embedded default").
    pub source_name: String,
}

/// The embedded default scenario (`data/models/demo-inserts.json`: the demo meshes with 2 mm
/// inserts where the default case's wheel rolls over the paper's snapshots, issue 24 item 6)
/// and the wheel it uses.
pub const EMBEDDED_DEFAULT_SCENARIO: &str = include_str!("../data/models/demo-inserts.json");
/// Where [`EMBEDDED_DEFAULT_SCENARIO`] came from, for messages.
pub const EMBEDDED_DEFAULT_SCENARIO_SOURCE: &str =
    "embedded default scenario (data/models/demo-inserts.json)";
/// The embedded default wheel.
pub const EMBEDDED_DEFAULT_WHEEL: &str = include_str!("../data/wheels/ns_intercity_920.json");

impl LoadedScenario {
    /// Load a scenario file and its wheel. A rolling case file (`data/cases/`) is accepted in
    /// its place: it names its model scenario (`model_scenario`), which is loaded.
    pub fn from_file(path: &Path) -> Result<Self> {
        let source_name = path.display().to_string();
        let (text, value) = crate::input::read_json_kind(path)?;
        if let Some(model) = value.get("model_scenario").and_then(|m| m.as_str()) {
            let model_path = path.parent().unwrap_or(Path::new(".")).join(model);
            let (_, model_value) = crate::input::read_json_kind(&model_path)?;
            if model_value.get("model_scenario").is_some() {
                return Err(Error::input(
                    &source_name,
                    "model_scenario",
                    format!(
                        "names {}, which is a case file too: it must name a model scenario \
                         (data/models/)",
                        model_path.display()
                    ),
                ));
            }
            return Self::from_file(&model_path);
        }
        let scenario: Scenario = crate::input::parse_json(&text, &source_name)?;
        let wheel_path: PathBuf = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(&scenario.wheel_file);
        if !wheel_path.exists() {
            return Err(Error::input(
                &source_name,
                "wheel_file",
                format!("file {} does not exist", wheel_path.display()),
            ));
        }
        let wheel: WheelSpec = read_json(&wheel_path)?;
        wheel.validate(&wheel_path.display().to_string())?;
        Self::finish(scenario, wheel, source_name)
    }

    /// A scenario given as JSON text with its wheel as JSON text (for embedded inputs).
    pub fn from_texts(scenario_json: &str, wheel_json: &str, source_name: &str) -> Result<Self> {
        let scenario: Scenario = parse_json(scenario_json, source_name)?;
        let wheel: WheelSpec = parse_json(wheel_json, &format!("{source_name} (wheel)"))?;
        wheel.validate(&format!("{source_name} (wheel)"))?;
        Self::finish(scenario, wheel, source_name.to_string())
    }

    /// The embedded default scenario (the demo meshes with 2 mm inserts).
    pub fn embedded_default() -> Result<Self> {
        let source_name = EMBEDDED_DEFAULT_SCENARIO_SOURCE.to_string();
        let scenario: Scenario = parse_json(EMBEDDED_DEFAULT_SCENARIO, &source_name)?;
        let wheel: WheelSpec = parse_json(EMBEDDED_DEFAULT_WHEEL, "embedded default wheel")?;
        Self::finish(scenario, wheel, source_name)
    }

    fn finish(scenario: Scenario, mut wheel: WheelSpec, source_name: String) -> Result<Self> {
        if let Some(m) = &scenario.wheel_mesh {
            wheel.mesh = m.clone();
            wheel.validate(&format!("{source_name} (wheel_mesh)"))?;
        }
        let loaded = LoadedScenario {
            scenario,
            wheel,
            source_name,
        };
        loaded.validate()?;
        Ok(loaded)
    }

    /// Check every scenario field.
    pub fn validate(&self) -> Result<()> {
        let s = &self.scenario;
        let c = Checker {
            source_name: &self.source_name,
        };
        let t = &s.track;
        c.within("track.length_m", t.length_m, 0.5, 200.0)?;
        c.within("track.sleeper_spacing_m", t.sleeper_spacing_m, 0.3, 2.0)?;
        c.within(
            "track.first_sleeper_x_m",
            t.first_sleeper_x_m,
            0.0,
            t.length_m,
        )?;
        c.within(
            "track.rail.running_surface_element_mm",
            t.rail.running_surface_element_mm,
            0.3,
            20.0,
        )?;
        c.within(
            "track.rail.section_element_mm",
            t.rail.section_element_mm,
            t.rail.running_surface_element_mm,
            30.0,
        )?;
        c.within(
            "track.rail.far_element_length_mm",
            t.rail.far_element_length_mm,
            t.solution_zone.element_length_mm,
            1000.0,
        )?;
        c.within("track.rail.growth_ratio", t.rail.growth_ratio, 1.01, 2.0)?;
        let z = &t.solution_zone;
        z.validate(&c, "solution_zone", 0.2, 100.0, t.length_m)?;
        if let Some(r) = &t.running_zone {
            r.validate(
                &c,
                "running_zone",
                z.element_length_mm,
                t.rail.far_element_length_mm,
                t.length_m,
            )?;
        }
        if let Some(ins) = &t.rail_insert {
            ins.validate(
                &c,
                "track.rail_insert",
                t.rail.running_surface_element_mm,
                t.rail.section_element_mm,
                t.length_m,
            )?;
        }
        let sl = &t.sleeper;
        c.within(
            "track.sleeper.width_m",
            sl.width_m,
            0.05,
            t.sleeper_spacing_m,
        )?;
        c.within("track.sleeper.height_m", sl.height_m, 0.05, 1.0)?;
        c.within(
            "track.sleeper.half_length_m",
            sl.half_length_m,
            -TRACK_CENTRE_FROM_RAIL_Y_M + 0.1,
            3.0,
        )?;
        for (k, &d) in sl.divisions.iter().enumerate() {
            c.require(
                (1..=50).contains(&d),
                &format!("track.sleeper.divisions[{k}]"),
                || format!("must be in [1, 50], got {d}"),
            )?;
        }
        c.within(
            "track.sleeper.pad_thickness_mm",
            sl.pad_thickness_mm,
            0.5,
            50.0,
        )?;
        c.within(
            "track.sleeper.pad_length_mm",
            sl.pad_length_mm,
            10.0,
            1000.0 * sl.width_m,
        )?;
        let w = &s.wheel_position;
        c.within("wheel_position.x_m", w.x_m, 0.5, t.length_m - 0.5)?;
        c.within(
            "wheel_position.tape_circle_y_mm",
            w.tape_circle_y_mm,
            -30.0,
            30.0,
        )?;
        c.within("wheel_position.initial_gap_mm", w.initial_gap_mm, 0.0, 5.0)?;
        if let Some(b) = &s.tread_band {
            b.validate(&self.source_name, "tread_band", &self.wheel)?;
        }
        Ok(())
    }

    /// The track layout of this scenario.
    pub fn track_layout(&self) -> TrackLayout {
        let t = &self.scenario.track;
        TrackLayout {
            length_m: t.length_m,
            rail_origin_y_m: 0.0,
            rail_origin_z_m: 0.0,
            solution_zone_start_m: t.solution_zone.start_m,
            solution_zone_length_m: t.solution_zone.length_m,
            zone_element_length_m: t.solution_zone.element_length_mm * 1e-3,
            running_zone: t.running_zone.as_ref().map(|r| RailZone {
                start_m: r.start_m,
                length_m: r.length_m,
                element_length_m: r.element_length_mm * 1e-3,
            }),
            far_element_length_m: t.rail.far_element_length_mm * 1e-3,
            growth_ratio: t.rail.growth_ratio,
            running_surface_element_mm: t.rail.running_surface_element_mm,
            section_element_mm: t.rail.section_element_mm,
            sleeper_spacing_m: t.sleeper_spacing_m,
            first_sleeper_x_m: t.first_sleeper_x_m,
            sleeper_width_m: t.sleeper.width_m,
            sleeper_height_m: t.sleeper.height_m,
            sleeper_y_min_m: TRACK_CENTRE_FROM_RAIL_Y_M,
            sleeper_y_max_m: TRACK_CENTRE_FROM_RAIL_Y_M + t.sleeper.half_length_m,
            sleeper_divisions: t.sleeper.divisions,
            pad_thickness_m: t.sleeper.pad_thickness_mm * 1e-3,
            pad_length_m: t.sleeper.pad_length_mm * 1e-3,
            rail_insert: t.rail_insert.clone(),
        }
    }

    /// Wheel placement: the tape circle centre height is chosen so that the closest point of
    /// the S1002 tread and the inclined 54E1 crown are `initial_gap_mm` apart.
    pub fn wheel_placement(&self) -> WheelPlacement {
        let w = &self.scenario.wheel_position;
        let layout = self.track_layout();
        let y_tape = w.tape_circle_y_mm * 1e-3;
        // Dense points of the inclined rail head top.
        let mut centre_z = f64::NEG_INFINITY;
        let mut y_mm = -36.0;
        while y_mm <= 36.0 {
            if let Some(z_mm) = rail54e1::top_surface_z_mm(y_mm) {
                let [y, z] = crate::mesh::track::place_rail_point(&layout, y_mm, z_mm);
                let s_mm = (y - y_tape) * 1e3;
                if (s1002::S_FLANGE_BACK_MM..=s1002::S_FIELD_FACE_MM).contains(&s_mm) {
                    let r = self.wheel.tread_radius_mm(s_mm) * 1e-3;
                    centre_z = centre_z.max(z + r);
                }
            }
            y_mm += 0.01;
        }
        WheelPlacement {
            tape_circle_centre_m: [w.x_m, y_tape, centre_z + w.initial_gap_mm * 1e-3],
        }
    }

    /// Build the whole model mesh: wheel (with its half axle and optional tread band) + track.
    pub fn model_mesh(&self) -> Mesh {
        let mut mesh = wheel_mesh(
            &self.wheel,
            self.scenario.tread_band.as_ref(),
            &self.wheel_placement(),
        );
        let track = track_mesh(&self.track_layout());
        // Keep the wheel's sets distinct from the track's by prefix.
        mesh.node_sets = std::mem::take(&mut mesh.node_sets)
            .into_iter()
            .map(|(k, v)| (prefixed(&k), v))
            .collect();
        mesh.surfaces = std::mem::take(&mut mesh.surfaces)
            .into_iter()
            .map(|(k, v)| (prefixed(&k), v))
            .collect();
        mesh.append(track);
        mesh
    }
}

fn prefixed(name: &str) -> String {
    if name.starts_with("wheel_") || name.starts_with("axle_") || name.starts_with("hub_") {
        name.to_string()
    } else {
        format!("wheel_{name}")
    }
}
