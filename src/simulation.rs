//! One simulation set-up for `run`, `sweep`, `study` and `accuracy` (and the tests that run
//! what they run) from a [`RunSpec`] as it is: the model and where it came from, the scene, the
//! back end, the method and its [`Options`], the window, the [`Guard`] (the caller's bounds and
//! flags, plus rk4's stability check, the force elements' tub ends and the clearance watch) and
//! the summary's labels. [`Simulation::new`] checks every setting before anything is written
//! (`RunSpec::validate`, the scene, the back end, a periodic start's constant speed);
//! [`Simulation::integrate`] runs it into a sink and completes the summary (model files,
//! rho_inf).

use crate::error::Error;
pub use crate::spec::Backend;
use crate::spec::{Context, Field, RunSpec};
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

/// What a run watches and labels beyond its [`RunSpec`]: facts of the caller, not settings.
#[derive(Clone, Debug, Default)]
pub struct RunControl {
    /// The caller's bounds and flags (stop factor, interrupt, stall window); the
    /// specification sets the validity stop and the progress budget, the set-up adds rk4's
    /// fixed step, the force elements' tub ends and the clearance watch.
    pub guard: Guard,
    /// Band of an analysis after the run, Hz (the sample rate must resolve it).
    pub analysis_band_hz: Option<f64>,
    /// A sweep's or study's variant: the summary's model label becomes `<model>/<variant>`.
    pub variant: Option<String>,
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
    pub fn new(source: Source, spec: &RunSpec, ctl: &RunControl) -> Result<Simulation, Error> {
        let scene = source
            .model
            .scene(spec.scene.as_deref())
            .map_err(|m| Error::setting(Field::Scene, m))?;
        Simulation::with_scene(source, scene, spec, ctl)
    }

    /// With a resolved scene (the accuracy study's changed mode cut-offs): the back end, the
    /// specification's rules (`RunSpec::validate`, every violation at once), a periodic start's
    /// constant speed; then the options, guard, labels and warnings.
    pub fn with_scene(
        source: Source,
        scene: EffectSet,
        spec: &RunSpec,
        ctl: &RunControl,
    ) -> Result<Simulation, Error> {
        let backend = spec.backend.unwrap_or(if source.built_in.is_some() {
            Backend::Generated
        } else {
            Backend::Interpreted
        });
        let mech = mechanical(&source, &scene, backend)?;
        let (method, tol) = spec.solver(&source.model);
        let cx = Context {
            method,
            tol,
            profile_end: mech.speed().end(),
            channels: Some(mech.channel_names().len()),
            analysis_band_hz: ctl.analysis_band_hz,
        };
        spec.validate(&cx).map_err(Error::Settings)?;
        if spec.start == Start::Periodic {
            washdyn_runtime::periodic::period(mech.speed(), spec.t_start)
                .map_err(|m| Error::setting(Field::Start, m))?;
        }
        let options = spec.options(method, tol);
        let model = &source.model;
        let eq = Equations::new(model, &scene);
        let guard = Guard {
            fixed_step: (method == Method::Rk4).then_some(options.h0),
            elements: element_tub_ends(model, &eq),
            watch: Watch::new(model, &eq),
            ..spec.guard(&ctl.guard)
        };
        let labels = Labels {
            model: match &ctl.variant {
                Some(v) => format!("{}/{v}", model.name),
                None => model.name.clone(),
            },
            scene: scene.name.clone(),
            backend: backend.name().into(),
        };
        let run = RunOptions {
            t_start: spec.t_start,
            t_end: spec.end(&cx),
            sample_rate: spec.sample_rate,
            start: spec.start,
        };
        Ok(Simulation {
            source,
            scene,
            backend,
            method,
            options,
            rho_inf: spec.rho_inf,
            run,
            guard,
            labels,
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

    /// The model files and rho_inf a summary of this simulation records.
    fn label(&self, s: &mut Summary) {
        s.model_files = self.source.files.clone();
        s.start = Some(self.run.start.name().to_string());
        s.sample_rate_hz = Some(self.run.sample_rate);
        if self.method == Method::GeneralizedAlpha {
            s.rho_inf = Some(self.options.rho_inf);
        }
    }

    /// Integrates into `sink`: the summary, and the error when the run failed (the summary says
    /// so too; what the sink received is kept). What the committed accuracy study says of the
    /// setting is the caller's to add (`error_class::Verdict`).
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
        (summary, error)
    }
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
                    Field::Backend,
                    format!(
                        "scene `{}` was changed in memory: generated code exists for the \
                         scenes as declared; use --backend interpreted",
                        scene.name
                    ),
                ));
            }
            washdyn_models::generated(name, &scene.name).ok_or_else(|| {
                Error::setting(
                    Field::Backend,
                    format!("no generated code for scene `{}`", scene.name),
                )
            })
        }
        (Backend::Generated, None) if source.generated_base.is_some() => {
            let name = source.generated_base.as_deref().unwrap_or_default();
            match washdyn_models::generated_for(name, &scene.name, model) {
                Some(Ok(m)) if model.scene(Some(&scene.name)).ok().as_ref() == Some(scene) => Ok(m),
                Some(Ok(_)) => Err(Error::setting(
                    Field::Backend,
                    format!(
                        "scene `{}` was changed in memory: generated code exists for the \
                         scenes as declared; use --backend interpreted",
                        scene.name
                    ),
                )),
                Some(Err(why)) => Err(Error::setting(Field::Backend, why)),
                None => Err(Error::setting(
                    Field::Backend,
                    format!("no generated code for scene `{}`", scene.name),
                )),
            }
        }
        (Backend::Generated, None) if source.files.is_empty() => Err(Error::setting(
            Field::Backend,
            format!(
                "model `{}` was built or changed in memory: generated code exists only for \
                 models compiled in with machine! as they are (built-in: {}); use --backend \
                 interpreted",
                model.name,
                washdyn_models::BUILT_IN.join(", ")
            ),
        )),
        (Backend::Generated, None) => Err(Error::setting(
            Field::Backend,
            format!(
                "`{}` is a model file: generated code exists only for models compiled in with \
                 machine! (built-in: {}); use --backend interpreted",
                source.spec,
                washdyn_models::BUILT_IN.join(", ")
            ),
        )),
    }
}
