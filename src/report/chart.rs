//! Line and scatter charts written as PNG and SVG.
//!
//! Text is drawn with the bundled DejaVu Sans (data/fonts, Bitstream Vera licence) through
//! plotters' `ab_glyph` backend, so no system font library is needed.

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{Error, Result};

static FONT_BYTES: &[u8] = include_bytes!("../../data/fonts/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The bundled file is a valid TrueType font; a failure here would be a packaging bug,
        // and text would then be missing rather than the program failing.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES);
    });
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stroke {
    /// Solid line.
    Solid,
    /// Dotted (dashed) line.
    Dotted,
    /// Markers only.
    Points,
    /// Solid line with markers.
    SolidWithPoints,
    /// Dotted line with hollow markers (a single point stays visible).
    DottedWithPoints,
}

/// One data series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label (empty: not in the legend).
    pub label: String,
    /// x values.
    pub x: Vec<f64>,
    /// y values.
    pub y: Vec<f64>,
    /// Drawing style.
    pub stroke: Stroke,
    /// Colour index into the palette (series with the same index share a colour).
    pub color: usize,
}

/// A chart with axes, title, legend.
#[derive(Clone, Debug, Default)]
pub struct LineChart {
    /// Title.
    pub title: String,
    /// x-axis label with unit, e.g. "time (ms)".
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Series.
    pub series: Vec<Series>,
    /// Logarithmic y axis (for PSDs).
    pub log_y: bool,
    /// Fixed x range (default: data range).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (default: data range with 5 % margin).
    pub y_range: Option<(f64, f64)>,
    /// Size in pixels (default 1000 x 620).
    pub size_px: Option<(u32, u32)>,
    /// Line width in pixels (default 2).
    pub stroke_width: Option<u32>,
}

impl Series {
    /// Adds a markers-only series of `points` (x, y) to `series`, unless it is empty.
    pub fn push_points(
        series: &mut Vec<Series>,
        label: &str,
        points: impl Iterator<Item = (f64, f64)>,
        color: usize,
    ) {
        let (x, y): (Vec<f64>, Vec<f64>) = points.unzip();
        if !x.is_empty() {
            series.push(Series {
                label: label.into(),
                x,
                y,
                stroke: Stroke::Points,
                color,
            });
        }
    }

    /// A solid line.
    pub fn line(label: &str, x: Vec<f64>, y: Vec<f64>, color: usize) -> Self {
        Series {
            label: label.to_string(),
            x,
            y,
            stroke: Stroke::Solid,
            color,
        }
    }
}

/// Edges of a quad section mesh as chart series (one per quad, unlabelled), for pictures of
/// cross-section meshes; `scale` converts the mesh coordinates (e.g. 1.0 for mm).
pub fn quad_mesh_series(
    nodes: &[[f64; 2]],
    quads: &[[usize; 4]],
    color: usize,
    label: &str,
) -> Vec<Series> {
    let mut out: Vec<Series> = quads
        .iter()
        .map(|q| {
            let idx = [q[0], q[1], q[2], q[3], q[0]];
            Series {
                label: String::new(),
                x: idx.iter().map(|&i| nodes[i][0]).collect(),
                y: idx.iter().map(|&i| nodes[i][1]).collect(),
                stroke: Stroke::Solid,
                color,
            }
        })
        .collect();
    if let Some(first) = out.first_mut() {
        first.label = label.to_string();
    }
    out
}

/// Palette (colour-blind friendly, Okabe-Ito).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];

