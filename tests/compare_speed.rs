//! The comparison over speed (`washdyn compare RUN MEASUREMENT`, `--over-speed`):
//! * a single-DOF oscillator's unbalance response, run up along two different linear ramps:
//!   equal at equal speed (0 dB), its resonance where the closed form has it;
//! * one side doubled: +6.02 dB and a calibration factor of 0.5, 0 dB once applied;
//! * a washdyn run against its own sensor file as a measurement, and against itself with
//!   `--over-speed`: 0 dB, factor 1.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use washdyn::analysis::{Channel, Signals};
use washdyn::compare::speed::DEFAULT_RANGE_EDGES;
use washdyn::compare::{OverSpeed, compare_signals_over_speed, options};

const FS: f64 = 2000.0;
/// The oscillator: a 50 kg mass on 126.3 kN/m (undamped natural frequency 8 Hz = 480 rpm),
/// 15 % damping, driven by a 0.144 kg m unbalance (0.6 kg at 0.24 m).
const M: f64 = 50.0;
const K: f64 = M * (2.0 * PI * 8.0) * (2.0 * PI * 8.0);
const ZETA: f64 = 0.15;
const ME: f64 = 0.144;
/// The run-ups: from 150 to 900 rpm, linear in time.
const RPM0: f64 = 150.0;
const RPM1: f64 = 900.0;

fn c() -> f64 {
    2.0 * ZETA * (K * M).sqrt()
}

/// Steady-state amplitude and phase lag of x for M x'' + c x' + K x = me W^2 sin(W t):
/// X = me W^2 / sqrt((K - M W^2)^2 + (c W)^2).
fn response(w: f64) -> (f64, f64) {
    let (re, im) = (K - M * w * w, c() * w);
    (ME * w * w / re.hypot(im), im.atan2(re))
}

/// The closed form's resonance: X is largest at W = w_n / sqrt(1 - 2 zeta^2), in rpm.
fn resonance_rpm() -> f64 {
    (K / M).sqrt() / (1.0 - 2.0 * ZETA * ZETA).sqrt() * 60.0 / (2.0 * PI)
}

/// A run-up from RPM0 to RPM1 in `duration` s sampled at FS, channel `tub1_ux` the quasi-steady
/// response X(W) sin(phi - theta(W)) times `gain` (the drum angle phi the speed's exact
/// integral).
fn run_up(duration: f64, gain: f64) -> Signals {
    let n = (duration * FS) as usize + 1;
    let rate = (RPM1 - RPM0) / duration;
    let mut rpm = Vec::with_capacity(n);
    let mut x = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 / FS;
        let r = RPM0 + rate * t;
        let phi = 2.0 * PI / 60.0 * (RPM0 * t + 0.5 * rate * t * t);
        let (amp, lag) = response(2.0 * PI * r / 60.0);
        rpm.push(r);
        x.push(gain * amp * (phi - lag).sin());
    }
    Signals::from_uniform(0.0, FS, rpm, vec![Channel::new("tub1_ux", x)]).unwrap()
}

fn over_speed(a: &Signals, b: &Signals, calibrate: bool) -> OverSpeed {
    let names = [Path::new("a"), Path::new("b")];
    let opts = options(11.25, false);
    compare_signals_over_speed(a, b, &opts, calibrate, &DEFAULT_RANGE_EDGES, names).unwrap()
}

/// Order 1's ranges that compare anything: (from rpm, RMS dB, largest dB).
fn order_one(o: &OverSpeed) -> Vec<(f64, f64, f64)> {
    let one = o.channels[0]
        .orders
        .iter()
        .find(|o| o.order == 1.0)
        .unwrap();
    one.ranges
        .iter()
        .filter(|r| r.points > 0)
        .map(|r| (r.from_rpm, r.rms_db.unwrap(), r.max_db.unwrap()))
        .collect()
}

