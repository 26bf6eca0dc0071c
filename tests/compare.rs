//! `washdyn compare` on two synthetic runs written with the project's writers (the sensor
//! recorder and the run summary), with known order amplitudes:
//! * `tub1_ax`: A = 1.0 sin(phi) + 0.3 sin(3 phi), B = 2.0 sin(phi + 0.7) + 0.3 sin(3 phi):
//!   order 1 is 20 log10(2.0 / 1.0) = 6.0206 dB up in B along the whole run-up, order 3 the same
//!   (0 dB), and RMS(B - A) / RMS(A) = sqrt((1 + 4 - 4 cos 0.7) / (1 + 0.3^2)) = 1.3343 (mean
//!   squares of the sines; the run holds 120 drum revolutions, so the average is good to about
//!   1 / (2 pi 120));
//! * `tub1_ay`, `drum_front_ux`: equal in both runs (0 dB);
//! * `cabinet1_ax`: zero in both (not compared).
//!
//! The drum runs up linearly from 120 to 1080 rpm in 12 s; the phase is the speed's exact
//! integral, so every component is locked to the drum.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use washdyn::commands::write_summary;
use washdyn::compare::{CompareArgs, CompareError, compare};
use washdyn::results::{Format, SensorRecorder};
use washdyn_runtime::output::SampleSink;
use washdyn_runtime::run::{Labels, Summary};

const FS: f64 = 2000.0;
const T_END: f64 = 12.0;

fn rpm(t: f64) -> f64 {
    120.0 + 80.0 * t
}

fn phi(t: f64) -> f64 {
    2.0 * PI / 60.0 * (120.0 * t + 40.0 * t * t)
}

/// A run directory as `washdyn run` leaves it: sensors.<format> and summary.json. `signal`
/// gives each channel's value at (t, phi).
fn write_run(
    dir: &Path,
    format: Format,
    channels: &[&str],
    t_end: f64,
    signal: impl Fn(usize, f64, f64) -> f64,
) {
    std::fs::create_dir_all(dir).unwrap();
    let mut rec = SensorRecorder::new(dir, format, false);
    let names: Vec<String> = channels.iter().map(|c| c.to_string()).collect();
    rec.header(&names).unwrap();
    let n = (t_end * FS).round() as usize + 1;
    let mut row = vec![0.0; channels.len()];
    for k in 0..n {
        let t = k as f64 / FS;
        for (c, v) in row.iter_mut().enumerate() {
            *v = signal(c, t, phi(t));
        }
        rec.sample(t, rpm(t), &row).unwrap();
    }
    rec.finish().unwrap();
    let labels = Labels {
        model: "synthetic".into(),
        scene: dir.file_name().unwrap().to_string_lossy().into(),
        backend: "none".into(),
    };
    let mut s = Summary::new(&labels, "rodas4", (1e-6, 1e-9), (0.0, t_end));
    s.t_reached = t_end;
    s.steps = 1234;
    s.rejected_steps = 5;
    s.wall_time_s = 0.5;
    s.samples = n as u64;
    write_summary(dir, &s).unwrap();
}

const CHANNELS: [&str; 4] = ["tub1_ax", "tub1_ay", "cabinet1_ax", "drum_front_ux"];

fn common(c: usize, p: f64) -> f64 {
    match c {
        1 => 0.5 * p.cos() + 0.1 * (11.25 * p).sin(),
        2 => 0.0,
        _ => 0.002 * p.sin() - 0.01,
    }
}

fn run_a(c: usize, _t: f64, p: f64) -> f64 {
    match c {
        0 => p.sin() + 0.3 * (3.0 * p).sin(),
        _ => common(c, p),
    }
}

