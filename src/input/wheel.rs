//! Parametric wheel (and half-axle) cross-section, read from `data/wheels/*.json`.
//!
//! Section coordinates: lateral `S` (mm) as in the S1002 definition (0 at the tape circle,
//! negative towards the flange, i.e. towards the track centre) and radius `r` (mm) from the axle
//! axis. The rim carries the S1002 tread over its full 135 mm width; the web joins rim and hub;
//! the hub sits on the wheel seat of the half axle, which runs from the track centre plane to
//! the journal end.

use serde::{Deserialize, Serialize};

use super::Checker;
use crate::geometry::s1002;
use crate::Result;

/// Web shape in the section.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum WebShape {
    /// Straight line from the hub centre to the rim centre (slanted if they differ).
    Straight,
    /// S-shaped (smoothstep) centre line, perpendicular to rim and hub at both ends.
    Curved,
}

/// Web of the wheel.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WebSpec {
    /// Shape of the centre line.
    pub shape: WebShape,
    /// Lateral position S of the web centre where it meets the rim (mm).
    pub centre_at_rim_mm: f64,
    /// Lateral position S of the web centre where it meets the hub (mm).
    pub centre_at_hub_mm: f64,
    /// Thickness at the rim (mm).
    pub thickness_at_rim_mm: f64,
    /// Thickness at the hub (mm).
    pub thickness_at_hub_mm: f64,
}

/// Hub of the wheel.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HubSpec {
    /// Bore radius = wheel-seat radius of the axle (mm).
    pub bore_radius_mm: f64,
    /// Outer radius (mm).
    pub outer_radius_mm: f64,
    /// Lateral start of the hub (S, mm; towards the track centre).
    pub s_min_mm: f64,
    /// Lateral end of the hub (S, mm; field side).
    pub s_max_mm: f64,
}

/// Half axle: radius as a piecewise-linear function of S.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AxleSpec {
    /// `[S_mm, radius_mm]` points, S strictly increasing; the first point is the track-centre
    /// (symmetry) plane, the last the journal end; the radius equals the hub bore over the hub.
    pub profile_mm: Vec<[f64; 2]>,
    /// Lateral position of the bearing centre (S, mm), where the primary suspension acts.
    pub bearing_centre_s_mm: f64,
}

/// Linear elastic isotropic material: the crate's one material type.
pub use crate::material::Material as MaterialSpec;

/// Validate a wheel material (E > 0, -1 < nu < 0.5, rho > 0), naming `prefix.<field>`.
fn check_material(m: &MaterialSpec, c: &Checker, prefix: &str) -> Result<()> {
    c.positive(&format!("{prefix}.youngs_modulus_pa"), m.youngs_modulus_pa)?;
    c.within(
        &format!("{prefix}.poisson_ratio"),
        m.poisson_ratio,
        -0.999,
        0.499,
    )?;
    c.positive(&format!("{prefix}.density_kg_per_m3"), m.density_kg_per_m3)
}

/// Mesh settings of the wheel body.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WheelMeshSpec {
    /// Target element size in the section (mm).
    pub element_size_mm: f64,
    /// Circumferential divisions of the rim and outer web (multiple of 8, at least 8).
    pub circumferential_divisions: usize,
    /// Circumferential divisions of the inner zone (inner web, hub, axle), multiple of 8, at
    /// most `circumferential_divisions`. Fewer divisions near the axis keep the hub and axle
    /// elements from shrinking with the radius (and the explicit time step with them); the two
    /// zones are joined by a tied interface in the web.
    pub inner_circumferential_divisions: usize,
    /// Where the web is split between the zones: fraction of the web height from the hub.
    #[serde(default = "default_web_split")]
    pub web_split_fraction: f64,
}

fn default_web_split() -> f64 {
    0.5
}

