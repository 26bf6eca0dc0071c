//! TOML front end: file -> IR -> the one checker, with every error located at its file line.

use super::Model;
use super::check::{CheckError, Path, Seg, check};
use super::files::DataFiles;
use std::fmt;
use std::path::{Path as FsPath, PathBuf};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// One problem in a model file, located.
#[derive(Clone, Debug, PartialEq)]
pub struct Located {
    pub file: String,
    /// 1-based; 0 when the position is unknown.
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for Located {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.file, self.line, self.column, self.message
        )
    }
}

/// All problems found in a model file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ModelFileError {
    pub errors: Vec<Located>,
}

impl fmt::Display for ModelFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.errors.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{e}")?;
        }
        Ok(())
    }
}

/// Load and check a model file.
pub fn load_file(path: &FsPath) -> Result<Model, ModelFileError> {
    let (src, name, base) = read_model(path)?;
    load_str(&src, &name, &base)
}

/// A model file's text, its name for errors and the directory its data files are relative to.
fn read_model(path: &FsPath) -> Result<(String, String, PathBuf), ModelFileError> {
    let name = path.display().to_string();
    let src = std::fs::read_to_string(path).map_err(|e| ModelFileError {
        errors: vec![Located {
            file: name.clone(),
            line: 0,
            column: 0,
            message: format!("cannot read: {e}"),
        }],
    })?;
    Ok((
        src,
        name,
        path.parent().map(PathBuf::from).unwrap_or_default(),
    ))
}

/// The built-in reference machine, for the runtime's unit tests.
#[cfg(test)]
pub(crate) fn reference_for_tests() -> Model {
    let src = include_str!("../../../models/data/reference.toml");
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/data");
    load_str(src, "reference.toml", &data).unwrap()
}

/// Load and check model text; `file` names it in errors, `base` resolves relative data files.
pub fn load_str(src: &str, file: &str, base: &FsPath) -> Result<Model, ModelFileError> {
    load_with(src, file, DataFiles::Dir(base))
}

/// Load and check model text whose data files come from `files` (on disk or compiled in);
/// `file` names the model text in errors.
pub fn load_with(src: &str, file: &str, files: DataFiles) -> Result<Model, ModelFileError> {
    load_checked(src, file, files, true)
}

/// Load and check a model file without reading its modal data (every `elastic` entry's `data`
/// stays `None`, and the checker skips the rules that need it): for the FE front end, which
/// makes that data from the model's attachments (`attachments::attachments`).
pub fn load_file_unresolved(path: &FsPath) -> Result<Model, ModelFileError> {
    let (src, name, base) = read_model(path)?;
    load_checked(&src, &name, DataFiles::Dir(&base), false)
}

/// [`load_file_unresolved`] for model text (a built-in model); `files` serves a speed CSV.
pub fn load_unresolved(src: &str, file: &str, files: DataFiles) -> Result<Model, ModelFileError> {
    load_checked(src, file, files, false)
}

fn load_checked(
    src: &str,
    file: &str,
    files: DataFiles,
    modal: bool,
) -> Result<Model, ModelFileError> {
    let at = |span: Option<std::ops::Range<usize>>, message: String| {
        let (line, column) = span.map_or((0, 0), |s| line_col(src, s.start));
        Located {
            file: file.to_string(),
            line,
            column,
            message,
        }
    };
    let mut model: Model = super::modal::from_toml(src).map_err(|(span, m)| ModelFileError {
        errors: vec![at(span, m)],
    })?;
    if let Some(csv) = model.speed.csv.clone() {
        if !model.speed.table.is_empty() {
            let span = span_of(src, &Path::default().key("speed").key("csv"));
            return Err(ModelFileError {
                errors: vec![at(
                    span,
                    "speed: give either `table` or `csv`, not both".into(),
                )],
            });
        }
        let table = match files.read(&csv) {
            Ok(f) => parse_speed_csv(&f.text, &f.shown),
            Err(e) => Err(Located {
                file: e.shown,
                line: 0,
                column: 1,
                message: e.why,
            }),
        };
        model.speed.table = table.map_err(|e| ModelFileError { errors: vec![e] })?;
    }
    let mut errs = if modal {
        super::modal::resolve(&mut model, files).1
    } else {
        Vec::new()
    };
    errs.extend(check(&model).err().unwrap_or_default());
    if !errs.is_empty() {
        return Err(ModelFileError {
            errors: errs
                .into_iter()
                .map(|CheckError { path, message }| at(span_of(src, &path), message))
                .collect(),
        });
    }
    Ok(model)
}

