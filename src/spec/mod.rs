//! One run specification for every command that runs the machine: [`RunSpec`] is `washdyn
//! run`'s and `sweep`'s arguments (clap) and a study file's `[run]` table (serde) from the same
//! fields, checked by one [`RunSpec::validate`] whose refusals name a typed [`Field`] (the
//! command line prints its option, a study file its key). `Simulation::new` takes it as it is;
//! `accuracy`, the hard cases and the benches build it with struct update syntax.

mod field;
mod rules;

pub use field::{Field, Refusal, Spelling, Subject};
pub use rules::{Context, MAX_OUTPUT_BYTES, RK4_STEP, SAMPLE_RATE, T_END_MAX, TOL};

use crate::results::Format;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use washdyn_model::ir::Model;
use washdyn_ode::{Method, Options};
use washdyn_runtime::run::{Guard, Start};

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

/// What a run is asked to do. [`Default`] is `washdyn run`'s defaults; a field a study file
/// does not take is `serde(skip)` (the model and scene sit at the file's top, the back end is
/// the study's choice per variant, the study writes Parquet), one `washdyn run` does not take
/// is `arg(skip)` (the window's start: the study's and the accuracy study's).
#[derive(Clone, Debug, clap::Args, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// A built-in model (`reference`, `compact`) or a model file (.toml).
    #[arg(value_name = "MODEL")]
    #[serde(skip)]
    pub model: String,
    /// A scene of the model (default: its first scene).
    #[arg(long)]
    #[serde(skip)]
    pub scene: Option<String>,
    /// generated (default for built-in models) or interpreted (default for model files and
    /// variants).
    #[arg(long)]
    #[serde(skip)]
    pub backend: Option<Backend>,
    /// rk4 (fixed step), dopri5 (adaptive, explicit), sdirk4 (L-stable SDIRK), rodas4
    /// (L-stable Rosenbrock), galpha (generalized-alpha on the second-order equations), imex
    /// (the modal bodies' own terms implicit, the elements explicit: ARK4(3)6L[2]SA), auto
    /// (dopri5 while not stiff, rodas4 while stiff, switching both ways). Default: the scene's
    /// own (`washdyn check` lists them; the reference's `damper_mass`: galpha), else dopri5.
    #[arg(long = "integrator", value_name = "INTEGRATOR")]
    #[serde(
        default,
        deserialize_with = "parsed_opt",
        serialize_with = "method_name",
        skip_serializing_if = "Option::is_none"
    )]
    pub method: Option<Method>,
    /// Relative tolerance of the adaptive integrators (absolute: 1e-3 x this, in m, m/s and
    /// rad; a modal coordinate in the metres it moves a marker by). 1e-2 or looser warns: no
    /// error class covers it. Default: the scene's own with its method, else 1e-6.
    #[arg(long, allow_hyphen_values = true)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
    /// Fixed step of rk4, s (default 1e-4).
    #[arg(long, allow_hyphen_values = true)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// galpha's spectral radius at infinity, in [0, 1] (default 0.8): 1 keeps the
    /// unresolved high modes undamped, 0 removes them in one step.
    #[arg(long, allow_hyphen_values = true)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    /// Step budget; the run stops with an error (keeping its output) when it is spent.
    #[arg(long, allow_hyphen_values = true)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
    /// Start of the window, s.
    #[arg(skip)]
    #[serde(default)]
    pub t_start: f64,
    /// A drum speed table run instead of the model's: CSV `time_s,drum_rpm` (header optional),
    /// as `sweep --profiles` reads; `washdyn analyse --speed-table` writes a measured run-up's.
    #[arg(long, value_name = "FILE")]
    #[serde(skip)]
    pub speed: Option<std::path::PathBuf>,
    /// End time, s (default: the end of the speed profile).
    #[arg(long, allow_hyphen_values = true)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_end: Option<f64>,
    /// Sampling rate of the sensor file, Hz.
    #[arg(long, default_value_t = 2000.0, allow_hyphen_values = true)]
    #[serde(default = "default_sample_rate")]
    pub sample_rate: f64,
    /// Format of the result files: parquet (columnar, compact) or csv.
    #[arg(long, default_value = "parquet")]
    #[serde(skip)]
    pub format: Format,
    /// How the run starts: `static` (equilibrium under every load at t = 0, a rotating
    /// unbalance's centrifugal force included as if it stood still), `mean` (at rest
    /// under gravity and the mean loads at the start speed) or `periodic` (on the
    /// periodic steady state by shooting; constant speed only).
    #[arg(long, default_value = "static")]
    #[serde(
        default = "static_start",
        deserialize_with = "parsed",
        serialize_with = "start_name"
    )]
    pub start: Start,
    /// Keep running when the tub motion exceeds 5 x the small-motion bounds (30 mm, 0.05 rad).
    #[arg(long = "no-validity-stop", action = clap::ArgAction::SetFalse)]
    #[serde(default = "yes")]
    pub validity_stop: bool,
    /// The progress guard: a run whose recent rate projects the rest of it beyond this many
    /// seconds of wall time stops (keeping its output). Raise it for a run meant to take hours.
    /// `inf` never stops.
    #[arg(long, default_value_t = Guard::default().max_projected_s, allow_hyphen_values = true)]
    #[serde(default = "default_max_projected_wall")]
    pub max_projected_wall: f64,
    /// Write sensor output beyond the 2 GB limit.
    #[arg(long)]
    #[serde(default)]
    pub allow_large_output: bool,
    /// Output directory (default: out/<model name>; a sweep's: out/<model>-sweep).
    #[arg(long)]
    #[serde(skip)]
    pub out: Option<std::path::PathBuf>,
    /// Also write the energy balance by category (DIR/energy.parquet and energy.png): the
    /// drive's work, gravity, each body's modal strain and damping, each element's stored
    /// and dissipated energy, and the kinetic energy, every 10 ms.
    #[arg(long)]
    #[serde(skip)]
    pub energy: bool,
    /// Also write the state at every sample (drum angle, q) to DIR/states.parquet, for
    /// `washdyn fields`.
    #[arg(long)]
    #[serde(skip)]
    pub states: bool,
    /// Replace the output folder where it holds another run's files (refused without).
    #[arg(long)]
    #[serde(skip)]
    pub force: bool,
}

