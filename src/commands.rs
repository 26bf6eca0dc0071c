//! The CLI's commands as library functions, so tests drive them without a subprocess.

use crate::results::{Format, SensorRecorder, StateRecorder};
use std::fs;
use std::path::{Path, PathBuf};
use washdyn_runtime::clearance::{Watch, element_tub_ends};
use washdyn_runtime::equations::Equations;
use washdyn_runtime::ir::toml_file::load_file;
use washdyn_runtime::ir::{DRUM, MOTOR, Model};
use washdyn_runtime::ode::{AnySolver, Method, Options};
use washdyn_runtime::run::{Guard, Labels, Progress, RunOptions, Start, Summary, run_guarded};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

/// Which evaluator of the equations runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Interpreted,
    Generated,
}

impl std::str::FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "interpreted" => Ok(Backend::Interpreted),
            "generated" => Ok(Backend::Generated),
            _ => Err(format!("unknown backend `{s}` (interpreted, generated)")),
        }
    }
}

/// A built-in model name or a path to a model file.
pub fn resolve_model(spec: &str) -> Result<(Model, bool), String> {
    if let Some(m) = washdyn_models::built_in(spec) {
        return m.map(|m| (m, true)).map_err(|e| e.to_string());
    }
    let p = Path::new(spec);
    if p.extension().is_some_and(|e| e == "toml") || p.exists() {
        return load_file(p).map(|m| (m, false)).map_err(|e| e.to_string());
    }
    Err(format!(
        "`{spec}` is neither a built-in model ({}) nor a model file",
        washdyn_models::BUILT_IN.join(", ")
    ))
}

/// Settings of `washdyn run`.
#[derive(Clone, Debug)]
pub struct RunArgs {
    pub model: String,
    pub t_end: Option<f64>,
    pub out: Option<PathBuf>,
    pub integrator: Method,
    pub tol: f64,
    /// Fixed step for rk4, s.
    pub step: Option<f64>,
    /// Generalized-alpha's spectral radius at infinity (galpha only; default
    /// `ode::generalized_alpha::DEFAULT_RHO_INF`).
    pub rho_inf: Option<f64>,
    pub backend: Option<Backend>,
    pub scene: Option<String>,
    pub sample_rate: f64,
    /// Step budget (accepted and rejected); `None`: the integrators' default.
    pub max_steps: Option<u64>,
    /// Format of the sensor file.
    pub format: Format,
    /// Keep the samples in memory for the analysis.
    pub keep_samples: bool,
    /// Write the states (`states.parquet`) for field recovery.
    pub states: bool,
    /// Keep the energy balance by category (`energy.parquet`, summary's `energy_closure`).
    pub energy: bool,
    /// How the run starts: static equilibrium (default), or at rest under the mean loads.
    pub start: Start,
}

/// Outcome of a run: where the files are, and the summary.
pub struct RunOutcome {
    pub out_dir: PathBuf,
    /// The sensor file written.
    pub sensors: PathBuf,
    pub summary: Summary,
    pub error: Option<String>,
    /// Column names and columns (time_s, drum_rpm, channels) when kept in memory.
    pub samples: Option<(Vec<String>, Vec<Vec<f64>>)>,
    /// The model's belt ratio (motor rotor speed / drum speed), for marking motor orders.
    pub motor_ratio: Option<f64>,
}

/// Motor speed / drum speed: the ratio of a rotor named `motor`, else of the fastest rotor
/// that is not the drum.
pub fn motor_ratio(model: &Model) -> Option<f64> {
    let drum = model.drum().map_or(1.0, |r| r.ratio);
    model
        .rotor(MOTOR)
        .or_else(|| {
            model
                .rotors
                .iter()
                .filter(|r| r.name != DRUM)
                .max_by(|a, b| a.ratio.total_cmp(&b.ratio))
        })
        .map(|r| r.ratio / drum)
}

/// The integrator settings the CLI documents: relative tolerance `tol`, absolute 1e-3 x `tol`
/// (m, rad), RK4's fixed step `step` (default 1e-4 s), an optional step budget.
pub fn integrator_options(
    method: Method,
    tol: f64,
    step: Option<f64>,
    max_steps: Option<u64>,
) -> Options {
    Options {
        rtol: tol,
        atol: tol * 1e-3,
        h0: match method {
            Method::Rk4 => step.unwrap_or(1e-4),
            _ => step.unwrap_or(0.0),
        },
        max_steps: max_steps.unwrap_or(Options::default().max_steps),
        ..Options::default()
    }
}

/// `DIR/summary.json`, written for finished and failed runs alike.
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<(), String> {
    let json = serde_json::to_string_pretty(summary).expect("summary serialises");
    fs::write(dir.join("summary.json"), json + "\n")
        .map_err(|e| format!("cannot write {}/summary.json: {e}", dir.display()))
}

/// What `run` watches and allows beyond [`RunArgs`].
#[derive(Clone, Debug, Default)]
pub struct RunControl {
    /// Validity bounds, interrupt flag, progress budget.
    pub guard: Guard,
    pub allow_large_output: bool,
    /// Band of the analysis that follows the run, Hz (the sample rate must resolve it).
    pub analysis_band_hz: Option<f64>,
}

