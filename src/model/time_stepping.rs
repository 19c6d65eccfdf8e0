//! How a rolling case steps in time (`time_stepping` in a case file): single rate, or
//! multi-rate (subcycled) over levels of stable step a power of two apart
//! (`crate::explicit::levels`, `crate::explicit::multirate`), chosen automatically by default.
//!
//! The automatic choice (`"multi_rate": "auto"`) is made on the built model by
//! `rolling::stepping`. Today it is always single rate: the engine's subcycling is
//! resonance-unstable on some meshes (tests/explicit_multirate_stability.rs), so `auto` only
//! plans the levels and reports what subcycling would save; `on` subcycles for study.

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// Whether a rolling run subcycles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MultiRateMode {
    /// The engine decides (`rolling::stepping`): today single rate, with the levels planned
    /// and reported.
    #[default]
    Auto,
    /// Always multi-rate (experimental: not stable on every mesh); an error if the contact
    /// surfaces do not carry the finest elements.
    On,
    /// Single rate: every element at the smallest stable step (the reference).
    Off,
}

/// The `time_stepping` block of a case file (every field optional).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSteppingSpec {
    /// `auto` (default), `on` or `off`.
    #[serde(default)]
    pub multi_rate: MultiRateMode,
    /// Most levels (default 8: steps up to 128 times the finest, beyond the spread of element
    /// sizes of every model in data/models).
    #[serde(default = "default_max_levels")]
    pub max_levels: usize,
    /// Ratio of neighbouring levels' steps, a power of two (default 2).
    #[serde(default = "default_level_ratio")]
    pub level_ratio: u32,
}

fn default_max_levels() -> usize {
    8
}

fn default_level_ratio() -> u32 {
    2
}

impl Default for TimeSteppingSpec {
    fn default() -> Self {
        TimeSteppingSpec {
            multi_rate: MultiRateMode::Auto,
            max_levels: default_max_levels(),
            level_ratio: default_level_ratio(),
        }
    }
}

impl TimeSteppingSpec {
    /// The level scheme of the block.
    pub fn scheme(&self) -> LevelScheme {
        LevelScheme {
            max_levels: self.max_levels,
            ratio: self.level_ratio,
        }
    }

    /// Checks the block; errors name `source` and `time_stepping.<field>` with the range.
    pub fn validate(&self, source: &str) -> Result<()> {
        self.scheme().check(source, "time_stepping.")
    }
}

/// How the levels are formed: at most `max_levels` levels, each stepping `ratio` times the
/// step of the level below it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelScheme {
    /// Number of levels, 1 (single rate) or more.
    pub max_levels: usize,
    /// Ratio of neighbouring levels' steps: a power of two, so that a coarse level's updates
    /// fall on the finer levels' (the engine's levels are binary: it uses every p-th of them
    /// for `ratio = 2^p`).
    pub ratio: u32,
}

/// The engine's binary levels: at most 16 (steps up to 2^15 times the finest).
pub const MAX_BINARY_LEVELS: usize = 16;

impl LevelScheme {
    /// Levels a factor of two apart.
    pub fn binary(max_levels: usize) -> Self {
        LevelScheme {
            max_levels,
            ratio: 2,
        }
    }

    /// `p` in `ratio = 2^p`: binary levels per level.
    pub fn ratio_log2(&self) -> usize {
        self.ratio.trailing_zeros() as usize
    }

    /// Binary levels the scheme spans: `(max_levels - 1) p + 1`.
    pub fn binary_levels(&self) -> usize {
        (self.max_levels.max(1) - 1) * self.ratio_log2() + 1
    }

    /// Checks the scheme; errors name `source`, the field (`field_prefix` + `max_levels` or
    /// `level_ratio`) and the allowed range.
    pub fn check(&self, source: &str, field_prefix: &str) -> Result<()> {
        if !self.ratio.is_power_of_two() || self.ratio < 2 {
            return Err(Error::input(
                source,
                format!("{field_prefix}level_ratio"),
                format!(
                    "must be a power of two, 2 to 32768 (got {}): a coarse level's updates must \
                     fall on the finer levels' steps",
                    self.ratio
                ),
            ));
        }
        if self.max_levels < 1 || self.binary_levels() > MAX_BINARY_LEVELS {
            let most = (MAX_BINARY_LEVELS - 1) / self.ratio_log2() + 1;
            return Err(Error::input(
                source,
                format!("{field_prefix}max_levels"),
                format!(
                    "must lie in [1, {most}] with level_ratio {} (got {}): the coarsest level \
                     may step at most 2^15 times the finest",
                    self.ratio, self.max_levels
                ),
            ));
        }
        Ok(())
    }
}
