//! `washdyn accuracy`: what accuracy costs in time. For each scene window, every method runs a
//! sweep of tolerances (rk4: step sizes); each run is compared with a reference computed at a
//! tight tolerance and confirmed by a second, different method. The errors are on what users
//! look at: the sensor accelerations (RMS over time, relative) and the first orders' amplitudes
//! in the order tracks (dB). Beside the method costs, the model's own: modal truncation, each
//! scene against the full (elastic) model, generated against interpreted code. Writes
//! `accuracy.md`, `accuracy.json` (read by `washdyn run` for its error class) and a log-log
//! work-precision plot per scene.

use crate::error::Error;
use crate::error_class::{CLASSES, Study, Trial, Window, WindowStudy};
use crate::simulation::{Backend, RunControl, Simulation, Source};
use crate::spec::{Context, DEFAULT_METHOD, DEFAULT_TOL, Field, RunSpec};
use std::fmt::Write as _;
use std::path::PathBuf;
use washdyn_model::ir::EffectSet;
use washdyn_ode::Method;
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Progress, Start, Summary};

mod report;
mod window;

use crate::analysis::metrics::{Tracks, band_rms_error, order_error, order_tracks, rms_error};
pub use report::{markdown, recommend, write};

/// Sample rate of the method runs, Hz (the analysis band is 300 Hz).
const SAMPLE_RATE: f64 = 2000.0;
/// Sample rate of the model comparisons (modal truncation, scenes), Hz: above twice the tub's
/// highest mode (6.6 kHz), so that what one model has and the other lacks does not alias.
const COMPARE_RATE: f64 = 20_000.0;
/// Model comparisons (modal truncation, scenes) start this long before the window and compare
/// only inside it, s: each model has its own start transient, which is not what is compared.
const SETTLE: f64 = 2.0;
/// Eigenmode cut-offs of the modal truncation study (Hz), each against all the data's modes.
pub const TRUNCATION_CUTS_HZ: [f64; 5] = [70.0, 210.0, 420.0, 700.0, 1000.0];
/// Windows longer than this (s) are run-ups: see `sweep`.
const LONG: f64 = 20.0;
/// The command's `--scene`; the record's window type is the error class's (`error_class::Window`).
impl std::str::FromStr for Window {
    type Err = Error;
    /// `NAME` (the whole speed profile) or `NAME:T0:T1`; refused as `--scene`.
    fn from_str(s: &str) -> Result<Window, Error> {
        let parts: Vec<&str> = s.split(':').collect();
        let refused = |why: String| Error::setting(Field::Scene, format!("--scene `{s}`: {why}"));
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
                let top = crate::spec::T_END_MAX;
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
    /// Windows without an end (`t1` NaN) run to `t_end`, or to the speed profile's end.
    pub windows: Vec<Window>,
    /// `--t-end`, s.
    pub t_end: Option<f64>,
    pub out: PathBuf,
    /// Fewer settings a method (for tests and a first look).
    pub quick: bool,
}

/// The spectral radii the study runs generalized-alpha at: from annihilating the unresolved
/// modes in one step (0) to keeping them undamped (1); 0.8 is the default.
pub const RHO_INF: [f64; 4] = [0.0, 0.5, 0.8, 1.0];

/// A finished or failed simulation in memory.
struct Sim {
    mem: MemorySink,
    summary: Summary,
    error: Option<Error>,
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
    progress: &dyn Fn(&str, Progress),
) -> Result<Sim, Error> {
    let (tol, step) = if method == Method::Rk4 {
        (1e-6, Some(tol))
    } else {
        (tol, None)
    };
    let spec = RunSpec {
        scene: Some(scene.name.clone()),
        backend: Some(backend),
        method: Some(method),
        tol: Some(tol),
        step,
        rho_inf,
        // A budget no setting of the study needs, so a hopeless one stops instead of hanging.
        max_steps: Some(30_000_000),
        sample_rate: rate,
        start: Start::MeanLoad,
        ..window_spec(source, w)
    };
    let sim = Simulation::with_scene(source.clone(), scene.clone(), &spec, &RunControl::default())?;
    let mut mem = MemorySink::default();
    let label = format!("{} {method} {tol:e} ({})", scene.name, backend.name());
    let (summary, error) = sim.integrate(&mut mem, &mut |p| progress(&label, p));
    Ok(Sim {
        mem,
        summary,
        error,
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

/// The run specification of a window: every run of the study over it is this with its own
/// settings.
fn window_spec(source: &Source, w: &Window) -> RunSpec {
    RunSpec {
        model: source.spec.clone(),
        scene: Some(w.scene.clone()),
        t_start: w.t0,
        t_end: Some(w.t1),
        ..RunSpec::default()
    }
}

/// Runs the whole study; `log` hears one line a run, `progress` each run's progress (its
/// label: scene, method, tolerance, back end). Every window is checked first, by the run
/// specification's rules (`RunSpec::validate`): nothing runs if one is refused.
pub fn study(
    args: &AccuracyArgs,
    log: &mut dyn FnMut(&str),
    progress: &dyn Fn(&str, Progress),
) -> Result<Study, Error> {
    let source = Source::load(&args.model)?;
    let model = &source.model;
    let profile_end = model.speed.table.last().map_or(1.0, |r| r[0]);
    let mut resolved = Vec::new();
    for w in &args.windows {
        let scene = model
            .scene(Some(&w.scene))
            .map_err(|m| Error::setting(Field::Scene, m))?;
        // A window without an end runs to --t-end, or to the profile's end (`None`).
        let spec = RunSpec {
            t_end: if w.t1.is_nan() {
                args.t_end
            } else {
                Some(w.t1)
            },
            ..window_spec(&source, w)
        };
        let cx = Context::bare(DEFAULT_METHOD, DEFAULT_TOL, profile_end);
        spec.validate(&cx).map_err(Error::Settings)?;
        let w = Window {
            t1: spec.end(&cx),
            ..w.clone()
        };
        resolved.push((scene, w));
    }
    let mut windows = Vec::new();
    for (scene, w) in resolved {
        windows.push(window::Stages::new(&source, scene, w, args.quick, progress).study(log)?);
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
        match (w.t1.is_nan(), args.t_end) {
            (true, None) => {
                let _ = write!(s, " --scene {}", w.scene);
            }
            (true, Some(t1)) => {
                let _ = write!(s, " --scene {}:{}:{t1}", w.scene, w.t0);
            }
            (false, _) => {
                let _ = write!(s, " --scene {}:{}:{}", w.scene, w.t0, w.t1);
            }
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

    /// A window's end (`--t-end` for a scene without its own) is refused by the run
    /// specification's rule, at its field, before any window runs.
    #[test]
    fn windows_are_checked_by_the_run_specifications_rules_before_any_runs() {
        for t1 in [f64::NAN, f64::INFINITY, -1.0, 0.0, 3601.0] {
            let args = AccuracyArgs {
                model: "reference".into(),
                windows: vec!["elastic:150:152".parse().unwrap(), "full".parse().unwrap()],
                t_end: Some(t1),
                out: PathBuf::from("unused"),
                quick: true,
            };
            let mut ran = 0;
            let e = study(&args, &mut |_| ran += 1, &|_, _| {}).unwrap_err();
            assert_eq!(e.fields(), [Field::TEnd], "{t1}: {e}");
            assert_eq!(
                e.to_string(),
                format!("--t-end must be > 0 and at most 3600 s, got {t1}")
            );
            assert_eq!(ran, 0);
        }
    }
}
