//! `squeal report` over synthetic run directories: every section is written, charts and WAV
//! files exist and are referenced from index.md and index.html.
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use squeal::analysis::identify::{ModeFamily, ModeRef};
use squeal::report::run_report::build_report;

fn write_run(dir: &Path, lateral_amp: f64) {
    std::fs::create_dir_all(dir).expect("dir");
    let fs = 20_000.0;
    let mut csv = String::from(
        "time_s,lateral_velocity_m_per_s,vertical_velocity_m_per_s,longitudinal_velocity_m_per_s\n",
    );
    let mut forces = String::from("time_s,normal_n,lateral_n,longitudinal_n\n");
    for i in 0..2_000 {
        let t = i as f64 / fs;
        let lat =
            lateral_amp * ((2.0 * PI * 1050.0 * t).sin() + 0.5 * (2.0 * PI * 300.0 * t).sin());
        let ver = 0.2 * (2.0 * PI * 1700.0 * t).sin();
        let lon = 0.1 * (2.0 * PI * 150.0 * t).sin();
        csv.push_str(&format!("{t:.8},{lat:.8},{ver:.8},{lon:.8}\n"));
        forces.push_str(&format!(
            "{t:.8},{},{},{}\n",
            110e3 + 1e3 * lat,
            5e3 * lon,
            30e3
        ));
    }
    std::fs::write(dir.join("histories.csv"), csv).expect("write");
    std::fs::write(dir.join("contact_forces.csv"), forces).expect("write");
    let modes = vec![
        ModeRef {
            frequency_hz: 300.0,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 0,
        },
        ModeRef {
            frequency_hz: 1050.0,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 3,
        },
        ModeRef {
            frequency_hz: 2000.0,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 4,
        },
        ModeRef {
            frequency_hz: 1700.0,
            family: ModeFamily::Radial,
            nodal_circles: 0,
            nodal_diameters: 2,
        },
    ];
    std::fs::write(
        dir.join("modes.json"),
        serde_json::to_string(&modes).expect("json"),
    )
    .expect("write");
    std::fs::write(
        dir.join("run.json"),
        r#"{"scenario": "synthetic", "time_step_s": 1e-7, "wall_time_s": 1.5}"#,
    )
    .expect("write");
}

