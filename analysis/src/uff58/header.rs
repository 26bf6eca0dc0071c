//! The 11 header records of dataset 58 and the number line of 58b, field by field.
//!
//! Records 6 and 8-11 mix integers and names, so they are cut at the format's columns
//! (`2(I5,I10),2(1X,10A1,I10,I4)` and `I10,3I5,2(1X,20A1)`); a blank integer field reads 0, as
//! Fortran's does. Records 7 and the 58b number line hold numbers only and are split at blanks,
//! which also takes exporters that write wider fields than `3I10,3E13.5` (more digits of dt).

use std::path::Path;

use super::error::{DatasetAt, FieldAt, FieldProblem, NotTimeHistory, Record, UffError};
use super::units;
use super::{Direction, Dof};

/// Where errors are reported: the file and the dataset being read.
#[derive(Clone, Copy)]
pub(super) struct Ctx<'a> {
    pub path: &'a Path,
    pub dataset: DatasetAt,
}

impl Ctx<'_> {
    /// A header field's error.
    pub fn field(&self, line: usize, field: FieldAt, problem: FieldProblem) -> UffError {
        UffError::Field {
            path: self.path.to_path_buf(),
            dataset: self.dataset,
            line,
            field,
            problem,
        }
    }
}

/// One header line with its 1-based line number in the file.
pub(super) type Line = (usize, String);

/// Records 8-11: what an axis holds and in which unit.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisInfo {
    /// Specific data type (field 1): 17 time, 12 acceleration, 8 displacement, ...
    pub data_type: i64,
    /// Length, force and temperature units exponents (fields 2-4).
    pub exponents: [i64; 3],
    /// Axis label (field 5; empty for `NONE`).
    pub label: String,
    /// Axis units label (field 6; empty for `NONE`).
    pub unit_label: String,
}

/// Ordinate precision (record 7 field 1): 2 real single, 4 real double.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// 4-byte floats (data type 2).
    Single,
    /// 8-byte floats (data type 4).
    Double,
}

impl Precision {
    /// Bytes per value in a 58b.
    pub fn width(self) -> usize {
        match self {
            Precision::Single => 4,
            Precision::Double => 8,
        }
    }
}

/// The parsed header of one dataset 58.
#[derive(Debug, Clone)]
pub(super) struct Header {
    pub id_lines: [String; 5],
    pub function_type: i64,
    pub response: Dof,
    pub reference: Dof,
    pub precision: Precision,
    pub points: usize,
    /// Abscissa minimum and increment in the abscissa's unit (record 7 fields 4, 5).
    pub start: f64,
    pub increment: f64,
    /// Abscissa, ordinate, ordinate denominator, z axis (records 8-11).
    pub axes: [AxisInfo; 4],
}

const fn at(record: u8, field: u8, name: &'static str) -> FieldAt {
    FieldAt {
        record: Record::Header(record),
        field,
        name,
    }
}

/// An integer field; blank reads 0 where `blank_zero`.
pub(super) fn int(
    ctx: &Ctx,
    line: usize,
    text: Option<&str>,
    field: FieldAt,
    blank_zero: bool,
) -> Result<i64, UffError> {
    match text.map(str::trim) {
        Some("") | None if blank_zero => Ok(0),
        Some("") | None => Err(ctx.field(line, field, FieldProblem::Missing)),
        Some(t) => t
            .parse()
            .map_err(|_| ctx.field(line, field, FieldProblem::NotAnInteger(t.into()))),
    }
}

/// A finite real field, with Fortran's `D` exponent taken.
fn real(ctx: &Ctx, line: usize, text: Option<&str>, field: FieldAt) -> Result<f64, UffError> {
    let t = text
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .ok_or_else(|| ctx.field(line, field, FieldProblem::Missing))?;
    parse_real(t).ok_or_else(|| ctx.field(line, field, FieldProblem::NotANumber(t.into())))
}

/// A finite real number as Fortran writes it (`1.5E+00`, `1.5D+00`).
pub(super) fn parse_real(t: &str) -> Option<f64> {
    let v: f64 = match t.parse() {
        Ok(v) => v,
        Err(_) => t.replace(['D', 'd'], "E").parse().ok()?,
    };
    v.is_finite().then_some(v)
}

/// `line` cut at the column `widths` (in characters), short lines padded with blanks.
fn columns<'a>(line: &'a str, widths: &[usize]) -> Vec<&'a str> {
    let mut out = Vec::with_capacity(widths.len());
    let mut rest = line;
    for &w in widths {
        let end = rest.char_indices().nth(w).map_or(rest.len(), |(i, _)| i);
        out.push(&rest[..end]);
        rest = &rest[end..];
    }
    out
}

