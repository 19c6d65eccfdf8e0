//! How a contact enforces its conditions: a case field (`contact_enforcement`) that the
//! contact stage reads ([`crate::contact`], `contact::exact`).

use serde::{Deserialize, Serialize};

/// How the contact conditions are enforced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Enforcement {
    /// Penalty springs (normal `k g`, tangential elastic stick `k de`; the paper's).
    #[default]
    Penalty,
    /// Forward-increment Lagrange multipliers (`contact::exact`).
    Exact,
}

impl Enforcement {
    /// The word a case file uses.
    pub fn word(self) -> &'static str {
        match self {
            Enforcement::Penalty => "penalty",
            Enforcement::Exact => "exact",
        }
    }
}
