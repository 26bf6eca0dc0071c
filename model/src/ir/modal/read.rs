//! Reading modal data: the TOML file or text into `ModalData` with file and line in its errors,
//! and the one resolver that reads every elastic body's file into a model.

use super::{Curves, ModalData, problems};
use crate::ir::Model;
use crate::ir::check::{CheckError, Path};
use crate::ir::files::DataFiles;
use std::path::{Path as FsPath, PathBuf};

/// Read a modal data file; errors carry the file (as `shown`) and line.
pub fn read_file(path: &FsPath, shown: &str) -> Result<ModalData, String> {
    let src = std::fs::read_to_string(path).map_err(|e| format!("{shown}: cannot read: {e}"))?;
    read_str(&src, shown)
}

/// Parse modal data text; errors carry the file (as `shown`) and line.
pub fn read_str(src: &str, shown: &str) -> Result<ModalData, String> {
    parse(src, shown)
}

/// Deserialize a data file's text; errors carry the file (as `shown`) and line.
fn parse<T: serde::de::DeserializeOwned>(src: &str, shown: &str) -> Result<T, String> {
    from_toml(src).map_err(|(span, m)| {
        let line = span.map_or(0, |s| src[..s.start.min(src.len())].lines().count().max(1));
        format!("{shown}:{line}: {m}")
    })
}

/// Deserialize TOML text; an error gives its span and a message that names the field
/// (`points[2].position: invalid length 4, ...`), as serde_path_to_error tracks it.
pub fn from_toml<T: serde::de::DeserializeOwned>(
    src: &str,
) -> Result<T, (Option<std::ops::Range<usize>>, String)> {
    let de = toml::Deserializer::parse(src).map_err(|e| (e.span(), e.message().trim().into()))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let e = e.into_inner();
        let m = e.message().trim();
        // A message of its own that starts with the field (`missing field`, `unknown field`)
        // or an error at the top needs no path.
        let m = if path == "." || m.contains(&format!("`{path}`")) {
            m.to_string()
        } else {
            format!("{path}: {m}")
        };
        (e.span(), m)
    })
}

/// Read every elastic body's modal data file (from `files`: relative to the model's directory,
/// or compiled in) into the model: the one resolver of both front ends. Returns the files read
/// from disk (the macro makes cargo watch them) and the problems, each at `elastic[i].file` and
/// naming the file (an absolute path, or the embedded file's origin).
pub fn resolve(model: &mut Model, files: DataFiles) -> (Vec<PathBuf>, Vec<CheckError>) {
    let (mut read, mut errors) = (Vec::new(), Vec::new());
    for (i, e) in model.elastic.iter_mut().enumerate() {
        let at = |key: &str, m: String| CheckError {
            path: Path::default().key("elastic").idx(i).key(key),
            message: format!("elastic `{}`: {m}", e.name),
        };
        // The file's own rules before anything computes with it (truncation's eigen-solver did
        // not return on NaN); the checker skips a body without data.
        let mut d = match read_checked(&files, &e.file, &mut read) {
            Ok(d) => d,
            Err(found) => {
                errors.extend(found.into_iter().map(|m| at("file", m)));
                continue;
            }
        };
        if let Some(file) = &e.curves {
            let curves = files.read(file).map_err(|e| e.to_string()).and_then(|f| {
                read.extend(f.path.clone());
                read_curves(&f.text, &f.shown, &e.name, &d)
            });
            match curves {
                Ok(c) => e.curves_data = Some(c),
                Err(m) => errors.push(at("curves", m)),
            }
        }
        if let Err(m) = keep_modes(&mut d, e.modes, &files.shown(&e.file)) {
            errors.push(at("modes", m));
        }
        e.data = Some(d);
        if let Some(file) = &e.bare {
            match read_checked(&files, file, &mut read) {
                Ok(mut b) => match keep_modes(&mut b, e.modes, &files.shown(file)) {
                    Ok(()) => e.bare_data = Some(b),
                    Err(m) => errors.push(at("bare", m)),
                },
                Err(found) => errors.extend(found.into_iter().map(|m| at("bare", m))),
            }
        }
    }
    (read, errors)
}

/// Read a modal data file (its path joins `read`) and hold it to its own rules
/// (`problems`): the messages name the file.
fn read_checked(
    files: &DataFiles,
    file: &str,
    read: &mut Vec<PathBuf>,
) -> Result<ModalData, Vec<String>> {
    let f = files.read(file).map_err(|e| vec![e.to_string()])?;
    read.extend(f.path.clone());
    let d = read_str(&f.text, &f.shown).map_err(|m| vec![m])?;
    let found = problems(&d);
    if found.is_empty() {
        Ok(d)
    } else {
        Err(found
            .into_iter()
            .map(|m| format!("{}: {m}", f.shown))
            .collect())
    }
}

/// Keep the first `n` eigenmodes of `d` (an entry's `modes`); the message names the file
/// (`shown`) when it has fewer.
fn keep_modes(d: &mut ModalData, n: Option<usize>, shown: &str) -> Result<(), String> {
    let Some(n) = n else { return Ok(()) };
    let fewer = (n > d.eigenmodes())
        .then(|| format!("asks for {n} modes, `{shown}` has {}", d.eigenmodes()));
    d.truncate(n, &[]);
    fewer.map_or(Ok(()), Err)
}

/// Parse a body's characteristic curves and check them against its modal data file (before
/// truncation); errors carry the file (as `shown`), and the line or the field.
fn read_curves(src: &str, shown: &str, body: &str, d: &ModalData) -> Result<Curves, String> {
    let c: Curves = parse(src, shown)?;
    let found = c.problems(body, d);
    if found.is_empty() {
        Ok(c)
    } else {
        Err(format!("{shown}: {}", found.join("; ")))
    }
}
