//! `washdyn accuracy`: what accuracy costs in time. For each scene window, every method runs a
//! sweep of tolerances (rk4: step sizes); each run is compared with a reference computed at a
//! tight tolerance and confirmed by a second, different method. The errors are on what users
//! look at: the sensor accelerations (RMS over time, relative) and the first orders' amplitudes
//! in the order tracks (dB). Beside the method costs, the model's own: modal truncation, each
//! scene against the full (elastic) model, generated against interpreted code. Writes
//! `accuracy.md`, `accuracy.json` (read by `washdyn run` for its error class) and a log-log
//! work-precision plot per scene.

use crate::analysis::plot::init_fonts;
use crate::analysis::{AnalysisOptions, Channel, RunUp, Signals};
use crate::commands::{Backend, integrator_options, resolve_model};
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use washdyn_runtime::clearance::element_tub_ends;
use washdyn_runtime::equations::Equations;
use washdyn_runtime::ir::{EffectSet, Model};
use washdyn_runtime::ode::{AnySolver, Method};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Guard, Labels, RunOptions, Start, Summary, run_guarded};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

/// Sample rate of the method runs, Hz (the analysis band is 300 Hz).
const SAMPLE_RATE: f64 = 2000.0;
/// Sample rate of the model comparisons (modal truncation, scenes), Hz: above twice the tub's
/// highest mode (6.6 kHz), so that what one model has and the other lacks does not alias.
const COMPARE_RATE: f64 = 20_000.0;
/// The band of the model comparisons' acceleration error, Hz (`band_error`): the analysis
/// band, where the order plots are.
pub const BAND_HZ: f64 = 300.0;
/// Orders compared in the order tracks.
const ORDERS: [f64; 3] = [1.0, 2.0, 3.0];
/// Blocks of an order track whose reference amplitude is below this fraction of the track's
/// peak (-40 dB) are not compared: there the order is noise, and dB errors mean nothing.
pub const ORDER_FLOOR: f64 = 1e-2;
/// Model comparisons (modal truncation, scenes) start this long before the window and compare
/// only inside it, s: each model has its own start transient, which is not what is compared.
const SETTLE: f64 = 2.0;
/// Eigenmode cut-offs of the modal truncation study (Hz), each against all the data's modes.
pub const TRUNCATION_CUTS_HZ: [f64; 5] = [70.0, 210.0, 420.0, 700.0, 1000.0];
/// Windows longer than this (s) are run-ups: see `sweep`.
const LONG: f64 = 20.0;
/// Error classes a run is told it reaches (relative RMS error of the sensor accelerations).
pub const CLASSES: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// A scene and the time window studied.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Window {
    pub scene: String,
    pub t0: f64,
    pub t1: f64,
}

impl std::str::FromStr for Window {
    type Err = String;
    /// `NAME` (the whole speed profile) or `NAME:T0:T1`.
    fn from_str(s: &str) -> Result<Window, String> {
        let parts: Vec<&str> = s.split(':').collect();
        let num = |p: &str| {
            p.parse::<f64>()
                .map_err(|_| format!("`{s}`: `{p}` is not a time in s (NAME or NAME:T0:T1)"))
        };
        match parts.as_slice() {
            [name] => Ok(Window {
                scene: name.to_string(),
                t0: 0.0,
                t1: f64::NAN,
            }),
            [name, a, b] => {
                let (t0, t1) = (num(a)?, num(b)?);
                let top = crate::validate::T_END_MAX;
                if !(t0 >= 0.0 && t1 > t0 && t1 <= top) {
                    return Err(format!("`{s}`: need 0 <= T0 < T1 <= {top} s"));
                }
                Ok(Window {
                    scene: name.to_string(),
                    t0,
                    t1,
                })
            }
            _ => Err(format!("`{s}`: expected NAME or NAME:T0:T1")),
        }
    }
}

/// Settings of `washdyn accuracy`.
#[derive(Clone, Debug)]
pub struct AccuracyArgs {
    pub model: String,
    pub windows: Vec<Window>,
    pub out: PathBuf,
    /// Fewer settings a method (for tests and a first look).
    pub quick: bool,
}

/// One run of the study and its errors against the reference.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Trial {
    pub method: String,
    /// Relative tolerance, or rk4's step in s.
    pub tol: f64,
    pub backend: String,
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub jacobians: u64,
    pub lu: u64,
    pub wall_s: f64,
    /// Largest relative RMS error over the acceleration channels; `None` when the run failed.
    pub accel_err: Option<f64>,
    /// Largest |dB| error of orders 1-3 over the acceleration channels and blocks.
    pub order_db: Option<f64>,
    pub status: String,
}

/// The study of one window.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WindowStudy {
    pub window: Window,
    pub reference: Trial,
    /// The second method's run at a tight tolerance, compared with the reference.
    pub confirmation: Trial,
    pub trials: Vec<Trial>,
    /// Generated against interpreted at one setting: (generated, interpreted).
    pub backends: Option<(Trial, Trial)>,
    /// Modes kept (cut-off Hz, coordinates) against the finest cut-off.
    pub truncation: Vec<(f64, usize, Trial)>,
    /// Other scenes over this window against this one.
    pub scenes: Vec<(String, Trial)>,
    /// Generalized-alpha at one tolerance for each spectral radius at infinity.
    #[serde(default)]
    pub rho_inf: Vec<(f64, Trial)>,
}