fn data_range(chart: &LineChart) -> ((f64, f64), (f64, f64)) {
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for s in &chart.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if !x.is_finite() || !y.is_finite() || (chart.log_y && y <= 0.0) {
                continue;
            }
            xr = (xr.0.min(x), xr.1.max(x));
            yr = (yr.0.min(y), yr.1.max(y));
        }
    }
    if !xr.0.is_finite() {
        xr = (0.0, 1.0);
    }
    if !yr.0.is_finite() {
        yr = if chart.log_y {
            (1e-12, 1.0)
        } else {
            (0.0, 1.0)
        };
    }
    if xr.1 <= xr.0 {
        xr = (xr.0 - 0.5, xr.0 + 0.5);
    }
    if yr.1 <= yr.0 {
        let pad = if yr.0 == 0.0 { 1.0 } else { 0.5 * yr.0.abs() };
        yr = (yr.0 - pad, yr.0 + pad);
    }
    let xr = chart.x_range.unwrap_or(xr);
    let yr = chart.y_range.unwrap_or_else(|| {
        if chart.log_y {
            (yr.0 * 0.8, yr.1 * 1.25)
        } else {
            let m = 0.05 * (yr.1 - yr.0);
            (yr.0 - m, yr.1 + m)
        }
    });
    (xr, yr)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    chart: &LineChart,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let ((x0, x1), (y0, y1)) = data_range(chart);
    let mut builder = framed(&root, &chart.title, 26);
    macro_rules! body {
        ($ctx:expr) => {{
            let mut ctx = $ctx;
            ctx.configure_mesh()
                .x_desc(chart.x_label.as_str())
                .y_desc(chart.y_label.as_str())
                .label_style(("sans-serif", 16))
                .axis_desc_style(("sans-serif", 19))
                .light_line_style(RGBColor(235, 235, 235))
                .x_label_formatter(&|v: &f64| tick_label_on_span(*v, x1 - x0))
                .y_label_formatter(&|v: &f64| tick_label_on_span(*v, y1 - y0))
                .draw()
                .map_err(|e| e.to_string())?;
            for s in &chart.series {
                let color = PALETTE[s.color % PALETTE.len()];
                let pts: Vec<(f64, f64)> = s
                    .x
                    .iter()
                    .zip(&s.y)
                    .map(|(&x, &y)| (x, y))
                    .filter(|p| p.0.is_finite() && p.1.is_finite() && (!chart.log_y || p.1 > 0.0))
                    .collect();
                let style = ShapeStyle {
                    color: color.to_rgba(),
                    filled: true,
                    stroke_width: chart.stroke_width.unwrap_or(2),
                };
                let legend_style = style;
                let labelled = !s.label.is_empty();
                match s.stroke {
                    Stroke::Solid | Stroke::SolidWithPoints => {
                        let drawn = ctx
                            .draw_series(LineSeries::new(pts.clone(), style))
                            .map_err(|e| e.to_string())?;
                        if labelled {
                            drawn.label(s.label.as_str()).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 24, y)], legend_style)
                            });
                        }
                    }
                    Stroke::Dotted | Stroke::DottedWithPoints => {
                        let drawn = ctx
                            .draw_series(DashedLineSeries::new(pts.clone(), 5, 5, style))
                            .map_err(|e| e.to_string())?;
                        if labelled {
                            drawn.label(s.label.as_str()).legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 8, y)], legend_style)
                            });
                        }
                    }
                    Stroke::Points => {
                        let drawn = ctx
                            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, style)))
                            .map_err(|e| e.to_string())?;
                        if labelled {
                            drawn
                                .label(s.label.as_str())
                                .legend(move |(x, y)| Circle::new((x + 12, y), 4, legend_style));
                        }
                    }
                }
                if s.stroke == Stroke::DottedWithPoints {
                    let hollow = ShapeStyle {
                        filled: false,
                        ..style
                    };
                    ctx.draw_series(pts.iter().map(|&p| Circle::new(p, 5, hollow)))
                        .map_err(|e| e.to_string())?;
                }
                if s.stroke == Stroke::SolidWithPoints {
                    ctx.draw_series(pts.iter().map(|&p| Circle::new(p, 3, style)))
                        .map_err(|e| e.to_string())?;
                }
            }
            if chart.series.iter().any(|s| !s.label.is_empty()) {
                ctx.configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(RGBColor(160, 160, 160))
                    .label_font(("sans-serif", 16))
                    .position(SeriesLabelPosition::UpperRight)
                    .draw()
                    .map_err(|e| e.to_string())?;
            }
        }};
    }
    if chart.log_y {
        body!(builder
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(|e| e.to_string())?);
    } else {
        body!(builder
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?);
    }
    root.present().map_err(|e| e.to_string())
}

