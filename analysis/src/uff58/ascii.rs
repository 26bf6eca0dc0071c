//! Dataset 58's data (record 12) as text: `6E13.5` single, `4E20.12` double per line.
//!
//! Values are split at blanks, which takes any field width; a line whose values touch (a
//! 3-digit exponent filling its field) is cut at the format's width instead. Single-precision
//! text is read as f64 without rounding to f32: the digits are what the file says.

use super::error::{Record, Side, UffError};
use super::header::{self, Ctx, Precision};
use super::{Cursor, Encoding, Uff58Channel, cut_short, is_delimiter, missing};

/// Read one dataset 58 after its number line, through its closing `-1`.
pub(super) fn dataset(ctx: &Ctx, cur: &mut Cursor) -> Result<Uff58Channel, UffError> {
    let lines = super::header_lines(ctx, cur)?;
    let header = header::parse(ctx, &lines)?;
    let time_factor = header.time_factor(ctx)?;
    let width = match header.precision {
        Precision::Single => 13,
        Precision::Double => 20,
    };
    // The header's count bounds the allocation, not the file: a wrong count cannot exhaust memory.
    let mut values = Vec::with_capacity(header.points.min(1 << 20));
    loop {
        match cur.raw_line() {
            Some((_, raw)) if is_delimiter(raw) => break,
            Some((n, raw)) => line_values(ctx, n, raw, width, &mut values)?,
            None if values.len() < header.points => {
                let found = values.len();
                return Err(cut_short(ctx, Record::Data, "values", header.points, found));
            }
            None => return Err(missing(ctx, Side::End, cur.line, None)),
        }
    }
    super::channel(ctx, header, time_factor, values, Encoding::Ascii)
}

/// A number as written, NaN and infinity included (refused later with the sample's index).
fn value(t: &str) -> Option<f64> {
    t.parse()
        .ok()
        .or_else(|| t.replace(['D', 'd'], "E").parse().ok())
}

/// The values of one data line, appended to `out`.
fn line_values(
    ctx: &Ctx,
    line: usize,
    raw: &[u8],
    width: usize,
    out: &mut Vec<f64>,
) -> Result<(), UffError> {
    let bad = |text: &str| UffError::BadValue {
        path: ctx.path.to_path_buf(),
        dataset: ctx.dataset,
        line,
        text: text.chars().take(40).collect(),
    };
    let text = std::str::from_utf8(raw).map_err(|_| bad(&String::from_utf8_lossy(raw)))?;
    let start = out.len();
    for t in text.split_whitespace() {
        match value(t) {
            Some(v) => out.push(v),
            None => {
                out.truncate(start);
                // The token that failed names the error better than a field cut at the width.
                return fixed_width(text, width, out).ok_or_else(|| bad(t));
            }
        }
    }
    Ok(())
}

/// The values of a line cut at the format's field width; `None` at a field that does not parse.
fn fixed_width(text: &str, width: usize, out: &mut Vec<f64>) -> Option<()> {
    if !text.is_ascii() {
        return None;
    }
    for field in text.as_bytes().chunks(width) {
        let t = std::str::from_utf8(field).ok()?.trim();
        if !t.is_empty() {
            out.push(value(t)?);
        }
    }
    Some(())
}