/// The spectral radii the study runs generalized-alpha at: from annihilating the unresolved
/// modes in one step (0) to keeping them undamped (1); 0.8 is the default.
pub const RHO_INF: [f64; 4] = [0.0, 0.5, 0.8, 1.0];

/// Everything the command measured; `accuracy.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Study {
    pub model: String,
    pub command: String,
    pub windows: Vec<WindowStudy>,
}

/// A finished or failed simulation in memory.
struct Sim {
    mem: MemorySink,
    summary: Summary,
    error: Option<String>,
    /// Samples per second of `mem`.
    rate: f64,
}

fn mechanical(
    model: &Model,
    model_name: &str,
    built_in: bool,
    scene: &EffectSet,
    backend: Backend,
) -> Result<Box<dyn Mechanical + Send>, String> {
    match backend {
        Backend::Interpreted => Ok(Box::new(Interpreter::new(model, scene))),
        Backend::Generated if built_in => washdyn_models::generated(model_name, &scene.name)
            .ok_or_else(|| format!("no generated code for scene `{}`", scene.name)),
        Backend::Generated => Err("generated code exists only for built-in models".into()),
    }
}

/// Runs one setting over the window into memory.
#[allow(clippy::too_many_arguments)]
fn simulate(
    model: &Model,
    model_name: &str,
    built_in: bool,
    scene: &EffectSet,
    backend: Backend,
    method: Method,
    tol: f64,
    w: &Window,
    rho_inf: Option<f64>,
    rate: f64,
) -> Result<Sim, String> {
    let mech = mechanical(model, model_name, built_in, scene, backend)?;
    let mut sys = FirstOrder::new(mech);
    let dim = 2 * sys.layout().n();
    let (tol_, step) = if method == Method::Rk4 {
        (1e-6, Some(tol))
    } else {
        (tol, None)
    };
    // A budget no setting of the study needs, so a hopeless one stops instead of hanging.
    let mut opts = integrator_options(method, tol_, step, Some(30_000_000));
    if let Some(r) = rho_inf {
        opts.rho_inf = r;
    }
    let mut solver = AnySolver::new(method, dim, opts);
    let mut mem = MemorySink::default();
    let ropts = RunOptions {
        t_start: w.t0,
        t_end: w.t1,
        sample_rate: rate,
        start: Start::MeanLoad,
    };
    let labels = Labels {
        model: model.name.clone(),
        scene: scene.name.clone(),
        backend: match backend {
            Backend::Generated => "generated".into(),
            Backend::Interpreted => "interpreted".into(),
        },
    };
    let guard = Guard {
        fixed_step: step,
        elements: element_tub_ends(model, &Equations::new(model, scene)),
        ..Guard::default()
    };
    let (summary, error) = match run_guarded(
        &mut sys,
        &mut solver,
        &ropts,
        &labels,
        (opts.rtol, opts.atol),
        &mut mem,
        &mut |_| {},
        &guard,
    ) {
        Ok(s) => (s, None),
        Err((e, s)) => (s, Some(e.to_string())),
    };
    Ok(Sim {
        mem,
        summary,
        error,
        rate,
    })
}

/// `m` from `skip` samples on, with only the channels whose name starts with `prefix`.
fn trim(m: &MemorySink, skip: usize, prefix: &str) -> MemorySink {
    let keep: Vec<usize> = (0..m.channels.len())
        .filter(|&c| m.channels[c].starts_with(prefix))
        .collect();
    let nc = m.channels.len();
    let mut out = MemorySink {
        channels: keep.iter().map(|&c| m.channels[c].clone()).collect(),
        ..MemorySink::default()
    };
    for k in skip.min(m.time.len())..m.time.len() {
        out.time.push(m.time[k]);
        out.rpm.push(m.rpm[k]);
        out.values
            .extend(keep.iter().map(|&c| m.values[k * nc + c]));
    }
    out
}

/// An acceleration channel: its name ends in `_ax`, `_ay` or `_az`.
pub fn is_accel(name: &str) -> bool {
    name.ends_with("_ax") || name.ends_with("_ay") || name.ends_with("_az")
}

/// The acceleration channels present in both runs.
fn accel_channels(a: &MemorySink, b: &MemorySink) -> Vec<(usize, usize, String)> {
    a.channels
        .iter()
        .enumerate()
        .filter(|(_, n)| is_accel(n))
        .filter_map(|(i, n)| {
            b.channels
                .iter()
                .position(|m| m == n)
                .map(|j| (i, j, n.clone()))
        })
        .collect()
}

/// Largest relative RMS difference of `x` against `r` over the shared acceleration channels.
pub fn rms_error(x: &MemorySink, r: &MemorySink) -> Option<f64> {
    if x.time.len() != r.time.len() || x.time.is_empty() {
        return None;
    }
    let mut worst = 0.0f64;
    for (i, j, _) in accel_channels(x, r) {
        if let Some(e) = relative_rms(&x.column(i), &r.column(j)) {
            worst = worst.max(e);
        }
    }
    Some(worst)
}

/// Largest `band_error` (to [`BAND_HZ`]) of `x` against `r` over the shared acceleration
/// channels, both sampled at `rate`.
fn band_rms_error(x: &MemorySink, r: &MemorySink, rate: f64) -> Option<f64> {
    if x.time.len() != r.time.len() || x.time.is_empty() {
        return None;
    }
    accel_channels(x, r)
        .into_iter()
        .filter_map(|(i, j, _)| band_error(&x.column(i), &r.column(j), rate, BAND_HZ))
        .reduce(f64::max)
}