/// A wheel (with optional half axle).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WheelSpec {
    /// Name.
    pub name: String,
    /// What it is and where the numbers come from.
    #[serde(default)]
    pub description: String,
    /// Nominal (tape circle) radius (mm).
    pub nominal_radius_mm: f64,
    /// Inner radius of the rim, where the web starts (mm).
    pub rim_inner_radius_mm: f64,
    /// Web.
    pub web: WebSpec,
    /// Hub.
    pub hub: HubSpec,
    /// Half axle (absent: wheel only, e.g. for a hammer test on a free or hub-clamped wheel).
    pub axle: Option<AxleSpec>,
    /// Material.
    pub material: MaterialSpec,
    /// Mesh settings.
    pub mesh: WheelMeshSpec,
}

/// Rim width from the flange back to the field face (mm).
pub const RIM_WIDTH_MM: f64 = s1002::S_FIELD_FACE_MM - s1002::S_FLANGE_BACK_MM;

impl WheelSpec {
    /// Check every field against its allowed range; errors name `source_name` and the field.
    ///
    /// The checks run part by part (radius and rim, web, hub, axle profile, material and mesh),
    /// in the file's order, so the first failing field is the one reported.
    pub fn validate(&self, source_name: &str) -> Result<()> {
        let c = Checker { source_name };
        self.check_radius_and_rim(&c)?;
        self.check_web(&c)?;
        self.check_hub(&c)?;
        if let Some(axle) = &self.axle {
            self.check_axle(axle, &c)?;
        }
        self.check_material_and_mesh(&c)
    }

    /// Nominal radius and rim inner radius: the rim must leave room for the hub below it and
    /// for the tread above it (20 mm each way), so the web has a height to span.
    fn check_radius_and_rim(&self, c: &Checker) -> Result<()> {
        c.within("nominal_radius_mm", self.nominal_radius_mm, 200.0, 1000.0)?;
        let tread_min_radius = self.nominal_radius_mm + s1002::height_mm(s1002::S_FIELD_FACE_MM);
        c.within(
            "rim_inner_radius_mm",
            self.rim_inner_radius_mm,
            self.hub.outer_radius_mm + 20.0,
            tread_min_radius - 20.0,
        )
    }

    /// Web thicknesses and where the web meets the rim: the web must fit within the rim's
    /// width (5 mm clear of either face), so the rim zone of the mesh has material on both
    /// sides of the web.
    fn check_web(&self, c: &Checker) -> Result<()> {
        let w = &self.web;
        c.within(
            "web.thickness_at_rim_mm",
            w.thickness_at_rim_mm,
            1.0,
            RIM_WIDTH_MM - 10.0,
        )
        .map_err(|e| {
            with_hint(
                e,
                "the web must be thinner than the rim (135 mm) by at least 10 mm",
            )
        })?;
        c.within(
            "web.thickness_at_hub_mm",
            w.thickness_at_hub_mm,
            1.0,
            self.hub.s_max_mm - self.hub.s_min_mm,
        )?;
        let rim_lo = s1002::S_FLANGE_BACK_MM + 5.0;
        let rim_hi = s1002::S_FIELD_FACE_MM - 5.0;
        c.require(
            w.centre_at_rim_mm - 0.5 * w.thickness_at_rim_mm >= rim_lo && w.centre_at_rim_mm + 0.5 * w.thickness_at_rim_mm <= rim_hi,
            "web.centre_at_rim_mm",
            || format!("web at the rim must lie within S = [{rim_lo}, {rim_hi}] mm, got centre {} with thickness {}", w.centre_at_rim_mm, w.thickness_at_rim_mm),
        )
    }

