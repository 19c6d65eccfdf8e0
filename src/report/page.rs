//! What the report's sections share: the runs as read, the page being written, and the
//! analysis options.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::analysis::identify::ModeRef;
use crate::analysis::per_n::PerNAnalysis;
use crate::analysis::ring_growth::RingGrowth;
use crate::analysis::RunAnalysis;
use crate::stability::output::StabilityBrief;
use crate::table::Table;

/// A run directory as the report reads it.
pub(super) struct Run {
    pub(super) name: String,
    pub(super) dir: PathBuf,
    pub(super) histories: Table,
    pub(super) analyses: Vec<RunAnalysis>,
    pub(super) modes: Option<Vec<ModeRef>>,
    /// The stability analysis of the run's case: its `stability.json`, else the one given.
    pub(super) stability: Option<StabilityBrief>,
    /// The growth analysis of its rim ring (None: no `ring.csv`; an error's text when the ring
    /// cannot be judged, e.g. a record shorter than the criteria's spans).
    pub(super) ring: Option<std::result::Result<RingGrowth, String>>,
    /// The lateral per-n map after the creep force's build-up (or over the report's window).
    pub(super) ring_map: Option<PerNAnalysis>,
}

/// The report page being written: its markdown, section headings and files.
pub(super) struct Page {
    pub(super) md: String,
    pub(super) sections: Vec<String>,
    pub(super) files: Vec<String>,
}

impl Page {
    pub(super) fn new() -> Page {
        Page {
            md: String::new(),
            sections: Vec::new(),
            files: Vec::new(),
        }
    }

    /// A level-2 heading, recorded as a section.
    pub(super) fn heading(&mut self, text: &str) {
        let _ = writeln!(self.md, "\n## {text}\n");
        self.sections.push(text.to_string());
    }
}

/// How the report analyses the vibration.
#[derive(Clone, Debug, Default)]
pub struct ReportOptions {
    /// Start of the analysed window (s); None: each run's lateral-motion onset, else its first
    /// sample (see [`crate::analysis`]).
    pub from_s: Option<f64>,
    /// End of the analysed window (s); None: the last sample.
    pub to_s: Option<f64>,
    /// Largest PSD bin spacing (Hz); None: [`crate::analysis::DEFAULT_RESOLUTION_HZ`].
    pub resolution_hz: Option<f64>,
    /// A `stability.json` (of `squeal stability`) for the runs that have none of their own.
    pub stability: Option<PathBuf>,
    /// PSD charts over the whole spectrum up to Nyquist instead of the squeal band
    /// (0 to [`SQUEAL_BAND_TOP_HZ`]).
    pub full_frequency_range: bool,
}

/// Top of the frequency band the PSD charts show by default (Hz): wheel squeal lies between
/// about 0.1 and 5 kHz (Thompson, Railway Noise and Vibration, 2009, ch. 9).
pub const SQUEAL_BAND_TOP_HZ: f64 = 5000.0;
