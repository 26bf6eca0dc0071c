//! The CLI's commands as library functions, so tests drive them without a subprocess.

use crate::results::{Format, SensorRecorder};
use std::fs;
use std::path::{Path, PathBuf};
use washdyn_runtime::ir::Model;
use washdyn_runtime::ir::toml_file::load_file;
use washdyn_runtime::ode::{AnySolver, Method, Options};
use washdyn_runtime::run::{Labels, Progress, RunOptions, Start, Summary, run};
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
    pub backend: Option<Backend>,
    pub scene: Option<String>,
    pub sample_rate: f64,
    /// Step budget (accepted and rejected); `None`: the integrators' default.
    pub max_steps: Option<u64>,
    /// Format of the sensor file.
    pub format: Format,
    /// Keep the samples in memory for the analysis.
    pub keep_samples: bool,
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
    let drum = model
        .rotors
        .iter()
        .find(|r| r.name == "drum")
        .map_or(1.0, |r| r.ratio);
    model
        .rotors
        .iter()
        .find(|r| r.name == "motor")
        .or_else(|| {
            model
                .rotors
                .iter()
                .filter(|r| r.name != "drum")
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

/// `washdyn run`: integrate, stream `sensors.parquet` (or `.csv`), write `summary.json`. A failed integration
/// still writes both and reports the error with its time.
pub fn run_command(
    args: &RunArgs,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutcome, String> {
    let (model, built_in) = resolve_model(&args.model)?;
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
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&model.name));
    fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;

    let t_end = args.t_end.unwrap_or_else(|| mech.speed().end());
    let mut sys = FirstOrder::new(mech);
    let dim = 2 * sys.layout().n();
    let ode = integrator_options(args.integrator, args.tol, args.step, args.max_steps);
    let mut solver = AnySolver::new(args.integrator, dim, ode);
    let mut sink = SensorRecorder::new(&out_dir, args.format, args.keep_samples);
    let opts = RunOptions {
        t_start: 0.0,
        t_end,
        sample_rate: args.sample_rate,
        start: Start::Static,
    };
    let labels = Labels {
        model: model.name.clone(),
        scene: scene.name.clone(),
        backend: match backend {
            Backend::Interpreted => "interpreted".into(),
            Backend::Generated => "generated".into(),
        },
    };
    let (summary, error) = match run(
        &mut sys,
        &mut solver,
        &opts,
        &labels,
        (ode.rtol, ode.atol),
        &mut sink,
        progress,
    ) {
        Ok(s) => (s, None),
        Err((e, s)) => (s, Some(e.to_string())),
    };
    let finished = sink.finish();
    write_summary(&out_dir, &summary)?;
    finished.map_err(|e| format!("cannot write {}: {e}", sink.path().display()))?;
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