/// Parse records 1-11 (`lines` holds exactly 11).
pub(super) fn parse(ctx: &Ctx, lines: &[Line]) -> Result<Header, UffError> {
    let id_lines = std::array::from_fn(|i| lines[i].1.trim_end().to_string());
    let (response, reference, function_type) = record6(ctx, &lines[5])?;
    let (precision, points, start, increment) = record7(ctx, &lines[6])?;
    let mut axes = Vec::with_capacity(4);
    for (i, l) in lines[7..11].iter().enumerate() {
        axes.push(axis(ctx, l, 8 + i as u8)?);
    }
    let axes: [AxisInfo; 4] = axes.try_into().expect("four axis records");
    let header = Header {
        id_lines,
        function_type,
        response,
        reference,
        precision,
        points,
        start,
        increment,
        axes,
    };
    Ok(header)
}

/// Record 6: the function type and the response and reference DOFs.
fn record6(ctx: &Ctx, (n, line): &Line) -> Result<(Dof, Dof, i64), UffError> {
    let c = columns(line, &[5, 10, 5, 10, 11, 10, 4, 11, 10, 4]);
    let function_type = int(ctx, *n, Some(c[0]), at(6, 1, "function type"), true)?;
    for (i, name) in [(1, "function identification number"), (2, "version number")] {
        int(ctx, *n, Some(c[i]), at(6, i as u8 + 1, name), true)?;
    }
    int(
        ctx,
        *n,
        Some(c[3]),
        at(6, 4, "load case identification number"),
        true,
    )?;
    let dof = |e: usize, names: [&'static str; 3]| -> Result<Dof, UffError> {
        let node = int(ctx, *n, Some(c[e + 1]), at(6, e as u8 + 2, names[1]), true)?;
        let dir_at = at(6, e as u8 + 3, names[2]);
        let dir = int(ctx, *n, Some(c[e + 2]), dir_at, true)?;
        let direction = Direction::new(dir).ok_or_else(|| {
            let value = dir.to_string();
            let allowed = "-6 to 6: 0 scalar, 1-3 X Y Z, 4-6 rotations about them, - negative";
            ctx.field(*n, dir_at, FieldProblem::OutOfRange { value, allowed })
        })?;
        let entity = units::clean_label(c[e]).to_string();
        Ok(Dof {
            entity,
            node,
            direction,
        })
    };
    let response = dof(
        4,
        [
            "response entity name",
            "response node",
            "response direction",
        ],
    )?;
    let reference = dof(
        7,
        [
            "reference entity name",
            "reference node",
            "reference direction",
        ],
    )?;
    Ok((response, reference, function_type))
}

/// Record 7: precision, points, spacing (even only), abscissa minimum and increment.
fn record7(ctx: &Ctx, (n, line): &Line) -> Result<(Precision, usize, f64, f64), UffError> {
    let t: Vec<&str> = line.split_whitespace().collect();
    let type_at = at(7, 1, "ordinate data type");
    let code = int(ctx, *n, t.first().copied(), type_at, false)?;
    let precision = match code {
        2 => Precision::Single,
        4 => Precision::Double,
        5 | 6 => {
            return Err(UffError::NotTimeHistory {
                path: ctx.path.to_path_buf(),
                dataset: ctx.dataset,
                field: type_at,
                reason: NotTimeHistory::Complex { code },
            });
        }
        _ => {
            let allowed = "2 real single, 4 real double, 5 complex single, 6 complex double";
            let value = code.to_string();
            return Err(ctx.field(*n, type_at, FieldProblem::OutOfRange { value, allowed }));
        }
    };
    let points_at = at(7, 2, "number of points");
    let points = int(ctx, *n, t.get(1).copied(), points_at, false)?;
    let points = usize::try_from(points)
        .ok()
        .filter(|&p| p > 0)
        .ok_or_else(|| {
            let value = points.to_string();
            let allowed = "at least 1";
            ctx.field(*n, points_at, FieldProblem::OutOfRange { value, allowed })
        })?;
    let spacing_at = at(7, 3, "abscissa spacing");
    match int(ctx, *n, t.get(2).copied(), spacing_at, false)? {
        1 => {}
        0 => {
            return Err(UffError::UnevenAbscissa {
                path: ctx.path.to_path_buf(),
                dataset: ctx.dataset,
                field: spacing_at,
            });
        }
        v => {
            let (value, allowed) = (v.to_string(), "0 uneven, 1 even");
            return Err(ctx.field(*n, spacing_at, FieldProblem::OutOfRange { value, allowed }));
        }
    }
    let start = real(ctx, *n, t.get(3).copied(), at(7, 4, "abscissa minimum"))?;
    let inc_at = at(7, 5, "abscissa increment");
    let increment = real(ctx, *n, t.get(4).copied(), inc_at)?;
    if increment <= 0.0 {
        let (value, allowed) = (increment.to_string(), "positive");
        return Err(ctx.field(*n, inc_at, FieldProblem::OutOfRange { value, allowed }));
    }
    if t.len() > 5 {
        real(ctx, *n, t.get(5).copied(), at(7, 6, "z-axis value"))?;
    }
    Ok((precision, points, start, increment))
}

