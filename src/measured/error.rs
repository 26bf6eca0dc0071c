//! Why a measurement is refused. A mapping file's problem names the file, its line and the
//! field (`channel[1].measured`); a measured file's names the file and the dataset (UFF) or
//! column (CSV/Parquet) and the field, so the user can open either at the fault.

use std::fmt;
use std::path::PathBuf;
use washdyn_analysis::AnalysisError;
use washdyn_analysis::tacho::TachoError;
use washdyn_analysis::uff58::UffError;

/// Where a measured channel came from: its file and its dataset or column.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelAt {
    pub file: PathBuf,
    /// `dataset 3 (58b)` for UFF, `column 4` for CSV/Parquet.
    pub place: String,
    /// The channel's name in its file.
    pub name: String,
}

impl fmt::Display for ChannelAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}, {} `{}`", self.file.display(), self.place, self.name)
    }
}

/// A refused entry of the mapping (or of `washdyn analyse`'s options standing for one).
#[derive(Debug, Clone, PartialEq)]
pub struct MappingAt {
    /// The mapping file, or `the command line`.
    pub file: String,
    /// 1-based line of the field; 0 on the command line.
    pub line: usize,
    /// The field as the file spells it (`channel[0].sensor`), or the option (`--tacho`).
    pub field: String,
}

impl fmt::Display for MappingAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            0 => write!(f, "{}: {}", self.file, self.field),
            l => write!(f, "{}:{l}: {}", self.file, self.field),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum MeasuredError {
    /// The mapping file cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A mapping entry refused at its line and field.
    #[error("{at}: {message}")]
    Mapping { at: MappingAt, message: String },
    /// A UFF file refused (the reader names the dataset, record and field).
    #[error(transparent)]
    Uff(#[from] UffError),
    /// A CSV or Parquet measurement refused (the reader names the line and column).
    #[error(transparent)]
    Signals(#[from] AnalysisError),
    /// Two channels that do not share a time base: resampling is out of scope, so the rig
    /// must export them at one rate, length and start.
    #[error(
        "{first} and {second} differ in {what} ({a} against {b}): the channels must share \
         one time base (resampling is not done; export them at one rate from the rig)"
    )]
    TimeBase {
        what: &'static str,
        first: Box<ChannelAt>,
        second: Box<ChannelAt>,
        a: String,
        b: String,
    },
    /// The tacho channel gives no speed.
    #[error("{channel}: {source}")]
    Tacho {
        channel: Box<ChannelAt>,
        #[source]
        source: TachoError,
    },
    /// A speed channel that is not in rpm (1/s after conversion).
    #[error("{channel}: the speed channel's unit is `{unit}`, not a rotational speed (rpm, 1/s)")]
    NotASpeed {
        channel: Box<ChannelAt>,
        unit: String,
    },
    /// The speed table could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl MeasuredError {
    /// A mapping refusal.
    pub fn at(at: &MappingAt, message: impl Into<String>) -> MeasuredError {
        MeasuredError::Mapping {
            at: at.clone(),
            message: message.into(),
        }
    }
}
