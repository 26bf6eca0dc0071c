//! Why a UFF file is refused. Every variant names the file, the dataset (its 1-based index
//! among all the file's datasets and its number, `58` or `58b`) and, where one field is at
//! fault, its record and field as the format's documentation numbers them, so a user can find
//! the byte a rig's exporter got wrong.

use std::fmt;
use std::path::PathBuf;

/// A dataset's place in the file: its 1-based index among all datasets (skipped ones count)
/// and, once its number line was read, that number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DatasetAt {
    /// 1-based index among the file's datasets.
    pub index: usize,
    /// The dataset number (`58`, `58b`, `151`), if its line was read.
    pub number: Option<DatasetNumber>,
}

impl fmt::Display for DatasetAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.number {
            Some(n) => write!(f, "dataset {} ({n})", self.index),
            None => write!(f, "dataset {}", self.index),
        }
    }
}

/// A dataset number and whether its data are binary (`58b`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DatasetNumber {
    /// The number: 58 for a function at a nodal DOF.
    pub number: u32,
    /// Whether the number carries the `b` of a binary dataset.
    pub binary: bool,
}

impl fmt::Display for DatasetNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.number, if self.binary { "b" } else { "" })
    }
}

/// A record of dataset 58: the dataset's number line (which in 58b carries the binary layout),
/// the 11 header records, or the data (record 12).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Record {
    /// The line after the opening `-1`: `58`, or `58b` with byte order, format and sizes.
    NumberLine,
    /// Header record 1 to 11.
    Header(u8),
    /// Record 12, the ordinates.
    Data,
}

impl fmt::Display for Record {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Record::NumberLine => f.write_str("the dataset number line"),
            Record::Header(n) => write!(f, "record {n}"),
            Record::Data => f.write_str("record 12 (data)"),
        }
    }
}

/// One field of a record, as the format's documentation numbers and names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FieldAt {
    /// The record.
    pub record: Record,
    /// 1-based field number within the record.
    pub field: u8,
    /// The field's name in the format's documentation.
    pub name: &'static str,
}

impl fmt::Display for FieldAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}, field {} ({})", self.record, self.field, self.name)
    }
}

/// What is wrong with one header field's text.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldProblem {
    /// Absent (the line is too short or has too few values).
    Missing,
    /// Not an integer.
    NotAnInteger(String),
    /// Not a finite real number.
    NotANumber(String),
    /// A number outside what the field allows.
    OutOfRange {
        value: String,
        allowed: &'static str,
    },
}

impl fmt::Display for FieldProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FieldProblem::Missing => f.write_str("missing"),
            FieldProblem::NotAnInteger(v) => write!(f, "`{v}` is not an integer"),
            FieldProblem::NotANumber(v) => write!(f, "`{v}` is not a finite number"),
            FieldProblem::OutOfRange { value, allowed } => {
                write!(f, "{value} is not allowed ({allowed})")
            }
        }
    }
}

/// Why a dataset 58 is not a time history this reader can take.
#[derive(Debug, Clone, PartialEq)]
pub enum NotTimeHistory {
    /// Ordinate data type 5 or 6 (complex): spectra and FRFs, not signals.
    Complex { code: i64 },
    /// A function type of the frequency or statistics domain (record 6 field 1).
    Function { code: i64 },
    /// An abscissa of frequency, rpm or order (record 8 field 1).
    Abscissa { code: i64 },
    /// An abscissa unit that is not one of time.
    AbscissaUnit { label: String },
}

impl fmt::Display for NotTimeHistory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotTimeHistory::Complex { code } => {
                write!(f, "complex ordinates (data type {code})")
            }
            NotTimeHistory::Function { code } => write!(
                f,
                "function type {code} ({}), not 1 (time response) or 0 (general)",
                super::header::function_name(*code)
            ),
            NotTimeHistory::Abscissa { code } => write!(
                f,
                "abscissa data type {code} ({}), not 17 (time)",
                super::header::data_type_name(*code)
            ),
            NotTimeHistory::AbscissaUnit { label } => {
                write!(f, "abscissa unit `{label}` is not one of time (s, ms)")
            }
        }
    }
}

/// Where a dataset's delimiter is missing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The `-1` line that opens a dataset.
    Start,
    /// The `-1` line that closes it.
    End,
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Side::Start => "opening",
            Side::End => "closing",
        })
    }
}

