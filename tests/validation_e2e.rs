//! Issue 51 point 4, end to end: a synthetic measurement made from a washdyn run goes through
//! a rig's files and back, and the comparison over speed finds the simulation in it.
//!
//! The "rig" is the reference machine's `rigid_low_speed` scene on a controller-like speed
//! profile: a ramp from 300 to 700 rpm over 8 s with a 0.5 Hz ripple of 2 rpm and a slower
//! 0.2 Hz one of 1 rpm (a motor controller's speed deviations, the paper's reason for measured
//! speed profiles). Its accelerations are written by pyuff (PyPI, independent of washdyn) as
//! UFF 58 (ASCII) and 58b (binary), in g, with white noise 40 dB below each channel's RMS, and
//! a 1-pulse-per-revolution drum tacho in V made from the run's own drum angle
//! (states.parquet); beside them, the same channels without the noise and the noise alone. washdyn imports them through a mapping file, recovers the speed from the
//! tacho, runs the same model on the recovered speed (`run --speed`) and compares the two over
//! speed. Where the numbers come from:
//! - the recovered speed against the rig's profile (the table it ran, interpolated): the
//!   issue's bound, 0.1 rpm;
//! - the order levels: simulation and measurement are the same model on the same speed up to
//!   the recovery's error, so order 1 of each channel (60-80 dB above the noise per order
//!   block) must agree within the issue's 0.2 dB.
//!
//! Measured (this machine, 2026-11-30): the speed within 0.012 rpm (ASCII and binary alike),
//! order 1 per range within 0.007 dB, the measurement path alone within 0.021 dB at every
//! order and speed compared, the 337 points 40 dB above the noise within 0.131 dB.

use crate::common;
use std::path::Path;
use std::process::Command;

fn pyuff() -> bool {
    common::python_modules("pyuff, pyarrow")
}

/// The rig's profile, rpm: the ramp, the ripples; as a table every 0.05 s (piecewise linear,
/// which is what the run follows exactly).
fn rig_rpm(t: f64) -> f64 {
    use std::f64::consts::PI;
    300.0 + 50.0 * t + 2.0 * (2.0 * PI * 0.5 * t).sin() + (2.0 * PI * 0.2 * t + 1.0).sin()
}

fn rig_table() -> Vec<[f64; 2]> {
    (0..=160)
        .map(|k| {
            let t = 0.05 * f64::from(k);
            [t, rig_rpm(t)]
        })
        .collect()
}

/// The reference model with `table` as its speed profile, its modal data named absolutely.
fn model_with(dir: &Path, name: &str, table: &[[f64; 2]]) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("models/data/reference.toml")).unwrap();
    let profile = "table = [[0.0, 0.0], [5.0, 93.0], [15.0, 93.0], [178.375, 1400.0]]";
    assert!(text.contains(profile), "the reference's speed table moved");
    let rows: Vec<String> = table.iter().map(|[t, r]| format!("[{t}, {r}]")).collect();
    let fe = root.join("models/fe").display().to_string() + "/";
    let text = text
        .replace(profile, &format!("table = [{}]", rows.join(", ")))
        .replace("../fe/", &fe);
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// rig/sensors.parquet and rig/states.parquet to ascii.uff and binary.uff (tub channels in g
/// with noise, the tacho in V) and a mapping file for each.
const RIG_FILES: &str = r#"
import sys, numpy as np, pyuff, pyarrow.parquet as pq
d = sys.argv[1]
s = pq.read_table(f'{d}/rig/sensors.parquet').to_pydict()
phi = np.array(pq.read_table(f'{d}/rig/states.parquet').column('drum_angle_rad').to_pylist())
t = np.array(s['time_s'])
names = ['tub1_ax', 'tub1_ay', 'tub1_az', 'tub3_az']
rng = np.random.default_rng(51)
revs = phi / (2 * np.pi)
frac = revs - np.floor(revs)
tacho = 5.0 * np.clip(np.minimum(frac / 0.04, (0.5 - frac) / 0.04), 0, 1)
def dset(name, node, data, dtype, unit, binary):
    return {'type': 58, 'binary': binary, 'func_type': 1, 'id1': name, 'id2': 'synthetic run-up',
            'rsp_node': node, 'rsp_dir': 1, 'ref_node': 0, 'ref_dir': 0, 'data': data, 'x': t,
            'abscissa_spacing': 1, 'abscissa_spec_data_type': 17, 'abscissa_axis_units_lab': 's',
            'ordinate_spec_data_type': dtype, 'ordinate_axis_units_lab': unit,
            'orddenom_spec_data_type': 0, 'z_axis_spec_data_type': 0}