/// A chart builder with the toolkit's frame: title, margins, room for axis labels.
fn framed<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    title_px: u32,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(root);
    builder
        .caption(title, ("sans-serif", title_px))
        .margin(14)
        .x_label_area_size(52)
        .y_label_area_size(86);
    builder
}

/// Create the parent folders of the given output files.
fn create_parents(paths: &[Option<&Path>]) -> Result<()> {
    for path in paths.iter().flatten() {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
    }
    Ok(())
}

fn drawing_error(path: &Path, message: String) -> Error {
    Error::io(path, std::io::Error::other(message))
}

/// Axis tick text on an axis spanning `span`: a tick within 1e-9 of the span from zero is
/// zero (tick positions stepped in floating point land at 1.39e-17 instead of 0), the rest as
/// [`tick_label`].
pub fn tick_label_on_span(v: f64, span: f64) -> String {
    if v.abs() <= 1e-9 * span.abs() {
        return "0".into();
    }
    tick_label(&v)
}

/// Axis tick text: plain numbers with at most 4 significant digits, powers of ten as 1e-6.
pub fn tick_label(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&a) {
        let e = a.log10().floor();
        let m = v / 10f64.powf(e);
        return if (m.abs() - 1.0).abs() < 1e-6 {
            format!("{}1e{}", if *v < 0.0 { "-" } else { "" }, e as i32)
        } else {
            format!("{m:.2}e{}", e as i32)
        };
    }
    let text = format!("{:.4}", v);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    text.to_string()
}

/// Write the chart as PNG and/or SVG (either path may be None).
pub fn write(chart: &LineChart, png: Option<&Path>, svg: Option<&Path>) -> Result<()> {
    register_font();
    let size = chart.size_px.unwrap_or((1000, 620));
    create_parents(&[png, svg])?;
    if let Some(path) = png {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        draw(root, chart).map_err(|e| drawing_error(path, e))?;
    }
    if let Some(path) = svg {
        let root = SVGBackend::new(path, size).into_drawing_area();
        draw(root, chart).map_err(|e| drawing_error(path, e))?;
    }
    Ok(())
}

/// A colour map over a time x frequency grid (wavelet power spectra).
#[derive(Clone, Debug, Default)]
pub struct Heatmap {
    /// Title.
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Cell centres along x (ascending).
    pub x: Vec<f64>,
    /// Cell centres along y (ascending).
    pub y: Vec<f64>,
    /// Values, `values[ix * y.len() + iy]`; drawn as 10 log10(v / max) dB over `range_db`.
    pub values: Vec<f64>,
    /// Dynamic range shown (dB below the maximum).
    pub range_db: f64,
    /// A linear colour scale over `(low, high)` instead of decibels (e.g. MAC in [0, 1]).
    pub linear_range: Option<(f64, f64)>,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Lines drawn on top (e.g. the cone of influence).
    pub overlay: Vec<Series>,
    /// Size in pixels.
    pub size_px: Option<(u32, u32)>,
}

fn cell_edges(c: &[f64], log: bool) -> Vec<f64> {
    let n = c.len();
    let mut e = Vec::with_capacity(n + 1);
    if n == 1 {
        return if log {
            vec![c[0] / 1.1, c[0] * 1.1]
        } else {
            vec![c[0] - 0.5, c[0] + 0.5]
        };
    }
    let mid = |a: f64, b: f64| if log { (a * b).sqrt() } else { 0.5 * (a + b) };
    let first = if log {
        c[0] * c[0] / mid(c[0], c[1])
    } else {
        2.0 * c[0] - mid(c[0], c[1])
    };
    e.push(first);
    for k in 0..n - 1 {
        e.push(mid(c[k], c[k + 1]));
    }
    let last = if log {
        c[n - 1] * c[n - 1] / mid(c[n - 2], c[n - 1])
    } else {
        2.0 * c[n - 1] - mid(c[n - 2], c[n - 1])
    };
    e.push(last);
    e
}