    /// Hub radii and width, then where the web meets the hub: the web seat is checked after
    /// the hub's own extent (3 mm clear of either end), since it is measured against it.
    fn check_hub(&self, c: &Checker) -> Result<()> {
        let w = &self.web;
        let h = &self.hub;
        c.positive("hub.bore_radius_mm", h.bore_radius_mm)?;
        c.within(
            "hub.outer_radius_mm",
            h.outer_radius_mm,
            h.bore_radius_mm + 10.0,
            self.rim_inner_radius_mm - 20.0,
        )?;
        c.require(h.s_max_mm > h.s_min_mm + 20.0, "hub.s_max_mm", || {
            format!(
                "must exceed hub.s_min_mm + 20 = {} mm, got {}",
                h.s_min_mm + 20.0,
                h.s_max_mm
            )
        })?;
        let hub_lo = h.s_min_mm + 3.0;
        let hub_hi = h.s_max_mm - 3.0;
        c.require(
            w.centre_at_hub_mm - 0.5 * w.thickness_at_hub_mm >= hub_lo && w.centre_at_hub_mm + 0.5 * w.thickness_at_hub_mm <= hub_hi,
            "web.centre_at_hub_mm",
            || format!("web at the hub must lie within S = [{hub_lo}, {hub_hi}] mm, got centre {} with thickness {}", w.centre_at_hub_mm, w.thickness_at_hub_mm),
        )
    }

    /// The half-axle profile: positive radii no larger than the hub bore, S strictly
    /// increasing, reaching 10 mm past the hub on both sides with the bore radius over the hub
    /// (the hub sits on the wheel seat), and the bearing centre between the hub and the journal
    /// end.
    fn check_axle(&self, axle: &AxleSpec, c: &Checker) -> Result<()> {
        let h = &self.hub;
        let p = &axle.profile_mm;
        c.require(p.len() >= 2, "axle.profile_mm", || {
            "needs at least two [S_mm, radius_mm] points".into()
        })?;
        for (i, pt) in p.iter().enumerate() {
            c.positive(&format!("axle.profile_mm[{i}][1]"), pt[1])?;
            c.require(
                pt[1] <= h.bore_radius_mm + 1e-9,
                &format!("axle.profile_mm[{i}][1]"),
                || {
                    format!(
                        "axle radius must not exceed the hub bore radius {} mm, got {}",
                        h.bore_radius_mm, pt[1]
                    )
                },
            )?;
            if i > 0 {
                c.require(
                    pt[0] > p[i - 1][0],
                    &format!("axle.profile_mm[{i}][0]"),
                    || {
                        format!(
                            "S must increase strictly along the axle, got {} after {}",
                            pt[0],
                            p[i - 1][0]
                        )
                    },
                )?;
            }
        }
        c.require(p[0][0] < h.s_min_mm - 10.0 && p[p.len() - 1][0] > h.s_max_mm + 10.0, "axle.profile_mm", || {
            format!("the axle must extend at least 10 mm beyond the hub on both sides (hub S = [{}, {}] mm)", h.s_min_mm, h.s_max_mm)
        })?;
        for s in [h.s_min_mm, h.s_max_mm, 0.5 * (h.s_min_mm + h.s_max_mm)] {
            let r = axle_radius_mm(p, s);
            c.require((r - h.bore_radius_mm).abs() < 1e-6, "axle.profile_mm", || {
                format!("the axle radius over the hub (S = {s} mm) must equal the hub bore radius {} mm, got {r}", h.bore_radius_mm)
            })?;
        }
        c.within(
            "axle.bearing_centre_s_mm",
            axle.bearing_centre_s_mm,
            h.s_max_mm,
            p[p.len() - 1][0],
        )
    }

    /// Material constants and mesh settings: the division counts are multiples of 8 because
    /// the axle core is an O-grid with a quarter of them per side, and the inner zone may not
    /// be finer than the outer one it is tied to.
    fn check_material_and_mesh(&self, c: &Checker) -> Result<()> {
        check_material(&self.material, c, "material")?;
        c.within("mesh.element_size_mm", self.mesh.element_size_mm, 0.5, 60.0)?;
        let n = self.mesh.circumferential_divisions;
        c.require(n >= 8 && n.is_multiple_of(8) && n <= 20000, "mesh.circumferential_divisions", || {
            format!("must be a multiple of 8 in [8, 20000] (the axle core is an O-grid with a quarter of them per side), got {n}")
        })?;
        let ni = self.mesh.inner_circumferential_divisions;
        c.require(ni >= 8 && ni.is_multiple_of(8) && ni <= n, "mesh.inner_circumferential_divisions", || {
            format!("must be a multiple of 8 in [8, mesh.circumferential_divisions = {n}], got {ni}")
        })?;
        c.within(
            "mesh.web_split_fraction",
            self.mesh.web_split_fraction,
            0.1,
            0.9,
        )?;
        Ok(())
    }

