//! How a rolling case steps in time (`time_stepping` in a case file): single rate, or
//! multi-rate (subcycled) over levels of stable step a power of two apart
//! (`crate::explicit::levels`, `crate::explicit::multirate`), chosen automatically by default.
//!
//! The automatic choice (`"multi_rate": "auto"`) is made on the built model by
//! `rolling::stepping`: subcycling when it saves enough element work to pay for its
//! bookkeeping, and only where the contact surfaces carry the model's finest elements. The
//! levels keep their elements at half their stable step ([`STABLE_COARSE_COURANT`]).

use serde::{Deserialize, Serialize};

use crate::mesh::quality::COURANT_FACTOR;
use crate::{Error, Result};

/// Whether a rolling run subcycles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MultiRateMode {
    /// Multi-rate when it pays (`rolling::stepping`), single rate otherwise.
    #[default]
    Auto,
    /// Always multi-rate; an error if the contact surfaces do not carry the finest elements.
    On,
    /// Single rate: every element at the smallest stable step (the reference).
    Off,
}

/// The `time_stepping` block of a case file (every field optional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
    /// The (finest) step as a fraction of the engine's, `COURANT_FACTOR` times the stable step
    /// (default 1; in [0.05, 1]): below 1 for a time-step convergence study (issue 57, item 5:
    /// the step halved).
    #[serde(default = "default_step_scale")]
    pub step_scale: f64,
}

fn default_step_scale() -> f64 {
    1.0
}

/// Smallest `step_scale`: a twentieth of the engine's step costs twenty times the run.
pub const SMALLEST_STEP_SCALE: f64 = 0.05;

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
            step_scale: default_step_scale(),
        }
    }
}

impl TimeSteppingSpec {
    /// The level scheme of the block.
    pub fn scheme(&self) -> LevelScheme {
        LevelScheme {
            max_levels: self.max_levels,
            ratio: self.level_ratio,
            coarse_courant: STABLE_COARSE_COURANT,
        }
    }

    /// Checks the block; errors name `source` and `time_stepping.<field>` with the range.
    pub fn validate(&self, source: &str) -> Result<()> {
        if !(self.step_scale >= SMALLEST_STEP_SCALE && self.step_scale <= 1.0) {
            return Err(Error::input(
                source,
                "time_stepping.step_scale",
                format!(
                    "must lie in [{SMALLEST_STEP_SCALE}, 1] (got {}): a fraction of the engine's \
                     step, which is already {COURANT_FACTOR} of the stable one",
                    self.step_scale
                ),
            ));
        }
        self.scheme().check(source, "time_stepping.")
    }
}

/// How the levels are formed: at most `max_levels` levels, each stepping `ratio` times the
/// step of the level below it, a level above the finest only for elements whose own stable
/// step holds its step `coarse_courant` times over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelScheme {
    /// Number of levels, 1 (single rate) or more.
    pub max_levels: usize,
    /// Ratio of neighbouring levels' steps: a power of two, so that a coarse level's updates
    /// fall on the finer levels' (the engine's levels are binary: it uses every p-th of them
    /// for `ratio = 2^p`).
    pub ratio: u32,
    /// The largest fraction of an element's own stable step (its transit `L / c`) at which a
    /// level above the finest steps it. The finest level runs at the engine's
    /// [`COURANT_FACTOR`] (0.9).
    pub coarse_courant: f64,
}

/// The engine's binary levels: at most 16 (steps up to 2^15 times the finest).
pub const MAX_BINARY_LEVELS: usize = 16;

/// `coarse_courant` of every scheme the engine forms by itself: a coarse level steps its
/// elements at no more than half their own stable step.
///
/// Why half (measured, tests/explicit_multirate_stability.rs, 2026-11-26): the nodal partition
/// with linear interpolation is not stable at the elements' own stable steps. Free graded
/// blocks (1 mm elements next to coarser ones, undamped, from random velocities) grew
/// exponentially at 12 of 44 coarse sizes between 1 and 16 mm with the coarse levels at 0.9 of
/// their elements' step, at 3 of 39 at 0.6, and at none of 78 (two block families, 200 000 to
/// 300 000 fine steps) at 0.5. A one-dimensional spring chain with the same update shows the
/// same (growth up to 1.6 % per cycle at 0.9, none found at 0.5). Smolinski, Sleith &
/// Belytschko (Comput. Mech. 18, 1996) bound the stable steps of nodal partitions by element
/// frequencies more tightly than each element's own step; 0.5 is the measured bound, not a
/// derived one.
pub const STABLE_COARSE_COURANT: f64 = 0.5;

impl LevelScheme {
    /// Levels a factor of two apart.
    pub fn binary(max_levels: usize) -> Self {
        LevelScheme {
            max_levels,
            ratio: 2,
            coarse_courant: STABLE_COARSE_COURANT,
        }
    }

    /// The same levels with the coarse levels at `coarse_courant` of their elements' own
    /// stable step ([`COURANT_FACTOR`] puts them at their own step, as the engine did before
    /// [`STABLE_COARSE_COURANT`]: kept for tests of the interface itself).
    pub fn with_coarse_courant(self, coarse_courant: f64) -> Self {
        LevelScheme {
            coarse_courant,
            ..self
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
        let c = self.coarse_courant;
        if c.is_nan() || c <= 0.0 || c > COURANT_FACTOR {
            return Err(Error::input(
                source,
                format!("{field_prefix}coarse_courant"),
                format!(
                    "must lie in (0, {COURANT_FACTOR}] (got {}): a coarse level may not step an \
                     element closer to its stable step than the finest level does",
                    self.coarse_courant
                ),
            ));
        }
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
