//! Measured time histories from Universal File Format dataset 58 (ASCII) and 58b (binary
//! ordinates), as test rigs export them (Simcenter Testlab, HEAD, B&K, ME'scope, OROS).
//!
//! A file is a sequence of datasets, each between two `    -1` lines; every 58 or 58b is one
//! channel, others (151 header, 164 units, ...) are skipped and listed. A channel must be a real
//! time history: even abscissa in seconds (record 8 data type 17, or unknown/general with a time
//! unit), single or double precision, ASCII or binary in either byte order. Complex data, uneven
//! spacing and frequency-domain functions are refused, and so is every malformed file, naming
//! the dataset and the record and field at fault ([`UffError`]). Samples are converted to SI
//! by their unit label ([`units`]); an unknown unit is kept with a warning on the channel.
//! pyuff (PyPI) is the independent writer the tests read back; it is no dependency.
//!
//! Files: `header.rs` (records 1-11), `ascii.rs` (58 data), `binary.rs` (58b number line and
//! data), `units.rs` (labels to SI), `error.rs`.

mod ascii;
mod binary;
pub mod error;
mod header;
pub mod units;

#[cfg(test)]
mod tests;

use std::fmt;
use std::path::Path;

pub use error::{DatasetAt, DatasetNumber, FieldAt, Record, UffError};
pub use header::{AxisInfo, Precision};
pub use units::{SiUnit, UffWarning, UnitConversion};

use crate::signals::Quantity;
use error::Side;
use header::{Ctx, Header, Line};

/// A measurement direction (record 6 fields 7 and 10): 0 scalar, 1-3 +X +Y +Z translations,
/// 4-6 rotations about them, negative for the negative sense.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Direction(i8);

impl Direction {
    /// The direction of a code in -6..=6.
    pub fn new(code: i64) -> Option<Direction> {
        (-6..=6).contains(&code).then_some(Direction(code as i8))
    }

    /// The format's code.
    pub fn code(self) -> i8 {
        self.0
    }

    /// Whether no direction is given (a scalar point: tacho, microphone, voltage).
    pub fn is_scalar(self) -> bool {
        self.0 == 0
    }

    /// Whether it is a rotation (codes 4-6).
    pub fn is_rotation(self) -> bool {
        self.0.abs() > 3
    }

    /// The axis 0 (X), 1 (Y), 2 (Z); `None` for a scalar.
    pub fn axis(self) -> Option<usize> {
        (self.0 != 0).then(|| (self.0.unsigned_abs() as usize - 1) % 3)
    }
}

impl fmt::Display for Direction {
    /// `+X`, `-Z`, `+RY`; `scalar`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(axis) = self.axis() else {
            return f.write_str("scalar");
        };
        let sign = if self.0 < 0 { '-' } else { '+' };
        let r = if self.is_rotation() { "R" } else { "" };
        write!(f, "{sign}{r}{}", ['X', 'Y', 'Z'][axis])
    }
}

/// A degree of freedom of record 6: entity name, node and direction.
#[derive(Debug, Clone, PartialEq)]
pub struct Dof {
    /// Entity name (empty for `NONE`).
    pub entity: String,
    /// Node number.
    pub node: i64,
    /// Direction.
    pub direction: Direction,
}

impl fmt::Display for Dof {
    /// `101+Z`, `tub:101+Z`, `7` (scalar).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.entity.is_empty() {
            write!(f, "{}:", self.entity)?;
        }
        write!(f, "{}", self.node)?;
        if !self.direction.is_scalar() {
            write!(f, "{}", self.direction)?;
        }
        Ok(())
    }
}

/// How the ordinates were stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// Dataset 58: text.
    Ascii,
    /// Dataset 58b, little endian (byte ordering 1).
    BinaryLittleEndian,
    /// Dataset 58b, big endian (byte ordering 2).
    BinaryBigEndian,
}

