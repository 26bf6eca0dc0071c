//! `washdyn study status` (where each variant stands) and `washdyn study collect` (every
//! summary row in variant order, with its wall time, as one `summary.parquet` and `summary.csv`
//! beside the datasets, then the Pareto plot and Sobol indices: `report.rs`).

use super::dataset::{Layout, Record, State, write_table};
use crate::error::Error;
use crate::results::{Column, read_table};
use std::path::{Path, PathBuf};

/// Where a study's variants stand.
#[derive(Clone, Debug, PartialEq)]
pub struct Status {
    pub total: usize,
    pub done: usize,
    /// (id, error) of each failed variant.
    pub failed: Vec<(String, String)>,
    pub missing: Vec<String>,
    /// Tmp directories a killed run left (the next run removes them).
    pub tmp: usize,
}

/// The standing of the study in `dir`.
pub fn status(dir: &Path) -> Result<Status, Error> {
    let record = Record::read(dir)?;
    let layout = Layout::new(dir);
    let mut s = Status {
        total: record.variants.len(),
        done: 0,
        failed: Vec::new(),
        missing: Vec::new(),
        tmp: layout.count_tmp(),
    };
    for v in &record.variants {
        match layout.state(&v.id) {
            State::Done => s.done += 1,
            State::Failed(e) => s.failed.push((v.id.clone(), e)),
            State::Missing => s.missing.push(v.id.clone()),
        }
    }
    Ok(s)
}

/// What `collect` wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Collected {
    pub rows: usize,
    /// Variants without a summary yet (not in the table).
    pub missing: Vec<String>,
    pub files: Vec<PathBuf>,
}

/// Every variant's summary row in variant order, its wall time (from `timing/`; null where
/// absent) appended, written as `<dir>/summary.parquet` and `<dir>/summary.csv`. Summaries of
/// another schema than the first's are refused, naming the file.
pub fn collect(dir: &Path) -> Result<Collected, Error> {
    let record = Record::read(dir)?;
    let layout = Layout::new(dir);
    let mut table: Option<crate::results::Table> = None;
    let mut wall = Vec::new();
    let mut missing = Vec::new();
    for v in &record.variants {
        let path = layout.summary_file(&v.id);
        if !path.is_file() {
            missing.push(v.id.clone());
            continue;
        }
        let t = read_table(&path).map_err(|message| Error::File { message })?;
        match &mut table {
            None => table = Some(t),
            Some(all) => {
                let same = all.names == t.names
                    && all.columns.iter().zip(&t.columns).all(|(a, b)| {
                        matches!(
                            (a, b),
                            (Column::F64(_), Column::F64(_)) | (Column::Text(_), Column::Text(_))
                        )
                    });
                if !same {
                    return Err(Error::File {
                        message: format!(
                            "{}: its columns differ from variant {}'s: not this study's summary",
                            path.display(),
                            record.variants[0].id
                        ),
                    });
                }
                for (a, b) in all.columns.iter_mut().zip(t.columns) {
                    match (a, b) {
                        (Column::F64(a), Column::F64(b)) => a.extend(b),
                        (Column::Text(a), Column::Text(b)) => a.extend(b),
                        _ => unreachable!("types compared above"),
                    }
                }
            }
        }
        let w = read_table(&layout.timing_file(&v.id)).ok().and_then(|t| {
            match t.column("wall_time_s") {
                Some(Column::F64(x)) => x.first().copied(),
                _ => None,
            }
        });
        wall.push(w.unwrap_or(f64::NAN));
    }
    let mut files = Vec::new();
    let Some(mut t) = table else {
        return Ok(Collected {
            rows: 0,
            missing,
            files,
        });
    };
    t.names.push("wall_time_s".into());
    t.columns.push(Column::F64(wall));
    t.nullable.push(true);
    t.metadata.retain(|(k, _)| k != "washdyn");
    t.metadata.push(("unit:wall_time_s".into(), "s".into()));
    t.metadata.push((
        "washdyn".into(),
        "a washdyn study's summary, one row a variant in variant order; wall_time_s is the one \
         column that differs between two runs of the same study"
            .into(),
    ));
    let text: Vec<bool> = t
        .columns
        .iter()
        .map(|c| matches!(c, Column::Text(_)))
        .collect();
    for ext in ["parquet", "csv"] {
        let to = dir.join(format!("summary.{ext}"));
        let tmp = dir.join(format!("summary.tmp-{}.{ext}", std::process::id()));
        write_table(&tmp, &t.names, &text, &t.nullable, &t.metadata, &t.columns)?;
        std::fs::rename(&tmp, &to).map_err(|e| Error::io("rename into place", &to, e))?;
        files.push(to);
    }
    files.extend(super::report::write(dir, &record, &t)?);
    Ok(Collected {
        rows: t.rows(),
        missing,
        files,
    })
}
