//! One simulation set-up for `run`, `sweep` and `accuracy` (and the tests that run what they
//! run): the model and where it came from, the scene, the back end, the method and its
//! [`Options`] (tolerances, rk4's step, rho_inf, step budget), the start, the window, the
//! [`Guard`] (the caller's bounds and flags, plus rk4's stability check, the force elements'
//! tub ends and the clearance watch) and the summary's labels. [`Simulation::new`] checks every
//! setting before anything is written (`validate::check`, the scene, the back end, a periodic
//! start's constant speed); [`Simulation::integrate`] runs it into a sink and completes the
//! summary (model files, rho_inf, set-up warnings, the error class).

use crate::error::Error;
use std::path::Path;
use washdyn_model::equations::Equations;
use washdyn_model::ir::files::{FileHash, model_files};
use washdyn_model::ir::toml_file::load_file;
use washdyn_model::ir::{EffectSet, Model};
use washdyn_ode::{AnySolver, Method, Options};
use washdyn_runtime::clearance::{Watch, element_tub_ends};
use washdyn_runtime::output::SampleSink;
use washdyn_runtime::run::{Guard, Labels, Progress, RunOptions, Start, Summary, run_guarded};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

/// Which evaluator of the equations runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Interpreted,
    Generated,
}

impl Backend {
    pub fn name(self) -> &'static str {
        match self {
            Backend::Interpreted => "interpreted",
            Backend::Generated => "generated",
        }
    }
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