/// [`run_command_with`] with the default [`RunControl`].
pub fn run_command(
    args: &RunArgs,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutcome, String> {
    run_command_with(args, &RunControl::default(), progress)
}

/// `washdyn run`: validate every setting (nothing is written before), integrate, stream
/// `sensors.parquet` (or `.csv`), write `summary.json`. A failed integration still writes both and reports the
/// error with its time.
pub fn run_command_with(
    args: &RunArgs,
    ctl: &RunControl,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutcome, String> {
    let (model, built_in) = resolve_model(&args.model)?;
    // A model file and its data files, hashed for `washdyn fields` (summary.json).
    let model_files = if built_in {
        Vec::new()
    } else {
        washdyn_runtime::ir::files::model_files(Path::new(&args.model), &model)?
    };
    let scene = model.scene(args.scene.as_deref())?;
    // Generated code exists for what was compiled in: the built-in models.
    let backend = args.backend.unwrap_or(if built_in {
        Backend::Generated
    } else {
        Backend::Interpreted
    });
    let mech: Box<dyn Mechanical + Send> = match backend {
        Backend::Interpreted => Box::new(Interpreter::new(&model, &scene)),
        Backend::Generated if built_in => washdyn_models::generated(&args.model, &scene.name)
            .ok_or_else(|| format!("no generated code for scene `{}`", scene.name))?,
        Backend::Generated => {
            return Err(format!(
                "`{}` is a model file: generated code exists only for models compiled in with \
                 machine! (built-in: {}); use --backend interpreted",
                args.model,
                washdyn_models::BUILT_IN.join(", ")
            ));
        }
    };
    crate::validate::check(&crate::validate::Settings {
        method: args.integrator,
        t_end: args.t_end,
        profile_end: mech.speed().end(),
        tol: args.tol,
        step: args.step,
        rho_inf: args.rho_inf,
        sample_rate: args.sample_rate,
        max_steps: args.max_steps,
        channels: Some(mech.channel_names().len()),
        analysis_band_hz: ctl.analysis_band_hz,
        allow_large_output: ctl.allow_large_output,
    })?;
    if args.start == Start::Periodic {
        washdyn_runtime::periodic::period(mech.speed(), 0.0)?;
    }
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&model.name));
    fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;

    let t_end = args.t_end.unwrap_or_else(|| mech.speed().end());
    let mut sys = FirstOrder::new(mech);
    let dim = 2 * sys.layout().n();
    let mut ode = integrator_options(args.integrator, args.tol, args.step, args.max_steps);
    if let Some(r) = args.rho_inf {
        ode.rho_inf = r;
    }
    let mut solver = AnySolver::new(args.integrator, dim, ode);
    let mut sink = SensorRecorder::new(&out_dir, args.format, args.keep_samples);
    sink.states = args.states.then(|| StateRecorder::new(&out_dir));
    sink.energy = args
        .energy
        .then(|| crate::results::EnergyRecorder::new(&out_dir, args.format));
    let opts = RunOptions {
        t_start: 0.0,
        t_end,
        sample_rate: args.sample_rate,
        start: args.start,
    };
    let labels = Labels {
        model: model.name.clone(),
        scene: scene.name.clone(),
        backend: match backend {
            Backend::Interpreted => "interpreted".into(),
            Backend::Generated => "generated".into(),
        },
    };
    let eq = Equations::new(&model, &scene);
    let guard = Guard {
        fixed_step: (args.integrator == Method::Rk4).then_some(ode.h0),
        elements: element_tub_ends(&model, &eq),
        watch: Watch::new(&model, &eq),
        ..ctl.guard.clone()
    };
    let (summary, error) = match run_guarded(
        &mut sys,
        &mut solver,
        &opts,
        &labels,
        (ode.rtol, ode.atol),
        &mut sink,
        progress,
        &guard,
    ) {
        Ok(s) => (s, None),
        Err((e, s)) => (s, Some(e.to_string())),
    };
    let mut summary = summary;
    summary.model_files = model_files;
    if args.integrator == Method::GeneralizedAlpha {
        summary.rho_inf = Some(ode.rho_inf);
    }
    // A run that failed reached no class; the study measured generalized-alpha at its default
    // spectral radius only.
    let default_rho = args.rho_inf.is_none_or(|r| r == Options::default().rho_inf);
    if error.is_none() && default_rho {
        let tol = match (args.integrator, args.step) {
            (Method::Rk4, h) => h.unwrap_or(ode.h0),
            _ => args.tol,
        };
        summary.error_class =
            crate::accuracy::error_class(&model.name, &scene.name, args.integrator, tol);
    }
    let finished = sink.finish();
    write_summary(&out_dir, &summary)?;
    finished.map_err(|e| format!("cannot write {}: {e}", sink.path().display()))?;
    if let Some(e) = &sink.energy {
        let (t, lines) = e.lines();
        let opts = crate::analysis::AnalysisOptions::default();
        crate::analysis::plot::energy_plot(&t, &lines, &opts, &out_dir.join("energy"))
            .map_err(|e| e.to_string())?;
    }
    let samples = args
        .keep_samples
        .then(|| (sink.names.clone(), std::mem::take(&mut sink.memory)));
    Ok(RunOutcome {
        out_dir,
        sensors: sink.path().to_path_buf(),
        summary,
        error,
        samples,
        motor_ratio: motor_ratio(&model),
    })
}

