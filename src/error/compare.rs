//! Why two runs cannot be compared (`washdyn compare`), with the crate's errors so that the
//! error enum reaches no module above it.

use crate::analysis::AnalysisError;
use std::path::PathBuf;
use washdyn_ode::Rounded;

/// Why two runs cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// The run directory does not exist.
    #[error("{dir}: no such run directory")]
    NoRun { dir: PathBuf },
    /// The sensor file is another run's than the summary's.
    #[error(transparent)]
    OtherRun(#[from] super::OtherRun),
    /// No sensor file in the run directory.
    #[error(
        "{dir}: no sensors.parquet or sensors.csv; a run directory is what `washdyn run` writes"
    )]
    NoSensors { dir: PathBuf },
    /// summary.json missing or unreadable.
    #[error("{path}: {message}")]
    Summary { path: PathBuf, message: String },
    /// The sensor file could not be read.
    #[error(transparent)]
    Read(#[from] AnalysisError),
    /// The measurement's mapping file, or the files it names, refused.
    #[error(transparent)]
    Measured(Box<crate::measured::MeasuredError>),
    /// A UFF file given alone: which channel is which sensor, and where the speed comes from,
    /// is a mapping file's to say.
    #[error(
        "{}: a UFF file is compared through a mapping file that names its sensors and its speed \
         channel (measurement.toml; docs/validation.md, \"Measured data in\")",
        path.display()
    )]
    UffWithoutMapping { path: PathBuf },
    /// The runs do not record the same channels.
    #[error(
        "{a} and {b} record different channels: only in the first: [{}], only in the second: [{}]",
        only_a.join(", "),
        only_b.join(", ")
    )]
    Channels {
        a: PathBuf,
        b: PathBuf,
        only_a: Vec<String>,
        only_b: Vec<String>,
    },
    /// The runs are sampled at different rates.
    #[error("{a} is sampled at {rate_a} Hz, {b} at {rate_b} Hz")]
    SampleRate {
        a: PathBuf,
        b: PathBuf,
        rate_a: f64,
        rate_b: f64,
    },
    /// The runs' drum speeds differ (length, start or values).
    #[error("{a} and {b} do not follow the same speed profile: {detail}")]
    Profile {
        a: PathBuf,
        b: PathBuf,
        detail: String,
    },
    /// A run that did not finish (summary status `failed` or `interrupted`), compared whole:
    /// its status, error and the end of its output, which `--until` may compare up to.
    #[error(
        "{dir}: the run did not finish (status {status}{}); its output ends at {} s: compare \
         up to there with --until {}",
        error.as_ref().map_or(String::new(), |e| format!(": {e}")),
        Rounded(*last),
        Rounded(*last)
    )]
    Unfinished {
        dir: PathBuf,
        status: String,
        error: Option<String>,
        /// Time of its last sample, s.
        last: f64,
    },
    /// `--until` outside a run's span.
    #[error(
        "{dir} runs from {} to {} s; --until {until} s is not inside it",
        Rounded(span[0]),
        Rounded(span[1])
    )]
    Until {
        dir: PathBuf,
        until: f64,
        span: [f64; 2],
    },
    /// Over speed: the two runs' order-1 tracks share no speed (the common grid is empty).
    #[error(
        "{a} resolves order 1 from {} to {} rpm, {b} from {} to {} rpm: no common speed to \
         compare over",
        Rounded(span_a[0]),
        Rounded(span_a[1]),
        Rounded(span_b[0]),
        Rounded(span_b[1])
    )]
    NoCommonSpeed {
        a: PathBuf,
        b: PathBuf,
        span_a: [f64; 2],
        span_b: [f64; 2],
    },
    /// Over speed: the edges of the speed ranges are not positive, finite and increasing.
    #[error("--speed-ranges must be positive, finite, increasing rpm, got {edges:?}")]
    SpeedRanges { edges: Vec<f64> },
    /// An output file could not be written.
    #[error("cannot write {path}: {message}")]
    Write { path: PathBuf, message: String },
}