/// (a) 25 rpm/s against 16.7 rpm/s: at equal speed the same amplitude, so every range within
/// 20 dB of the peak reads |dB| < 0.2 (what is left is the blocks' smear over 16-24 rpm at the
/// resonance, which the two ramps smear differently); both resonances at the closed form's
/// w_n / sqrt(1 - 2 zeta^2) = 491.2 rpm within the grid's 10 rpm.
#[test]
fn one_oscillator_on_two_ramps_is_0_db_at_equal_speed() {
    let (a, b) = (run_up(30.0, 1.0), run_up(45.0, 1.0));
    let o = over_speed(&a, &b, false);
    let ch = &o.channels[0];
    let ranges = order_one(&o);
    // Measured: |dB| at most 0.036 dB (RMS 0.017, 0.011, 0.0004 dB in 0-400, 400-800,
    // 800-900 rpm); resonances at 491.8 and 491.5 rpm against the closed form's 491.18.
    // 0-400 (from ~245 rpm, where X is 20 dB below its peak), 400-800, 800-900.
    assert_eq!(ranges.len(), 3, "{ranges:?}");
    for (from, rms, max) in &ranges {
        assert!(
            rms.abs() < 0.2 && max.abs() < 0.2,
            "{from} rpm: {rms} / {max} dB"
        );
    }
    let expected = resonance_rpm();
    assert!((expected - 491.2).abs() < 0.1, "{expected}");
    assert_eq!(ch.resonances.len(), 1, "{:?}", ch.resonances);
    let r = &ch.resonances[0];
    for rpm in [r.rpm_a.unwrap(), r.rpm_b.unwrap()] {
        assert!((rpm - expected).abs() < 10.0, "{rpm} against {expected}");
    }
    assert!(r.diff_rpm.unwrap().abs() < 10.0);
    // Factor 1 to within the 0.2 dB: nothing to correct.
    let f = ch.calibration.factor.unwrap();
    assert!(
        (20.0 * f.log10()).abs() < 0.2 && !ch.calibration.applied,
        "{f}"
    );
    assert!(ch.from_rpm >= RPM0 && ch.to_rpm <= RPM1, "{ch:?}");
}

/// (b) B doubled: 20 log10 2 = +6.02 dB in every range (the 0.2 dB of (a) on top), a factor
/// of 1/2 reported and, applied, 0 dB within (a)'s 0.2 dB; the resonance speeds do not move.
#[test]
fn a_doubled_side_reads_6_02_db_and_calibrates_to_0_db() {
    let (a, b) = (run_up(30.0, 1.0), run_up(45.0, 2.0));
    let six = 20.0 * 2f64.log10();
    let o = over_speed(&a, &b, false);
    for (from, rms, max) in order_one(&o) {
        assert!(
            (rms - six).abs() < 0.2 && (max - six).abs() < 0.2,
            "{from}: {rms} {max}"
        );
    }
    let k = &o.channels[0].calibration;
    assert!((k.factor.unwrap() - 0.5).abs() < 0.5 * 0.025, "{k:?}");
    assert!(
        (k.factor_db.unwrap() + six).abs() < 0.2 && !k.applied,
        "{k:?}"
    );
    let cal = over_speed(&a, &b, true);
    assert!(cal.channels[0].calibration.applied);
    assert_eq!(cal.channels[0].calibration.factor, k.factor);
    for (from, rms, max) in order_one(&cal) {
        assert!(rms.abs() < 0.2 && max.abs() < 0.2, "{from}: {rms} {max}");
    }
    // The plots' B is the calibrated one: its track is A's to 0.2 dB, not twice it.
    let [ra, rb] = &cal.runs[0];
    let (pa, pb) = (ra.tracks[0].max(&ra.blocks), rb.tracks[0].max(&rb.blocks));
    assert!((pb.unwrap().0 / pa.unwrap().0 - 1.0).abs() < 0.025);
    let r = &cal.channels[0].resonances[0];
    assert!((r.rpm_b.unwrap() - resonance_rpm()).abs() < 10.0, "{r:?}");
}

/// A model file: the reference machine with a short linear ramp, 300 to 700 rpm in 6 s.
fn short_model(dir: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("models/data/reference.toml")).unwrap();
    let speed = "table = [[0.0, 0.0], [5.0, 93.0], [15.0, 93.0], [178.375, 1400.0]]";
    assert!(text.contains(speed), "the reference's speed table moved");
    let fe = root.join("models/fe").display().to_string() + "/";
    let text = text
        .replace(speed, "table = [[0.0, 300.0], [6.0, 700.0]]")
        .replace("../fe/", &fe);
    let path = dir.join("short.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn washdyn(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(args)
        .output()
        .unwrap()
}

