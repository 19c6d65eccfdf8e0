//! The paper's modal chart: wheel modes' frequency against nodal diameters, one line per family
//! and nodal-circle count, FE dotted, measured (hammer test) solid.

use std::path::Path;

use super::chart::{write, LineChart, Series, Stroke};
use crate::modal::mode::{ModeFamily, ModeRef};
use crate::testdata::hammer::MeasuredMode;
use crate::Result;

/// Palette indices ([`super::chart::PALETTE`]) of the nine lines (axial, radial,
/// circumferential; nodal circles 0, 1, 2 within each): nine different colours, the three
/// families' m = 0 lines in the three most distinct (blue, vermillion, green), the pale yellow
/// left out. (Indices 3 k + m into the Okabe-Ito eight gave circumferential m = 2 axial
/// m = 0's colour.)
const LINE_COLOURS: [usize; 9] = [0, 5, 7, 1, 4, 8, 2, 3, 6];

/// The standard picture of a modal comparison: frequency against nodal diameters, one colour
/// per family and nodal-circle count, FE dotted, measured solid with markers.
pub fn write_modal_chart(
    fe: &[ModeRef],
    measured: Option<&[MeasuredMode]>,
    png: Option<&Path>,
    svg: Option<&Path>,
) -> Result<()> {
    let mut series = Vec::new();
    let families = [
        ModeFamily::Axial,
        ModeFamily::Radial,
        ModeFamily::Circumferential,
    ];
    for (k, fam) in families.into_iter().enumerate() {
        for m in 0..=2u32 {
            let color = LINE_COLOURS[3 * k + m as usize];
            let mut pts: Vec<(f64, f64)> = fe
                .iter()
                .filter(|f| f.family == fam && f.nodal_circles == m)
                .map(|f| (f.nodal_diameters as f64, f.frequency_hz))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
            pts.dedup_by(|a, b| a.0 == b.0);
            if !pts.is_empty() {
                series.push(Series {
                    label: format!("{fam:?} m={m}, FE"),
                    x: pts.iter().map(|p| p.0).collect(),
                    y: pts.iter().map(|p| p.1).collect(),
                    stroke: Stroke::DottedWithPoints,
                    color,
                });
            }
            if let Some(meas) = measured {
                let mut pts: Vec<(f64, f64)> = meas
                    .iter()
                    .filter(|f| f.family == fam && f.nodal_circles == m)
                    .map(|f| (f.nodal_diameters as f64, f.frequency_hz))
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                if !pts.is_empty() {
                    series.push(Series {
                        label: format!("{fam:?} m={m}, measured"),
                        x: pts.iter().map(|p| p.0).collect(),
                        y: pts.iter().map(|p| p.1).collect(),
                        stroke: Stroke::SolidWithPoints,
                        color,
                    });
                }
            }
        }
    }
    let max_nd = fe
        .iter()
        .map(|f| f.nodal_diameters)
        .chain(measured.unwrap_or(&[]).iter().map(|m| m.nodal_diameters))
        .max()
        .unwrap_or(1) as f64;
    let chart = LineChart {
        title: "Wheel modes: frequency against nodal diameters (m = nodal circles)".into(),
        x_range: Some((-0.5, max_nd + 0.5)),
        x_label: "nodal diameters".into(),
        y_label: "frequency (Hz)".into(),
        series,
        ..Default::default()
    };
    write(&chart, png, svg)
}

#[cfg(test)]
mod tests {
    use super::LINE_COLOURS;
    use crate::report::chart::PALE;

    /// Issue 53, item 18: every family and nodal-circle count has a colour of its own, never
    /// the pale yellow.
    #[test]
    fn every_line_has_a_colour_of_its_own() {
        let mut colours = LINE_COLOURS.to_vec();
        colours.sort();
        colours.dedup();
        assert_eq!(colours.len(), LINE_COLOURS.len());
        assert!(!colours.contains(&PALE));
    }
}