/// RMS of `x - r` over the RMS of `r` (one channel of [`rms_error`]); `None` where `r` is zero
/// throughout or the lengths differ.
pub fn relative_rms(x: &[f64], r: &[f64]) -> Option<f64> {
    if x.len() != r.len() {
        return None;
    }
    let num: f64 = x.iter().zip(r).map(|(p, q)| (p - q) * (p - q)).sum();
    let den: f64 = r.iter().map(|q| q * q).sum();
    (den > 0.0).then(|| (num / den).sqrt())
}

/// Relative error of `x` against `r` (sampled at `fs`) in the band up to `f_max`: the RMS of
/// the Hann-windowed spectrum of x - r over the bins to `f_max`, over that of r. A model's
/// accelerations carry its highest modes (the tub's to 6.6 kHz); compared raw, or sampled
/// below twice their frequency (aliased), a model with fewer modes differs by what no order
/// plot shows. `None` where r has nothing in the band or the lengths differ.
pub fn band_error(x: &[f64], r: &[f64], fs: f64, f_max: f64) -> Option<f64> {
    let n = r.len();
    if x.len() != n || n < 2 {
        return None;
    }
    let hann = crate::analysis::spectrum::Window::hann(n);
    let w = hann.coeffs();
    let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let spectrum = |v: Vec<f64>| {
        let mut v = v;
        let mut out = fft.make_output_vec();
        fft.process(&mut v, &mut out)
            .expect("lengths from the plan");
        out
    };
    let d = spectrum((0..n).map(|k| (x[k] - r[k]) * w[k]).collect());
    let s = spectrum((0..n).map(|k| r[k] * w[k]).collect());
    let bins = ((f_max * n as f64 / fs).floor() as usize + 1).min(s.len());
    let num: f64 = d[..bins].iter().map(|c| c.norm_sqr()).sum();
    let den: f64 = s[..bins].iter().map(|c| c.norm_sqr()).sum();
    (den > 0.0).then(|| (num / den).sqrt())
}

/// The order tracks of orders 1-3 of every acceleration channel.
fn order_tracks(m: &MemorySink, t0: f64, rate: f64) -> Vec<(String, Vec<Vec<Option<f64>>>)> {
    let opts = AnalysisOptions {
        track_orders: ORDERS.to_vec(),
        motor_orders: 0,
        cascades: false,
        ..AnalysisOptions::default()
    };
    let names: Vec<(usize, String)> = m
        .channels
        .iter()
        .enumerate()
        .filter(|(_, n)| is_accel(n))
        .map(|(i, n)| (i, n.clone()))
        .collect();
    let mut out = Vec::new();
    for (i, name) in names {
        let ch = Channel::new(name.clone(), m.column(i));
        let Ok(sig) = Signals::from_uniform(t0, rate, m.rpm.clone(), vec![ch.clone()]) else {
            continue;
        };
        let Ok(ru) = RunUp::analyse(&sig, &ch, &opts) else {
            continue;
        };
        let tracks = ORDERS
            .iter()
            .map(|o| {
                ru.tracks
                    .iter()
                    .find(|t| (t.order - o).abs() < 1e-9)
                    .map_or_else(Vec::new, |t| t.amplitude.clone())
            })
            .collect();
        out.push((name, tracks));
    }
    out
}

type Tracks = Vec<(String, Vec<Vec<Option<f64>>>)>;

/// Largest |20 log10(x / r)| over channels, orders and the blocks where the reference is within
/// 40 dB of its track's peak.
fn order_error(x: &Tracks, r: &Tracks) -> Option<f64> {
    let mut worst: Option<f64> = None;
    for (name, rt) in r {
        let Some((_, xt)) = x.iter().find(|(n, _)| n == name) else {
            continue;
        };
        for (ra, xa) in rt.iter().zip(xt) {
            if let Some((db, _)) = track_error(xa, ra) {
                worst = Some(worst.map_or(db.abs(), |w: f64| w.max(db.abs())));
            }
        }
    }
    worst
}

/// One order track `x` against the reference track `r` (one value per block): 20 log10(x / r)
/// at the block where its magnitude is largest, and that block, over the blocks where both are
/// resolved and positive and `r` is at least [`ORDER_FLOOR`] of its own peak (one track of
/// [`order_error`]).
pub fn track_error(x: &[Option<f64>], r: &[Option<f64>]) -> Option<(f64, usize)> {
    let peak = r.iter().flatten().fold(0.0f64, |m, v| m.max(*v));
    let mut worst: Option<(f64, usize)> = None;
    for (k, (a, b)) in r.iter().zip(x).enumerate() {
        if let (Some(a), Some(b)) = (a, b)
            && *a >= ORDER_FLOOR * peak
            && *a > 0.0
            && *b > 0.0
        {
            let db = 20.0 * (b / a).log10();
            if worst.is_none_or(|(w, _)| db.abs() > w.abs()) {
                worst = Some((db, k));
            }
        }
    }
    worst
}

fn trial(method: &str, tol: f64, sim: &Sim, reference: Option<(&MemorySink, &Tracks)>) -> Trial {
    let s = &sim.summary;
    let (accel_err, order_db) = match (reference, &sim.error) {
        (Some((r, rt)), None) => (
            if sim.rate > SAMPLE_RATE {
                band_rms_error(&sim.mem, r, sim.rate)
            } else {
                rms_error(&sim.mem, r)
            },
            order_error(&order_tracks(&sim.mem, s.t_start, sim.rate), rt),
        ),
        _ => (None, None),
    };
    Trial {
        method: method.into(),
        tol,
        backend: s.backend.clone(),
        steps: s.steps,
        rejected: s.rejected_steps,
        rhs_evals: s.rhs_evals,
        jacobians: s.jacobian_evals,
        lu: s.lu_decompositions,
        wall_s: s.wall_time_s,
        accel_err,
        order_db,
        status: match &sim.error {
            None => "ok".into(),
            Some(e) => format!("failed: {e}"),
        },
    }
}

