//! End-to-end: a synthetic run-up CSV goes through `analyse_file`; every promised
//! file exists and is non-trivial. Set `WASHDYN_ANALYSIS_OUT=/some/dir` to keep the
//! output for looking at the pictures.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;

use washdyn::analysis::{AnalysisOptions, ColourScale, analyse_file, plot};
use washdyn::results::Format;

/// Linear run-up `r0 -> r1` rpm over `duration` s at `fs` Hz, phase integrated from
/// the speed so the orders are exact:
/// * `tub1_ax`: orders 1 (1.0), 3 (0.3), motor order 1 = 11.25 (0.05 m/s^2);
/// * `tub1_ay`: order 1 (1.0), motor order 2 = 22.5 (0.05 m/s^2);
/// * `cabinet2_az`: what a measurement looks like: order 1 through a suspension
///   resonance at 250 rpm, motor orders growing with speed, a panel resonance at
///   85 Hz excited by noise, and broadband noise;
/// * `drum_front_ux`, `drum_front_uy`: displacements, order 1 around a static offset.
fn write_run_up_csv(path: &std::path::Path, r0: f64, r1: f64, duration: f64, fs: f64) {
    let n = (duration * fs) as usize;
    let mut s =
        String::from("time_s,drum_rpm,tub1_ax,tub1_ay,cabinet2_az,drum_front_ux,drum_front_uy\n");
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut rand = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    // Panel resonance: two-pole resonator at 85 Hz, pole radius 0.99.
    let (r, th) = (0.99, 2.0 * PI * 85.0 / fs);
    let (mut y1, mut y2) = (0.0, 0.0);
    for i in 0..n {
        let t = i as f64 / fs;
        let rpm = r0 + (r1 - r0) * t / duration;
        let phi = 2.0 * PI / 60.0 * (r0 * t + 0.5 * (r1 - r0) * t * t / duration);
        let ax = (phi).sin() + 0.3 * (3.0 * phi).sin() + 0.05 * (11.25 * phi).sin();
        let ay = (phi).cos() + 0.05 * (22.5 * phi).sin();
        let eta = rpm / 250.0;
        let suspension = 0.4 * eta * eta / ((1.0 - eta * eta).powi(2) + (0.2 * eta).powi(2)).sqrt();
        let y = 2.0 * r * th.cos() * y1 - r * r * y2 + 0.02 * rand();
        (y2, y1) = (y1, y);
        let speed = rpm / 1400.0;
        let az = suspension * phi.sin()
            + 0.08 * (2.0 * phi).sin()
            + 0.03 * speed * speed * (11.25 * phi).sin()
            + 0.01 * speed * (22.5 * phi).sin()
            + y
            + 0.005 * rand();
        let ux = 0.002 * (phi).sin() - 0.01;
        let uy = 0.002 * (phi).cos() * (1.0 + 0.5 * t / duration);
        writeln!(
            s,
            "{t:.6},{rpm:.4},{ax:.7e},{ay:.7e},{az:.7e},{ux:.7e},{uy:.7e}"
        )
        .unwrap();
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn analyse_file_writes_all_plots_and_csvs() {
    plot::init_fonts();
    plot::init_fonts(); // idempotent
    let tmp = tempfile::tempdir().unwrap();
    let out: PathBuf = std::env::var_os("WASHDYN_ANALYSIS_OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| tmp.path().join("out"));
    let csv = tmp.path().join("runup.csv");
    write_run_up_csv(&csv, 100.0, 1400.0, 40.0, 2000.0);

    if std::env::var_os("WASHDYN_ANALYSIS_OUT").is_some() {
        std::fs::create_dir_all(&out).unwrap();
        std::fs::copy(&csv, out.join("input_runup.csv")).unwrap();
    }
    let opts = AnalysisOptions {
        format: Format::Csv,
        ..AnalysisOptions::default()
    };
    let report = analyse_file(&csv, &out, &opts).unwrap();
    println!("{report}");

    for ch in [
        "tub1_ax",
        "tub1_ay",
        "cabinet2_az",
        "drum_front_ux",
        "drum_front_uy",
    ] {
        for kind in ["order", "cascade", "speed"] {
            for ext in ["png", "svg"] {
                let p = out.join(format!("{ch}_{kind}.{ext}"));
                assert!(report.files.contains(&p), "{p:?} not reported");
                let len = std::fs::metadata(&p).unwrap().len();
                assert!(len > 20_000, "{p:?} only {len} bytes");
            }
        }
    }
    // One table each for all channels (CSV here; Parquet by default, read back by pyarrow in
    // tests/parquet_roundtrip.rs).
    let text = std::fs::read_to_string(out.join("spectra.csv")).unwrap();
    assert!(
        text.starts_with("channel,time_s,drum_rpm,frequency_hz,order,amplitude,amplitude_energy\n")
    );
    let orders = std::fs::read_to_string(out.join("orders.csv")).unwrap();
    assert!(orders.starts_with("channel,order,time_s,drum_rpm,amplitude\n"));
    for ch in ["tub1_ax", "drum_front_uy"] {
        let rows = text
            .lines()
            .filter(|l| l.starts_with(&format!("{ch},")))
            .count();
        assert!(rows > 1000, "{ch}: {rows} spectra rows");
        assert!(
            orders.lines().any(|l| l.starts_with(&format!("{ch},1.0,"))),
            "{ch}"
        );
    }
    assert!(out.join("displacements_speed.png").exists());

    // Report: order 1 of tub1_ax has amplitude 1.0 (within 1 %).
    let ax = &report.channels[0];
    assert_eq!(ax.name, "tub1_ax");
    let o1 = ax.orders.iter().find(|o| o.order == 1.0).unwrap();
    let a = o1.max_amplitude.unwrap();
    assert!((a - 1.0).abs() < 0.01, "order 1 max {a}");
    let m1 = ax.orders.iter().find(|o| o.order == 11.25).unwrap();
    let a = m1.max_amplitude.unwrap();
    assert!((a - 0.05).abs() < 0.01 * 0.05, "motor order 1 max {a}");
}

#[test]
fn every_colour_scale_renders() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("short.csv");
    write_run_up_csv(&csv, 300.0, 600.0, 6.0, 1000.0);
    for (i, scale) in [
        ColourScale::Linear,
        ColourScale::Log { range_db: 40.0 },
        ColourScale::Decibel { range_db: 30.0 },
    ]
    .into_iter()
    .enumerate()
    {
        let opts = AnalysisOptions {
            colour_scale: scale,
            plot_size: (800, 500),
            ..AnalysisOptions::default()
        };
        let out = tmp.path().join(format!("out{i}"));
        let report = analyse_file(&csv, &out, &opts).unwrap();
        // 6 plots per channel (PNG, SVG), 2 tables, the displacement overview (PNG, SVG).
        assert_eq!(report.files.len(), 5 * 6 + 2 + 2);
        for f in report
            .files
            .iter()
            .filter(|f| f.extension().unwrap() != "parquet")
        {
            assert!(std::fs::metadata(f).unwrap().len() > 2_000, "{f:?}");
        }
    }
}

#[test]
fn analyse_signals_in_memory_with_awkward_names() {
    use washdyn::analysis::{Channel, Signals, analyse_signals};
    // Names that sanitise to the same stem, or to the overview plot's name.
    let fs = 500.0;
    let n = 2000;
    let rpm: Vec<f64> = (0..n).map(|i| 300.0 + 0.05 * i as f64).collect();
    let x: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).sin()).collect();
    let s = Signals::from_uniform(
        0.0,
        fs,
        rpm,
        vec![
            Channel::new("left/front", x.clone()),
            Channel::new("left front", x.clone()),
            Channel::new("displacements", x),
        ],
    )
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let opts = AnalysisOptions {
        plot_size: (640, 400),
        ..AnalysisOptions::default()
    };
    let report = analyse_signals(&s, tmp.path(), &opts).unwrap();
    assert_eq!(report.files.len(), 3 * 6 + 2);
    let mut names: Vec<String> = report
        .files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), 20, "file names collide: {names:?}");
    assert!(names.contains(&"left_front_order.png".to_string()));
    assert!(names.contains(&"left_front_4_order.png".to_string()));
    assert!(names.contains(&"displacements_5_speed.svg".to_string()));
    // Generic channel: unit unknown, so no displacement overview.
    assert!(!tmp.path().join("displacements_speed.png").exists());
}

#[test]
fn degenerate_signals_still_render() {
    use washdyn::analysis::{Channel, Signals, analyse_signals};
    // Drum at standstill, a silent channel and a constant one: no orders, nothing
    // to scale by; the plots must still come out (grey where there is no data).
    let n = 3000;
    let s = Signals::from_uniform(
        0.0,
        1000.0,
        vec![0.0; n],
        vec![
            Channel::new("silent_az", vec![0.0; n]),
            Channel::new("offset_uz", vec![0.01; n]),
        ],
    )
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let opts = AnalysisOptions {
        plot_size: (640, 400),
        ..AnalysisOptions::default()
    };
    let report = analyse_signals(&s, tmp.path(), &opts).unwrap();
    assert_eq!(report.files.len(), 2 * 6 + 2 + 2);
    for c in &report.channels {
        assert!(c.orders.iter().all(|o| o.max_amplitude.is_none()), "{c:?}");
    }
}