#[test]
fn report_has_every_section_and_file() {
    let root: PathBuf = std::env::temp_dir().join(format!("squeal-report-{}", std::process::id()));
    let (a, b) = (root.join("case1"), root.join("case3"));
    write_run(&a, 0.1);
    write_run(&b, 1.0);
    let out = root.join("out");
    let summary = build_report(&[a, b], &out, "test report", &Default::default()).expect("report");
    for s in [
        "Wheel vibration: time histories and PSDs (all runs)",
        "Wavelet power spectra (Morlet)",
        "Contact forces",
        "Wheel modes",
        "Dominant frequencies and wheel modes",
        "Listen",
        "Run metadata",
    ] {
        assert!(
            summary.sections.iter().any(|x| x == s),
            "section {s} missing: {:?}",
            summary.sections
        );
    }
    let md = std::fs::read_to_string(out.join("index.md")).expect("md");
    let html = std::fs::read_to_string(out.join("index.html")).expect("html");
    for f in &summary.files {
        assert!(out.join(f).exists(), "{f} missing");
        if f.ends_with(".png") || f.ends_with(".wav") {
            assert!(md.contains(f.as_str()), "{f} not referenced in index.md");
            assert!(
                html.contains(f.as_str()),
                "{f} not referenced in index.html"
            );
        }
    }
    for f in [
        "vibration_lateral_psd.png",
        "wps_case1_lateral.png",
        "wps_case3_longitudinal.png",
        "contact_forces_case3.png",
        "modes.png",
        "case1_lateral.wav",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    // The mode table identifies the (0,3) peak of the lateral vibration.
    assert!(md.contains("| (0,3) | Axial |"), "{md}");
    assert!(md.contains("wall_time_s"));
    // The verdict comes first: these runs have no rim ring, and it says so (issue 57); then
    // the summary, which says whether the squeal modes are among the peaks.
    assert_eq!(summary.sections[0], "Does the wheel squeal?");
    assert!(
        md.contains("**cannot be judged**: the run has no rim ring"),
        "{md}"
    );
    assert_eq!(summary.sections[1], "Summary");
    assert!(md.contains("(0,3) / (0,4) among them"), "{md}");
    assert!(md.contains("yes / "), "the (0,3) run's verdict: {md}");
    // Issue 53, item 18: the markdown's bold and code (run names are in backticks) are
    // rendered, not shown as literal `**` and backticks.
    assert!(md.contains("**") && md.contains('`'), "{md}");
    let text = text_outside_tags(&html);
    assert!(!text.contains("**"), "literal ** in the page: {text}");
    assert!(!text.contains('`'), "literal backtick in the page: {text}");
    assert!(html.contains("<strong>cannot be judged</strong>"), "{html}");
    assert!(html.contains("<code>case1</code>"), "{html}");
    // The metadata table: one row per value, nested keys joined with dots.
    assert!(md.contains("| wall_time_s | 1.5 |"), "{md}");
    page_loads_as_a_reader_sees_it(&out, &html);
    let _ = std::fs::remove_dir_all(&root);
}

/// The HTML page as a reader's browser takes it: every image it shows exists and is a PNG,
/// every table-of-contents link leads to a section; and, where a headless Chromium is
/// installed, the page as the browser shows it ([`in_a_browser`]).
fn page_loads_as_a_reader_sees_it(out: &Path, html: &str) {
    let attribute = |tag: &str, name: &str| -> Vec<String> {
        html.split(tag)
            .skip(1)
            .filter_map(|rest| {
                let start = rest.find(&format!("{name}=\""))? + name.len() + 2;
                let end = rest[start..].find('"')? + start;
                Some(rest[start..end].to_string())
            })
            .collect()
    };
    let images = attribute("<img ", "src");
    assert!(!images.is_empty());
    for src in &images {
        let bytes = std::fs::read(out.join(src)).unwrap_or_default();
        assert!(bytes.starts_with(b"\x89PNG"), "image {src} does not load");
    }
    let links = attribute("<a ", "href");
    let toc: Vec<&String> = links
        .iter()
        .filter(|l| l.starts_with("#section-"))
        .collect();
    assert!(!toc.is_empty(), "no table of contents");
    for link in toc {
        assert!(
            html.contains(&format!("id=\"{}\"", &link[1..])),
            "{link} leads nowhere"
        );
    }
    assert!(html.contains("<style>") && html.contains("nav.toc"));
    in_a_browser(out, images.len());
}

/// The page's text outside its tags (the stylesheet left out), as a reader sees it.
fn text_outside_tags(html: &str) -> String {
    let body = html.split("</style>").last().unwrap_or(html);
    let mut text = String::new();
    let mut in_tag = false;
    for c in body.chars() {
        match c {
            '<' => in_tag = true,
            '>' => in_tag = false,
            c if !in_tag => text.push(c),
            _ => {}
        }
    }
    text
}

/// What a page reports of itself once loaded: its images (how many, which did not load), its
/// visible text (literal markdown left in it) and its width (anything running off the page).
const PAGE_CHECK_SCRIPT: &str = r#"<script>
window.addEventListener('load', function () {
  var images = Array.from(document.images);
  var text = document.body.innerText;
  var root = document.documentElement;
  var report = {
    images: images.length,
    broken: images.filter(function (i) { return !(i.complete && i.naturalWidth > 0); })
      .map(function (i) { return i.getAttribute('src'); }),
    markdown: ['*' + '*', String.fromCharCode(96), '!' + '[', ']' + '(']
      .filter(function (m) { return text.indexOf(m) >= 0; }),
    width: root.clientWidth,
    scroll_width: root.scrollWidth
  };
  var pre = document.createElement('pre');
  pre.id = 'page-check';
  pre.textContent = JSON.stringify(report);
  document.body.appendChild(pre);
});
</script>"#;

/// The page in a real headless browser (Chromium) 1400 px wide, where one is installed: every
/// image loads (`images` of them), the visible text holds no literal markdown (`**`, backtick,
/// `![`, `](`), nothing is wider than the window, and a screenshot 1400 px wide is written
/// (`screenshot.png` in the report folder). Skipped with a note where no Chromium is found
/// (`chromium`, `chromium-browser` or `google-chrome` on PATH; `.ci/run` installs one where it
/// can) or where the environment sets SQUEAL_NO_BROWSER.
fn in_a_browser(out: &Path, images: usize) {
    if std::env::var_os("SQUEAL_NO_BROWSER").is_some() {
        println!("SQUEAL_NO_BROWSER is set: the page was checked as files only, not in a browser");
        return;
    }
    let browser = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|b| {
            std::process::Command::new(b)
                .arg("--version")
                .stderr(std::process::Stdio::null())
                .output()
                .is_ok_and(|o| o.status.success())
        });
    let Some(browser) = browser else {
        println!("no headless Chromium here: the page was checked as files only");
        return;
    };
    let page = std::fs::read_to_string(out.join("index.html")).expect("page");
    let checked = out.join("index-check.html");
    std::fs::write(
        &checked,
        page.replace("</body>", &format!("{PAGE_CHECK_SCRIPT}</body>")),
    )
    .expect("write");
    let common = |extra: &str, url: &Path| -> Vec<String> {
        vec![
            "--headless".into(),
            "--disable-gpu".into(),
            "--no-sandbox".into(),
            "--hide-scrollbars".into(),
            "--window-size=1400,1800".into(),
            format!("--user-data-dir={}", out.join("browser-profile").display()),
            extra.into(),
            format!("file://{}", url.display()),
        ]
    };
    let dom = out.join("dom.html");
    run_browser(browser, &common("--dump-dom", &checked), &dom);
    let dumped = std::fs::read_to_string(&dom).unwrap_or_default();
    let report = dumped
        .split("<pre id=\"page-check\">")
        .nth(1)
        .and_then(|r| r.split("</pre>").next())
        .unwrap_or_else(|| panic!("{browser} did not run the page's check: {dumped}"))
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    let report: serde_json::Value = serde_json::from_str(&report).expect("check's JSON");
    println!("{browser}, 1400 px wide: {report}");
    assert_eq!(report["images"], images, "{report}");
    assert_eq!(
        report["broken"],
        serde_json::json!([]),
        "images not loaded: {report}"
    );
    assert_eq!(
        report["markdown"],
        serde_json::json!([]),
        "literal markdown: {report}"
    );
    assert!(
        report["scroll_width"].as_u64().unwrap_or(u64::MAX)
            <= report["width"].as_u64().unwrap_or(0),
        "the page is wider than the window: {report}"
    );
    let shot = out.join("screenshot.png");
    run_browser(
        browser,
        &common(
            &format!("--screenshot={}", shot.display()),
            &out.join("index.html"),
        ),
        &out.join("screenshot.log"),
    );
    let png = std::fs::read(&shot).unwrap_or_default();
    assert!(png.starts_with(b"\x89PNG"), "{browser} wrote no screenshot");
    let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
    assert_eq!(width, 1400, "screenshot {} px wide", width);
}