/// The sweep of each method: tolerances (rk4: steps, s). A long window of the elastic scene
/// (a whole run-up) sweeps the settings near the error class 1e-3 only: each run there costs
/// minutes, and rk4 at a step dopri5's stiffness limit allows would cost more than dopri5.
fn sweep(quick: bool, elastic: bool, long: bool) -> Vec<(Method, Vec<f64>)> {
    if quick {
        return vec![
            (Method::Dopri5, vec![1e-4, 1e-6]),
            (Method::Rodas4, vec![1e-4, 1e-6]),
            (Method::GeneralizedAlpha, vec![1e-4, 1e-5]),
        ];
    }
    if elastic && long {
        vec![
            (Method::Dopri5, vec![1e-5, 1e-6]),
            (Method::Sdirk4, vec![1e-5, 1e-6]),
            (Method::Rodas4, vec![1e-4, 1e-5, 1e-6]),
            (Method::GeneralizedAlpha, vec![1e-5, 1e-6]),
            (Method::Auto, vec![1e-5, 1e-6]),
        ]
    } else if elastic {
        vec![
            (Method::Rk4, vec![2.5e-5, 1e-5]),
            (Method::Dopri5, vec![1e-3, 1e-5, 1e-7]),
            (Method::Sdirk4, vec![1e-3, 1e-4, 1e-5, 1e-6]),
            (Method::Rodas4, vec![1e-3, 1e-4, 1e-5, 1e-6]),
            (Method::GeneralizedAlpha, vec![1e-3, 1e-4, 1e-5, 1e-6]),
            (Method::Auto, vec![1e-4, 1e-5, 1e-6]),
        ]
    } else {
        vec![
            (Method::Rk4, vec![2e-4, 1e-4, 5e-5, 2.5e-5]),
            (Method::Dopri5, vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]),
            (Method::Sdirk4, vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
            (Method::Rodas4, vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
            (Method::GeneralizedAlpha, vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
            (Method::Auto, vec![1e-5, 1e-6, 1e-7]),
        ]
    }
}

fn is_elastic(scene: &EffectSet) -> bool {
    scene
        .effects
        .iter()
        .any(|e| matches!(e, washdyn_runtime::ir::Effect::Elastic(_)))
}

/// Runs the whole study; `log` hears one line a run.
pub fn study(args: &AccuracyArgs, log: &mut dyn FnMut(&str)) -> Result<Study, String> {
    let (model, built_in) = resolve_model(&args.model)?;
    let backend = if built_in {
        Backend::Generated
    } else {
        Backend::Interpreted
    };
    let mut windows = Vec::new();
    for w in &args.windows {
        let scene = model.scene(Some(&w.scene))?;
        let mut w = w.clone();
        if w.t1.is_nan() {
            w.t1 = model.speed.table.last().map_or(1.0, |r| r[0]);
        }
        let elastic = is_elastic(&scene);
        // A whole run-up: the comparisons that need their own long runs (back ends, modal
        // truncation, scenes) are the short windows' job.
        let long = w.t1 - w.t0 > LONG;
        let run = |method: Method, tol: f64, scene: &EffectSet, b: Backend| {
            simulate(
                &model,
                &args.model,
                built_in,
                scene,
                b,
                method,
                tol,
                &w,
                None,
                SAMPLE_RATE,
            )
        };
        // Reference and its confirmation by a different method (explicit against implicit).
        // A whole elastic run-up: dopri5 runs on its stability limit there, far below 1e-8.
        let (ref_tol, conf_tol) = if args.quick || (elastic && long) {
            (1e-8, 1e-7)
        } else if elastic {
            (1e-9, 1e-8)
        } else {
            (1e-10, 1e-9)
        };
        let r = run(Method::Dopri5, ref_tol, &scene, backend)?;
        if let Some(e) = &r.error {
            return Err(format!("reference run failed: {e}"));
        }
        let rt = order_tracks(&r.mem, w.t0, SAMPLE_RATE);
        let reference = trial("dopri5", ref_tol, &r, Some((&r.mem, &rt)));
        log(&format!(
            "{}: reference dopri5 {ref_tol:e}, {:.2} s",
            w.scene, reference.wall_s
        ));
        // A whole elastic run-up: rodas4 at 1e-7 would run for hours (it is held by accuracy
        // as dopri5 is by stability, at about 15 000 steps per simulated second) and the
        // run's stall guard stops it; dopri5 a decade looser confirms the reference there.
        let conf_method = if elastic && long {
            Method::Dopri5
        } else {
            Method::Rodas4
        };
        let c = run(conf_method, conf_tol, &scene, backend)?;
        let confirmation = trial(conf_method.name(), conf_tol, &c, Some((&r.mem, &rt)));
        log(&format!(
            "{}: confirmation {conf_method} {conf_tol:e}: accel {:?}, orders {:?} dB, {}",
            w.scene, confirmation.accel_err, confirmation.order_db, confirmation.status
        ));
        let mut trials = Vec::new();
        for (m, tols) in sweep(args.quick, elastic, long) {
            for tol in tols {
                let s = run(m, tol, &scene, backend)?;
                let t = trial(m.name(), tol, &s, Some((&r.mem, &rt)));
                log(&format!(
                    "{}: {} {tol:e}: {} steps, {:.3} s, accel {:?}, orders {:?} dB, {}",
                    w.scene, m, t.steps, t.wall_s, t.accel_err, t.order_db, t.status
                ));
                trials.push(t);
            }
        }
        // Generalized-alpha's numerical damping of the unresolved modes: each spectral radius
        // at the tolerance of its error class 1e-3 (a whole run-up: left to the short windows).
        let mut rho_inf = Vec::new();
        if !long {
            let tol = if elastic || args.quick { 1e-5 } else { 1e-6 };
            for rho in RHO_INF {
                let m = Method::GeneralizedAlpha;
                let s = simulate(
                    &model,
                    &args.model,
                    built_in,
                    &scene,
                    backend,
                    m,
                    tol,
                    &w,
                    Some(rho),
                    SAMPLE_RATE,
                )?;
                let t = trial(m.name(), tol, &s, Some((&r.mem, &rt)));
                log(&format!(
                    "{}: galpha {tol:e} rho_inf {rho}: {} steps, {:.3} s, accel {:?}, orders {:?} dB, {}",
                    w.scene, t.steps, t.wall_s, t.accel_err, t.order_db, t.status
                ));
                rho_inf.push((rho, t));
            }
        }
        // Generated against interpreted, dopri5 at 1e-6.
        let backends = if built_in && !args.quick && !long {
            let g = run(Method::Dopri5, 1e-6, &scene, Backend::Generated)?;
            let i = run(Method::Dopri5, 1e-6, &scene, Backend::Interpreted)?;
            let tg = trial("dopri5", 1e-6, &g, Some((&r.mem, &rt)));
            // The interpreter against the generated run at the same setting: round-off only.
            let gt = order_tracks(&g.mem, w.t0, SAMPLE_RATE);
            let ti = trial("dopri5", 1e-6, &i, Some((&g.mem, &gt)));
            log(&format!(
                "{}: generated {:.3} s, interpreted {:.3} s, difference {:?}",
                w.scene, tg.wall_s, ti.wall_s, ti.accel_err
            ));
            Some((tg, ti))
        } else {
            None
        };
        // Model comparisons run from SETTLE before the window and compare inside it.
        let early = Window {
            t0: (w.t0 - SETTLE).max(0.0),
            ..w.clone()
        };
        let skip = ((w.t0 - early.t0) * COMPARE_RATE).round() as usize;
        let run_early = |method: Method, tol: f64, scene: &EffectSet, b: Backend| {
            simulate(
                &model,
                &args.model,
                built_in,
                scene,
                b,
                method,
                tol,
                &early,
                None,
                COMPARE_RATE,
            )
        };
        // Modal truncation (interpreted: any cut-off), against the finest.
        let mut truncation = Vec::new();
        if elastic && !args.quick && !long {
            let finest = EffectSet {
                mode_cutoff: None,
                ..scene.clone()
            };
            let f = run_early(Method::Dopri5, 1e-7, &finest, Backend::Interpreted)?;
            let fm = trim(&f.mem, skip, "");
            let ft = order_tracks(&fm, w.t0, COMPARE_RATE);
            for c in TRUNCATION_CUTS_HZ {
                let sc = EffectSet {
                    mode_cutoff: Some(c),
                    ..scene.clone()
                };
                let n = Interpreter::new(&model, &sc).eq.layout.n();
                let mut s = run_early(Method::Dopri5, 1e-7, &sc, Backend::Interpreted)?;
                s.mem = trim(&s.mem, skip, "");
                s.summary.t_start = w.t0;
                let t = trial("dopri5", 1e-7, &s, Some((&fm, &ft)));
                log(&format!(
                    "{}: modes to {c:.0} Hz ({n} coordinates): accel {:?}, orders {:?} dB, {:.2} s",
                    w.scene, t.accel_err, t.order_db, t.wall_s
                ));
                truncation.push((c, n, t));
            }
        }
        // Other scenes against this one (the full model is the elastic scene).
        let mut scenes = Vec::new();
        if elastic && !args.quick && !long {
            // Tub channels only: the rigid scenes' cabinet is fixed and reads zero.
            let e = run_early(Method::Dopri5, 1e-7, &scene, backend)?;
            let em = trim(&e.mem, skip, "tub");
            let et = order_tracks(&em, w.t0, COMPARE_RATE);
            for other in &model.scenes {
                if other.name == w.scene {
                    continue;
                }
                let sc = model.scene(Some(&other.name))?;
                let mut s = run_early(Method::Dopri5, 1e-7, &sc, backend)?;
                s.mem = trim(&s.mem, skip, "tub");
                s.summary.t_start = w.t0;
                let t = trial("dopri5", 1e-7, &s, Some((&em, &et)));
                log(&format!(
                    "{}: scene {} against it: accel {:?}, orders {:?} dB, {:.2} s",
                    w.scene, other.name, t.accel_err, t.order_db, t.wall_s
                ));
                scenes.push((other.name.clone(), t));
            }
        }
        windows.push(WindowStudy {
            window: w.clone(),
            reference,
            confirmation,
            trials,
            backends,
            truncation,
            scenes,
            rho_inf,
        });
    }
    Ok(Study {
        model: model.name.clone(),
        command: command_line(args),
        windows,
    })
}

fn command_line(args: &AccuracyArgs) -> String {
    let mut s = format!("washdyn accuracy --model {}", args.model);
    for w in &args.windows {
        if w.t1.is_nan() {
            let _ = write!(s, " --scene {}", w.scene);
        } else {
            let _ = write!(s, " --scene {}:{}:{}", w.scene, w.t0, w.t1);
        }
    }
    let _ = write!(s, " --out {}", args.out.display());
    if args.quick {
        s += " --quick";
    }
    s
}

fn e(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.1e}"))
}

fn db(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

/// For each error class, the cheapest (wall time) setting measured that reaches it.
pub fn recommend(trials: &[Trial]) -> Vec<(f64, Option<&Trial>)> {
    CLASSES
        .iter()
        .map(|&c| {
            let best = trials
                .iter()
                .filter(|t| t.accel_err.is_some_and(|e| e <= c))
                .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
            (c, best)
        })
        .collect()
}

fn setting(t: &Trial) -> String {
    if t.method == "rk4" {
        format!("rk4 --step {:e}", t.tol)
    } else {
        format!("{} --tol {:e}", t.method, t.tol)
    }
}

/// `accuracy.md` from the study.
pub fn markdown(s: &Study) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "# What accuracy costs in time: model `{}`\n", s.model);
    let _ = writeln!(
        m,
        "Regenerate with `{}` (release build; every number below is from that one run, on one \
         core of the machine it ran on).\n",
        s.command
    );
    m += "Errors are against a reference at a tight tolerance (dopri5), confirmed by a second \
          method (rodas4); the difference of the two is stated. **accel** is the largest \
          relative RMS error over time of the acceleration channels; **orders** the largest \
          error in dB of the order tracks of orders 1 to 3 over all acceleration channels and \
          blocks (where the reference is within 40 dB of the track's peak). Wall time is the \
          whole run (integration and sampling at 2 kHz). rk4's `tol` column is its step in s.\n\n";
    for w in &s.windows {
        let _ = writeln!(
            m,
            "## Scene `{}`, t = {} .. {} s\n",
            w.window.scene, w.window.t0, w.window.t1
        );
        let _ = writeln!(
            m,
            "Reference: dopri5 at rtol {:e}, {} steps, {:.2} s. Confirmation: {} at rtol {:e}, \
             {} steps, {:.2} s; it differs from the reference by accel {} and orders {} dB.\n",
            w.reference.tol,
            w.reference.steps,
            w.reference.wall_s,
            w.confirmation.method,
            w.confirmation.tol,
            w.confirmation.steps,
            w.confirmation.wall_s,
            e(w.confirmation.accel_err),
            db(w.confirmation.order_db)
        );
        m += "| method | tol | steps | rejected | f evals | Jacobians | LU | wall s | accel | orders dB | status |\n";
        m += "|---|---|---|---|---|---|---|---|---|---|---|\n";
        for t in &w.trials {
            let _ = writeln!(
                m,
                "| {} | {:e} | {} | {} | {} | {} | {} | {:.3} | {} | {} | {} |",
                t.method,
                t.tol,
                t.steps,
                t.rejected,
                t.rhs_evals,
                t.jacobians,
                t.lu,
                t.wall_s,
                e(t.accel_err),
                db(t.order_db),
                t.status
            );
        }
        let _ = writeln!(
            m,
            "\n![work-precision {}](accuracy_{}.png)\n",
            w.window.scene, w.window.scene
        );
        m += "Cheapest measured setting for a target error on the accelerations:\n\n";
        m += "| target | setting | wall s | accel | orders dB |\n|---|---|---|---|---|\n";
        for (c, t) in recommend(&w.trials) {
            match t {
                Some(t) => {
                    let _ = writeln!(
                        m,
                        "| {c:.0e} | `{}` | {:.3} | {} | {} |",
                        setting(t),
                        t.wall_s,
                        e(t.accel_err),
                        db(t.order_db)
                    );
                }
                None => {
                    let _ = writeln!(m, "| {c:.0e} | none measured | | | |");
                }
            }
        }
        m.push('\n');
        if let Some((g, i)) = &w.backends {
            let _ = writeln!(
                m,
                "Generated against interpreted (dopri5, rtol 1e-6): {:.3} s against {:.3} s, \
                 ratio {:.2}; the two runs differ by accel {} and orders {} dB.\n",
                g.wall_s,
                i.wall_s,
                i.wall_s / g.wall_s,
                e(i.accel_err),
                db(i.order_db)
            );
        }
        if let Some((_, t0)) = w.rho_inf.first() {
            let _ = writeln!(
                m,
                "Generalized-alpha's spectral radius at infinity (`--rho-inf`; rtol {:e}): \
                 the amplitude it leaves a mode it does not resolve per step, 1 keeping such \
                 modes undamped, 0 removing them in one step; the default 0.8.\n",
                t0.tol
            );
            m += "| rho_inf | steps | rejected | wall s | accel | orders dB | status |\n|---|---|---|---|---|---|---|\n";
            for (rho, t) in &w.rho_inf {
                let _ = writeln!(
                    m,
                    "| {rho} | {} | {} | {:.3} | {} | {} | {} |",
                    t.steps,
                    t.rejected,
                    t.wall_s,
                    e(t.accel_err),
                    db(t.order_db),
                    t.status
                );
            }
            m.push('\n');
        }
        if !w.truncation.is_empty() {
            let _ = writeln!(
                m,
                "Modal truncation (interpreted, dopri5 rtol 1e-7, started {SETTLE} s before the \
                 window, compared inside it, sampled at {COMPARE_RATE} Hz; accel in the \
                 {BAND_HZ} Hz band), against all modes of the modal data \
                 (docs/truncation.md: the same at constant speeds):\n"
            );
            m += "| modes up to Hz | coordinates | wall s | accel | orders dB |\n|---|---|---|---|---|\n";
            for (c, n, t) in &w.truncation {
                let _ = writeln!(
                    m,
                    "| {c:.0} | {n} | {:.3} | {} | {} |",
                    t.wall_s,
                    e(t.accel_err),
                    db(t.order_db)
                );
            }
            m.push('\n');
        }
        if !w.scenes.is_empty() {
            let _ = writeln!(
                m,
                "Scenes against `{}` (the full model), dopri5 rtol 1e-7, started {SETTLE} s \
                 before the window and compared inside it, sampled at {COMPARE_RATE} Hz, \
                 accel in the {BAND_HZ} Hz band, on the tub's channels (a rigid scene's \
                 cabinet is fixed):\n",
                w.window.scene
            );
            m += "| scene | wall s | accel | orders dB |\n|---|---|---|---|\n";
            for (n, t) in &w.scenes {
                let _ = writeln!(
                    m,
                    "| {n} | {:.3} | {} | {} |",
                    t.wall_s,
                    e(t.accel_err),
                    db(t.order_db)
                );
            }
            m.push('\n');
        }
    }
    m
}