noisy, noise, clean = [], [], []
for k, n in enumerate(names):
    x = np.array(s[n])
    e = rng.normal(0.0, 0.01 * np.sqrt(np.mean(x * x)), x.size)
    noisy.append((n, k + 1, (x + e) / 9.80665))
    noise.append((n, k + 1, e / 9.80665))
    clean.append((n, k + 1, x / 9.80665))
for name, binary, chans in [('ascii', 0, noisy), ('binary', 1, noisy), ('noise', 0, noise), ('clean', 0, clean)]:
    sets = [dset(n, node, x, 12, 'g', binary) for n, node, x in chans]
    sets.append(dset('tacho', 99, tacho, 0, 'V', binary))
    open(f'{d}/{name}.uff', 'w').close()
    pyuff.UFF(f'{d}/{name}.uff').write_sets(sets, mode='add', force_double=True)
    m = [f'files = ["{name}.uff"]', '']
    for n, node, _ in chans:
        m += ['[[channel]]', f'measured = "{n} [{node}+X]"', f'sensor = "{n}"', '']
    m += ['[speed]', 'tacho = { channel = "tacho [99+X]", pulses_per_rev = 1, edge = "rising", side = "drum" }']
    open(f'{d}/{name}.toml', 'w').write('\n'.join(m) + '\n')
"#;