/// A built-in model name or a path to a model file: the model, and whether it is built in.
pub fn resolve_model(spec: &str) -> Result<(Model, bool), Error> {
    if let Some(m) = washdyn_models::built_in(spec) {
        return Ok((m?, true));
    }
    let p = Path::new(spec);
    if p.extension().is_some_and(|e| e == "toml") || p.exists() {
        return Ok((load_file(p)?, false));
    }
    Err(Error::UnknownModel { spec: spec.into() })
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

/// A model and where it came from.
#[derive(Clone, Debug)]
pub struct Source {
    /// The model as given: a built-in name or a file's path (named in errors).
    pub spec: String,
    pub model: Model,
    /// The built-in model's name when the model is compiled in unchanged: generated code
    /// exists for its scenes.
    pub built_in: Option<String>,
    /// For a variant of a built-in model (`Source::variant`): that model's name. Its generated
    /// code runs the variant when the two differ in free parameters only (`Model::free`).
    pub generated_base: Option<String>,
    /// A model file and the data files it names, hashed (`summary.json`'s `model_files`);
    /// empty for a built-in model.
    pub files: Vec<FileHash>,
}

impl Source {
    /// A built-in model or a model file (with its files hashed).
    pub fn load(spec: &str) -> Result<Source, Error> {
        let (model, built_in) = resolve_model(spec)?;
        let files = if built_in {
            Vec::new()
        } else {
            model_files(Path::new(spec), &model).map_err(|message| Error::File { message })?
        };
        Ok(Source {
            spec: spec.into(),
            model,
            built_in: built_in.then(|| spec.to_string()),
            generated_base: None,
            files,
        })
    }

    /// A model built or changed in memory: the interpreter runs it.
    pub fn in_memory(model: Model) -> Source {
        Source {
            spec: model.name.clone(),
            model,
            built_in: None,
            generated_base: None,
            files: Vec::new(),
        }
    }

    /// This model changed in memory (a sweep's or study's variant); it keeps the files it was
    /// loaded from. The interpreter runs it, or a built-in's generated code where the variant
    /// differs from the built-in in free parameters only.
    pub fn variant(&self, model: Model) -> Source {
        Source {
            spec: self.spec.clone(),
            model,
            built_in: None,
            generated_base: self.built_in.clone().or(self.generated_base.clone()),
            files: self.files.clone(),
        }
    }
}

/// What a simulation is asked to do: the CLI's run options. [`Default`] is the CLI's defaults.
#[derive(Clone, Debug)]
pub struct Settings {
    /// `--scene` (default: the model's first scene).
    pub scene: Option<String>,
    /// `--backend` (default: generated for a built-in model, else interpreted).
    pub backend: Option<Backend>,
    pub method: Method,
    pub tol: f64,
    /// rk4's fixed step, s (default 1e-4).
    pub step: Option<f64>,
    /// galpha's spectral radius at infinity (default `Options::default().rho_inf`).
    pub rho_inf: Option<f64>,
    pub max_steps: Option<u64>,
    /// Start of the window, s (the CLI: 0; the accuracy study's windows).
    pub t_start: f64,
    /// End of the window, s (default: the end of the speed profile).
    pub t_end: Option<f64>,
    pub sample_rate: f64,
    pub start: Start,
    /// The caller's bounds and flags (stop factor, interrupt, progress budget); the set-up
    /// adds rk4's fixed step, the force elements' tub ends and the clearance watch.
    pub guard: Guard,
    pub allow_large_output: bool,
    /// Band of an analysis after the run, Hz (the sample rate must resolve it).
    pub analysis_band_hz: Option<f64>,
    /// A sweep's variant: the summary's model label becomes `<model>/<variant>`.
    pub variant: Option<String>,
}

/// The method of a run that names none and whose scene names none.
pub const DEFAULT_METHOD: Method = Method::Dopri5;
/// The relative tolerance of a run that names none and whose scene names none for its method.
pub const DEFAULT_TOL: f64 = 1e-6;

/// The method and relative tolerance of a run: the caller's, else the scene's default
/// (`Model::scene_solver`: its tolerance only with its own method), else [`DEFAULT_METHOD`] at
/// [`DEFAULT_TOL`].
pub fn solver_for(
    model: &washdyn_model::ir::Model,
    scene: Option<&str>,
    method: Option<Method>,
    tol: Option<f64>,
) -> (Method, f64) {
    let own = model
        .scene_solver(scene)
        .map(|s| (washdyn_runtime::run::method_of(s.method), s.tol));
    let method = method.or(own.map(|o| o.0)).unwrap_or(DEFAULT_METHOD);
    let tol = tol
        .or(own.filter(|o| o.0 == method).map(|o| o.1))
        .unwrap_or(DEFAULT_TOL);
    (method, tol)
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            scene: None,
            backend: None,
            method: DEFAULT_METHOD,
            tol: DEFAULT_TOL,
            step: None,
            rho_inf: None,
            max_steps: None,
            t_start: 0.0,
            t_end: None,
            sample_rate: 2000.0,
            start: Start::Static,
            guard: Guard::default(),
            allow_large_output: false,
            analysis_band_hz: None,
            variant: None,
        }
    }
}

/// A checked simulation, ready to run.
pub struct Simulation {
    pub source: Source,
    pub scene: EffectSet,
    pub backend: Backend,
    pub method: Method,
    pub options: Options,
    /// `--rho-inf` as given (`None`: the default).
    pub rho_inf: Option<f64>,
    /// Window, sample rate and start.
    pub run: RunOptions,
    pub guard: Guard,
    pub labels: Labels,
    /// Warnings of the set-up (a tolerance looser than every error class), the summary's first.
    pub warnings: Vec<String>,
    /// The back end, taken by [`Simulation::integrate`].
    mech: Option<Box<dyn Mechanical + Send>>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("model", &self.source.model.name)
            .field("scene", &self.scene)
            .field("backend", &self.backend)
            .field("method", &self.method)
            .field("options", &self.options)
            .field("run", &self.run)
            .field("labels", &self.labels)
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// Checks every setting against the model (nothing is written): the scene by name, then
    /// as [`Simulation::with_scene`].
    pub fn new(source: Source, s: &Settings) -> Result<Simulation, Error> {
        let scene = source
            .model
            .scene(s.scene.as_deref())
            .map_err(|m| Error::setting("--scene", m))?;
        Simulation::with_scene(source, scene, s)
    }