type PResult = Result<(), Box<dyn std::error::Error + Send + Sync>>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    w: &WindowStudy,
) -> PResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let pts: Vec<(f64, f64)> = w
        .trials
        .iter()
        .filter_map(|t| t.accel_err.map(|e| (t.wall_s.max(1e-4), e.max(1e-12))))
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in &pts {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    if pts.is_empty() {
        (x0, x1, y0, y1) = (1e-3, 1.0, 1e-6, 1.0);
    }
    let mut chart = ChartBuilder::on(root)
        .caption(
            format!(
                "work-precision: scene {} ({} .. {} s)",
                w.window.scene, w.window.t0, w.window.t1
            ),
            ("sans-serif", 24),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 3.0..y1 * 3.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("wall time [s]")
        .y_desc("acceleration error (relative RMS)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .x_label_formatter(&|v| format!("{v:.2}"))
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 20))
        .draw()?;
    let colours = [RED, BLUE, GREEN, MAGENTA, BLACK, CYAN];
    let methods = ["rk4", "dopri5", "sdirk4", "rodas4", "galpha", "auto"];
    for (k, name) in methods.iter().enumerate() {
        let mut line: Vec<(f64, f64)> = w
            .trials
            .iter()
            .filter(|t| t.method == *name)
            .filter_map(|t| t.accel_err.map(|e| (t.wall_s.max(1e-4), e.max(1e-12))))
            .collect();
        if line.is_empty() {
            continue;
        }
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        let c = colours[k % colours.len()];
        chart
            .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart.draw_series(line.iter().map(|p| Circle::new(*p, 4, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 18))
        .draw()?;
    Ok(())
}

/// Writes `accuracy.md`, `accuracy.json` and `accuracy_<scene>.png/.svg` into `out`.
pub fn write(s: &Study, out: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut files = Vec::new();
    let md = out.join("accuracy.md");
    std::fs::write(&md, markdown(s)).map_err(|e| format!("{}: {e}", md.display()))?;
    files.push(md);
    let js = out.join("accuracy.json");
    let text = serde_json::to_string_pretty(s).expect("study serialises");
    std::fs::write(&js, text + "\n").map_err(|e| format!("{}: {e}", js.display()))?;
    files.push(js);
    init_fonts();
    for w in &s.windows {
        let png = out.join(format!("accuracy_{}.png", w.window.scene));
        {
            let root = BitMapBackend::new(&png, (1024, 640)).into_drawing_area();
            draw(&root, w).map_err(|e| format!("{}: {e}", png.display()))?;
            root.present()
                .map_err(|e| format!("{}: {e}", png.display()))?;
        }
        let svg = out.join(format!("accuracy_{}.svg", w.window.scene));
        {
            let root = SVGBackend::new(&svg, (1024, 640)).into_drawing_area();
            draw(&root, w).map_err(|e| format!("{}: {e}", svg.display()))?;
            root.present()
                .map_err(|e| format!("{}: {e}", svg.display()))?;
        }
        files.push(png);
        files.push(svg);
    }
    Ok(files)
}

/// The committed study (`docs/accuracy.json`), compiled in for `washdyn run`'s error class.
const COMMITTED: &str = include_str!("../docs/accuracy.json");

/// What the committed study measured for this setting: the error class (the smallest class
/// at least as large as the measured error) and a sentence saying where it comes from. `None`
/// when the study has no run of this model, scene and method at this tolerance.
pub fn error_class(model: &str, scene: &str, method: Method, tol: f64) -> Option<String> {
    let s: Study = serde_json::from_str(COMMITTED).ok()?;
    if s.model != model {
        return None;
    }
    let w = s.windows.iter().find(|w| w.window.scene == scene)?;
    let t = w
        .trials
        .iter()
        .filter(|t| t.method == method.name() && t.accel_err.is_some())
        // The measured setting nearest in log(tol): tolerances a decade apart.
        .min_by(|a, b| {
            (a.tol.ln() - tol.ln())
                .abs()
                .total_cmp(&(b.tol.ln() - tol.ln()).abs())
        })?;
    if (t.tol.ln() - tol.ln()).abs() > 0.5 * 10f64.ln() {
        return None;
    }
    let err = t.accel_err?;
    let class = CLASSES
        .iter()
        .rev()
        .find(|c| err <= **c)
        .map_or_else(|| "worse than 1e-2".to_string(), |c| format!("{c:.0e}"));
    Some(format!(
        "{class} (docs/accuracy.md: {} at {:e} on scene {scene}, t = {} .. {} s, measured \
         acceleration error {err:.1e}, order amplitudes {} dB)",
        method.name(),
        t.tol,
        w.window.t0,
        w.window.t1,
        db(t.order_db)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_parse_or_say_why_not() {
        let w: Window = "full".parse().unwrap();
        assert_eq!(w.scene, "full");
        assert!(w.t1.is_nan());
        let w: Window = "elastic:150:152".parse().unwrap();
        assert_eq!((w.t0, w.t1), (150.0, 152.0));
        assert!("elastic:3:1".parse::<Window>().is_err());
        assert!("elastic:x:1".parse::<Window>().unwrap_err().contains("`x`"));
    }

    fn sink(ch: &[&str], rows: &[[f64; 2]]) -> MemorySink {
        let mut m = MemorySink {
            channels: ch.iter().map(|s| s.to_string()).collect(),
            ..Default::default()
        };
        for (k, r) in rows.iter().enumerate() {
            m.time.push(k as f64);
            m.rpm.push(0.0);
            m.values.extend_from_slice(r);
        }
        m
    }

    /// RMS error by hand: channel a_ax differs by 0.1 everywhere on a reference of RMS 1 ->
    /// 0.1; the displacement channel is ignored; different lengths give no number.
    #[test]
    fn band_error_sees_only_the_band() {
        // 1 s at 20 kHz: r = sin 50 Hz; x adds 1 % at 120 Hz (in the 300 Hz band) and a
        // tenfold tone at 1500 Hz (out of it). Closed form: a Hann-windowed tone's energy is
        // proportional to its amplitude squared, so the in-band error is 0.01.
        let fs = 20_000.0;
        let t: Vec<f64> = (0..20_000).map(|k| k as f64 / fs).collect();
        let s = |f: f64, a: f64| -> Vec<f64> {
            t.iter()
                .map(|t| a * (2.0 * std::f64::consts::PI * f * t).sin())
                .collect()
        };
        let (r, a, b) = (s(50.0, 1.0), s(120.0, 0.01), s(1500.0, 10.0));
        let x: Vec<f64> = (0..t.len()).map(|k| r[k] + a[k] + b[k]).collect();
        let e = band_error(&x, &r, fs, 300.0).expect("in band");
        assert!((e - 0.01).abs() < 1e-6, "{e}");
        // The raw RMS sees the out-of-band tone: 10.
        let raw = relative_rms(&x, &r).expect("raw");
        assert!((raw - 10.0).abs() < 1e-3, "{raw}");
    }

    #[test]
    fn rms_error_is_relative_and_only_on_accelerations() {
        let r = sink(&["a_ax", "d_ux"], &[[1.0, 5.0], [-1.0, 5.0]]);
        let x = sink(&["a_ax", "d_ux"], &[[1.1, 0.0], [-0.9, 0.0]]);
        assert!((rms_error(&x, &r).unwrap() - 0.1).abs() < 1e-12);
        let short = sink(&["a_ax", "d_ux"], &[[1.1, 0.0]]);
        assert_eq!(rms_error(&short, &r), None);
    }

    #[test]
    fn recommendation_takes_the_cheapest_setting_that_reaches_the_class() {
        let t = |m: &str, wall: f64, err: f64| Trial {
            method: m.into(),
            tol: 1e-6,
            backend: "generated".into(),
            steps: 0,
            rejected: 0,
            rhs_evals: 0,
            jacobians: 0,
            lu: 0,
            wall_s: wall,
            accel_err: Some(err),
            order_db: None,
            status: "ok".into(),
        };
        let trials = vec![t("a", 1.0, 5e-3), t("b", 0.5, 2e-2), t("c", 2.0, 5e-5)];
        let r = recommend(&trials);
        assert_eq!(r[0].1.unwrap().method, "a");
        assert_eq!(r[1].1.unwrap().method, "c");
        assert_eq!(r[2].1.unwrap().method, "c");
    }

    /// The committed study answers for the settings it measured, with the measured error
    /// inside the class it names, and nothing for a scene or model it did not study.
    #[test]
    fn error_class_comes_from_the_committed_study() {
        let s: Study = serde_json::from_str(COMMITTED).expect("docs/accuracy.json parses");
        let w = &s.windows[0];
        let t = w.trials.iter().find(|t| t.accel_err.is_some()).unwrap();
        let m: Method = t.method.parse().unwrap();
        let c = error_class(&s.model, &w.window.scene, m, t.tol).unwrap();
        let err = t.accel_err.unwrap();
        let class = CLASSES.iter().rev().find(|c| err <= **c);
        match class {
            Some(cl) => assert!(c.starts_with(&format!("{cl:.0e}")), "{c}"),
            None => assert!(c.starts_with("worse than"), "{c}"),
        }
        assert_eq!(error_class(&s.model, "no_such_scene", m, t.tol), None);
        assert_eq!(
            error_class("no_such_model", &w.window.scene, m, t.tol),
            None
        );
        // Two decades off every measured tolerance: no claim.
        assert_eq!(error_class(&s.model, &w.window.scene, m, 1e-12), None);
    }
}