/// `washdyn check`: the model's own checks (done on loading), then what a run needs of each
/// scene: a static equilibrium at t = 0 (a model without springs has none) and a rest position
/// inside the small-motion bounds of [`Guard`].
pub fn check_model(model: &Model) -> Result<String, String> {
    let guard = Guard::default();
    let mut lines = vec![format!(
        "{}: ok; scenes: {}",
        model.name,
        model.scene_names().join(", ")
    )];
    let mut errors = Vec::new();
    for name in model.scene_names() {
        let scene = model.scene(Some(&name))?;
        let mut sys = Interpreter::new(model, &scene);
        match washdyn_runtime::statics::static_equilibrium(&mut sys, 0.0) {
            Ok(q) => {
                let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
                let (u, a) = Equations::new(model, &scene).bodies.rigid_motion(&q);
                let (u, a) = (norm(u), norm(a));
                let msg = format!(
                    "scene `{name}`: static rest position at t = 0: tub translation {:.2} mm, \
                     rotation {a:.2e} rad",
                    u * 1e3
                );
                // A NaN compares false: test finiteness first, then the bounds negated.
                if !(q.iter().all(|x| x.is_finite()) && u.is_finite() && a.is_finite()) {
                    errors.push(format!("{msg}: not a number (non-finite model data)"));
                } else if !(u <= guard.translation_m && a <= guard.rotation_rad) {
                    errors.push(format!(
                        "{msg}: beyond the small-motion bounds ({} mm, {} rad); a spring pulling \
                         the wrong way or too soft?",
                        guard.translation_m * 1e3,
                        guard.rotation_rad
                    ));
                } else {
                    lines.push(msg);
                }
            }
            Err(e) => errors.push(format!("scene `{name}` cannot run: {e}")),
        }
    }
    if errors.is_empty() {
        Ok(lines.join("\n"))
    } else {
        Err(format!("{}: {}", model.name, errors.join("\n")))
    }
}

/// The rules of [`crate::validate`] for the settings a sweep shares across its variants (the
/// output size is checked per variant by `run`'s rule only when the sweep calls it).
pub fn validate_sweep(
    model: &Model,
    scene: Option<&str>,
    method: Method,
    tol: f64,
    t_end: Option<f64>,
    sample_rate: f64,
) -> Result<(), String> {
    let scene = model.scene(scene)?;
    let sys = Interpreter::new(model, &scene);
    crate::validate::check(&crate::validate::Settings {
        method,
        t_end,
        profile_end: sys.speed().end(),
        tol,
        step: None,
        rho_inf: None,
        sample_rate,
        max_steps: None,
        channels: Some(sys.channel_names().len()),
        analysis_band_hz: None,
        allow_large_output: false,
    })
}

/// `washdyn fe modal`'s report: the sections of `old` (one per body, starting with a line
/// `NAME: ...` at column 0) with those in `new` replaced or added, in the bodies' `order`.
pub fn merge_report(old: &str, new: &[(String, String)], order: &[String]) -> String {
    let mut sections: Vec<(String, String)> = Vec::new();
    for line in old.lines() {
        let head = line
            .split_once(": ")
            .filter(|_| !line.starts_with(' '))
            .map(|(n, _)| n.to_string());
        match (head, sections.last_mut()) {
            (Some(name), _) => sections.push((name, format!("{line}\n"))),
            (None, Some((_, text))) => {
                text.push_str(line);
                text.push('\n');
            }
            (None, None) => {}
        }
    }
    for (name, text) in new {
        match sections.iter_mut().find(|(n, _)| n == name) {
            Some(s) => s.1 = text.clone(),
            None => sections.push((name.clone(), text.clone())),
        }
    }
    let rank = |n: &str| order.iter().position(|o| o == n).unwrap_or(order.len());
    sections.sort_by_key(|(n, _)| rank(n));
    sections.into_iter().map(|(_, t)| t).collect()
}

#[cfg(test)]
mod report_tests {
    use super::merge_report;

    #[test]
    fn only_the_solved_bodies_sections_change() {
        let old = "cabinet: 3 nodes\n  lumped mass 1 kg\ntub: 1 nodes\n  old tub\n";
        let order = ["tub", "drum", "cabinet"].map(String::from);
        let new = vec![("tub".to_string(), "tub: 2 nodes\n  new tub\n".to_string())];
        assert_eq!(
            merge_report(old, &new, &order),
            "tub: 2 nodes\n  new tub\ncabinet: 3 nodes\n  lumped mass 1 kg\n"
        );
        assert_eq!(merge_report("", &new, &order), "tub: 2 nodes\n  new tub\n");
    }
}
