//! End-to-end: `squeal psd | cwt | wav` on a small CSV, and exit code 2 on bad input.

use std::path::PathBuf;
use std::process::Command;

fn squeal() -> Command {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-cli-signal-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_csv(dir: &std::path::Path) -> PathBuf {
    let path = dir.join("signal.csv");
    let mut text = String::from("time_s,uy_m\n");
    for i in 0..8000 {
        let t = i as f64 / 8000.0;
        let value = 1e-5 * (2.0 * std::f64::consts::PI * 1000.0 * t).sin()
            + 4e-6 * (2.0 * std::f64::consts::PI * 2000.0 * t).sin();
        text.push_str(&format!("{t},{value}\n"));
    }
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn psd_cwt_and_wav_write_their_files() {
    let dir = temp_dir("ok");
    let csv = write_csv(&dir);
    let out = dir.join("out");
    let status = squeal()
        .args([
            "psd",
            csv.to_str().unwrap(),
            "--column",
            "uy_m",
            "--nperseg",
            "1024",
            "--peaks",
            "2",
        ])
        .args(["--out", out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    let psd = std::fs::read_to_string(out.join("psd.csv")).unwrap();
    assert!(psd.starts_with("frequency_hz,psd_m^2_per_hz\n"));
    assert_eq!(psd.lines().count(), 1 + 513);
    let peaks: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("peaks.json")).unwrap()).unwrap();
    let first = peaks["peaks"][0]["refined_frequency_hz"].as_f64().unwrap();
    assert!((first - 1000.0).abs() < 1.0, "{first}");

    let status = squeal()
        .args([
            "cwt",
            csv.to_str().unwrap(),
            "--column",
            "uy_m",
            "--fmin-hz",
            "500",
            "--fmax-hz",
            "3000",
        ])
        .args([
            "--voices",
            "4",
            "--time-stride",
            "100",
            "--out",
            out.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let power = std::fs::read_to_string(out.join("cwt_power.csv")).unwrap();
    assert!(power.starts_with("time_s,frequency_hz,power_m^2\n"));
    assert!(out.join("cwt_coi.csv").exists() && out.join("cwt.json").exists());

    // --out names the folder; the file is <column>.wav in it.
    let wav_dir = dir.join("wav");
    let status = squeal()
        .args([
            "wav",
            csv.to_str().unwrap(),
            "--column",
            "uy_m",
            "--out",
            wav_dir.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let wav = wav_dir.join("uy_m.wav");
    assert_eq!(
        squeal::signal::wav::read_pcm16_wav(&wav)
            .unwrap()
            .sample_rate_hz,
        44_100
    );

    // SOURCE may be a run directory: its histories.csv is read.
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    std::fs::copy(&csv, run.join("histories.csv")).unwrap();
    let run_out = dir.join("run-psd");
    let status = squeal()
        .args(["psd", run.to_str().unwrap(), "--column", "uy_m"])
        .args(["--nperseg", "1024", "--out", run_out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());
    let peaks: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run_out.join("peaks.json")).unwrap())
            .unwrap();
    assert!(peaks["source"].as_str().unwrap().ends_with("histories.csv"));
    assert_eq!(
        std::fs::read_to_string(run_out.join("psd.csv")).unwrap(),
        psd
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_exits_with_code_2_and_says_why() {
    let dir = temp_dir("bad");
    let csv = write_csv(&dir);
    let csv = csv.to_str().unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "psd",
                "/nonexistent/file.csv",
                "--column",
                "uy_m",
                "--out",
                out,
            ],
            "/nonexistent/file.csv",
        ),
        (
            vec!["psd", csv, "--column", "uz_m", "--out", out],
            "available columns: time_s, uy_m",
        ),
        (
            vec![
                "psd",
                csv,
                "--column",
                "uy_m",
                "--nperseg",
                "9000",
                "--out",
                out,
            ],
            "2..=8000",
        ),
        (
            vec![
                "psd",
                csv,
                "--column",
                "uy_m",
                "--overlap",
                "1.2",
                "--out",
                out,
            ],
            "[0, 1)",
        ),
        (
            vec![
                "cwt",
                csv,
                "--column",
                "uy_m",
                "--fmin-hz",
                "10",
                "--fmax-hz",
                "5000",
                "--out",
                out,
            ],
            "Nyquist",
        ),
    ];
    for (args, expected) in cases {
        let output = squeal().args(&args).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
