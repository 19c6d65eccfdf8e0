//! Line and scatter charts written as PNG and SVG.
//!
//! Text is drawn with the bundled DejaVu Sans (data/fonts, Bitstream Vera licence) through
//! plotters' `ab_glyph` backend, so no system font library is needed.

use std::path::Path;
use std::sync::Once;

use plotters::coord::ranged1d::AsRangedCoord;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::clip::{clip_polyline, inside};
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
    /// Size in pixels (default 1000 x 620); a legend adds a band below.
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

/// Palette: colour-blind friendly, the Okabe-Ito eight with four of Paul Tol's muted scheme
/// (indigo, wine, olive, grey) before the last, Okabe-Ito's yellow, which hardly shows on
/// white: lines numbered from 0 get it only after eleven others (for backgrounds, e.g. the
/// FRF behind a stabilisation diagram).
pub const PALETTE: [RGBColor; 12] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(51, 34, 136),
    RGBColor(136, 34, 85),
    RGBColor(153, 153, 51),
    RGBColor(119, 119, 119),
    RGBColor(240, 228, 66),
];

/// The palette's pale yellow ([`PALETTE`]'s last), for a background line.
pub const PALE: usize = 11;

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

/// The frame of a line chart `size` pixels (before its legend band).
fn line_frame(chart: &LineChart, size: (u32, u32)) -> Frame {
    let ((x0, x1), (y0, y1)) = data_range(chart);
    let x_ticks = |n: usize| tick_texts(x0..x1, n, &|v| tick_label_on_span(v, x1 - x0));
    let y_ticks = |n: usize| {
        if chart.log_y {
            tick_texts((y0..y1).log_scale(), n, &|v| tick_label(&v))
        } else {
            tick_texts(y0..y1, n, &|v| tick_label_on_span(v, y1 - y0))
        }
    };
    Frame::new(
        size,
        &chart.title,
        &chart.x_label,
        &chart.y_label,
        &x_ticks,
        &y_ticks,
        &chart.series,
    )
}