/// Read a speed profile CSV: `time_s, rpm` per line, an optional header, `#` comments.
pub fn read_speed_csv(path: &FsPath) -> Result<Vec<[f64; 2]>, Located> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Located {
        file: file.clone(),
        line: 0,
        column: 1,
        message: format!("cannot read: {e}"),
    })?;
    parse_speed_csv(&text, &file)
}

/// Parse a speed profile CSV's text; `file` names it in errors.
pub fn parse_speed_csv(text: &str, file: &str) -> Result<Vec<[f64; 2]>, Located> {
    let err = |line: usize, message: String| Located {
        file: file.to_string(),
        line,
        column: 1,
        message,
    };
    let line_at = |byte: u64| line_col(text, byte as usize).0;
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut rows = Vec::new();
    let mut header_seen = false;
    for rec in rd.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| line_at(p.byte()));
            err(line, e.to_string())
        })?;
        // The record may start at blank lines before it: name the line of its first field.
        let start = rec.position().map_or(0, |p| p.byte() as usize);
        let skip = text[start..].len() - text[start..].trim_start().len();
        let line = line_at((start + skip) as u64);
        if rec.iter().all(str::is_empty) || rec.get(0).is_some_and(|c| c.starts_with('#')) {
            continue;
        }
        let nums: Result<Vec<f64>, _> = rec.iter().map(|c| c.parse::<f64>()).collect();
        match nums {
            Ok(v) if v.len() == 2 => rows.push([v[0], v[1]]),
            Ok(v) => {
                return Err(err(
                    line,
                    format!("expected 2 columns (time_s, rpm), found {}", v.len()),
                ));
            }
            // The first row that is not a comment may name the columns.
            Err(_) if rows.is_empty() && !header_seen => header_seen = true,
            Err(e) => {
                let row: Vec<&str> = rec.iter().collect();
                return Err(err(
                    line,
                    format!("not a number: {e} in `{}`", row.join(",")),
                ));
            }
        }
    }
    if rows.is_empty() {
        return Err(err(0, "no data rows".into()));
    }
    Ok(rows)
}

/// Where `path` sits in TOML text `src`: the 1-based line and column of the deepest part of it
/// present, (0, 0) when the text does not parse. For other TOML files' errors (a study file's),
/// located as a model file's are.
pub fn locate(src: &str, path: &Path) -> (usize, usize) {
    span_of(src, path).map_or((0, 0), |s| line_col(src, s.start))
}

/// The 1-based line and column of byte `offset` in `src`.
pub fn line_col(src: &str, offset: usize) -> (usize, usize) {
    let before = &src[..offset.min(src.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
    (line, column)
}

/// The span of the deepest part of `path` present in the document: a missing field points at
/// its table, so the user still lands next to the problem.
fn span_of(src: &str, path: &Path) -> Option<std::ops::Range<usize>> {
    let root = DeTable::parse(src).ok()?;
    let mut best = None;
    let mut cur: Option<&Spanned<DeValue>> = None;
    let mut table: Option<&DeTable> = Some(root.get_ref());
    for seg in &path.0 {
        let next = match (seg, table, cur.map(|c| c.get_ref())) {
            (Seg::Key(k), Some(t), _) => t.get(k.as_str()),
            (Seg::Index(i), _, Some(DeValue::Array(a))) => a.get(*i),
            _ => None,
        };
        let Some(v) = next else { break };
        best = Some(v.span());
        cur = Some(v);
        table = v.get_ref().as_table();
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_from_one() {
        assert_eq!(line_col("a\nbc\nd", 3), (2, 2));
        assert_eq!(line_col("abc", 0), (1, 1));
    }
}