    /// With a resolved scene (the accuracy study's changed mode cut-offs): the back end, the
    /// settings' rules (`validate::check`, every violation at once), a periodic start's
    /// constant speed; then the options, guard, labels and warnings.
    pub fn with_scene(source: Source, scene: EffectSet, s: &Settings) -> Result<Simulation, Error> {
        let backend = s.backend.unwrap_or(if source.built_in.is_some() {
            Backend::Generated
        } else {
            Backend::Interpreted
        });
        let mech = mechanical(&source, &scene, backend)?;
        crate::validate::check(&crate::validate::Settings {
            method: s.method,
            t_end: s.t_end,
            profile_end: mech.speed().end(),
            tol: s.tol,
            step: s.step,
            rho_inf: s.rho_inf,
            sample_rate: s.sample_rate,
            max_steps: s.max_steps,
            channels: Some(mech.channel_names().len()),
            analysis_band_hz: s.analysis_band_hz,
            allow_large_output: s.allow_large_output,
            max_projected_s: s.guard.max_projected_s,
        })?;
        if s.start == Start::Periodic {
            washdyn_runtime::periodic::period(mech.speed(), s.t_start)
                .map_err(|m| Error::setting("--start", m))?;
        }
        let mut options = integrator_options(s.method, s.tol, s.step, s.max_steps);
        if let Some(r) = s.rho_inf {
            options.rho_inf = r;
        }
        let model = &source.model;
        let eq = Equations::new(model, &scene);
        let guard = Guard {
            fixed_step: (s.method == Method::Rk4).then_some(options.h0),
            elements: element_tub_ends(model, &eq),
            watch: Watch::new(model, &eq),
            ..s.guard.clone()
        };
        let labels = Labels {
            model: match &s.variant {
                Some(v) => format!("{}/{v}", model.name),
                None => model.name.clone(),
            },
            scene: scene.name.clone(),
            backend: backend.name().into(),
        };
        let run = RunOptions {
            t_start: s.t_start,
            t_end: s.t_end.unwrap_or_else(|| mech.speed().end()),
            sample_rate: s.sample_rate,
            start: s.start,
        };
        let warnings = crate::accuracy::class::tolerance_warning(s.method, s.tol)
            .into_iter()
            .collect();
        Ok(Simulation {
            source,
            scene,
            backend,
            method: s.method,
            options,
            rho_inf: s.rho_inf,
            run,
            guard,
            labels,
            warnings,
            mech: Some(mech),
        })
    }

    pub fn model(&self) -> &Model {
        &self.source.model
    }

    /// The sensor channels the run records, in the sensor file's order (after `time_s` and
    /// `drum_rpm`): known before the run, so a study's columns are the same for every variant.
    pub fn channel_names(&self) -> Vec<String> {
        self.mech
            .as_ref()
            .map_or_else(Vec::new, |m| m.channel_names())
    }

    /// What the error class is looked up at: the relative tolerance, rk4's step.
    pub fn class_tolerance(&self) -> f64 {
        match self.method {
            Method::Rk4 => self.options.h0,
            _ => self.options.rtol,
        }
    }

    /// The model files, rho_inf and set-up warnings a summary of this simulation records.
    fn label(&self, s: &mut Summary) {
        s.model_files = self.source.files.clone();
        if self.method == Method::GeneralizedAlpha {
            s.rho_inf = Some(self.options.rho_inf);
        }
        s.warnings.splice(0..0, self.warnings.iter().cloned());
    }

    /// Integrates into `sink`: the summary, and the error when the run failed (the summary says
    /// so too; what the sink received is kept). A run that completed gets the error class the
    /// committed study measured for it ([`Simulation::error_class`]).
    pub fn integrate(
        mut self,
        sink: &mut dyn SampleSink,
        progress: &mut dyn FnMut(Progress),
    ) -> (Summary, Option<Error>) {
        let mech = self.mech.take().expect("built by Simulation::with_scene");
        let mut sys = FirstOrder::new(mech);
        let mut solver = AnySolver::new(self.method, sys.layout().dim(), self.options);
        let (mut summary, error) = match run_guarded(
            &mut sys,
            &mut solver,
            &self.run,
            &self.labels,
            (self.options.rtol, self.options.atol),
            sink,
            progress,
            &self.guard,
        ) {
            Ok(s) => (s, None),
            Err((e, s)) => (s, Some(Error::integration(e))),
        };
        self.label(&mut summary);
        if error.is_none() {
            summary.error_class = self.error_class();
        }
        (summary, error)
    }