/// Draws `chart` in `frame` on `root`; `per_segment`: draw lines one segment at a time (for
/// bitmaps).
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    chart: &LineChart,
    frame: &Frame,
    per_segment: bool,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let ((x0, x1), (y0, y1)) = data_range(chart);
    let (plot, band) = root.split_vertically(frame.chart_height);
    let mut builder = frame.builder(&plot)?;
    // A log axis has no zero: its small ticks keep their values.
    let y_label = |v: &f64| {
        if chart.log_y {
            tick_label(v)
        } else {
            tick_label_on_span(*v, y1 - y0)
        }
    };
    macro_rules! body {
        ($ctx:expr) => {{
            let mut ctx = $ctx;
            ctx.configure_mesh()
                .x_desc(chart.x_label.as_str())
                .y_desc(chart.y_label.as_str())
                .x_labels(frame.x_labels)
                .y_labels(frame.y_labels)
                .label_style(("sans-serif", frame.fonts.tick))
                .axis_desc_style(("sans-serif", frame.x_desc_px.min(frame.y_desc_px)))
                .light_line_style(RGBColor(235, 235, 235))
                .x_label_formatter(&|v: &f64| tick_label_on_span(*v, x1 - x0))
                .y_label_formatter(&y_label)
                .draw()
                .map_err(|e| e.to_string())?;
            for s in &chart.series {
                let pts: Vec<(f64, f64)> = s
                    .x
                    .iter()
                    .zip(&s.y)
                    .map(|(&x, &y)| (x, y))
                    .filter(|p| p.0.is_finite() && p.1.is_finite() && (!chart.log_y || p.1 > 0.0))
                    .collect();
                let style = ShapeStyle {
                    color: PALETTE[s.color % PALETTE.len()].to_rgba(),
                    filled: true,
                    stroke_width: chart.stroke_width.unwrap_or(2),
                };
                // Lines cut at the plot's edges, markers inside it only.
                let runs = clip_polyline(&pts, (x0, x1), (y0, y1), chart.log_y);
                let markers = pts.iter().filter(|&&p| inside(p, (x0, x1), (y0, y1)));
                let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
                match s.stroke {
                    // A bitmap draws each segment alone: plotters joins thick segments with
                    // mitres that shoot far out where a dense signal turns back.
                    Stroke::Solid | Stroke::SolidWithPoints if per_segment => {
                        for run in &runs {
                            ctx.draw_series(
                                run.windows(2)
                                    .map(|w| PathElement::new(vec![w[0], w[1]], style)),
                            )
                            .map_err(e)?;
                        }
                    }
                    Stroke::Solid | Stroke::SolidWithPoints => {
                        for run in runs {
                            ctx.draw_series(LineSeries::new(run, style)).map_err(e)?;
                        }
                    }
                    Stroke::Dotted | Stroke::DottedWithPoints => {
                        for run in runs {
                            ctx.draw_series(DashedLineSeries::new(run, 5, 5, style))
                                .map_err(e)?;
                        }
                    }
                    Stroke::Points => {
                        ctx.draw_series(markers.clone().map(|&p| Circle::new(p, 4, style)))
                            .map_err(e)?;
                    }
                }
                if s.stroke == Stroke::DottedWithPoints {
                    let hollow = ShapeStyle {
                        filled: false,
                        ..style
                    };
                    ctx.draw_series(markers.clone().map(|&p| Circle::new(p, 5, hollow)))
                        .map_err(e)?;
                }
                if s.stroke == Stroke::SolidWithPoints {
                    ctx.draw_series(markers.map(|&p| Circle::new(p, 3, style)))
                        .map_err(e)?;
                }
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
    frame.draw_legend(&band, &chart.series, chart.stroke_width.unwrap_or(2))?;
    root.present().map_err(|e| e.to_string())
}

/// Text sizes of a chart `width` pixels wide. The report shows a chart at half its column,
/// about 680 px on a page 1400 px wide; the sizes scale with the width so that tick labels
/// show there at about 16 px, like the page's text (24 px on the default 1000 px).
#[derive(Clone, Copy, Debug)]
struct Fonts {
    title: f64,
    tick: f64,
    desc: f64,
    legend: f64,
    pad: u32,
}

impl Fonts {
    fn for_width(width: u32) -> Fonts {
        let s = width as f64 / 1000.0;
        let px = |v: f64, min: f64| (v * s).max(min).round();
        Fonts {
            title: px(28.0, 16.0),
            tick: px(24.0, 14.0),
            desc: px(24.0, 14.0),
            legend: px(22.0, 14.0),
            pad: px(14.0, 8.0) as u32,
        }
    }
}

/// Width in pixels of `text` in the bundled font at `px` (an estimate if the font fails).
fn text_width(text: &str, px: f64) -> u32 {
    register_font();
    FontDesc::new(FontFamily::SansSerif, px, FontStyle::Normal)
        .box_size(text)
        .map(|(w, _)| w)
        .unwrap_or_else(|_| (0.6 * px * text.chars().count() as f64) as u32)
}

/// The largest size up to `px` (but not below 70 % of it) at which `text` fits `room` pixels.
fn fitted(text: &str, px: f64, room: u32) -> f64 {
    let w = text_width(text, px).max(1) as f64;
    (px * (room as f64 / w).min(1.0)).max(0.7 * px).floor()
}

/// The tick texts plotters draws on an axis with at most `n` labels.
fn tick_texts<R: AsRangedCoord<Value = f64>>(
    range: R,
    n: usize,
    label: &dyn Fn(f64) -> String,
) -> Vec<String> {
    R::CoordDescType::from(range)
        .key_points(n)
        .into_iter()
        .map(label)
        .collect()
}

/// The most labels (up to 11) whose texts fit along an axis `room` pixels long, each taking
/// `size(text)` pixels: labels never overlap.
fn label_count(
    room: u32,
    ticks: &dyn Fn(usize) -> Vec<String>,
    size: &dyn Fn(&str) -> f64,
) -> usize {
    (3..=11)
        .rev()
        .find(|&n| {
            let t = ticks(n);
            t.len() as f64 * t.iter().map(|s| size(s)).fold(0.0, f64::max) <= room as f64
        })
        .unwrap_or(3)
}

/// How a chart is laid out: its title (wrapped to the width), the room for the axes' labels
/// (measured on the tick texts, so that none is cut off, the last x tick included), and a
/// legend band below the chart, where the legend cannot cover data.
struct Frame {
    fonts: Fonts,
    width: u32,
    /// Height of the chart above the legend band.
    chart_height: u32,
    title: Vec<String>,
    title_height: u32,
    x_desc_px: f64,
    y_desc_px: f64,
    x_labels: usize,
    y_labels: usize,
    x_area: u32,
    y_area: u32,
    right: u32,
    /// Each labelled series' index and the place of its entry (left, middle) in the band.
    legend: Vec<(usize, i32, i32)>,
    legend_height: u32,
}

/// Axis ticks of a frame: the texts plotters will draw for at most `n` labels.
type Ticks<'a> = &'a dyn Fn(usize) -> Vec<String>;

impl Frame {
    fn new(
        (width, height): (u32, u32),
        title: &str,
        x_desc: &str,
        y_desc: &str,
        x_ticks: Ticks,
        y_ticks: Ticks,
        series: &[Series],
    ) -> Frame {
        let fonts = Fonts::for_width(width);
        let pad = fonts.pad;
        // The title, wrapped at spaces to the width.
        let mut title_lines: Vec<String> = Vec::new();
        for word in title.split(' ') {
            match title_lines.last_mut() {
                Some(line)
                    if text_width(&format!("{line} {word}"), fonts.title) + 2 * pad <= width =>
                {
                    line.push(' ');
                    line.push_str(word);
                }
                _ => title_lines.push(word.to_string()),
            }
        }
        let title_height = (title_lines.len() as f64 * 1.25 * fonts.title).round() as u32 + pad;
        let x_area = (1.3 * (fonts.tick + fonts.desc)).round() as u32 + pad;
        let plot_height = height
            .saturating_sub(title_height + x_area + 2 * pad)
            .max(50);
        let line_height = |_: &str| 2.0 * fonts.tick;
        let y_labels = label_count(plot_height, y_ticks, &line_height);
        let y_text = y_ticks(y_labels)
            .iter()
            .map(|t| text_width(t, fonts.tick))
            .max()
            .unwrap_or(0);
        let y_desc_px = fitted(y_desc, fonts.desc, plot_height);
        let y_area = y_text + (1.3 * y_desc_px).round() as u32 + pad + 6;
        // Room right of the plot for half the widest x tick text (the last one is centred on
        // the plot's right edge).
        let x_text = x_ticks(11)
            .iter()
            .map(|t| text_width(t, fonts.tick))
            .max()
            .unwrap_or(0);
        let right = pad.max(x_text / 2 + pad / 2);
        let plot_width = width.saturating_sub(pad + y_area + right).max(50);
        let x_labels = label_count(plot_width, x_ticks, &|t| {
            text_width(t, fonts.tick) as f64 + fonts.tick
        });
        let x_desc_px = fitted(x_desc, fonts.desc, plot_width);
        // The legend: entries in rows under the plot, from its left edge.
        let (left, row) = ((pad + y_area) as i32, (1.5 * fonts.legend).round() as i32);
        let limit = (width - right.min(width)) as i32;
        let mut legend = Vec::new();
        let (mut x, mut y) = (left, row / 2);
        for (k, s) in series
            .iter()
            .enumerate()
            .filter(|(_, s)| !s.label.is_empty())
        {
            let w = Self::entry_width(&fonts, &s.label);
            if x > left && x + w > limit {
                (x, y) = (left, y + row);
            }
            legend.push((k, x, y));
            x += w + (1.2 * fonts.legend) as i32;
        }
        let legend_height = if legend.is_empty() {
            0
        } else {
            (y + row / 2) as u32 + pad
        };
        Frame {
            fonts,
            width,
            chart_height: height,
            title: title_lines,
            title_height,
            x_desc_px,
            y_desc_px,
            x_labels,
            y_labels,
            x_area,
            y_area,
            right,
            legend,
            legend_height,
        }
    }

    /// The image's size: the chart and the legend band below it.
    fn size(&self) -> (u32, u32) {
        (self.width, self.chart_height + self.legend_height)
    }

    /// Width of a legend entry: the line or marker sample, a gap, the text.
    fn entry_width(fonts: &Fonts, label: &str) -> i32 {
        (2.6 * fonts.legend) as i32 + text_width(label, fonts.legend) as i32
    }

    /// Draws the title on `area` and returns a chart builder inside the frame.
    fn builder<'a, 'b, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
    ) -> std::result::Result<ChartBuilder<'a, 'b, DB>, String>
    where
        DB::ErrorType: 'static,
    {
        let style = TextStyle::from(("sans-serif", self.fonts.title).into_font())
            .pos(Pos::new(HPos::Center, VPos::Top));
        for (k, line) in self.title.iter().enumerate() {
            let y = self.fonts.pad as f64 / 2.0 + k as f64 * 1.25 * self.fonts.title;
            area.draw(&Text::new(
                line.clone(),
                ((self.width / 2) as i32, y.round() as i32),
                style.clone(),
            ))
            .map_err(|e| e.to_string())?;
        }
        let mut builder = ChartBuilder::on(area);
        builder
            .margin_top(self.title_height)
            .margin_left(self.fonts.pad)
            .margin_bottom(self.fonts.pad)
            .margin_right(self.right)
            .x_label_area_size(self.x_area)
            .y_label_area_size(self.y_area);
        Ok(builder)
    }

    /// Draws the legend entries of `series` on the band below the chart.
    fn draw_legend<DB: DrawingBackend>(
        &self,
        band: &DrawingArea<DB, Shift>,
        series: &[Series],
        stroke_width: u32,
    ) -> std::result::Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let px = self.fonts.legend;
        let sample = (2.0 * px) as i32;
        let text =
            TextStyle::from(("sans-serif", px).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
        for &(k, x, y) in &self.legend {
            let s = &series[k];
            let style = ShapeStyle {
                color: PALETTE[s.color % PALETTE.len()].to_rgba(),
                filled: true,
                stroke_width,
            };
            let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
            let dotted = matches!(s.stroke, Stroke::Dotted | Stroke::DottedWithPoints);
            if s.stroke != Stroke::Points {
                let dash = if dotted { 5 } else { sample };
                let mut x0 = x;
                while x0 < x + sample {
                    let x1 = (x0 + dash).min(x + sample);
                    band.draw(&PathElement::new(vec![(x0, y), (x1, y)], style))
                        .map_err(e)?;
                    x0 = x1 + 5;
                }
            }
            let middle = (x + sample / 2, y);
            match s.stroke {
                Stroke::Points => band.draw(&Circle::new(middle, 5, style)).map_err(e)?,
                Stroke::SolidWithPoints => band.draw(&Circle::new(middle, 4, style)).map_err(e)?,
                Stroke::DottedWithPoints => band
                    .draw(&Circle::new(
                        middle,
                        5,
                        ShapeStyle {
                            filled: false,
                            ..style
                        },
                    ))
                    .map_err(e)?,
                Stroke::Solid | Stroke::Dotted => {}
            }
            band.draw(&Text::new(
                s.label.clone(),
                (x + sample + (0.5 * px) as i32, y),
                text.clone(),
            ))
            .map_err(e)?;
        }
        Ok(())
    }
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
    let frame = line_frame(chart, chart.size_px.unwrap_or((1000, 620)));
    let size = frame.size();
    create_parents(&[png, svg])?;
    if let Some(path) = png {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        draw(root, chart, &frame, true).map_err(|e| drawing_error(path, e))?;
    }
    if let Some(path) = svg {
        let root = SVGBackend::new(path, size).into_drawing_area();
        draw(root, chart, &frame, false).map_err(|e| drawing_error(path, e))?;
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

/// The frame of a heatmap `size` pixels (no legend: its colours are said in its labels or
/// under it).
fn heatmap_frame(map: &Heatmap, size: (u32, u32)) -> Frame {
    let (nx, ny) = (map.x.len(), map.y.len());
    let (xe, ye) = (cell_edges(&map.x, false), cell_edges(&map.y, map.log_y));
    let (x0, x1) = (xe[0], xe[nx.min(xe.len() - 1)]);
    let (y0, y1) = (ye[0], ye[ny.min(ye.len() - 1)]);
    let x_ticks = |n: usize| tick_texts(x0..x1, n, &|v| tick_label(&v));
    let y_ticks = |n: usize| {
        if map.log_y {
            tick_texts((y0..y1).log_scale(), n, &|v| tick_label(&v))
        } else {
            tick_texts(y0..y1, n, &|v| tick_label(&v))
        }
    };
    Frame::new(
        size,
        &map.title,
        &map.x_label,
        &map.y_label,
        &x_ticks,
        &y_ticks,
        &[],
    )
}

fn draw_heatmap<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    map: &Heatmap,
    frame: &Frame,
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
    let mut builder = frame.builder(&root)?;
    macro_rules! body {
        ($ctx:expr) => {{
            let mut ctx = $ctx;
            ctx.configure_mesh()
                .disable_mesh()
                .x_label_formatter(&tick_label)
                .y_label_formatter(&tick_label)
                .x_desc(map.x_label.as_str())
                .y_desc(map.y_label.as_str())
                .x_labels(frame.x_labels)
                .y_labels(frame.y_labels)
                .label_style(("sans-serif", frame.fonts.tick))
                .axis_desc_style(("sans-serif", frame.x_desc_px.min(frame.y_desc_px)))
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
                        .filter(|p| p.0.is_finite() && p.1.is_finite() && (!map.log_y || p.1 > 0.0))
                        .collect();
                let style = ShapeStyle {
                    color: WHITE.to_rgba(),
                    filled: false,
                    stroke_width: 2,
                };
                for run in clip_polyline(&pts, (xe[0], xe[nx]), (ye[0], ye[ny]), map.log_y) {
                    ctx.draw_series(DashedLineSeries::new(run, 6, 4, style))
                        .map_err(|e| e.to_string())?;
                }
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
    let Some(path) = png.or(svg) else {
        return Ok(());
    };
    if map.x.is_empty() || map.y.is_empty() || map.values.len() != map.x.len() * map.y.len() {
        return Err(drawing_error(
            path,
            format!(
                "heatmap needs {} x {} values, got {}",
                map.x.len(),
                map.y.len(),
                map.values.len()
            ),
        ));
    }
    let frame = heatmap_frame(map, size);
    if let Some(path) = png {
        draw_heatmap(
            BitMapBackend::new(path, size).into_drawing_area(),
            map,
            &frame,
        )
        .map_err(|e| Error::io(path, std::io::Error::other(e)))?;
    }
    if let Some(path) = svg {
        draw_heatmap(SVGBackend::new(path, size).into_drawing_area(), map, &frame)
            .map_err(|e| Error::io(path, std::io::Error::other(e)))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 53, item 18: the legend has a band of its own below the chart (the image grows by
    /// it, the chart keeps its size), its entries wrap within the width, the right margin holds
    /// half of the last x tick's text (centred on the plot's edge), and tick labels show at
    /// 16 px where the report shows a chart 680 px wide.
    #[test]
    fn legend_sits_below_the_plot_and_the_last_x_tick_fits() {
        let series: Vec<Series> = (0..9)
            .map(|k| {
                let label = format!("a rather long legend label {k}");
                Series::line(&label, vec![0.0, 5000.0], vec![1.0, 2.0], k)
            })
            .collect();
        let chart = LineChart {
            title: "t".into(),
            series,
            x_range: Some((0.0, 5000.0)),
            ..Default::default()
        };
        let frame = line_frame(&chart, (1000, 620));
        assert_eq!(frame.legend.len(), 9);
        assert_eq!(frame.size(), (1000, 620 + frame.legend_height));
        let rows: std::collections::BTreeSet<i32> = frame.legend.iter().map(|e| e.2).collect();
        assert!(rows.len() > 1, "nine long labels in one row");
        for &(k, x, y) in &frame.legend {
            let w = Frame::entry_width(&frame.fonts, &chart.series[k].label);
            assert!(x + w <= 1000, "entry {k} runs off the image: {x} + {w}");
            assert!(y > 0 && (y as u32) < frame.legend_height);
        }
        assert!(frame.right >= text_width("5000", frame.fonts.tick) / 2);
        assert!(frame.fonts.tick * 680.0 / 1000.0 >= 16.0);
        // The PNG has the band below the chart.
        let png = std::env::temp_dir().join(format!("squeal_legend_{}.png", std::process::id()));
        write(&chart, Some(&png), None).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        let be =
            |k: usize| u32::from_be_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
        assert_eq!((be(16), be(20)), frame.size());
        let _ = std::fs::remove_file(&png);
        // Without labels, no band.
        let bare = LineChart {
            series: vec![Series::line("", vec![0.0, 1.0], vec![0.0, 1.0], 0)],
            ..Default::default()
        };
        assert_eq!(line_frame(&bare, (1000, 620)).size(), (1000, 620));
    }

    /// The palette's colours differ, the pale one last.
    #[test]
    fn palette_colours_differ() {
        for (i, a) in PALETTE.iter().enumerate() {
            assert!(PALETTE[..i].iter().all(|b| b != a), "colour {i} repeats");
        }
        assert_eq!(PALETTE[PALE], RGBColor(240, 228, 66));
    }
}