fn washdyn_ok(args: &[&str]) {
    let out = washdyn(args);
    assert!(
        out.status.success(),
        "washdyn {args:?}: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `args` refused with exit code `code`, its message holding `says`, nothing written to `out`.
fn refused(args: &[&str], code: i32, says: &str, out: &Path) {
    let o = washdyn(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "washdyn {args:?}: {err}");
    assert!(err.contains(says), "washdyn {args:?}: {err}");
    assert!(!out.exists(), "{args:?} wrote {}", out.display());
}

/// (c) A run of the reference machine (rigid, low-speed scene, 6 s) against its own sensor
/// file read as a measurement, and against itself with `--over-speed`: the same samples on the
/// same grid, so 0 dB in every range, a factor of exactly 1 and the same resonances.
#[test]
fn a_run_against_its_own_sensors_over_speed_is_0_db() {
    let dir = tempfile::tempdir().unwrap();
    let model = short_model(dir.path());
    let run = dir.path().join("run");
    let s = |p: &Path| p.display().to_string();
    washdyn_ok(&[
        "run",
        &s(&model),
        "--scene",
        "rigid_low_speed",
        "--no-plots",
        "--out",
        &s(&run),
    ]);
    let sensors = run.join("sensors.parquet");
    for (name, args) in [
        ("measured", vec![s(&run), s(&sensors)]),
        ("runs", vec!["--over-speed".into(), s(&run), s(&run)]),
    ] {
        let out = dir.path().join(name);
        let mut all = args.clone();
        all.extend(["--out".into(), s(&out), "--calibrate".into()]);
        let mut cmd = vec!["compare"];
        cmd.extend(all.iter().map(String::as_str));
        washdyn_ok(&cmd);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap())
                .unwrap();
        let channels = json["channels"].as_array().unwrap();
        assert!(!channels.is_empty(), "{json}");
        for ch in channels {
            assert_eq!(ch["calibration"]["factor"], 1.0, "{ch}");
            for o in ch["orders"].as_array().unwrap() {
                for r in o["ranges"].as_array().unwrap() {
                    for k in ["rms_db", "max_db"] {
                        assert!(r[k].is_null() || r[k] == 0.0, "{name}: {r}");
                    }
                }
            }
            for r in ch["resonances"].as_array().unwrap() {
                assert_eq!(r["diff_rpm"], 0.0, "{r}");
            }
        }
        let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
        assert!(md.contains("## Level difference per speed range"), "{md}");
        let title = if name == "measured" {
            "# measurement against simulation over speed"
        } else {
            "# run against run over speed"
        };
        assert!(md.starts_with(title), "{md}");
    }
    // Refused at their option (exit 2): ranges not increasing, --calibrate or --until where
    // they do not apply; a measurement file that is not there (exit 4, named).
    let out = dir.path().join("refused");
    let (r, o) = (s(&run), s(&out));
    let m = s(&dir.path().join("missing.csv"));
    for (args, code, says) in [
        (
            vec![&*r, &*s(&sensors), "--speed-ranges", "800,400"],
            2,
            "--speed-ranges",
        ),
        (
            vec![&*r, &*s(&sensors), "--speed-ranges", "nan"],
            2,
            "--speed-ranges",
        ),
        (vec![&*r, &*s(&sensors), "--until", "1"], 2, "--until"),
        (vec![&*r, &*r, "--calibrate"], 2, "--calibrate"),
        (vec![&*r, &*r, "--speed-ranges", "400"], 2, "--speed-ranges"),
        (vec![&*r, &*m], 4, "missing.csv"),
    ] {
        let mut all = vec!["compare", "--out", &*o];
        all.extend(args);
        refused(&all, code, says, &out);
    }
}

/// Channels by name: B's extra channel is listed, not compared; sides with no speed in common
/// or no channel in common are refused naming both; bad range edges are refused.
#[test]
fn channels_by_name_and_what_cannot_be_compared() {
    use washdyn::compare::CompareError;
    let a = run_up(12.0, 1.0);
    let mut b = run_up(12.0, 1.0);
    let extra = b.channels[0].data.clone();
    b.channels.push(Channel::new("tub9_ax", extra));
    let o = over_speed(&a, &b, false);
    assert_eq!(
        (o.only_a.len(), o.only_b.clone()),
        (0, vec!["tub9_ax".to_string()])
    );
    assert_eq!(o.channels.len(), 1);
    let names = [Path::new("sim"), Path::new("meas.csv")];
    let opts = options(11.25, false);
    let go = |a: &Signals, b: &Signals, edges: &[f64]| {
        compare_signals_over_speed(a, b, &opts, false, edges, names).unwrap_err()
    };
    // B turns 2000-2750 rpm, A 150-900: nothing in common.
    let fast = Signals::from_uniform(
        0.0,
        FS,
        a.drum_rpm.iter().map(|r| r + 1850.0).collect(),
        a.channels.clone(),
    )
    .unwrap();
    let e = go(&a, &fast, &DEFAULT_RANGE_EDGES);
    assert!(matches!(e, CompareError::NoCommonSpeed { .. }), "{e}");
    assert!(e.to_string().contains("meas.csv"), "{e}");
    let mut other = b.clone();
    other.channels = vec![Channel::new("tub1_ay", a.channels[0].data.clone())];
    let e = go(&a, &other, &DEFAULT_RANGE_EDGES);
    assert!(matches!(e, CompareError::Channels { .. }), "{e}");
    for edges in [vec![-1.0], vec![500.0, 500.0], vec![f64::INFINITY]] {
        let e = go(&a, &b, &edges);
        assert!(matches!(e, CompareError::SpeedRanges { .. }), "{e}");
    }
}