    /// The error class the committed study measured for this setting (`accuracy::class`):
    /// the same model content, scene, method, tolerance and window; none off
    /// generalized-alpha's default spectral radius (the study measured that one).
    pub fn error_class(&self) -> Option<String> {
        if self
            .rho_inf
            .is_some_and(|r| r != Options::default().rho_inf)
        {
            return None;
        }
        crate::accuracy::class::committed_class(
            &crate::accuracy::class::Query {
                scene: &self.scene.name,
                method: self.method,
                tol: self.class_tolerance(),
                window: (self.run.t_start, self.run.t_end),
            },
            &mut || crate::accuracy::class::content_hash(&self.source.model, &self.scene),
        )
    }
}

/// The summary of a run that took no step (a sweep's variant refused before its run), labelled
/// as [`Simulation::integrate`] labels one: the method's name, galpha's rho_inf.
pub fn unstarted_summary(
    labels: &Labels,
    method: Method,
    options: &Options,
    span: (f64, f64),
) -> Summary {
    let mut s = Summary::new(labels, method.name(), (options.rtol, options.atol), span);
    if method == Method::GeneralizedAlpha {
        s.rho_inf = Some(options.rho_inf);
    }
    s
}

/// The back end's equations of `scene`.
fn mechanical(
    source: &Source,
    scene: &EffectSet,
    backend: Backend,
) -> Result<Box<dyn Mechanical + Send>, Error> {
    let model = &source.model;
    match (backend, &source.built_in) {
        (Backend::Interpreted, _) => Ok(Box::new(Interpreter::new(model, scene))),
        (Backend::Generated, Some(name)) => {
            // The generated code is the scene as the model declares it.
            if model.scene(Some(&scene.name)).ok().as_ref() != Some(scene) {
                return Err(Error::setting(
                    "--backend",
                    format!(
                        "scene `{}` was changed in memory: generated code exists for the \
                         scenes as declared; use --backend interpreted",
                        scene.name
                    ),
                ));
            }
            washdyn_models::generated(name, &scene.name).ok_or_else(|| {
                Error::setting(
                    "--backend",
                    format!("no generated code for scene `{}`", scene.name),
                )
            })
        }
        (Backend::Generated, None) if source.generated_base.is_some() => {
            let name = source.generated_base.as_deref().unwrap_or_default();
            match washdyn_models::generated_for(name, &scene.name, model) {
                Some(Ok(m)) if model.scene(Some(&scene.name)).ok().as_ref() == Some(scene) => Ok(m),
                Some(Ok(_)) => Err(Error::setting(
                    "--backend",
                    format!(
                        "scene `{}` was changed in memory: generated code exists for the \
                         scenes as declared; use --backend interpreted",
                        scene.name
                    ),
                )),
                Some(Err(why)) => Err(Error::setting("--backend", why)),
                None => Err(Error::setting(
                    "--backend",
                    format!("no generated code for scene `{}`", scene.name),
                )),
            }
        }
        (Backend::Generated, None) if source.files.is_empty() => Err(Error::setting(
            "--backend",
            format!(
                "model `{}` was built or changed in memory: generated code exists only for \
                 models compiled in with machine! as they are (built-in: {}); use --backend \
                 interpreted",
                model.name,
                washdyn_models::BUILT_IN.join(", ")
            ),
        )),
        (Backend::Generated, None) => Err(Error::setting(
            "--backend",
            format!(
                "`{}` is a model file: generated code exists only for models compiled in with \
                 machine! (built-in: {}); use --backend interpreted",
                source.spec,
                washdyn_models::BUILT_IN.join(", ")
            ),
        )),
    }
}