/// One time history: a dataset 58 or 58b.
#[derive(Debug, Clone, PartialEq)]
pub struct Uff58Channel {
    /// ID line 1 with the response DOF: `tub front [101+Z]`; either alone where the other is
    /// absent (`NONE`, node 0).
    pub name: String,
    /// Records 1-5 as written (trailing blanks removed).
    pub id_lines: [String; 5],
    /// Record 6 field 1: 1 time response, 0 general.
    pub function_type: i64,
    /// Record 6 fields 5-7.
    pub response: Dof,
    /// Record 6 fields 8-10.
    pub reference: Dof,
    /// Record 9: the ordinate's data type, exponents and labels.
    pub ordinate: AxisInfo,
    /// Record 8: the abscissa's (time).
    pub abscissa: AxisInfo,
    /// How `samples` were brought to SI from the file's unit.
    pub unit: UnitConversion,
    /// Sample spacing, s (record 7 field 5).
    pub dt: f64,
    /// Time of the first sample, s (record 7 field 4).
    pub start_time: f64,
    /// The ordinates in SI units (`unit.si`), or as in the file where the unit is unknown.
    pub samples: Vec<f64>,
    /// Record 7 field 1.
    pub precision: Precision,
    /// ASCII or binary, and the byte order.
    pub encoding: Encoding,
    /// 1-based index of the dataset among all the file's datasets.
    pub dataset: usize,
    /// What a user should know (unknown unit, assumed unit): shown, never silent.
    pub warnings: Vec<UffWarning>,
}

impl Uff58Channel {
    /// Samples per second.
    pub fn sample_rate(&self) -> f64 {
        1.0 / self.dt
    }

    /// The analysis's quantity of the channel (acceleration, displacement, or unknown).
    pub fn quantity(&self) -> Quantity {
        match self.unit.si {
            Some(SiUnit::MetrePerSecondSquared) => Quantity::Acceleration,
            Some(SiUnit::Metre) => Quantity::Displacement,
            _ => Quantity::Unknown,
        }
    }
}

/// A dataset other than 58 that the reader passed over.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Skipped {
    /// 1-based index among the file's datasets.
    pub index: usize,
    /// Its number (`151`, `164`, `2414b`).
    pub number: DatasetNumber,
}

/// Everything read from one file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Uff58File {
    /// The 58 and 58b datasets, in file order.
    pub channels: Vec<Uff58Channel>,
    /// The other datasets.
    pub skipped: Vec<Skipped>,
}

/// The time histories of a UFF file; refused if it holds none.
pub fn read(path: impl AsRef<Path>) -> Result<Vec<Uff58Channel>, UffError> {
    let path = path.as_ref();
    let file = read_file(path)?;
    if file.channels.is_empty() {
        return Err(UffError::NoTimeHistories {
            path: path.to_path_buf(),
            skipped: file.skipped,
        });
    }
    Ok(file.channels)
}

/// The time histories of a UFF file and the datasets skipped.
pub fn read_file(path: impl AsRef<Path>) -> Result<Uff58File, UffError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| UffError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse(&bytes, path)
}

/// Parse a file's bytes; `path` names it in errors.
pub fn parse(bytes: &[u8], path: &Path) -> Result<Uff58File, UffError> {
    let mut cur = Cursor::new(bytes);
    let mut file = Uff58File::default();
    let mut index = 0;
    while let Some((n, raw)) = cur.nonblank_line() {
        index += 1;
        let mut ctx = Ctx {
            path,
            dataset: DatasetAt {
                index,
                number: None,
            },
        };
        if !is_delimiter(raw) {
            return Err(missing(&ctx, Side::Start, n, Some(raw)));
        }
        let Some((n, raw)) = cur.raw_line() else {
            return Err(cut_short(&ctx, Record::NumberLine, "lines", 1, 0));
        };
        let number = binary::number(&ctx, n, raw)?;
        ctx.dataset.number = Some(number);
        match (number.number, number.binary) {
            (58, false) => file.channels.push(ascii::dataset(&ctx, &mut cur)?),
            (58, true) => file.channels.push(binary::dataset(&ctx, &mut cur, n, raw)?),
            (_, binary) => {
                binary::skip(&ctx, &mut cur, binary.then_some((n, raw)))?;
                file.skipped.push(Skipped { index, number });
            }
        }
    }
    Ok(file)
}

/// Records 1-11 of a dataset 58: 11 lines, none of them the closing delimiter.
fn header_lines(ctx: &Ctx, cur: &mut Cursor) -> Result<Vec<Line>, UffError> {
    let mut lines = Vec::with_capacity(11);
    while lines.len() < 11 {
        match cur.raw_line() {
            Some((n, raw)) if !is_delimiter(raw) => lines.push((n, decode(raw))),
            _ => {
                let record = Record::Header(lines.len() as u8 + 1);
                return Err(cut_short(ctx, record, "header records", 11, lines.len()));
            }
        }
    }
    Ok(lines)
}

