//! Errors of the run-up analysis. Input errors carry the 1-based line number of
//! the file, so a user can open the CSV at the offending line.

use std::path::PathBuf;

/// Everything that can go wrong while reading signals, analysing or writing output.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// The file could not be opened or read.
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// The file has no header line (empty, or only comments).
    #[error("{path}: empty file, expected a header line starting with `time_s,drum_rpm`")]
    EmptyFile { path: PathBuf },

    /// The header is malformed: missing/misnamed time or speed column, empty or duplicate names.
    #[error("{path}, line {line}: {message}")]
    Header {
        path: PathBuf,
        line: usize,
        message: String,
    },

    /// A row has a different number of fields than the header.
    #[error("{path}, line {line}: expected {expected} fields (as in the header), found {found}")]
    RaggedRow {
        path: PathBuf,
        line: usize,
        expected: usize,
        found: usize,
    },

    /// A cell is not a finite number.
    #[error("{path}, line {line}, column `{column}`: cannot read `{value}` as a finite number")]
    NotANumber {
        path: PathBuf,
        line: usize,
        column: String,
        value: String,
    },

    /// Time does not increase strictly from one row to the next.
    #[error(
        "{path}, line {line}: time {time} s does not increase (previous row: {previous} s); \
         time_s must be strictly increasing"
    )]
    TimeNotIncreasing {
        path: PathBuf,
        line: usize,
        time: f64,
        previous: f64,
    },

    /// A time step differs from the median step by more than the tolerance (dropped or jittered samples).
    #[error(
        "{path}, line {line}: time step {step} s differs from the typical (median) step \
         {typical_step} s by more than {tolerance_percent} %; the analysis needs uniformly \
         sampled time"
    )]
    TimeNotUniform {
        path: PathBuf,
        line: usize,
        step: f64,
        typical_step: f64,
        tolerance_percent: f64,
    },

    /// Not enough rows to define a sample rate or to fill one analysis block.
    #[error("{context}: too few samples: {found}, need at least {needed}")]
    TooFewSamples {
        context: String,
        found: usize,
        needed: usize,
    },

    /// In-memory signals are inconsistent (lengths, sample rate, names).
    #[error("invalid signals: {0}")]
    InvalidSignals(String),

    /// Options outside their valid range.
    #[error("invalid analysis option: {0}")]
    InvalidOptions(String),

    /// A variant study's input is inconsistent (bounds, design size, outputs against the layout).
    #[error("invalid study: {0}")]
    InvalidStudy(String),

    /// Writing an output file failed.
    #[error("cannot write {path}: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// plotters failed to draw or encode a plot.
    #[error("cannot draw {path}: {message}")]
    Plot { path: PathBuf, message: String },
}