    /// Radius of the tread at lateral position S (mm).
    pub fn tread_radius_mm(&self, s_mm: f64) -> f64 {
        self.nominal_radius_mm + s1002::height_mm(s_mm)
    }

    /// Web centre S and thickness at fraction `t` from the hub (0) to the rim (1).
    pub fn web_at(&self, t: f64) -> (f64, f64) {
        let w = &self.web;
        let blend = match w.shape {
            WebShape::Straight => t,
            WebShape::Curved => t * t * (3.0 - 2.0 * t),
        };
        let centre = w.centre_at_hub_mm + (w.centre_at_rim_mm - w.centre_at_hub_mm) * blend;
        let thickness = w.thickness_at_hub_mm + (w.thickness_at_rim_mm - w.thickness_at_hub_mm) * t;
        (centre, thickness)
    }
}

fn with_hint(e: crate::Error, hint: &str) -> crate::Error {
    match e {
        crate::Error::Input {
            source_name,
            field,
            message,
        } => crate::Error::Input {
            source_name,
            field,
            message: format!("{message} ({hint})"),
        },
        other => other,
    }
}

/// Axle radius (mm) at S (mm) by linear interpolation of the profile (clamped at the ends).
pub fn axle_radius_mm(profile: &[[f64; 2]], s_mm: f64) -> f64 {
    if s_mm <= profile[0][0] {
        return profile[0][1];
    }
    for w in profile.windows(2) {
        if s_mm <= w[1][0] {
            let t = (s_mm - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + t * (w[1][1] - w[0][1]);
        }
    }
    profile[profile.len() - 1][1]
}

/// The closed outline of the wheel body section (rim, web, hub; without the axle) as a polygon
/// in (S, r) mm, counter-clockwise, for exact area/centroid (Pappus) checks.
pub fn body_outline_mm(spec: &WheelSpec, step_mm: f64) -> Vec<[f64; 2]> {
    let mut pts = Vec::new();
    let r_in = spec.rim_inner_radius_mm;
    // Hub bottom (bore), left to right.
    pts.push([spec.hub.s_min_mm, spec.hub.bore_radius_mm]);
    pts.push([spec.hub.s_max_mm, spec.hub.bore_radius_mm]);
    pts.push([spec.hub.s_max_mm, spec.hub.outer_radius_mm]);
    // Right web face, hub to rim.
    let n_web = 200;
    for i in 0..=n_web {
        let (c, t) = spec.web_at(i as f64 / n_web as f64);
        let r =
            spec.hub.outer_radius_mm + (r_in - spec.hub.outer_radius_mm) * i as f64 / n_web as f64;
        pts.push([c + 0.5 * t, r]);
    }
    pts.push([s1002::S_FIELD_FACE_MM, r_in]);
    // Tread from the field face to the flange back.
    let mut s = s1002::S_FIELD_FACE_MM;
    while s > s1002::S_FLANGE_BACK_MM {
        pts.push([s, spec.tread_radius_mm(s)]);
        s -= step_mm;
    }
    pts.push([
        s1002::S_FLANGE_BACK_MM,
        spec.tread_radius_mm(s1002::S_FLANGE_BACK_MM),
    ]);
    pts.push([s1002::S_FLANGE_BACK_MM, r_in]);
    // Left web face, rim to hub.
    for i in (0..=n_web).rev() {
        let (c, t) = spec.web_at(i as f64 / n_web as f64);
        let r =
            spec.hub.outer_radius_mm + (r_in - spec.hub.outer_radius_mm) * i as f64 / n_web as f64;
        pts.push([c - 0.5 * t, r]);
    }
    pts.push([spec.hub.s_min_mm, spec.hub.outer_radius_mm]);
    pts
}