fn draw_heatmap<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    map: &Heatmap,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (nx, ny) = (map.x.len(), map.y.len());
    if nx == 0 || ny == 0 || map.values.len() != nx * ny {
        return Err(format!(
            "heatmap needs {nx} x {ny} values, got {}",
            map.values.len()
        ));
    }
    let xe = cell_edges(&map.x, false);
    let ye = cell_edges(&map.y, map.log_y);
    let vmax = map
        .values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max)
        .max(1e-300);
    let range = map.range_db.max(1.0);
    let mut builder = framed(&root, &map.title, 24);
    macro_rules! body {
        ($ctx:expr) => {{
            let mut ctx = $ctx;
            ctx.configure_mesh()
                .disable_mesh()
                .x_label_formatter(&tick_label)
                .y_label_formatter(&tick_label)
                .x_desc(map.x_label.as_str())
                .y_desc(map.y_label.as_str())
                .label_style(("sans-serif", 16))
                .axis_desc_style(("sans-serif", 19))
                .draw()
                .map_err(|e| e.to_string())?;
            let cells = (0..nx)
                .flat_map(|ix| (0..ny).map(move |iy| (ix, iy)))
                .map(|(ix, iy)| {
                    let v = map.values[ix * ny + iy];
                    let t = match map.linear_range {
                        Some((low, high)) => ((v - low) / (high - low)).clamp(0.0, 1.0),
                        None => {
                            let db = if v > 0.0 {
                                10.0 * (v / vmax).log10()
                            } else {
                                -range
                            };
                            ((db + range) / range).clamp(0.0, 1.0)
                        }
                    };
                    let c = ViridisRGB.get_color(t as f32);
                    Rectangle::new([(xe[ix], ye[iy]), (xe[ix + 1], ye[iy + 1])], c.filled())
                });
            ctx.draw_series(cells).map_err(|e| e.to_string())?;
            for s in &map.overlay {
                let pts: Vec<(f64, f64)> =
                    s.x.iter()
                        .zip(&s.y)
                        .map(|(&x, &y)| (x, y))
                        .filter(|p| p.1.is_finite() && p.1 > ye[0] && p.1 < ye[ny])
                        .collect();
                let style = ShapeStyle {
                    color: WHITE.to_rgba(),
                    filled: false,
                    stroke_width: 2,
                };
                ctx.draw_series(DashedLineSeries::new(pts, 6, 4, style))
                    .map_err(|e| e.to_string())?;
            }
        }};
    }
    if map.log_y {
        body!(builder
            .build_cartesian_2d(xe[0]..xe[nx], (ye[0]..ye[ny]).log_scale())
            .map_err(|e| e.to_string())?);
    } else {
        body!(builder
            .build_cartesian_2d(xe[0]..xe[nx], ye[0]..ye[ny])
            .map_err(|e| e.to_string())?);
    }
    root.present().map_err(|e| e.to_string())
}

/// Write a heatmap as PNG and/or SVG.
pub fn write_heatmap(map: &Heatmap, png: Option<&Path>, svg: Option<&Path>) -> Result<()> {
    register_font();
    let size = map.size_px.unwrap_or((900, 560));
    create_parents(&[png, svg])?;
    if let Some(path) = png {
        draw_heatmap(BitMapBackend::new(path, size).into_drawing_area(), map)
            .map_err(|e| Error::io(path, std::io::Error::other(e)))?;
    }
    if let Some(path) = svg {
        draw_heatmap(SVGBackend::new(path, size).into_drawing_area(), map)
            .map_err(|e| Error::io(path, std::io::Error::other(e)))?;
    }
    Ok(())
}
