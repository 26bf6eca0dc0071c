//! The dataset number line, 58b's binary layout on it, its binary data, and skipping the
//! datasets this reader does not take.
//!
//! 58b's number line is `(I6,1A1,I6,I6,I12,I12,I6,I6,I12,I12)`: `58`, `b`, byte ordering
//! (1 little, 2 big endian), floating-point format (2 IEEE 754; 1 DEC VMS and 3 IBM 5/370 are
//! refused), ASCII lines that follow (11), bytes of binary data after them. The data follow the
//! 11th header line's line end directly; the closing `-1` follows the last byte, though some
//! exporters put a line end between them (taken).

use super::error::{DatasetNumber, FieldAt, FieldProblem, Record, Side, UffError};
use super::header::{self, Ctx, Precision};
use super::{Cursor, Encoding, Uff58Channel, cut_short, is_delimiter, missing};

const fn at(field: u8, name: &'static str) -> FieldAt {
    FieldAt {
        record: Record::NumberLine,
        field,
        name,
    }
}

/// The dataset number of its line: `58`, `58b`, `151`.
pub(super) fn number(ctx: &Ctx, line: usize, raw: &[u8]) -> Result<DatasetNumber, UffError> {
    let text = super::decode(raw);
    let first = text.split_whitespace().next();
    let field = at(1, "dataset number");
    let (digits, binary) = match first {
        Some(t) => t.strip_suffix(['b', 'B']).map_or((t, false), |d| (d, true)),
        None => return Err(ctx.field(line, field, FieldProblem::Missing)),
    };
    let number = digits
        .parse()
        .map_err(|_| ctx.field(line, field, FieldProblem::NotAnInteger(digits.into())))?;
    Ok(DatasetNumber { number, binary })
}

/// A binary dataset's layout from its number line.
struct Layout {
    /// Field 3: 1 little endian, 2 big endian.
    order: i64,
    /// Field 4: 2 IEEE 754.
    format: i64,
    /// Field 5: header lines before the binary data.
    ascii_lines: usize,
    /// Field 6: bytes of binary data.
    bytes: usize,
}

fn layout(ctx: &Ctx, line: usize, raw: &[u8]) -> Result<Layout, UffError> {
    let text = super::decode(raw);
    let t: Vec<&str> = text.split_whitespace().skip(1).collect();
    let order = header::int(ctx, line, t.first().copied(), at(3, "byte ordering"), false)?;
    let format = header::int(
        ctx,
        line,
        t.get(1).copied(),
        at(4, "floating point format"),
        false,
    )?;
    let count = |i: usize, field: FieldAt| -> Result<usize, UffError> {
        let v = header::int(ctx, line, t.get(i).copied(), field, false)?;
        usize::try_from(v).map_err(|_| {
            let (value, allowed) = (v.to_string(), "not negative");
            ctx.field(line, field, FieldProblem::OutOfRange { value, allowed })
        })
    };
    let ascii_lines = count(2, at(5, "number of ASCII lines"))?;
    let bytes = count(3, at(6, "number of bytes"))?;
    Ok(Layout {
        order,
        format,
        ascii_lines,
        bytes,
    })
}

/// Read one dataset 58b after its number line (`line`, `raw`), through its closing `-1`.
pub(super) fn dataset(
    ctx: &Ctx,
    cur: &mut Cursor,
    line: usize,
    raw: &[u8],
) -> Result<Uff58Channel, UffError> {
    let l = layout(ctx, line, raw)?;
    let encoding = match l.order {
        1 => Encoding::BinaryLittleEndian,
        2 => Encoding::BinaryBigEndian,
        value => {
            let (path, dataset) = (ctx.path.to_path_buf(), ctx.dataset);
            return Err(UffError::ByteOrder {
                path,
                dataset,
                value,
            });
        }
    };
    if l.format != 2 {
        let (path, dataset, value) = (ctx.path.to_path_buf(), ctx.dataset, l.format);
        return Err(UffError::FloatFormat {
            path,
            dataset,
            value,
        });
    }
    if l.ascii_lines != 11 {
        let field = at(5, "number of ASCII lines");
        let (value, allowed) = (l.ascii_lines.to_string(), "11 for dataset 58");
        return Err(ctx.field(line, field, FieldProblem::OutOfRange { value, allowed }));
    }
    let lines = super::header_lines(ctx, cur)?;
    let header = header::parse(ctx, &lines)?;
    let time_factor = header.time_factor(ctx)?;
    let width = header.precision.width();
    let expected = header.points.checked_mul(width);
    if expected != Some(l.bytes) {
        return Err(UffError::ByteCount {
            path: ctx.path.to_path_buf(),
            dataset: ctx.dataset,
            announced: l.bytes,
            points: header.points,
            width,
            expected: expected.unwrap_or(usize::MAX),
        });
    }
    let data = cur
        .take(l.bytes)
        .map_err(|left| cut_short(ctx, Record::Data, "bytes", l.bytes, left))?;
    let little = encoding == Encoding::BinaryLittleEndian;
    let samples = decode_floats(data, header.precision, little);
    closing(ctx, cur)?;
    super::channel(ctx, header, time_factor, samples, encoding)
}

/// The values of binary data of whole `precision` floats.
fn decode_floats(data: &[u8], precision: Precision, little: bool) -> Vec<f64> {
    match precision {
        Precision::Single => data
            .chunks_exact(4)
            .map(|c| {
                let b = [c[0], c[1], c[2], c[3]];
                f64::from(if little {
                    f32::from_le_bytes(b)
                } else {
                    f32::from_be_bytes(b)
                })
            })
            .collect(),
        Precision::Double => data
            .chunks_exact(8)
            .map(|c| {
                let b: [u8; 8] = c.try_into().expect("chunks of 8");
                if little {
                    f64::from_le_bytes(b)
                } else {
                    f64::from_be_bytes(b)
                }
            })
            .collect(),
    }
}

/// The closing `-1` after binary data, a line end between them allowed.
fn closing(ctx: &Ctx, cur: &mut Cursor) -> Result<(), UffError> {
    let at_line = cur.line;
    match cur.nonblank_line() {
        Some((_, raw)) if is_delimiter(raw) => Ok(()),
        Some((n, raw)) => Err(missing(ctx, Side::End, n, Some(raw))),
        None => Err(missing(ctx, Side::End, at_line, None)),
    }
}

/// Pass over a dataset other than 58: to its closing `-1`, or for a binary one (its number
/// line given) over its header lines and bytes.
pub(super) fn skip(
    ctx: &Ctx,
    cur: &mut Cursor,
    binary: Option<(usize, &[u8])>,
) -> Result<(), UffError> {
    if let Some((line, raw)) = binary {
        let l = layout(ctx, line, raw)?;
        for i in 0..l.ascii_lines {
            if cur.raw_line().is_none() {
                return Err(cut_short(
                    ctx,
                    Record::NumberLine,
                    "header lines",
                    l.ascii_lines,
                    i,
                ));
            }
        }
        cur.take(l.bytes)
            .map_err(|left| cut_short(ctx, Record::Data, "bytes", l.bytes, left))?;
        return closing(ctx, cur);
    }
    loop {
        match cur.raw_line() {
            Some((_, raw)) if is_delimiter(raw) => return Ok(()),
            Some(_) => {}
            None => return Err(missing(ctx, Side::End, cur.line, None)),
        }
    }
}
