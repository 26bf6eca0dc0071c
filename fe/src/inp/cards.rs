//! The deck as cards: keyword lines with their parameters and data lines, `*INCLUDE` followed,
//! continuation lines joined, each with the file and line it stands at; the numbers, integers
//! and set members of a card's data, refused with file and line. Separate from the reader
//! (`mod.rs`) as the syntax, which knows no keyword's meaning.

use super::{InpError, InpProblem};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A data line: its line number and its fields.
pub(super) type DataLine = (usize, Vec<String>);

/// One card: keyword, parameters (upper-cased keys; values as written, upper-cased where they
/// name something), data lines with their line numbers, where it stands.
pub(super) struct Card {
    pub(super) keyword: String,
    pub(super) params: Vec<(String, String)>,
    pub(super) data: Vec<DataLine>,
    pub(super) file: PathBuf,
    pub(super) line: usize,
}

impl Card {
    pub(super) fn param(&self, key: &str) -> Option<&str> {
        self.params
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    pub(super) fn err(&self, line: usize, problem: InpProblem) -> InpError {
        InpError {
            file: self.file.clone(),
            line,
            problem,
        }
    }
    pub(super) fn need(&self, key: &str) -> Result<String, InpError> {
        self.param(key).map(str::to_uppercase).ok_or_else(|| {
            let (keyword, key) = (self.keyword.clone(), key.to_string());
            self.err(self.line, InpProblem::NeedsParameter { keyword, key })
        })
    }
    /// The first data line, or an error naming the card.
    pub(super) fn first(&self) -> Result<&DataLine, InpError> {
        self.data.first().ok_or_else(|| {
            let keyword = self.keyword.clone();
            self.err(self.line, InpProblem::NoData { keyword })
        })
    }
}

/// A number of a data line, or an error naming the field.
pub(super) fn num(
    card: &Card,
    line: usize,
    fields: &[String],
    i: usize,
    what: &str,
) -> Result<f64, InpError> {
    let (keyword, what) = (card.keyword.clone(), what.to_string());
    let Some(s) = fields.get(i) else {
        return Err(card.err(line, InpProblem::MissingField { keyword, what }));
    };
    let Ok(value) = s.replace(['d', 'D'], "e").parse::<f64>() else {
        let text = s.clone();
        return Err(card.err(
            line,
            InpProblem::NotANumber {
                keyword,
                what,
                text,
            },
        ));
    };
    if !value.is_finite() {
        return Err(card.err(
            line,
            InpProblem::NotFinite {
                keyword,
                what,
                value,
            },
        ));
    }
    Ok(value)
}

pub(super) fn int(card: &Card, line: usize, s: &str, what: &str) -> Result<i64, InpError> {
    s.parse().map_err(|_| {
        let (keyword, what, text) = (card.keyword.clone(), what.to_string(), s.to_string());
        card.err(
            line,
            InpProblem::NotAnInteger {
                keyword,
                what,
                text,
            },
        )
    })
}

/// Split the deck into cards, following `*INCLUDE` (relative to the including file).
pub(super) fn cards(path: &Path, out: &mut Vec<Card>, depth: usize) -> Result<(), InpError> {
    let at = |line: usize, problem: InpProblem| InpError {
        file: path.to_path_buf(),
        line,
        problem,
    };
    let text = std::fs::read_to_string(path).map_err(|e| at(0, InpProblem::Read(e)))?;
    let mut continued = false;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with("**") {
            continue;
        }
        if let Some(rest) = l.strip_prefix('*') {
            let mut parts = rest.split(',').map(str::trim);
            let keyword = format!("*{}", parts.next().unwrap_or("").to_uppercase());
            let mut params = Vec::new();
            for p in parts.filter(|p| !p.is_empty()) {
                let (k, v) = p.split_once('=').unwrap_or((p, ""));
                params.push((k.trim().to_uppercase(), v.trim().to_string()));
            }
            if keyword == "*INCLUDE" {
                let Some((_, inc)) = params.iter().find(|(k, _)| k == "INPUT") else {
                    let (keyword, key) = ("*INCLUDE".into(), "INPUT".into());
                    return Err(at(line, InpProblem::NeedsParameter { keyword, key }));
                };
                if depth > 8 {
                    return Err(at(line, InpProblem::IncludeTooDeep));
                }
                let inc = path
                    .parent()
                    .unwrap_or(Path::new("."))
                    .join(inc.trim_matches('"'));
                cards(&inc, out, depth + 1)?;
                continued = false;
                continue;
            }
            out.push(Card {
                keyword,
                params,
                data: Vec::new(),
                file: path.to_path_buf(),
                line,
            });
            continued = false;
            continue;
        }
        let Some(card) = out.last_mut() else {
            return Err(at(line, InpProblem::DataBeforeKeyword));
        };
        let fields: Vec<String> = l
            .split(',')
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect();
        // A line ending with a comma continues on the next (elements of more than 16 nodes);
        // MASS and SPRING data end with one by ccx's convention and stand alone.
        let joins = continued && card.keyword == "*ELEMENT";
        match card.data.last_mut() {
            Some(last) if joins => last.1.extend(fields),
            _ => card.data.push((line, fields)),
        }
        continued = l.ends_with(',');
    }
    Ok(())
}

/// A set's members: ids, or (for `GENERATE`) first, last, step; names of sets already
/// defined are expanded.
pub(super) fn members(
    card: &Card,
    sets: &BTreeMap<String, Vec<i64>>,
    generate: bool,
) -> Result<Vec<i64>, InpError> {
    let mut ids = Vec::new();
    for (line, f) in &card.data {
        if generate {
            let a = int(card, *line, f.first().map_or("", |s| s), "first id")?;
            let b = int(card, *line, f.get(1).map_or("", |s| s), "last id")?;
            let step = match f.get(2) {
                Some(s) => int(card, *line, s, "step")?,
                None => 1,
            };
            if step <= 0 || b < a {
                return Err(card.err(*line, InpProblem::BadGenerate));
            }
            ids.extend((a..=b).step_by(step as usize));
            continue;
        }
        for s in f {
            match s.parse::<i64>() {
                Ok(id) => ids.push(id),
                Err(_) => {
                    let name = s.to_uppercase();
                    let set = sets.get(&name).ok_or_else(|| {
                        let (keyword, set) = (card.keyword.clone(), s.clone());
                        card.err(*line, InpProblem::SetNotAbove { keyword, set })
                    })?;
                    ids.extend(set);
                }
            }
        }
    }
    Ok(ids)
}