/// Runs the browser with `args`, its output into `stdout`, for at most two minutes.
fn run_browser(browser: &str, args: &[String], stdout: &Path) {
    let mut child = std::process::Command::new(browser)
        .args(args)
        .stdout(std::fs::File::create(stdout).expect("output file"))
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("browser");
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("browser") {
            break status;
        }
        if start.elapsed() > std::time::Duration::from_secs(120) {
            let _ = child.kill();
            panic!("{browser} took more than 120 s: {args:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    assert!(status.success(), "{browser} failed ({status}): {args:?}");
}

/// Issue 53, item 17: a run without a ring whose (0,3) wavelet ridge grows while (0,3) stays
/// out of the dominant lateral peaks gets a first line that says so in words and why the two
/// do not contradict each other. The rim point less the rim mean carries a 1050 Hz (0,3) tone
/// growing as exp(100 t) from 1e-3 m/s; the lateral velocity (standing for the rim point's
/// spectrum after the hub's motion has rung the n = 0 modes) holds 300, 1700 and 2400 Hz tones.
#[test]
fn a_growing_ridge_outside_the_dominant_peaks_is_explained_in_the_first_lines() {
    let root: PathBuf =
        std::env::temp_dir().join(format!("squeal-report-ridge-{}", std::process::id()));
    let run = root.join("ridge");
    write_run(&run, 1.0);
    let fs = 20_000.0;
    let growth_per_s = 100.0;
    let mut csv = String::from(
        "time_s,lateral_velocity_m_per_s,rim_mean_lateral_velocity_m_per_s,\
         rim_point_minus_mean_lateral_velocity_m_per_s\n",
    );
    for i in 0..2_000 {
        let t = i as f64 / fs;
        let n3 = 1e-3 * (growth_per_s * t).exp() * (2.0 * PI * 1050.0 * t).sin();
        let n0 = (2.0 * PI * 300.0 * t).sin();
        let lateral =
            n0 + 0.8 * (2.0 * PI * 1700.0 * t).sin() + 0.6 * (2.0 * PI * 2400.0 * t).sin();
        csv.push_str(&format!("{t:.8},{lateral:.10},{n0:.10},{n3:.10}\n"));
    }
    std::fs::write(run.join("histories.csv"), csv).unwrap();
    let out = root.join("out");
    build_report(&[run], &out, "ridge", &Default::default()).expect("report");
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    let line = md
        .lines()
        .find(|l| l.starts_with("- `ridge`:"))
        .expect("verdict line");
    assert!(line.contains("**cannot be judged**"), "{line}");
    assert!(
        line.contains("neither (0,3) nor (0,4) is among the 3 dominant lateral peaks"),
        "{line}"
    );
    assert!(line.contains("do not contradict each other"), "{line}");
    // The fastest window's rate: the Morlet transform of exp(g t) sin(w t) is that of the
    // sine scaled by exp(g t) (times a constant), so every window outside the cone of influence
    // gives g; 10 % allows for the 4 ms windows' least-squares fit on the sampled ridge.
    let rate: f64 = line
        .split("(0,3) 1050 Hz at ")
        .nth(1)
        .and_then(|r| r.split(" /s").next())
        .and_then(|r| r.trim_start_matches('+').parse().ok())
        .unwrap_or_else(|| panic!("no rate in {line}"));
    assert!(
        (rate - growth_per_s).abs() <= 0.1 * growth_per_s,
        "{rate} /s against {growth_per_s} /s: {line}"
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn report_without_histories_is_an_input_error() {
    let root = std::env::temp_dir().join(format!("squeal-report-empty-{}", std::process::id()));
    std::fs::create_dir_all(&root).expect("dir");
    let e = build_report(
        std::slice::from_ref(&root),
        &root.join("out"),
        "x",
        &Default::default(),
    )
    .expect_err("no histories");
    assert!(e.to_string().contains("histories.csv"));
    assert_eq!(e.exit_code(), 2);
    let _ = std::fs::remove_dir_all(&root);
}

/// A run with a `stability.json`: the report's stability section lists the predicted unstable
/// modes with the nearest PSD peak (the synthetic lateral vibration peaks at 1050 Hz, 1 %
/// above the predicted 1040 Hz: within the 5 % tolerance; no peak within 5 % of 4000 Hz).
#[test]
fn report_shows_predicted_unstable_modes_beside_the_psd_peaks() {
    let root: PathBuf =
        std::env::temp_dir().join(format!("squeal-report-stab-{}", std::process::id()));
    let run = root.join("case3");
    write_run(&run, 1.0);
    std::fs::write(
        run.join("stability.json"),
        r#"{"operating_point": {"origin": "case file x (eta 0.430 %)"},
            "settings": {"fmax_hz": 5000.0},
            "unstable": [
              {"frequency_hz": 1040.0, "growth_rate_per_s": 12.5, "dominant": "(0,3) axial 1011 Hz", "share": 0.9},
              {"frequency_hz": 4000.0, "growth_rate_per_s": 3.0, "dominant": "rail lateral 4000 Hz", "share": 0.6}
            ]}"#,
    )
    .unwrap();
    let out = root.join("out");
    let summary =
        build_report(std::slice::from_ref(&run), &out, "t", &Default::default()).expect("report");
    assert!(summary
        .sections
        .iter()
        .any(|s| s == "Predicted unstable modes beside the PSD peaks"));
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    println!("{md}");
    let row = |start: &str| {
        md.lines()
            .find(|l| l.starts_with(start))
            .unwrap_or_else(|| panic!("no row {start}: {md}"))
            .to_string()
    };
    let first = row("| 1040.0 | +12.50 | (0,3) axial 1011 Hz (90 %) |");
    assert!(first.contains("| 1050 Hz lateral (rank 1) |"), "{first}");
    assert!(first.ends_with("| yes |"), "{first}");
    assert!(row("| 4000.0 | +3.00 | rail lateral 4000 Hz (60 %) |").ends_with("| no |"));
    // A broken file is an input error naming it.
    std::fs::write(run.join("stability.json"), r#"{"settings": {}}"#).unwrap();
    let e = build_report(std::slice::from_ref(&run), &out, "t", &Default::default())
        .expect_err("broken stability.json");
    assert!(e.to_string().contains("stability.json"), "{e}");
    assert_eq!(e.exit_code(), 2);
    let _ = std::fs::remove_dir_all(&root);
}

/// A snapshot sampled from Hertz's pressure on a square lattice of spacing `h_mm`, with the
/// pressure centre on a node.
fn hertz_snapshot(dir: &Path, hertz: &squeal::kalker::hertz::HertzContact, h_mm: f64) -> PathBuf {
    let mut csv = String::from(
        "x_m,y_m,pressure_pa,shear_x_pa,shear_y_pa,slip_vx_m_per_s,slip_vy_m_per_s,slip_by_bound,slip_by_velocity\n",
    );
    for i in -20i32..=20 {
        for j in -20i32..=20 {
            let (x, y) = (i as f64 * h_mm * 1e-3, j as f64 * h_mm * 1e-3);
            let p = hertz.pressure_pa(x, y);
            csv.push_str(&format!("{x},{y},{p},{},0,0.001,0,0,1\n", 0.3 * p));
        }
    }
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join("patch.csv");
    std::fs::write(&path, csv).unwrap();
    path
}

/// Every patch chart states its resolution and its peak against Hertz: on a Hertz patch
/// sampled on a lattice the loaded nodes on the centre lines are the lattice points strictly
/// inside the ellipse (|x| < a, |y| < b; measured 33 x 15 at 0.5 mm and 5 x 1 at 4 mm for
/// a = 8.11, b = 3.91 mm), and the peak is Hertz's p0 where a node sits at the centre.
#[test]
fn patch_maps_state_nodes_across_and_peak_against_hertz() {
    use squeal::kalker::hertz::HertzContact;
    use squeal::report::patch_maps::{write_patch_maps, RESOLVED_NODES_ACROSS};
    let material = squeal::kalker::Material::validated(210e9, 0.3, "test").unwrap();
    // An elliptic contact (A : B = 1 : 3); its axes are read back.
    let hertz = HertzContact::from_curvatures(1.0, 3.0, 100e3, material).unwrap();
    let (a_mm, b_mm) = (hertz.semi_axis_a_m * 1e3, hertz.semi_axis_b_m * 1e3);
    let dir = std::env::temp_dir().join(format!("squeal_patch_maps_{}", std::process::id()));
    for h_mm in [0.5, 4.0] {
        let csv = hertz_snapshot(&dir.join(format!("h{h_mm}")), &hertz, h_mm);
        let out = dir.join(format!("out{h_mm}"));
        let (files, r) = write_patch_maps(&csv, 0.3, 18.0, Some(&hertz), &out, "p").unwrap();
        // Lattice points strictly inside (-a, a) on the centre row, (-b, b) on the column.
        let inside = |half: f64| 2 * ((half / h_mm - 1e-9).ceil() as usize - 1) + 1;
        println!(
            "h {h_mm} mm, a {a_mm:.2} b {b_mm:.2} mm: {}",
            r.statement(Some(hertz.peak_pressure_pa * 1e-6))
        );
        assert_eq!(r.nodes_along_x, inside(a_mm));
        assert_eq!(r.nodes_across_y, inside(b_mm));
        assert!((r.node_spacing_mm - h_mm).abs() < 1e-9);
        // The centre node carries p0 (rounding only).
        assert!((r.peak_pressure_mpa / (hertz.peak_pressure_pa * 1e-6) - 1.0).abs() < 1e-12);
        assert_eq!(r.nodes_across() >= RESOLVED_NODES_ACROSS, h_mm < 1.0);
        assert_eq!(files.len(), 3);
        for f in &files {
            assert!(out.join(f).exists());
            // The SVG twin carries the statement as text.
            let svg = std::fs::read_to_string(out.join(f).with_extension("svg")).unwrap();
            assert!(svg.contains("nodes across"), "{f}");
            assert!(svg.contains("Hertz p0"), "{f}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every snapshot a case asks for is drawn (the paper cases ask for 8; the report drew only the
/// first 6 until 2026-11-28), up to 12 per run, and a run with more says how many were left
/// out. 13 snapshots of a Hertz patch (the mesh of the test above at 1 mm) in one run: 12 drawn
/// in time order, the note names 13.
#[test]
fn report_draws_every_patch_snapshot_up_to_twelve() {
    use squeal::kalker::hertz::HertzContact;
    let material = squeal::kalker::Material::validated(210e9, 0.3, "test").unwrap();
    let hertz = HertzContact::from_curvatures(1.0, 3.0, 100e3, material).unwrap();
    let root = std::env::temp_dir().join(format!("squeal_report_patches_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let run = root.join("run");
    write_run(&run, 1.0);
    let patches = run.join("patches");
    let lattice = hertz_snapshot(&root.join("lattice"), &hertz, 1.0);
    std::fs::create_dir_all(&patches).unwrap();
    for k in 0..13 {
        let name = format!("patch_{:07}.0us.csv", 16_000 + 500 * k);
        std::fs::copy(&lattice, patches.join(name)).unwrap();
    }
    let out = root.join("out");
    build_report(std::slice::from_ref(&run), &out, "t", &Default::default()).unwrap();
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert_eq!(md.matches("Resolution: ").count(), 12, "{md}");
    assert!(md.contains("12 of run's 13 snapshots drawn"), "{md}");
    // The last one drawn is the 12th by time, the 13th is not drawn.
    assert!(md.contains("patch_0021500.0us"), "{md}");
    assert!(!md.contains("patch_0022000.0us"), "{md}");
    let _ = std::fs::remove_dir_all(&root);
}