/// Records 8-11: data type, units exponents and labels of one axis.
fn axis(ctx: &Ctx, (n, line): &Line, record: u8) -> Result<AxisInfo, UffError> {
    let c = columns(line, &[10, 5, 5, 5, 21, 21]);
    let data_type = int(
        ctx,
        *n,
        Some(c[0]),
        at(record, 1, "specific data type"),
        true,
    )?;
    let names = [
        "length units exponent",
        "force units exponent",
        "temperature units exponent",
    ];
    let mut exponents = [0; 3];
    for (i, name) in names.into_iter().enumerate() {
        exponents[i] = int(ctx, *n, Some(c[i + 1]), at(record, i as u8 + 2, name), true)?;
    }
    Ok(AxisInfo {
        data_type,
        exponents,
        label: units::clean_label(c[4]).to_string(),
        unit_label: units::clean_label(c[5]).to_string(),
    })
}

impl Header {
    /// Refuse what is not a time history (function type, abscissa); the factor from the
    /// abscissa's unit to seconds.
    pub fn time_factor(&self, ctx: &Ctx) -> Result<f64, UffError> {
        let refuse = |field, reason| UffError::NotTimeHistory {
            path: ctx.path.to_path_buf(),
            dataset: ctx.dataset,
            field,
            reason,
        };
        if !matches!(self.function_type, 0 | 1) {
            let code = self.function_type;
            return Err(refuse(
                at(6, 1, "function type"),
                NotTimeHistory::Function { code },
            ));
        }
        let abscissa = &self.axes[0];
        if !matches!(abscissa.data_type, 0 | 1 | 17) {
            let code = abscissa.data_type;
            return Err(refuse(
                at(8, 1, "specific data type"),
                NotTimeHistory::Abscissa { code },
            ));
        }
        match abscissa.unit_label.as_str() {
            "" => Ok(1.0),
            "s" | "sec" => Ok(1.0),
            "ms" => Ok(1e-3),
            other => {
                let label = other.to_string();
                Err(refuse(
                    at(8, 6, "axis units label"),
                    NotTimeHistory::AbscissaUnit { label },
                ))
            }
        }
    }
}

/// The name of a function type (record 6 field 1).
pub fn function_name(code: i64) -> &'static str {
    const NAMES: [&str; 28] = [
        "general or unknown",
        "time response",
        "auto spectrum",
        "cross spectrum",
        "frequency response function",
        "transmissibility",
        "coherence",
        "auto correlation",
        "cross correlation",
        "power spectral density",
        "energy spectral density",
        "probability density function",
        "spectrum",
        "cumulative frequency distribution",
        "peaks valley",
        "stress/cycles",
        "strain/cycles",
        "orbit",
        "mode indicator function",
        "force pattern",
        "partial power",
        "partial coherence",
        "eigenvalue",
        "eigenvector",
        "shock response spectrum",
        "finite impulse response filter",
        "multiple coherence",
        "order function",
    ];
    usize::try_from(code)
        .ok()
        .and_then(|i| NAMES.get(i))
        .copied()
        .unwrap_or("unknown")
}

/// The name of a specific data type (records 8-11 field 1).
pub fn data_type_name(code: i64) -> &'static str {
    match code {
        0 => "unknown",
        1 => "general",
        2 => "stress",
        3 => "strain",
        5 => "temperature",
        6 => "heat flux",
        8 => "displacement",
        9 => "reaction force",
        11 => "velocity",
        12 => "acceleration",
        13 => "excitation force",
        15 => "pressure",
        16 => "mass",
        17 => "time",
        18 => "frequency",
        19 => "rpm",
        20 => "order",
        _ => "not in the format's list",
    }
}
