//! The one isotropic linear-elastic material every stage uses (the wheel file's steel, the
//! case file's concrete, the explicit engine's elements, the modal elements, Kalker's bodies):
//! Young's modulus, Poisson's ratio and density, with the derived constants.
//!
//! Lame's constants `lambda = E nu / ((1 + nu)(1 - 2 nu))` and `mu = G = E / (2 (1 + nu))`; the
//! dilatational wave speed `c_L = sqrt((lambda + 2 mu) / rho)` (docs/references.md, section 6);
//! the combined modulus of two identical bodies in contact `E* = E / (2 (1 - nu^2))` (Johnson,
//! Contact Mechanics, 1985; docs/references.md, section 5).

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// Isotropic linear-elastic material (SI units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus (Pa).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio (-).
    pub poisson_ratio: f64,
    /// Density (kg/m^3).
    pub density_kg_per_m3: f64,
}

impl Material {
    /// Wheel and rail steel (docs/references.md, section 3): E = 210 GPa, nu = 0.3, rho = 7850
    /// kg/m^3.
    pub const STEEL: Material = Material {
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
        density_kg_per_m3: 7850.0,
    };

    /// [`Material::STEEL`].
    pub fn steel() -> Material {
        Material::STEEL
    }

    /// An elastic body for contact theory, where only E and nu matter (the density is steel's),
    /// checked so that every formula downstream is finite: E > 0, 0 <= nu < 0.5; the errors
    /// name the command-line options `--youngs-modulus-pa` and `--poisson-ratio`.
    pub fn validated(youngs_modulus_pa: f64, poisson_ratio: f64, source: &str) -> Result<Material> {
        if !(youngs_modulus_pa.is_finite() && youngs_modulus_pa > 0.0) {
            return Err(Error::input(
                source,
                "--youngs-modulus-pa",
                format!("Young's modulus must be > 0 Pa, got {youngs_modulus_pa}"),
            ));
        }
        if !(poisson_ratio.is_finite() && (0.0..0.5).contains(&poisson_ratio)) {
            return Err(Error::input(
                source,
                "--poisson-ratio",
                format!("Poisson's ratio must be in [0, 0.5), got {poisson_ratio}"),
            ));
        }
        Ok(Material {
            youngs_modulus_pa,
            poisson_ratio,
            density_kg_per_m3: Material::STEEL.density_kg_per_m3,
        })
    }

    /// Range checks naming `field.<name>`: density > 0, E > 0, -1 < nu < 0.5.
    pub fn validate(&self, source_name: &str, field: &str) -> Result<()> {
        let bad = |name: &str, msg: String| {
            Err(Error::input(source_name, format!("{field}.{name}"), msg))
        };
        if !(self.density_kg_per_m3 > 0.0 && self.density_kg_per_m3.is_finite()) {
            return bad(
                "density_kg_per_m3",
                format!("must be > 0 (got {})", self.density_kg_per_m3),
            );
        }
        if !(self.youngs_modulus_pa > 0.0 && self.youngs_modulus_pa.is_finite()) {
            return bad(
                "youngs_modulus_pa",
                format!("must be > 0 (got {})", self.youngs_modulus_pa),
            );
        }
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return bad(
                "poisson_ratio",
                format!("must lie in (-1, 0.5) (got {})", self.poisson_ratio),
            );
        }
        Ok(())
    }

    /// Lame's first parameter lambda (Pa).
    pub fn lambda_pa(&self) -> f64 {
        let (e, nu) = (self.youngs_modulus_pa, self.poisson_ratio);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus G = mu = E / (2 (1 + nu)) (Pa).
    pub fn mu_pa(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Shear modulus G (Pa), the contact-mechanics name of [`Material::mu_pa`].
    pub fn shear_modulus_pa(&self) -> f64 {
        self.mu_pa()
    }

    /// Bulk modulus K = E / (3 (1 - 2 nu)) (Pa).
    pub fn bulk_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * self.poisson_ratio))
    }

    /// Combined modulus of two identical bodies in contact, E* = E / (2 (1 - nu^2)) (Pa).
    pub fn combined_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 - self.poisson_ratio * self.poisson_ratio))
    }

    /// Dilatational (P-wave) speed `sqrt((lambda + 2 mu) / rho)` (m/s).
    pub fn dilatational_wave_speed_m_per_s(&self) -> f64 {
        ((self.lambda_pa() + 2.0 * self.mu_pa()) / self.density_kg_per_m3).sqrt()
    }

    /// The 6x6 isotropic elasticity matrix (three normal strains, then three engineering shear
    /// strains): lambda + 2G on the normal diagonal, lambda off it, G on the shear diagonal.
    pub fn d_matrix(&self) -> [[f64; 6]; 6] {
        let (lambda, mu) = (self.lambda_pa(), self.mu_pa());
        let mut d = [[0.0; 6]; 6];
        for i in 0..3 {
            d[i][..3].fill(lambda);
            d[i][i] = lambda + 2.0 * mu;
            d[i + 3][i + 3] = mu;
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steel's constants against hand values: G = 80.77 GPa, K = 175 GPa, E* = 115.4 GPa,
    /// c_L = 6001 m/s (docs/references.md, section 6); and D's diagonal and off-diagonal.
    #[test]
    fn steel_constants_and_elasticity_matrix() {
        let s = Material::STEEL;
        assert!((s.mu_pa() - 210e9 / 2.6).abs() < 1.0);
        assert!((s.bulk_modulus_pa() - 175e9).abs() < 1.0);
        assert!((s.combined_modulus_pa() - 210e9 / 1.82).abs() < 1.0);
        assert!((s.dilatational_wave_speed_m_per_s() - 6001.0).abs() < 1.0);
        let d = s.d_matrix();
        assert_eq!(d[0][1], s.lambda_pa());
        assert_eq!(d[3][3], s.mu_pa());
        assert_eq!(d[0][0], s.lambda_pa() + 2.0 * s.mu_pa());
        let e = Material::validated(210e9, 0.5, "x").unwrap_err();
        assert!(e.to_string().contains("--poisson-ratio"), "{e}");
        let bad = Material {
            density_kg_per_m3: -1.0,
            ..s
        };
        assert!(bad
            .validate("case", "sleeper_material")
            .unwrap_err()
            .to_string()
            .contains("sleeper_material.density_kg_per_m3"));
    }
}
