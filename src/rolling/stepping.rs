//! Single rate or multi-rate for a rolling run: the case's `time_stepping` block
//! ([`crate::model::time_stepping`]), the command line's override, the automatic rule and the
//! contact guard, decided on the built model before the time loop.
//!
//! Multi-rate stepping holds the contact's nodes at the finest level (`explicit::multirate`):
//! a penalty contact must be integrated at the step its stiffness was sized for. That pays
//! only where the contact surfaces carry the model's finest elements anyway, as the rolling
//! models' tread band and rail band do. A model whose finest elements sit elsewhere would have
//! its contact zone stepped finer than its own elements need: the guard refuses a request for
//! subcycling there (`on`), and `auto` runs it single rate.
//!
//! `auto` subcycles when the planned partition's element work is at most
//! [`AUTO_MAX_ELEMENT_WORK`] of single rate, so that the saving outweighs the levels'
//! bookkeeping. The partition keeps the coarse levels at half their elements' stable step
//! ([`crate::explicit::levels::STABLE_COARSE_COURANT`]): at their own step the subcycled update
//! resonates (tests/explicit_multirate_stability.rs), which is what made the `paper` case 5 run
//! multi-rate go unstable at 5.2 ms. With that margin none of the models in data/models saves
//! enough for `auto` to subcycle (`paper` 0.894, `demo` 0.986 of the element work).

use crate::contact::Enforcement;
use crate::explicit::levels::{partition_with, LevelPartition, LevelScheme};
use crate::explicit::multirate::element_transits_s;
use crate::model::time_stepping::{MultiRateMode, TimeSteppingSpec};
use crate::{Error, Result};

use super::build::{RollingModel, StepLevels};

/// Largest element work, relative to single rate, at which `auto` subcycles. Measured in one
/// session on 2 cores (data/runs/LOG.md, performance history, 2026-11-26): the `paper` mesh, planned at 0.780,
/// stepped 13-15 % faster multi-rate (elements 25.5 to 18.7 ms, the rest of the step 11.4 to
/// 12.6 ms); the `demo` mesh, at 0.895, was no faster: its element saving (0.99 to 0.89 ms)
/// was eaten by the levels' bookkeeping (0.80 to 0.94 ms), which puts its break-even near
/// 0.86. 0.85 keeps `auto` on the side where subcycling was measured to win.
pub const AUTO_MAX_ELEMENT_WORK: f64 = 0.85;

/// The decision for one run.
#[derive(Clone, Debug)]
pub struct SteppingChoice {
    /// The levels' scheme of the case.
    pub scheme: LevelScheme,
    /// Subcycle or not.
    pub multi_rate: bool,
    /// Why, in words (for `run.json` and the console).
    pub reason: String,
    /// The partition multi-rate stepping would use, when it was planned.
    pub planned: Option<LevelPartition>,
}

/// The contact's slave nodes and master-face nodes: the nodes multi-rate stepping holds at
/// the finest level.
pub fn contact_nodes(m: &RollingModel) -> Vec<usize> {
    let mut nodes = m.contact.pair.slaves.clone();
    nodes.extend(m.contact.pair.faces.iter().flatten());
    nodes
}

/// Decides how the rolling run of `m` steps: `mode_override` (the command line) or the case's
/// `spec.multi_rate`, the scheme of `spec`. Errors name `source` and the field: a scheme the
/// engine cannot step (`time_stepping.level_ratio`, `time_stepping.max_levels`), and a request
/// for subcycling (`on`) on a model whose contact slaves would not sit at the finest level.
pub fn choose_stepping(
    m: &RollingModel,
    spec: &TimeSteppingSpec,
    mode_override: Option<MultiRateMode>,
    source: &str,
) -> Result<SteppingChoice> {
    spec.validate(source)?;
    let scheme = spec.scheme();
    let (mode, by) = match mode_override {
        Some(mode) => (mode, "the command line"),
        None => (spec.multi_rate, "time_stepping.multi_rate"),
    };
    let single = |reason: String, planned: Option<LevelPartition>| SteppingChoice {
        scheme,
        multi_rate: false,
        reason,
        planned,
    };
    if mode == MultiRateMode::Off {
        return Ok(single(format!("single rate ({by}: off)"), None));
    }
    // Exact contact needs every contact node's free motion over the step it solves for
    // (explicit::aux::StepPredictor), which a subcycled level does not have.
    if m.contact.pair.enforcement == Enforcement::Exact {
        if mode == MultiRateMode::On {
            return Err(Error::input(
                source,
                "time_stepping.multi_rate",
                "`on` refused: exact contact (contact_enforcement) steps single rate; must be \
                 `off` or `auto` with it",
            ));
        }
        return Ok(single(
            format!("single rate ({by}: exact contact steps single rate)"),
            None,
        ));
    }
    // The guard: the slaves' own levels, from their elements' stable steps alone.
    let model = &m.solver.model;
    let transits = element_transits_s(model);
    let free = partition_with(
        &model.mesh.elements,
        &transits,
        model.node_count(),
        &[],
        scheme,
    );
    let slave_level = m
        .contact
        .pair
        .slaves
        .iter()
        .map(|&s| free.node_level[s])
        .min()
        .unwrap_or(0);
    if slave_level > 0 {
        let why = format!(
            "the contact's slave nodes would not sit at the finest level: the finest of their \
             elements has a stable step 2^{slave_level} times the model's smallest ({:.3e} s, \
             elsewhere in the model), and multi-rate stepping holds the contact at the finest \
             step",
            free.finest_step_s
        );
        if mode == MultiRateMode::On {
            return Err(Error::input(
                source,
                "time_stepping.multi_rate",
                format!(
                    "`on` refused: {why}; refine the contact surfaces to the model's finest \
                     elements, or run single rate (`off`)"
                ),
            ));
        }
        return Ok(single(format!("single rate (auto: {why})"), None));
    }
    let planned = m.solver.plan_multi_rate(scheme, &contact_nodes(m))?;
    let work = planned.element_work_fraction;
    if mode == MultiRateMode::Auto && work > AUTO_MAX_ELEMENT_WORK {
        return Ok(single(
            format!(
                "single rate (auto: multi-rate would do {work:.3} of the element work, above \
                 {AUTO_MAX_ELEMENT_WORK})"
            ),
            Some(planned),
        ));
    }
    let how = if mode == MultiRateMode::On {
        format!("{by}: on")
    } else {
        format!("auto: {work:.3} of the element work, at most {AUTO_MAX_ELEMENT_WORK}")
    };
    Ok(SteppingChoice {
        scheme,
        multi_rate: true,
        reason: format!(
            "multi-rate, {} levels {}x apart ({how})",
            planned.counts.iter().filter(|&&c| c > 0).count(),
            scheme.ratio
        ),
        planned: Some(planned),
    })
}

/// Applies `choice` to `m`: switches multi-rate stepping on when chosen, and records the
/// decision (and the levels) in the model's `run.json` information.
pub fn apply_stepping(m: &mut RollingModel, choice: &SteppingChoice) -> Result<()> {
    m.info.time_stepping = choice.reason.clone();
    if choice.multi_rate {
        let finest = contact_nodes(m);
        let p = m.solver.enable_multi_rate_with(choice.scheme, &finest)?;
        m.info.step_levels = Some(StepLevels {
            elements_per_level: p.counts.clone(),
            element_work_fraction: p.element_work_fraction,
        });
    }
    Ok(())
}