fn washdyn(args: &[&str], dir: &Path) {
    let o = common::washdyn_in(args, dir);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn a_synthetic_measurement_round_trips_through_uff_and_the_comparison_over_speed() {
    if !pyuff() {
        return;
    }
    // WASHDYN_E2E_DIR keeps the rig's files, the runs and the comparison's plots there
    // (docs/validation.md's figure); otherwise a temporary directory.
    let tmp = tempfile::tempdir().unwrap();
    let kept = std::env::var_os("WASHDYN_E2E_DIR").map(std::path::PathBuf::from);
    if let Some(k) = &kept {
        std::fs::create_dir_all(k).unwrap();
        assert!(
            std::fs::read_dir(k).unwrap().next().is_none(),
            "WASHDYN_E2E_DIR {} is not empty",
            k.display()
        );
    }
    let d = kept.as_deref().unwrap_or(tmp.path());
    // The rig: the model on the controller's profile, its drum angle kept.
    model_with(d, "rig.toml", &rig_table());
    washdyn(
        &[
            "run",
            "rig.toml",
            "--scene",
            "rigid_low_speed",
            "--t-end",
            "8",
            "--states",
            "--no-plots",
            "--out",
            "rig",
        ],
        d,
    );
    let o = Command::new("python3")
        .args(["-c", RIG_FILES])
        .arg(d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for file in ["ascii", "binary"] {
        // The speed from the tacho, against the rig's profile.
        let m = washdyn::measured::load(d.join(format!("{file}.toml"))).unwrap();
        let s = &m.signals;
        // Between the first and the last pulse (one revolution at 300 rpm is 0.2 s): beyond
        // them the tacho's speed is extrapolated, not measured.
        let (worst, at) = s
            .time
            .iter()
            .zip(&s.drum_rpm)
            .filter(|(t, _)| **t > 0.25 && **t < 7.75)
            .map(|(t, r)| ((r - rig_rpm_table(*t)).abs(), *t))
            .fold((0.0, 0.0), |m, x| if x.0 > m.0 { x } else { m });
        println!("{file}: worst at t = {at} s");
        println!(
            "{file}: recovered speed within {worst:.4} rpm over {} samples",
            s.len()
        );
        assert!(worst < 0.1, "{file}: {worst} rpm");
        assert!(s.len() > 12_000, "{file}: valid span {} samples", s.len());
        // The simulation on the recovered speed, and the comparison over speed.
        let sim = format!("sim_{file}");
        washdyn(
            &[
                "analyse",
                &format!("{file}.toml"),
                "--speed-table",
                &format!("{file}_speed.csv"),
                "--out",
                &format!("an_{file}"),
            ],
            d,
        );
        washdyn(
            &[
                "run",
                "rig.toml",
                "--scene",
                "rigid_low_speed",
                "--speed",
                &format!("{file}_speed.csv"),
                "--t-end",
                "8",
                "--no-plots",
                "--out",
                &sim,
            ],
            d,
        );
        let args = washdyn::compare::SpeedArgs {
            run: d.join(&sim),
            other: d.join(format!("{file}.toml")),
            labels: ["simulation".into(), "measurement".into()],
            out: d.join(format!("cmp_{file}")),
            motor_ratio: 11.25,
            svg: false,
            calibrate: false,
            range_edges: vec![400.0, 500.0, 600.0],
        };
        let (c, _) = washdyn::compare::compare_over_speed(&args).unwrap();
        assert_eq!(c.channels.len(), 4, "{:?}", c.only_a);
        for ch in &c.channels {
            let o1 = ch.orders.iter().find(|o| o.order == 1.0).unwrap();
            for r in o1.ranges.iter().filter(|r| r.points > 0) {
                let max = r.max_db.unwrap();
                println!(
                    "{file} {} order 1 from {} rpm: max {max:.3} dB, rms {:.3} dB",
                    ch.channel,
                    r.from_rpm,
                    r.rms_db.unwrap()
                );
                assert!(max.abs() < 0.2, "{file} {}: {r:?}", ch.channel);
            }
            let f = ch.calibration.factor.unwrap();
            assert!((f - 1.0).abs() < 0.01, "{file} {}: factor {f}", ch.channel);
        }
    }
    every_order_where_it_stands_above_the_noise(d);
}

/// Every tracked order at every speed of the common grid (not only order 1, not range
/// statistics). Two questions, kept apart:
/// - the measurement path (UFF, g, the tacho's speed and angle, resampling): the noise-free
///   files against the very run they were made from, within the issue's 0.2 dB at every point
///   the comparison compares (both within its floor, 20 dB, of their own peak);
/// - the issue's check: the simulation on the recovered speed against the noisy files where
///   the order stands 20 dB or more above the noise's own level in that order and block (the
///   noise-only file, analysed on the same tacho: the analysis is linear, so its amplitude
///   `|N|` is the noise's share of `|S + N|` exactly). There: within 0.2 dB plus what that
///   noise can do at most, `-20 log10(1 - |N|/|S|)` (0.92 dB at 20 dB, 0.09 dB at 40 dB; a
///   flat 0.2 dB at 20 dB is no bound noise obeys). Only orders whose peak is within
///   [`SIM_FLOOR_DB`] of order 1's: below that, two simulations whose speeds differ by the
///   recovery's 0.01 rpm differ by themselves (measured here and printed: up to 1.7 dB for
///   orders 40-50 dB below order 1, 6 dB for the motor order the scene does not excite,
///   the friction dampers' stick-slip and the integrator's tolerance), which no measurement
///   can do better than.
fn every_order_where_it_stands_above_the_noise(d: &Path) {
    use washdyn::compare::speed::{
        SPEED_STEP_RPM, db_over_speed, on_grid, resolved_span, speed_grid, track_points,
    };
    let run = |dir: &str| washdyn::compare::load(&d.join(dir), dir).unwrap().0;
    let load = |f: &str| washdyn::compare::load_measured(&d.join(f)).unwrap();
    let (rig, sim) = (run("rig"), run("sim_ascii"));
    let (noisy, noise, clean) = (load("ascii.toml"), load("noise.toml"), load("clean.toml"));
    let opts = washdyn::compare::options(11.25, false);
    let over = |a, b| {
        washdyn::compare::compare_signals_over_speed(a, b, &opts, false, &[], [d, d])
            .unwrap()
            .runs
    };
    // Each pair's track `k` on a common grid: (grid, A, B), A's and B's points as given.
    let tracks = |pair: &[washdyn_analysis::RunUp; 2], k: usize| {
        let (a, b) = (track_points(&pair[0], k), track_points(&pair[1], k));
        let grid = match (resolved_span(&a), resolved_span(&b)) {
            (Some(x), Some(y)) => speed_grid(x.0.max(y.0), x.1.min(y.1), SPEED_STEP_RPM),
            _ => Vec::new(),
        };
        let (ga, gb) = (on_grid(&a, &grid), on_grid(&b, &grid));
        (grid, ga, gb)
    };
    let peak = |v: &[Option<f64>]| v.iter().flatten().fold(0.0f64, |m, x| m.max(*x));
    let mut path_worst = 0.0f64;
    for pair in over(&rig, &clean) {
        for k in 0..pair[0].tracks.len() {
            let (grid, a, b) = tracks(&pair, k);
            for (g, diff) in grid.iter().zip(db_over_speed(&a, &b)) {
                let Some(diff) = diff else { continue };
                path_worst = path_worst.max(diff.abs());
                let order = pair[0].tracks[k].order;
                assert!(
                    diff.abs() < 0.2,
                    "{} order {order} at {g} rpm, the path alone: {diff} dB",
                    pair[0].channel
                );
            }
        }
    }
    let (mut worst, mut points, mut above_40) = (0.0f64, 0, 0);
    let mut sim_vs_sim: Vec<(String, f64, f64, f64)> = Vec::new();
    let rig_sim = over(&rig, &sim);
    for (n, e) in over(&sim, &noisy).iter().zip(&over(&noisy, &noise)) {
        let r = rig_sim
            .iter()
            .find(|r| r[0].channel == n[0].channel)
            .unwrap();
        assert_eq!(n[1].channel, e[0].channel);
        let order_1 = peak(&tracks(n, 0).1);
        for k in 0..n[0].tracks.len() {
            let order = n[0].tracks[k].order;
            let (grid, s, m) = tracks(n, k);
            let (g2, _, noise_only) = tracks(e, k);
            let (_, r_a, r_b) = tracks(r, k);
            let below_1 = 20.0 * (peak(&s) / order_1).log10();
            let reproducible = db_over_speed(&r_a, &r_b)
                .iter()
                .flatten()
                .fold(0.0f64, |x, v| x.max(v.abs()));
            sim_vs_sim.push((n[0].channel.clone(), order, below_1, reproducible));
            if below_1 < SIM_FLOOR_DB {
                continue;
            }
            for (i, diff) in db_over_speed(&s, &m).into_iter().enumerate() {
                let Some(diff) = diff else { continue };
                let Some(j) = g2.iter().position(|g| *g == grid[i]) else {
                    continue;
                };
                let (Some(total), Some(nz)) = (m[i], noise_only[j]) else {
                    continue;
                };
                // |S| >= |S + N| - |N|: the signal's own level, at least.
                let snr = 20.0 * ((total - nz).max(0.0) / nz).log10();
                if snr < 20.0 {
                    continue;
                }
                points += 1;
                let allowed = 0.2 - 20.0 * (1.0 - 10f64.powf(-snr / 20.0)).log10();
                if snr >= 40.0 {
                    above_40 += 1;
                    worst = worst.max(diff.abs());
                }
                assert!(
                    diff.abs() < allowed,
                    "{} order {order} at {} rpm, {snr:.1} dB above the noise: {diff} dB \
                     (allowed {allowed})",
                    n[0].channel,
                    grid[i]
                );
            }
        }
    }
    for (ch, order, below, rep) in &sim_vs_sim {
        println!(
            "{ch} order {order}: peak {below:.1} dB re order 1, two simulations differ by up to {rep:.3} dB"
        );
    }
    println!(
        "measurement path alone: every order within {path_worst:.4} dB; simulation against the \
         noisy measurement: {points} points 20 dB above the noise in orders within \
         {SIM_FLOOR_DB} dB of order 1 held, {above_40} of them 40 dB above it, within \
         {worst:.4} dB"
    );
    assert!(above_40 > 100, "{above_40} points 40 dB above the noise");
}

/// Orders whose peak lies further below order 1's than this (dB) are left out of the
/// simulation-against-measurement check (see `every_order_where_it_stands_above_the_noise`).
const SIM_FLOOR_DB: f64 = -35.0;

/// The rig's table interpolated (what the rig's run followed).
fn rig_rpm_table(t: f64) -> f64 {
    let table = rig_table();
    let k = ((t / 0.05).floor() as usize).min(table.len() - 2);
    let [t0, r0] = table[k];
    let [t1, r1] = table[k + 1];
    r0 + (r1 - r0) * (t - t0) / (t1 - t0)
}