/// The channel of a parsed header and its ordinates as in the file.
fn channel(
    ctx: &Ctx,
    header: Header,
    time_factor: f64,
    mut samples: Vec<f64>,
    encoding: Encoding,
) -> Result<Uff58Channel, UffError> {
    if samples.len() != header.points {
        return Err(UffError::PointsMismatch {
            path: ctx.path.to_path_buf(),
            dataset: ctx.dataset,
            announced: header.points,
            found: samples.len(),
        });
    }
    if let Some((sample, &value)) = samples.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(UffError::NotFinite {
            path: ctx.path.to_path_buf(),
            dataset: ctx.dataset,
            sample,
            value,
        });
    }
    let [abscissa, ordinate, _, _] = header.axes;
    let (unit, warnings) =
        units::conversion(&ordinate.unit_label, ordinate.data_type, ordinate.exponents);
    if unit.factor != 1.0 {
        samples.iter_mut().for_each(|v| *v *= unit.factor);
    }
    let id1 = units::clean_label(&header.id_lines[0]);
    let dof = &header.response;
    let no_dof = dof.entity.is_empty() && dof.node == 0 && dof.direction.is_scalar();
    let name = match (id1.is_empty(), no_dof) {
        (true, _) => dof.to_string(),
        (false, true) => id1.to_string(),
        (false, false) => format!("{id1} [{dof}]"),
    };
    Ok(Uff58Channel {
        name,
        id_lines: header.id_lines,
        function_type: header.function_type,
        response: header.response,
        reference: header.reference,
        ordinate,
        abscissa,
        unit,
        dt: header.increment * time_factor,
        start_time: header.start * time_factor,
        samples,
        precision: header.precision,
        encoding,
        dataset: ctx.dataset.index,
        warnings,
    })
}

fn missing(ctx: &Ctx, side: Side, line: usize, found: Option<&[u8]>) -> UffError {
    UffError::MissingDelimiter {
        path: ctx.path.to_path_buf(),
        dataset: ctx.dataset,
        side,
        line,
        found: found.map(|raw| {
            let text: String = decode(raw).trim().chars().take(40).collect();
            text.escape_debug().to_string()
        }),
    }
}

fn cut_short(
    ctx: &Ctx,
    record: Record,
    what: &'static str,
    expected: usize,
    found: usize,
) -> UffError {
    UffError::CutShort {
        path: ctx.path.to_path_buf(),
        dataset: ctx.dataset,
        record,
        what,
        expected,
        found,
    }
}

/// Whether a line is a `-1` delimiter (the format puts it in columns 1-6; blanks are allowed).
fn is_delimiter(raw: &[u8]) -> bool {
    raw.trim_ascii() == b"-1"
}

/// Header text: UTF-8, or else Latin-1 (Windows exporters write `µ` as the byte 0xB5).
fn decode(raw: &[u8]) -> String {
    match std::str::from_utf8(raw) {
        Ok(s) => s.to_string(),
        Err(_) => raw.iter().map(|&b| b as char).collect(),
    }
}

/// A position in the file's bytes, counting lines for messages.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// 1-based number of the next line.
    line: usize,
}

impl<'a> Cursor<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Cursor {
            bytes,
            pos: 0,
            line: 1,
        }
    }

    /// The next line without its `\n` or `\r\n`, and its number; `None` at the end.
    fn raw_line(&mut self) -> Option<(usize, &'a [u8])> {
        let rest = self.bytes.get(self.pos..).filter(|r| !r.is_empty())?;
        let (line, used) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.pos += used;
        let n = self.line;
        self.line += 1;
        Some((n, line.strip_suffix(b"\r").unwrap_or(line)))
    }

    /// The next line that is not blank.
    fn nonblank_line(&mut self) -> Option<(usize, &'a [u8])> {
        loop {
            let (n, raw) = self.raw_line()?;
            if !raw.trim_ascii().is_empty() {
                return Some((n, raw));
            }
        }
    }

    /// The next `n` bytes (binary data), or how many are left.
    fn take(&mut self, n: usize) -> Result<&'a [u8], usize> {
        let rest = &self.bytes[self.pos..];
        let taken = rest.get(..n).ok_or(rest.len())?;
        self.pos += n;
        self.line += taken.iter().filter(|&&b| b == b'\n').count();
        Ok(taken)
    }
}
