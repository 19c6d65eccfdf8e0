//! The stability model of a rolling case: the wheel's modes, the track, and the settings, and
//! the analysis of one operating point (contact linearisation, coupled system, eigenvalues).

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use super::contact::{linearise, ContactFrame, TangentialLaw, TangentialModel};
use super::operating::OperatingPoint;
use super::rail::{Direction, Track};
use super::rail_modes::{rail_body, rail_modal_model, RailModalModel};
use super::system::{CoupledSystem, LinearContact, ModalBody, SystemEigen};
use super::wheel::{check_fmax, WheelDamping, WheelModes};
use crate::input::wheel::WheelSpec;
use crate::kalker::Method;
use crate::material::Material;
use crate::model::case::LoadedCase;
use crate::Result;

/// What the analysis is built with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Settings {
    /// Wheel modes up to this frequency (Hz); eigenvalues are reported up to it.
    pub fmax_hz: f64,
    /// The rail's modes are kept up to this multiple of fmax, the rest lumped (rail_modes).
    pub rail_truncation_factor: f64,
    /// Wheel modal damping.
    pub wheel_damping: WheelDamping,
    /// Split the wheel's n-diameter pairs by its rotation.
    pub rotation: bool,
    /// The tangential contact law.
    pub tangential: TangentialModel,
}

/// Rail modes to 1.5 fmax explicitly: 1-2 % rms error of the rail's receptance below fmax
/// against the direct solve (tests/stability_rail.rs), with half the coordinates of 2 fmax.
pub const RAIL_TRUNCATION_FACTOR: f64 = 1.5;

/// The band the rail's beam model is meant for (Hz): above about 5 kHz the real rail's
/// cross-section deforms (web bending, foot flapping), which a beam does not have.
pub const RAIL_BAND_HZ: f64 = 5000.0;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            fmax_hz: 5000.0,
            rail_truncation_factor: RAIL_TRUNCATION_FACTOR,
            wheel_damping: WheelDamping::default(),
            rotation: false,
            tangential: TangentialModel::Kalker {
                method: Method::Exact,
                elements: 24,
            },
        }
    }
}

/// The model of a case.
pub struct StabilityModel {
    /// The wheel's modes.
    pub wheel: WheelModes,
    /// The track.
    pub track: Track,
    /// Wheel and rail steel for Hertz and Kalker.
    pub material: Material,
    /// Settings.
    pub settings: Settings,
}

/// The wheel file of a case (its own section mesh, not the scenario's 3D mesh override).
pub fn wheel_file(loaded: &LoadedCase) -> PathBuf {
    Path::new(&loaded.scenario.source_name)
        .parent()
        .unwrap_or(Path::new("."))
        .join(&loaded.scenario.scenario.wheel_file)
}

/// One operating point analysed.
#[derive(Clone, Debug, Serialize)]
pub struct PointAnalysis {
    /// The linearised law.
    pub law: TangentialLaw,
    /// The contact matrices in global axes.
    pub contact: LinearContact,
    /// Eigenvalues up to fmax, by frequency.
    pub eigen: Vec<SystemEigen>,
    /// Coupled second-order coordinates (wheel + rail).
    pub coordinates: usize,
    /// Wall time of linearisation + eigen solution (s).
    pub seconds: f64,
}

impl PointAnalysis {
    /// The growing eigenvalues, largest growth first.
    pub fn unstable(&self) -> Vec<&SystemEigen> {
        let mut out: Vec<&SystemEigen> = self.eigen.iter().filter(|e| e.unstable()).collect();
        out.sort_by(|a, b| b.growth_rate_per_s.total_cmp(&a.growth_rate_per_s));
        out
    }
}

impl StabilityModel {
    /// Solve the case's wheel to `settings.fmax_hz` and set up its track.
    pub fn build(loaded: &LoadedCase, settings: Settings) -> Result<StabilityModel> {
        check_fmax(settings.fmax_hz, "--fmax-hz")?;
        let path = wheel_file(loaded);
        let spec: WheelSpec = crate::input::read_json(&path)?;
        spec.validate(&path.display().to_string())?;
        let wheel = WheelModes::solve(&spec, settings.fmax_hz)?;
        Ok(StabilityModel {
            wheel,
            track: Track::from_case(loaded)?,
            // Validated with the wheel file above.
            material: spec.material,
            settings,
        })
    }

    /// The rail's modal models and body with the wheel at `wheel_x_m` along the rail and the
    /// contact `contact_offset_m` off the rail's centre line (the operating point's
    /// `contact_rail_y_m`).
    pub fn rail(
        &self,
        wheel_x_m: f64,
        contact_offset_m: f64,
    ) -> Result<(ModalBody, Vec<RailModalModel>)> {
        // The beam model stands for the rail below RAIL_BAND_HZ only (no cross-section
        // deformation), so more rail modes would add coordinates, not accuracy.
        let truncation =
            self.settings.rail_truncation_factor * self.settings.fmax_hz.min(RAIL_BAND_HZ);
        let models: Vec<RailModalModel> = Direction::ALL
            .iter()
            .map(|&d| rail_modal_model(&self.track, d, wheel_x_m, truncation))
            .collect::<Result<_>>()?;
        Ok((rail_body(&models, contact_offset_m), models))
    }

    /// The wheel's body at the operating point's contact.
    pub fn wheel_body(&self, op: &OperatingPoint) -> Result<ModalBody> {
        let spin = self
            .settings
            .rotation
            .then(|| op.speed_m_per_s / op.rolling_radius_m);
        self.wheel.contact_body(
            op.contact_s_mm,
            self.settings.fmax_hz,
            &self.settings.wheel_damping,
            spin,
        )
    }

    /// Linearise at `op` and solve the coupled system of `wheel` and `rail`.
    pub fn analyse(
        &self,
        op: &OperatingPoint,
        wheel: &ModalBody,
        rail: &ModalBody,
    ) -> Result<PointAnalysis> {
        let t0 = Instant::now();
        let law = linearise(&op.contact_state(self.material), self.settings.tangential)?;
        let contact = law.linear_contact(&ContactFrame::wheel_rail(op.contact_angle_deg));
        let system = CoupledSystem {
            wheel: wheel.clone(),
            rail: rail.clone(),
            contact,
        };
        let fmax = self.settings.fmax_hz;
        let eigen: Vec<SystemEigen> = system
            .eigen()?
            .into_iter()
            .filter(|e| e.frequency_hz <= fmax)
            .collect();
        Ok(PointAnalysis {
            law,
            contact,
            eigen,
            coordinates: system.len(),
            seconds: t0.elapsed().as_secs_f64(),
        })
    }
}
