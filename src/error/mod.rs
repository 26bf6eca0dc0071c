//! The errors of the commands above the runtime (`washdyn::Error`), one enum: what was refused
//! or failed, with the option, file, field or time it concerns. `washdyn`'s exit code is a
//! function of the variant (`src/main.rs`, `exit_code`; docs/commands.md).

pub use crate::spec::Refusal;
pub mod campbell;
pub mod compare;
pub mod fe;
pub mod fields;
pub mod modes;
pub mod slurm;
pub mod study;
pub mod vtk;

use crate::spec::{Field, Subject};
use std::fmt;
use std::path::PathBuf;
use washdyn_model::ir::check::CheckError;
use washdyn_model::ir::toml_file::ModelFileError;
use washdyn_runtime::run::RunError;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Settings refused before anything was written; every violation found, one a line.
    #[error("{}", join(.0))]
    Settings(Vec<Refusal>),
    /// A model text that does not load or fails the checker: each problem with its file, line
    /// and column (the field in its message).
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// A model in memory (a sweep's variant) that fails the checker: each problem at its field.
    #[error("model check: {}", errors.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "))]
    Check {
        model: String,
        errors: Vec<CheckError>,
    },
    /// A model that loads but whose scenes cannot run (`washdyn check`: no static equilibrium,
    /// a rest position beyond the small-motion bounds).
    #[error("{model}: {}", problems.join("\n"))]
    Scene {
        model: String,
        problems: Vec<String>,
    },
    /// Neither a built-in model nor a model file.
    #[error(
        "`{spec}` is neither a built-in model ({}) nor a model file",
        washdyn_models::BUILT_IN.join(", ")
    )]
    UnknownModel { spec: String },
    /// A file or directory the command writes or reads could not be.
    #[error(transparent)]
    Io(ActionError),
    /// A file named by the model or a run that cannot be read or hashed (the message names it).
    #[error("{message}")]
    File { message: String },
    /// The integration stopped at `t` (the output up to then is kept).
    #[error("{source}")]
    Integration {
        t: f64,
        #[source]
        source: RunError,
    },
    /// A signal file the analysis cannot read or analyse.
    #[error(transparent)]
    Analysis(#[from] crate::analysis::AnalysisError),
    /// A measurement refused: its mapping file at a line and field, a measured file at its
    /// dataset or column.
    #[error(transparent)]
    Measured(Box<crate::measured::MeasuredError>),
    /// Two runs that cannot be compared.
    #[error(transparent)]
    Compare(#[from] compare::CompareError),
    /// A study refused: its file (at its lines), variants the checker refuses, its directory.
    #[error(transparent)]
    Study(#[from] study::StudyError),
    /// `washdyn fields`: the run, its states, the instants asked for, the field files.
    #[error(transparent)]
    Fields(#[from] fields::FieldsError),
    /// `washdyn campbell`: its source, its speeds, the diagram.
    #[error(transparent)]
    Campbell(#[from] campbell::CampbellError),
    /// `washdyn modes`: the model, the scene, the rest position.
    #[error(transparent)]
    Modes(#[from] modes::ModesError),
    /// `washdyn fe solve | write | modal | deck`.
    #[error(transparent)]
    Fe(#[from] fe::FeError),
    /// `washdyn fe reference`: the full-mesh study.
    #[error(transparent)]
    FullMesh(#[from] fe::FullMeshError),
    /// The accuracy study's reference run did not finish: no method can be measured
    /// against it.
    #[error("reference run failed: {0}")]
    Reference(Box<Error>),
    /// A plot the accuracy study could not draw or write (plotters' message).
    #[error("{}: {message}", path.display())]
    Plot { path: PathBuf, message: String },
    /// A run's file that another run wrote.
    #[error(transparent)]
    OtherRun(#[from] OtherRun),
    /// The threads of a sweep's or study's parallel runs could not start.
    #[error("cannot start the parallel runs: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
}

impl From<crate::measured::MeasuredError> for Error {
    /// Boxed: a refusal names two channels, more than the other variants carry.
    fn from(e: crate::measured::MeasuredError) -> Error {
        Error::Measured(Box::new(e))
    }
}

/// What a command could not do to a file or directory: `cannot {action} {path}: {source}`
/// (`washdyn::Error::Io`, and `modes`' table).
#[derive(Debug, thiserror::Error)]
#[error("cannot {action} {}: {source}", path.display())]
pub struct ActionError {
    pub action: &'static str,
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

/// A run's file that another run wrote: its id and its folder's summary.json's differ
/// (`run_dir::check_same_run`).
#[derive(Debug, thiserror::Error)]
#[error(
    "{} belongs to the run {file_id}, but {} to the run {summary_id}: the folder mixes two \
     runs; run again into a fresh folder",
    file.display(),
    summary.display()
)]
pub struct OtherRun {
    pub file: PathBuf,
    pub file_id: String,
    pub summary: PathBuf,
    pub summary_id: String,
}

/// A file or directory a command could not read or write: `path: the system's message`.
/// One type for every command's enum (`Io(#[from] FileError)`).
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct FileError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

impl FileError {
    /// The error of an I/O call on `path`, for `map_err`.
    pub fn at<E: From<FileError>>(path: &std::path::Path) -> impl FnOnce(std::io::Error) -> E {
        let path = path.to_path_buf();
        move |source| E::from(FileError { path, source })
    }
}

/// A plot that could not be drawn or written: `path: plotters' message`.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct PlotError {
    pub path: PathBuf,
    #[source]
    pub source: Box<dyn std::error::Error + Send + Sync>,
}

impl PlotError {
    /// The error of drawing or writing the plot at `path`, for `map_err`.
    pub fn at<E: From<PlotError>>(
        path: &std::path::Path,
    ) -> impl FnOnce(Box<dyn std::error::Error + Send + Sync>) -> E {
        let path = path.to_path_buf();
        move |source| E::from(PlotError { path, source })
    }
}

fn join<T: fmt::Display>(v: &[T]) -> String {
    v.iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

impl Error {
    /// One refused setting whose message names no other field.
    pub fn setting(subject: impl Into<Subject>, message: impl Into<String>) -> Error {
        Error::Settings(vec![Refusal::plain(subject, message)])
    }

    /// The options a [`Error::Settings`] refuses, as the command line spells them (empty for
    /// other errors).
    pub fn options(&self) -> Vec<&'static str> {
        match self {
            Error::Settings(r) => r.iter().map(|r| r.subject.option()).collect(),
            _ => Vec::new(),
        }
    }

    /// The specification's fields a [`Error::Settings`] refuses.
    pub fn fields(&self) -> Vec<Field> {
        match self {
            Error::Settings(r) => r.iter().filter_map(Refusal::field).collect(),
            _ => Vec::new(),
        }
    }

    /// A run's failure, with its time.
    pub fn integration(source: RunError) -> Error {
        Error::Integration {
            t: source.time(),
            source,
        }
    }

    /// An I/O failure on `path`.
    pub fn io(action: &'static str, path: impl Into<PathBuf>, source: std::io::Error) -> Error {
        Error::Io(ActionError {
            action,
            path: path.into(),
            source,
        })
    }
}