fn run_b(c: usize, _t: f64, p: f64) -> f64 {
    match c {
        0 => 2.0 * (p + 0.7).sin() + 0.3 * (3.0 * p).sin(),
        _ => common(c, p),
    }
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("washdyn-compare-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn args(a: &Path, b: &Path, out: &Path) -> CompareArgs {
    CompareArgs {
        runs: [a.to_path_buf(), b.to_path_buf()],
        labels: ["A".into(), "B".into()],
        out: out.to_path_buf(),
        motor_ratio: 11.25,
        svg: false,
        until: None,
    }
}

#[test]
fn order_one_doubled_reads_6_02_db_and_equal_channels_0_db() {
    let root = scratch("known");
    let (a, b, out) = (root.join("a"), root.join("b"), root.join("out"));
    // A as Parquet, B as CSV: both go through the analysis' reader.
    write_run(&a, Format::Parquet, &CHANNELS, T_END, run_a);
    write_run(&b, Format::Csv, &CHANNELS, T_END, run_b);
    let (c, files) = compare(&args(&a, &b, &out)).unwrap();

    assert_eq!(c.zero_in_both, vec!["cabinet1_ax".to_string()]);
    let names: Vec<&str> = c.channels.iter().map(|c| c.channel.as_str()).collect();
    assert_eq!(names, ["tub1_ax", "tub1_ay", "drum_front_ux"]);
    let ch = |n: &str| c.channels.iter().find(|c| c.channel == n).unwrap();
    let order = |n: &str, o: f64| {
        ch(n)
            .orders
            .iter()
            .find(|x| x.order == o)
            .unwrap_or_else(|| panic!("{n}: order {o} tracked"))
            .clone()
    };

    // Order 1 of tub1_ax: amplitudes 1.0 and 2.0, so 20 log10(2) dB, at the peak and all along
    // the track, up to the analysis' error (the resampler's kernel; the Hann window puts order 3
    // and motor order 11.25 on their own bins, and CSV round-trips f64 exactly). Measured when
    // written: peaks 8.9e-8 (A) and 7.1e-8 (B) relative above their amplitudes, dB 1.6e-7 off
    // at the peak and 4.8e-7 along the track (at 960 rpm); bounds about 10x that.
    let expected = 20.0 * 2f64.log10();
    let o1 = order("tub1_ax", 1.0);
    let (pa, pb) = (o1.peak_a.unwrap(), o1.peak_b.unwrap());
    eprintln!(
        "order 1: peak A {pa:.8} (err {:.2e}), peak B {pb:.8} (err {:.2e}), dB {:.6} (err \
         {:.2e}), worst track dB {:.6} (err {:.2e}) at {:.0} rpm",
        pa - 1.0,
        pb / 2.0 - 1.0,
        o1.db.unwrap(),
        o1.db.unwrap() - expected,
        o1.worst_db.unwrap(),
        o1.worst_db.unwrap() - expected,
        o1.worst_rpm.unwrap()
    );
    assert!((pa - 1.0).abs() < 1e-6, "peak A {pa}");
    assert!((pb / 2.0 - 1.0).abs() < 1e-6, "peak B {pb}");
    assert!((o1.db.unwrap() - expected).abs() < 2e-6, "{o1:?}");
    assert!((o1.worst_db.unwrap() - expected).abs() < 5e-6, "{o1:?}");
    // Order 3 equal in both runs: 0 dB, its peak 0.3. Measured: 4.8e-7 dB at the peak, 1.9e-6
    // along the track.
    let o3 = order("tub1_ax", 3.0);
    eprintln!(
        "order 3: dB {:.2e}, worst {:.2e}",
        o3.db.unwrap(),
        o3.worst_db.unwrap()
    );
    assert!((o3.peak_a.unwrap() - 0.3).abs() < 1e-6, "{o3:?}");
    assert!(o3.db.unwrap().abs() < 5e-6, "{o3:?}");
    assert!(o3.worst_db.unwrap().abs() < 2e-5, "{o3:?}");

    // Equal channels: the same samples (CSV round-trips them) through the same analysis: 0 dB.
    for n in ["tub1_ay", "drum_front_ux"] {
        for o in &ch(n).orders {
            for v in [o.db, o.worst_db].into_iter().flatten() {
                assert!(v.abs() < 1e-12, "{n}: {o:?}");
            }
        }
    }
    assert!(order("tub1_ay", 1.0).db.is_some());
    assert!(order("tub1_ay", 11.25).db.is_some(), "motor order tracked");
    assert!(ch("tub1_ay").rms_diff.unwrap() < 1e-12);
    // Displacements carry no RMS difference (accelerations only).
    assert_eq!(ch("drum_front_ux").rms_diff, None);

    // RMS(B - A) / RMS(A) of tub1_ax against the mean squares of the sines: measured 1.1e-3
    // above (the 120 revolutions' end effect, about 1 / (2 pi 120) = 1.3e-3).
    let rms = ch("tub1_ax").rms_diff.unwrap();
    let want = ((5.0 - 4.0 * 0.7f64.cos()) / 1.09).sqrt();
    eprintln!("rms diff {rms:.6} against {want:.6}");
    assert!((rms / want - 1.0).abs() < 1e-2, "{rms} vs {want}");
    // In the 300 Hz band (every line of these signals is in it, orders 1 and 3 at 10 Hz, motor
    // order 1 at 112 Hz): the same ratio, Hann-weighted over the run.
    let band = ch("tub1_ax").band_diff.unwrap();
    eprintln!("band diff {band:.6} against {want:.6}");
    assert!((band / want - 1.0).abs() < 1e-2, "{band} vs {want}");
    assert!(ch("tub1_ay").band_diff.unwrap() < 1e-12);
    assert_eq!(ch("drum_front_ux").band_diff, None);
    // The strong part of order 1's track (within 20 dB of its peak) reads the same 6.02 dB.
    let strong = o1.worst_strong_db.unwrap();
    assert!((strong - expected).abs() < 5e-6, "{strong}");

    // The costs from the summaries, the tables and the plots.
    assert_eq!(c.runs[0].steps, Some(1234));
    assert_eq!(c.runs[1].method.as_deref(), Some("rodas4"));
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(md.contains("| tub1_ax [m/s²] | 1 |"), "{md}");
    assert!(md.contains("+6.02"), "{md}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(json["channels"].as_array().unwrap().len(), 3);
    for n in ["tub1_ax", "tub1_ay", "drum_front_ux"] {
        for kind in ["order", "tracks"] {
            let p = out.join(format!("{n}_{kind}_compare.png"));
            assert!(files.contains(&p), "{p:?} listed");
            assert!(std::fs::metadata(&p).unwrap().len() > 10_000, "{p:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn runs_that_do_not_match_are_refused_naming_the_directories() {
    let root = scratch("refused");
    let a = root.join("a");
    // Short runs: the checks come before any analysis.
    let t = 2.0;
    write_run(&a, Format::Parquet, &CHANNELS, t, run_a);

    // Another channel set.
    let other = root.join("other_channels");
    write_run(&other, Format::Parquet, &["tub1_ax", "tub1_az"], t, run_a);
    let e = compare(&args(&a, &other, &root.join("out"))).unwrap_err();
    assert!(matches!(e, CompareError::Channels { .. }), "{e}");
    let msg = e.to_string();
    for part in ["/a ", "other_channels", "tub1_az", "tub1_ay"] {
        assert!(msg.contains(part), "`{part}` in: {msg}");
    }

    // A run that stopped early: another speed profile.
    let short = root.join("short");
    write_run(&short, Format::Parquet, &CHANNELS, 1.5, run_a);
    let e = compare(&args(&a, &short, &root.join("out"))).unwrap_err();
    assert!(matches!(e, CompareError::Profile { .. }), "{e}");
    assert!(e.to_string().contains("short"), "{e}");

    // `--until` compares the common span: the run that stopped at 1.5 s against the first
    // 1.5 s of the 2 s run (the same signals: 0 dB, RMS difference 0). A time past either run's
    // end, or before its start, is refused naming that run.
    let (c, _) = compare(&CompareArgs {
        until: Some(1.5),
        ..args(&a, &short, &root.join("out_until"))
    })
    .unwrap();
    assert_eq!(c.samples, (1.5 * FS) as usize + 1);
    assert!((c.t_end_s - 1.5).abs() < 1e-12, "{}", c.t_end_s);
    let ax = c.channels.iter().find(|c| c.channel == "tub1_ax").unwrap();
    assert_eq!(ax.rms_diff, Some(0.0), "the same run up to 1.5 s");
    for until in [1.8, -1.0, f64::NAN] {
        let e = compare(&CompareArgs {
            until: Some(until),
            ..args(&a, &short, &root.join("out"))
        })
        .unwrap_err();
        assert!(matches!(e, CompareError::Until { .. }), "{until}: {e}");
        let culprit = if until > 0.0 { "short" } else { "/a " };
        assert!(e.to_string().contains(culprit), "{until}: {e}");
    }
    let _ = std::fs::remove_dir_all(root.join("out_until"));

    // Missing directory, missing sensor file, missing summary.
    let e = compare(&args(&a, &root.join("nothing"), &root.join("out"))).unwrap_err();
    assert!(matches!(e, CompareError::NoRun { .. }), "{e}");
    assert!(e.to_string().contains("nothing"), "{e}");
    let empty = root.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let e = compare(&args(&empty, &a, &root.join("out"))).unwrap_err();
    assert!(matches!(e, CompareError::NoSensors { .. }), "{e}");
    let no_summary = root.join("no_summary");
    write_run(&no_summary, Format::Parquet, &CHANNELS, t, run_a);
    std::fs::remove_file(no_summary.join("summary.json")).unwrap();
    let e = compare(&args(&a, &no_summary, &root.join("out"))).unwrap_err();
    assert!(matches!(e, CompareError::Summary { .. }), "{e}");
    assert!(e.to_string().contains("summary.json"), "{e}");
    assert!(!root.join("out").exists(), "nothing written");

    // A belt ratio that marks no motor order (issue 23): refused before anything is written,
    // by compare and by analyse (the CLI, exit code 2).
    for r in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
        let e = compare(&CompareArgs {
            motor_ratio: r,
            ..args(&a, &a, &root.join("out"))
        })
        .unwrap_err();
        assert!(
            matches!(
                e,
                CompareError::Read(washdyn::analysis::AnalysisError::InvalidOptions(_))
            ),
            "{r}: {e}"
        );
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
            .arg("analyse")
            .arg(&a)
            .arg(format!("--motor-ratio={r}"))
            .arg("--out")
            .arg(root.join("out"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{r}: {err}");
        assert!(err.contains("motor_ratio must be positive"), "{r}: {err}");
    }
    assert!(!root.join("out").exists(), "nothing written");
    let _ = std::fs::remove_dir_all(&root);
}

/// A run whose summary says it did not finish is refused as such (its status, its error and
/// where its output ends), not as another speed profile, unless `--until` compares the span it
/// reached; a span shorter than the analysis' 1 s block is analysed in one block over all of it,
/// down to 0.25 s, and refused below (issue 50).
#[test]
fn unfinished_runs_and_spans_shorter_than_a_block() {
    let root = scratch("unfinished");
    let a = root.join("a");
    write_run(&a, Format::Parquet, &CHANNELS, 2.0, run_a);
    let failed = root.join("failed");
    write_run(&failed, Format::Parquet, &CHANNELS, 1.5, run_a);
    let path = failed.join("summary.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    v["status"] = "failed".into();
    v["error"] = "integration failed: step size underflow at t = 1.5 s (h = 1e-14 s)".into();
    std::fs::write(&path, v.to_string()).unwrap();
    let e = compare(&args(&a, &failed, &root.join("out"))).unwrap_err();
    assert!(
        matches!(&e, CompareError::Unfinished { status, last, .. } if status == "failed" && *last == 1.5),
        "{e}"
    );
    let msg = e.to_string();
    for part in [
        "failed: the run did not finish (status failed: integration failed: step size underflow",
        "its output ends at 1.5 s: compare up to there with --until 1.5",
    ] {
        assert!(msg.contains(part), "`{part}` in: {msg}");
    }
    assert!(!root.join("out").exists(), "nothing written");
    let (c, _) = compare(&CompareArgs {
        until: Some(1.5),
        ..args(&a, &failed, &root.join("out_until"))
    })
    .unwrap();
    assert_eq!(c.note, None, "1.5 s holds a 1 s block");

    // Half a second: one block of its 1001 samples; a tenth: refused, nothing written.
    let (c, _) = compare(&CompareArgs {
        until: Some(0.5),
        ..args(&a, &a, &root.join("out_short"))
    })
    .unwrap();
    assert_eq!(c.samples, 1001);
    let note = c.note.expect("a note");
    assert!(
        note.contains("0.5005 s, is shorter than the analysis' 1 s blocks"),
        "{note}"
    );
    let md = std::fs::read_to_string(root.join("out_short").join("compare.md")).unwrap();
    assert!(md.contains(&note), "{md}");
    let e = compare(&CompareArgs {
        until: Some(0.1),
        ..args(&a, &a, &root.join("out"))
    })
    .unwrap_err();
    assert!(
        matches!(
            e,
            CompareError::Read(washdyn::analysis::AnalysisError::TooFewSamples {
                found: 201,
                needed: 500,
                ..
            })
        ),
        "{e}"
    );
    assert!(!root.join("out").exists(), "nothing written");
    // The command line takes a negative --until as a value, and the comparison refuses it.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .arg("compare")
        .args([&a, &a])
        .args(["--until", "-1", "--out"])
        .arg(root.join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(err.contains("--until -1 s is not inside it"), "{err}");
    let _ = std::fs::remove_dir_all(&root);
}