fn default_sample_rate() -> f64 {
    2000.0
}

fn default_max_projected_wall() -> f64 {
    Guard::default().max_projected_s
}

fn static_start() -> Start {
    Start::Static
}

fn yes() -> bool {
    true
}

/// A value a study file writes as its command-line word (`method = "rodas4"`).
fn parsed<'de, D, T>(d: D) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: std::str::FromStr<Err: std::fmt::Display>,
{
    let s = String::deserialize(d)?;
    s.parse().map_err(serde::de::Error::custom)
}

/// A study file's `method` as its command-line word (`RunSpec` written as a sweep's study).
fn method_name<S: Serializer>(m: &Option<Method>, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(m.map_or("", Method::name))
}

fn start_name<S: Serializer>(start: &Start, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(start.name())
}

fn parsed_opt<'de, D, T>(d: D) -> Result<Option<T>, D::Error>
where
    D: Deserializer<'de>,
    T: std::str::FromStr<Err: std::fmt::Display>,
{
    parsed(d).map(Some)
}

impl Default for RunSpec {
    fn default() -> Self {
        RunSpec {
            model: String::new(),
            scene: None,
            backend: None,
            method: None,
            tol: None,
            step: None,
            rho_inf: None,
            max_steps: None,
            t_start: 0.0,
            speed: None,
            t_end: None,
            sample_rate: default_sample_rate(),
            format: Format::Parquet,
            start: Start::Static,
            validity_stop: true,
            max_projected_wall: default_max_projected_wall(),
            allow_large_output: false,
            out: None,
            energy: false,
            states: false,
            force: false,
        }
    }
}

/// The method of a run that names none and whose scene names none.
pub const DEFAULT_METHOD: Method = Method::Dopri5;
/// The relative tolerance of a run that names none and whose scene names none for its method.
pub const DEFAULT_TOL: f64 = 1e-6;

impl RunSpec {
    /// `model` with every other field at its default.
    pub fn of(model: impl Into<String>) -> RunSpec {
        RunSpec {
            model: model.into(),
            ..RunSpec::default()
        }
    }

    /// The method and relative tolerance on `model`: the specification's, else the scene's
    /// default (`Model::scene_solver`: its tolerance only with its own method), else
    /// [`DEFAULT_METHOD`] at [`DEFAULT_TOL`].
    pub fn solver(&self, model: &Model) -> (Method, f64) {
        let own = model
            .scene_solver(self.scene.as_deref())
            .map(|s| (washdyn_runtime::run::method_of(s.method), s.tol));
        let method = self.method.or(own.map(|o| o.0)).unwrap_or(DEFAULT_METHOD);
        let tol = self
            .tol
            .or(own.filter(|o| o.0 == method).map(|o| o.1))
            .unwrap_or(DEFAULT_TOL);
        (method, tol)
    }

    /// The integrator's options for `method` at `tol`: absolute tolerance 1e-3 x `tol` (m,
    /// rad), rk4's fixed step (default 1e-4 s), the step budget, galpha's rho_inf.
    pub fn options(&self, method: Method, tol: f64) -> Options {
        let mut o = Options {
            rtol: tol,
            atol: tol * 1e-3,
            h0: match method {
                Method::Rk4 => self.step.unwrap_or(1e-4),
                _ => self.step.unwrap_or(0.0),
            },
            max_steps: self.max_steps.unwrap_or(Options::default().max_steps),
            ..Options::default()
        };
        if let Some(r) = self.rho_inf {
            o.rho_inf = r;
        }
        o
    }

    /// The run's guard: `base` (the caller's bounds and interrupt flag) with the validity stop
    /// off when the specification says so and its progress budget.
    pub fn guard(&self, base: &Guard) -> Guard {
        Guard {
            stop_factor: base.stop_factor.filter(|_| self.validity_stop),
            max_projected_s: self.max_projected_wall,
            ..base.clone()
        }
    }
}
