//! Reports: charts (plotters, PNG and SVG with the bundled font) and, later, tables and the
//! markdown/HTML report.

pub mod chart;
mod clip;
pub mod ema_charts;
mod html;
pub mod kalker_charts;
pub mod modal_chart;
mod page;
pub mod patch_maps;
mod ring_sections;
pub mod run_report;
mod sections;
pub mod stability_charts;
pub mod table3;