/// Everything that refuses a UFF file.
#[derive(Debug, thiserror::Error)]
pub enum UffError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// A `-1` delimiter line is not where a dataset opens or closes.
    #[error(
        "{path}, {dataset}, line {line}: missing the {side} `    -1` delimiter line{}",
        found.as_ref().map_or(String::new(), |f| format!(" (found `{f}`)"))
    )]
    MissingDelimiter {
        path: PathBuf,
        dataset: DatasetAt,
        side: Side,
        line: usize,
        found: Option<String>,
    },

    /// The file ends inside a dataset: fewer header lines, values or bytes than announced.
    #[error("{path}, {dataset}, {record}: cut short, {found} of {expected} {what}")]
    CutShort {
        path: PathBuf,
        dataset: DatasetAt,
        record: Record,
        what: &'static str,
        expected: usize,
        found: usize,
    },

    /// A header field does not parse or is out of range.
    #[error("{path}, {dataset}, line {line}, {field}: {problem}")]
    Field {
        path: PathBuf,
        dataset: DatasetAt,
        line: usize,
        field: FieldAt,
        problem: FieldProblem,
    },

    /// A data value that is not a number.
    #[error("{path}, {dataset}, line {line}, record 12 (data): `{text}` is not a number")]
    BadValue {
        path: PathBuf,
        dataset: DatasetAt,
        line: usize,
        text: String,
    },

    /// The data hold another number of values than record 7 announces.
    #[error(
        "{path}, {dataset}, record 12 (data): {found} values, but record 7, field 2 (number of \
         points) announces {announced}"
    )]
    PointsMismatch {
        path: PathBuf,
        dataset: DatasetAt,
        announced: usize,
        found: usize,
    },

    /// A 58b's byte count disagrees with the points and precision of record 7.
    #[error(
        "{path}, {dataset}, the dataset number line, field 6 (number of bytes): {announced} \
         bytes, but record 7 announces {points} points of {width} bytes ({expected} bytes)"
    )]
    ByteCount {
        path: PathBuf,
        dataset: DatasetAt,
        announced: usize,
        points: usize,
        width: usize,
        expected: usize,
    },

    /// A 58b's byte order is neither 1 (little endian) nor 2 (big endian).
    #[error(
        "{path}, {dataset}, the dataset number line, field 3 (byte ordering): {value} is \
         neither 1 (little endian) nor 2 (big endian)"
    )]
    ByteOrder {
        path: PathBuf,
        dataset: DatasetAt,
        value: i64,
    },

    /// A 58b's floating-point format is not 2 (IEEE 754): DEC VMS (1) and IBM 370 (3) are not read.
    #[error(
        "{path}, {dataset}, the dataset number line, field 4 (floating point format): {value} \
         is not 2 (IEEE 754); DEC VMS (1) and IBM 5/370 (3) floats are not read"
    )]
    FloatFormat {
        path: PathBuf,
        dataset: DatasetAt,
        value: i64,
    },

    /// A sample is NaN or infinite.
    #[error("{path}, {dataset}, record 12 (data): sample {sample} (0-based) is {value}")]
    NotFinite {
        path: PathBuf,
        dataset: DatasetAt,
        sample: usize,
        value: f64,
    },

    /// A dataset 58 that holds something other than a real time history.
    #[error("{path}, {dataset}, {field}: not a time history: {reason}")]
    NotTimeHistory {
        path: PathBuf,
        dataset: DatasetAt,
        field: FieldAt,
        reason: NotTimeHistory,
    },

    /// Uneven abscissa spacing (samples with their own times), which the analysis cannot use.
    #[error(
        "{path}, {dataset}, {field}: uneven abscissa spacing (0); only evenly sampled time \
         histories (1) are read"
    )]
    UnevenAbscissa {
        path: PathBuf,
        dataset: DatasetAt,
        field: FieldAt,
    },

    /// A file without any dataset 58 or 58b ([`super::read`] only).
    #[error("{path}: no dataset 58 or 58b (time history){}", skipped_list(skipped))]
    NoTimeHistories {
        path: PathBuf,
        skipped: Vec<super::Skipped>,
    },
}

/// `; skipped: 151, 164` for the message of [`UffError::NoTimeHistories`].
fn skipped_list(skipped: &[super::Skipped]) -> String {
    if skipped.is_empty() {
        return " (no datasets at all)".into();
    }
    let numbers: Vec<String> = skipped.iter().map(|s| s.number.to_string()).collect();
    format!("; datasets found: {}", numbers.join(", "))
}
