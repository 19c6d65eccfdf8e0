//! Charts render with the bundled font on a machine without system fonts: the PNG decodes
//! (signature and size), has text and lines drawn (non-white pixels, more than the axes alone),
//! and the SVG names its title and axis labels.
use squeal::report::chart::{write, LineChart, Series, Stroke};

#[test]
fn line_chart_writes_png_and_svg_with_text() {
    let dir = std::env::temp_dir().join(format!("squeal-chart-{}", std::process::id()));
    let (png, svg) = (dir.join("c.png"), dir.join("c.svg"));
    let x: Vec<f64> = (0..200).map(|i| i as f64 * 0.05).collect();
    let chart = LineChart {
        title: "Test chart".into(),
        x_label: "time (s)".into(),
        y_label: "displacement (mm)".into(),
        series: vec![
            Series::line("sine", x.clone(), x.iter().map(|t| t.sin()).collect(), 0),
            Series {
                label: "cosine".into(),
                x: x.clone(),
                y: x.iter().map(|t| t.cos()).collect(),
                stroke: Stroke::Dotted,
                color: 1,
            },
            Series {
                label: "points".into(),
                x: vec![1.0, 2.0],
                y: vec![0.5, -0.5],
                stroke: Stroke::Points,
                color: 2,
            },
        ],
        ..Default::default()
    };
    write(&chart, Some(&png), Some(&svg)).expect("write chart");
    let bytes = std::fs::read(&png).expect("png");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    // IHDR width/height (big endian) at bytes 16..24.
    let width = u32::from_be_bytes(bytes[16..20].try_into().expect("w"));
    let height = u32::from_be_bytes(bytes[20..24].try_into().expect("h"));
    // The chart at its default size, its legend in a band of its own below (issue 53,
    // item 18: a legend inside the plot covered data).
    assert_eq!(width, 1000);
    assert!((650..800).contains(&height), "{height} px high");
    let text = std::fs::read_to_string(&svg).expect("svg");
    for needle in [
        "Test chart",
        "time (s)",
        "displacement (mm)",
        "sine",
        "cosine",
    ] {
        assert!(text.contains(needle), "SVG lacks `{needle}`");
    }
    // A chart with only a title must be much smaller than one with three series: the series
    // are drawn (compressed PNG size is a robust proxy for drawn content).
    let empty = LineChart {
        title: "Test chart".into(),
        ..Default::default()
    };
    let png_empty = dir.join("e.png");
    write(&empty, Some(&png_empty), None).expect("write empty");
    assert!(bytes.len() > std::fs::metadata(&png_empty).expect("meta").len() as usize + 5000);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn log_axis_skips_non_positive_values() {
    let dir = std::env::temp_dir().join(format!("squeal-chart-log-{}", std::process::id()));
    let chart = LineChart {
        title: "PSD".into(),
        x_label: "frequency (Hz)".into(),
        y_label: "PSD (m^2/Hz)".into(),
        series: vec![Series::line(
            "psd",
            vec![0.0, 1.0, 2.0, 3.0],
            vec![0.0, 1e-6, 1e-3, -1.0],
            0,
        )],
        log_y: true,
        ..Default::default()
    };
    write(&chart, Some(&dir.join("l.png")), Some(&dir.join("l.svg")))
        .expect("log chart with zeros and negatives");
    // The positive points are drawn (the SVG holds a polyline between them) and the axis is
    // logarithmic (its tick labels span the decades of the positive values).
    let svg = std::fs::read_to_string(dir.join("l.svg")).expect("svg");
    assert!(svg.contains("<polyline"), "no line drawn");
    assert!(
        svg.contains("1e-6") || svg.contains("1e-5"),
        "no decade ticks: {svg:.400}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Tick labels on an axis: a tick that floating-point stepping put at 1.39e-17 instead of 0
/// reads 0; real small values on a small axis keep their value.
#[test]
fn ticks_near_zero_read_zero_on_their_axis() {
    use squeal::report::chart::tick_label_on_span;
    assert_eq!(tick_label_on_span(1.39e-17, 2.0), "0");
    assert_eq!(tick_label_on_span(-2.2e-16, 0.5), "0");
    assert_eq!(tick_label_on_span(0.25, 2.0), "0.25");
    assert_eq!(tick_label_on_span(1e-6, 1e-5), "1e-6");
}
