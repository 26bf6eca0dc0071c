//! Why `washdyn fields` cannot recover a run's fields: its summary, model and states, the
//! instants asked for, the field files, what it writes. Here with the crate's errors so that
//! the error enum reaches no module above it.

use super::vtk::VtkError;
use super::{Error, FileError, PlotError};
use std::path::PathBuf;
use washdyn_ode::Rounded;

#[derive(Debug, thiserror::Error)]
pub enum FieldsError {
    /// The run directory has no readable summary.json.
    #[error("{}/summary.json: {source}", dir.display())]
    NoSummary {
        dir: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// summary.json is no JSON.
    #[error("summary.json: {0}")]
    Summary(#[source] serde_json::Error),
    /// summary.json lacks a key the recovery needs (`model`, `scene`).
    #[error("summary.json: no {0}")]
    SummaryKey(&'static str),
    /// summary.json's `model_files` is not a list of hashed files.
    #[error("summary.json: model_files: {0}")]
    ModelFiles(#[source] serde_json::Error),
    /// A file of the run's model changed since the run (the model crate's message).
    #[error("{message}: the run's model differs now (give it with --model to recover anyway)")]
    ModelChanged { message: String },
    /// The model cannot be resolved.
    #[error(transparent)]
    Model(Box<Error>),
    /// The summary's scene is not one of the model's (the model's message).
    #[error("{0}")]
    Scene(String),
    /// The run kept no states (or unreadable ones): how to get them.
    #[error("{source} (run with --states to keep the states for field recovery)")]
    NoStates {
        #[source]
        source: Box<FieldsError>,
    },
    /// The states are another run's than the summary's.
    #[error(transparent)]
    OtherRun(#[from] super::OtherRun),
    /// The states file cannot be read as Parquet (the reader's message).
    #[error("{message}")]
    StatesFile { message: String },
    /// A Parquet file without the states' columns.
    #[error("{}: not a states file (time_s, drum_angle_rad, q...)", path.display())]
    NotStates { path: PathBuf },
    /// An instant outside the stored states (a NaN one too).
    #[error(
        "t = {t} s is outside the stored states ({} to {} s)",
        Rounded(*first),
        Rounded(*last)
    )]
    Outside { t: f64, first: f64, last: f64 },
    /// The instants of `option` outside the stored states, every one.
    #[error("{option}: {}", outside.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "))]
    Instants {
        option: &'static str,
        outside: Vec<FieldsError>,
    },
    /// More instants than one call writes (`fields::MAX_FRAMES`).
    #[error("{option}: {count} instants, more than {max}")]
    TooMany {
        option: &'static str,
        count: usize,
        max: usize,
    },
    /// A `--range` that is empty, backwards or not finite.
    #[error("--range {from}:{to}:{step}: need from <= to and step > 0, all finite")]
    Range { from: f64, to: f64, step: f64 },
    /// A `--range` of more instants than one call writes.
    #[error("--range {from}:{to}:{step}: {count:e} instants, more than {max}")]
    RangeTooLong {
        from: f64,
        to: f64,
        step: f64,
        count: f64,
        max: usize,
    },
    /// `--revolution` from a time less than a turn before the run's end.
    #[error("the run ends before one revolution from t = {t} s")]
    Revolution { t: f64 },
    /// States of another scene.
    #[error("the states have {states} coordinates, the scene {scene}: another scene's run?")]
    Coordinates { states: usize, scene: usize },
    /// A field file that cannot be read or does not fit its modal data.
    #[error(transparent)]
    Fe(Box<washdyn_fe::Error>),
    /// No body of the scene has a field file.
    #[error(
        "no field files (<body>.field.bin) in {}: `washdyn fe modal` writes them there \
         (with CalculiX)",
        dir.display()
    )]
    NoFieldFiles { dir: PathBuf },
    /// Field files there, but none of a body the run's scene moves (the cabinet is rigid and
    /// fixed outside the elastic scenes): which files, and the scenes that keep one elastic.
    #[error(
        "{} holds {}, but in the run's scene `{scene}` none of these bodies is elastic or moves \
         (rigid on the fixed frame): no deformation to recover; {}",
        dir.display(),
        files.join(", "),
        elastic_advice(elastic_scenes)
    )]
    NoMovingBody {
        dir: PathBuf,
        scene: String,
        /// The `<body>.field.bin` files found.
        files: Vec<String>,
        /// The model's scenes that keep one of their bodies elastic.
        elastic_scenes: Vec<String>,
    },
    /// `--drum-edge` without the drum's field.
    #[error("no drum field")]
    NoDrumField,
    /// `--drum-edge` in a scene whose drum is rigid.
    #[error("the drum is rigid in this scene: no deformation to show")]
    RigidDrum,
    /// A file or directory that cannot be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A plot that cannot be drawn or written.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A VTK grid or collection that cannot be written.
    #[error(transparent)]
    Vtk(#[from] VtkError),
}

/// What to run instead, for [`FieldsError::NoMovingBody`].
fn elastic_advice(scenes: &[String]) -> String {
    if scenes.is_empty() {
        "this model has no scene that keeps them elastic".into()
    } else {
        format!(
            "run a scene that keeps them elastic ({}) with --states and recover that run's fields",
            scenes.join(", ")
        )
    }
}

impl From<Error> for FieldsError {
    fn from(e: Error) -> FieldsError {
        FieldsError::Model(Box::new(e))
    }
}

/// Boxed: washdyn-fe's error is large, and `washdyn::Error` carries this one.
impl From<washdyn_fe::Error> for FieldsError {
    fn from(e: washdyn_fe::Error) -> FieldsError {
        FieldsError::Fe(Box::new(e))
    }
}
