//! `washdyn accuracy`: what accuracy costs in time. For each scene window, every method runs a
//! sweep of tolerances (rk4: step sizes); each run is compared with a reference computed at a
//! tight tolerance and confirmed by a second, different method. The errors are on what users
//! look at: the sensor accelerations (RMS over time, relative) and the first orders' amplitudes
//! in the order tracks (dB). Beside the method costs, the model's own: modal truncation, each
//! scene against the full (elastic) model, generated against interpreted code. Writes
//! `accuracy.md`, `accuracy.json` (read by `washdyn run` for its error class) and a log-log
//! work-precision plot per scene.

use crate::error::Error;
use crate::simulation::{Backend, Settings, Simulation, Source};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::PathBuf;
use washdyn_model::ir::EffectSet;
use washdyn_ode::Method;
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Start, Summary};
use washdyn_runtime::system::Interpreter;

pub mod class;
mod metrics;
mod report;

use metrics::{Tracks, band_rms_error, order_error, order_tracks, trim};
pub use metrics::{band_error, is_accel, relative_rms, rms_error, track_error, track_error_above};
pub use report::{markdown, recommend, write};

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
/// The strong part of an order track: at least this fraction of its peak (within 20 dB), where
/// a model comparison's 0.1 dB target applies (issue 21).
pub const STRONG_FLOOR: f64 = 0.1;
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
    type Err = Error;
    /// `NAME` (the whole speed profile) or `NAME:T0:T1`; refused as `--scene`.
    fn from_str(s: &str) -> Result<Window, Error> {
        let parts: Vec<&str> = s.split(':').collect();
        let refused = |why: String| Error::setting("--scene", format!("--scene `{s}`: {why}"));
        let num = |p: &str| {
            p.parse::<f64>()
                .map_err(|_| refused(format!("`{p}` is not a time in s (NAME or NAME:T0:T1)")))
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
                    return Err(refused(format!("need 0 <= T0 < T1 <= {top} s")));
                }
                Ok(Window {
                    scene: name.to_string(),
                    t0,
                    t1,
                })
            }
            _ => Err(refused("expected NAME or NAME:T0:T1".into())),
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
    /// The content hash of the model as this window's scene ran it (`class::content_hash`);
    /// `None`: measured on a model nobody recorded, which gives no run an error class.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_hash: Option<String>,
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

/// Runs one setting over the window into memory, from the mean-load rest (so a window at
/// constant speed needs no settling time).
#[allow(clippy::too_many_arguments)]
fn simulate(
    source: &Source,
    scene: &EffectSet,
    backend: Backend,
    method: Method,
    tol: f64,
    w: &Window,
    rho_inf: Option<f64>,
    rate: f64,
) -> Result<Sim, Error> {
    let (tol, step) = if method == Method::Rk4 {
        (1e-6, Some(tol))
    } else {
        (tol, None)
    };
    let settings = Settings {
        backend: Some(backend),
        method,
        tol,
        step,
        rho_inf,
        // A budget no setting of the study needs, so a hopeless one stops instead of hanging.
        max_steps: Some(30_000_000),
        t_start: w.t0,
        t_end: Some(w.t1),
        sample_rate: rate,
        start: Start::MeanLoad,
        ..Settings::default()
    };
    let sim = Simulation::with_scene(source.clone(), scene.clone(), &settings)?;
    let mut mem = MemorySink::default();
    let (summary, error) = sim.integrate(&mut mem, &mut |_| {});
    Ok(Sim {
        mem,
        summary,
        error: error.map(|e| e.to_string()),
        rate,
    })
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
        .any(|e| matches!(e, washdyn_model::ir::Effect::Elastic(_)))
}

/// Runs the whole study; `log` hears one line a run.
pub fn study(args: &AccuracyArgs, log: &mut dyn FnMut(&str)) -> Result<Study, Error> {
    let source = Source::load(&args.model)?;
    let model = &source.model;
    let built_in = source.built_in.is_some();
    let backend = if built_in {
        Backend::Generated
    } else {
        Backend::Interpreted
    };
    let mut windows = Vec::new();
    for w in &args.windows {
        let scene = model
            .scene(Some(&w.scene))
            .map_err(|m| Error::setting("--scene", m))?;
        let mut w = w.clone();
        if w.t1.is_nan() {
            w.t1 = model.speed.table.last().map_or(1.0, |r| r[0]);
        }
        let elastic = is_elastic(&scene);
        // A whole run-up: the comparisons that need their own long runs (back ends, modal
        // truncation, scenes) are the short windows' job.
        let long = w.t1 - w.t0 > LONG;
        let run = |method: Method, tol: f64, scene: &EffectSet, b: Backend| {
            simulate(&source, scene, b, method, tol, &w, None, SAMPLE_RATE)
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
            return Err(Error::refused(
                "accuracy",
                format!("reference run failed: {e}"),
            ));
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
                let s = simulate(&source, &scene, backend, m, tol, &w, Some(rho), SAMPLE_RATE)?;
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
            simulate(&source, scene, b, method, tol, &early, None, COMPARE_RATE)
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
                let n = Interpreter::new(model, &sc).eq.layout.n();
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
                let sc = model
                    .scene(Some(&other.name))
                    .map_err(|m| Error::setting("--scene", m))?;
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
            model_hash: Some(class::content_hash(model, &scene)),
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
        for bad in ["elastic:3:1", "elastic:x:1", "a:b"] {
            let e = bad.parse::<Window>().unwrap_err();
            assert_eq!(e.options(), ["--scene"], "{bad}: {e}");
        }
    }
}
