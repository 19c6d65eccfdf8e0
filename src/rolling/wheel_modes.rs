//! The run's wheel modes: `modes.json` in the run directory, written when a run starts, so
//! that `identify`, `check-modes`, `growth` and `report` label the run's peaks without a
//! separate modal step.
//!
//! The modes are the axisymmetric solver's for the case's own wheel file, clamped where the
//! rolling model holds the wheel ([`crate::modal::axisym::rolling_wheel_modes`]): the labels
//! of the converged section model. The explicit mesh's own frequencies differ from them by
//! its discretisation error (docs/modal.md), which the identification's tolerance covers.

use std::path::Path;

use crate::input::wheel::WheelSpec;
use crate::modal::axisym::rolling_wheel_modes;
use crate::modal::mode::{write_modes_json, MODES_FILE};
use crate::Result;

/// Write the wheel's modes into `run_dir` unless a resumed run has them already.
pub fn write_run_wheel_modes(wheel: &WheelSpec, run_dir: &Path, resume: bool) -> Result<()> {
    if resume && run_dir.join(MODES_FILE).exists() {
        return Ok(());
    }
    let result = rolling_wheel_modes(wheel)?;
    write_modes_json(run_dir, &result.modes)?;
    Ok(())
}
