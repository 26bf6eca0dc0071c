//! A study's directory, one hive-partitioned Parquet dataset per table:
//!
//! ```text
//! <out>/study.toml                          the study file as given
//! <out>/study.json                          the study as checked (a re-run must match it)
//! <out>/design.parquet                      variant_id, one column per parameter
//! <out>/variants/variant=<id>/sensors.parquet   the variant's sensor signals
//! <out>/summary/variant=<id>/summary.parquet    one row: parameters, outputs, status
//! <out>/timing/variant=<id>/timing.parquet      one row: wall_time_s
//! <out>/summary.parquet, summary.csv        every row in variant order (`study collect`)
//! ```
//!
//! Every file but the timing is a function of the study alone: the same study gives the same
//! bytes (no timestamps; the sensors written in row groups of a fixed size). Wall time is the
//! one number that is not, so it has a dataset of its own: a second file in a summary partition
//! would enter every one-line reader of `<out>/summary` as rows of another schema. A partition
//! holds one file name, so `read_parquet('<out>/summary/*/*.parquet', hive_partitioning=true)`
//! and `pandas.read_parquet('<out>/summary')` read the whole study. In the files the id is
//! `variant_id` (text, `0000`); the directory's `variant` is what each reader makes of it.
//!
//! A variant's partitions are written under `variant=<id>.tmp-<pid>-<n>` and renamed into place
//! when it finished, the summary last: a summary partition means a finished variant. A killed
//! run leaves tmp directories only, which the next run removes.

use super::file::Study;
use super::outputs::Outputs;
use super::variants::Variant;
use crate::error::Error;
use crate::results::{Column, Format, Schema, TableWriter, read_table};
use serde::{Deserialize, Serialize};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use washdyn_runtime::run::RunStatus;

/// The three datasets' directories under the study's.
pub const VARIANTS: &str = "variants";
pub const SUMMARY: &str = "summary";
pub const TIMING: &str = "timing";
const DATASETS: [&str; 3] = [VARIANTS, SUMMARY, TIMING];

/// What a tmp directory's name holds after `variant=<id>`.
const TMP: &str = ".tmp-";

/// The study's directory.
#[derive(Clone, Debug)]
pub struct Layout {
    pub root: PathBuf,
}

impl Layout {
    pub fn new(root: impl Into<PathBuf>) -> Layout {
        Layout { root: root.into() }
    }
    pub fn study_json(&self) -> PathBuf {
        self.root.join("study.json")
    }
    /// `<root>/<dataset>/variant=<id>`.
    pub fn partition(&self, dataset: &str, id: &str) -> PathBuf {
        self.root.join(dataset).join(format!("variant={id}"))
    }
    pub fn summary_file(&self, id: &str) -> PathBuf {
        self.partition(SUMMARY, id).join("summary.parquet")
    }
    pub fn timing_file(&self, id: &str) -> PathBuf {
        self.partition(TIMING, id).join("timing.parquet")
    }
    /// A fresh tmp directory beside a partition, unique in this process and among processes.
    pub fn tmp(&self, dataset: &str, id: &str) -> Result<PathBuf, Error> {
        static N: AtomicUsize = AtomicUsize::new(0);
        let n = N.fetch_add(1, Ordering::Relaxed);
        let p = self
            .root
            .join(dataset)
            .join(format!("variant={id}{TMP}{}-{n}", std::process::id()));
        fs::create_dir_all(&p).map_err(|e| Error::io("create", &p, e))?;
        Ok(p)
    }

    /// Remove what a killed run left (tmp directories); how many.
    pub fn clean_tmp(&self) -> Result<usize, Error> {
        let mut n = 0;
        for d in DATASETS {
            let dir = self.root.join(d);
            let Ok(entries) = fs::read_dir(&dir) else {
                continue;
            };
            for e in entries.flatten() {
                if e.file_name().to_string_lossy().contains(TMP) {
                    let p = e.path();
                    fs::remove_dir_all(&p).map_err(|e| Error::io("remove", &p, e))?;
                    n += 1;
                }
            }
        }
        Ok(n)
    }

    /// Leftover tmp directories, for `status`.
    pub fn count_tmp(&self) -> usize {
        DATASETS
            .iter()
            .filter_map(|d| fs::read_dir(self.root.join(d)).ok())
            .flat_map(|e| e.flatten())
            .filter(|e| e.file_name().to_string_lossy().contains(TMP))
            .count()
    }

    /// Move a finished tmp directory to its partition, replacing an older one.
    pub fn publish(&self, tmp: &Path, dataset: &str, id: &str) -> Result<(), Error> {
        let to = self.partition(dataset, id);
        if to.exists() {
            fs::remove_dir_all(&to).map_err(|e| Error::io("remove", &to, e))?;
        }
        fs::rename(tmp, &to).map_err(|e| Error::io("rename into place", &to, e))
    }

    /// Where a variant stands: finished (`ok`), failed (with the error), or missing.
    pub fn state(&self, id: &str) -> State {
        let Ok(t) = read_table(&self.summary_file(id)) else {
            return State::Missing;
        };
        let text = |c: &str| match t.column(c) {
            Some(Column::Text(v)) => v.first().cloned(),
            _ => None,
        };
        match text("status").as_deref().and_then(RunStatus::parse) {
            Some(RunStatus::Ok)
                if self
                    .partition(VARIANTS, id)
                    .join("sensors.parquet")
                    .is_file() =>
            {
                State::Done
            }
            Some(RunStatus::Ok) => State::Missing,
            Some(_) => State::Failed(text("error").unwrap_or_default()),
            None => State::Missing,
        }
    }
}

/// A variant's standing in the directory.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    Done,
    Failed(String),
    Missing,
}

/// `study.json`: the study as checked, every number a run depends on. A re-run into the same
/// directory must give the same record, so finished variants are the study's own.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// The model as the study file names it, and its content as the scene runs it (the
    /// accuracy study's hash: a changed model file is another study).
    pub model: String,
    pub model_content: String,
    pub scene: String,
    pub run: RunRecord,
    pub parameters: Vec<ParamRecord>,
    pub design: serde_json::Value,
    /// Two outputs for a Pareto plot, if named.
    pub pareto: Option<[String; 2]>,
    /// The summary's columns after the parameters.
    pub columns: Vec<String>,
    pub variants: Vec<VariantRecord>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    pub method: String,
    pub tol: f64,
    pub step: Option<f64>,
    pub rho_inf: Option<f64>,
    pub max_steps: Option<u64>,
    pub t_start: f64,
    pub t_end: f64,
    pub sample_rate: f64,
    pub start: String,
    pub validity_stop: bool,
    pub allow_large_output: bool,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamRecord {
    /// As the study file writes it (the column name), and resolved on the model.
    pub path: String,
    pub resolved: String,
    /// The base model's value (none for speed profiles).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub base: Option<f64>,
    pub axis: serde_json::Value,
    /// A speed-profile parameter's files and tables (level k is the k-th): a changed file is
    /// another study.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub profiles: Vec<ProfileRecord>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProfileRecord {
    pub file: String,
    pub table: Vec<[f64; 2]>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantRecord {
    pub id: String,
    pub values: Vec<f64>,
}

impl Record {
    pub fn new(study: &Study, vars: &[Variant]) -> Record {
        let s = &study.spec;
        let (method, tol) = s.solver(&study.source.model);
        Record {
            model: study.model_spec.clone(),
            model_content: study.model_content.clone(),
            scene: study.scene.clone(),
            run: RunRecord {
                method: method.name().to_string(),
                tol,
                step: s.step,
                rho_inf: s.rho_inf,
                max_steps: s.max_steps,
                t_start: s.t_start,
                t_end: study.t_end,
                sample_rate: s.sample_rate,
                start: s.start.name().to_string(),
                validity_stop: s.validity_stop,
                allow_large_output: s.allow_large_output,
            },
            parameters: study
                .parameters
                .iter()
                .map(|p| ParamRecord {
                    path: p.text.clone(),
                    resolved: p.param.path.to_string(),
                    base: p.base,
                    axis: serde_json::to_value(&p.axis).expect("an axis serialises"),
                    profiles: p
                        .profiles
                        .iter()
                        .map(|f| ProfileRecord {
                            file: f.file.display().to_string(),
                            table: f.table.clone(),
                        })
                        .collect(),
                })
                .collect(),
            design: serde_json::to_value(&study.design).expect("a design serialises"),
            pareto: study.pareto.clone(),
            columns: summary_columns(&study.outputs)
                .into_iter()
                .map(|c| c.0)
                .collect(),
            variants: vars
                .iter()
                .map(|v| VariantRecord {
                    id: v.id.clone(),
                    values: v.values.clone(),
                })
                .collect(),
        }
    }

    /// The record of the study in `root` (`status`, `collect`).
    pub fn read(root: &Path) -> Result<Record, Error> {
        let path = Layout::new(root).study_json();
        let text = fs::read_to_string(&path).map_err(|e| {
            super::StudyError::dir(
                root,
                format!(
                    "not a study's directory: cannot read {}: {e}",
                    path.display()
                ),
            )
        })?;
        serde_json::from_str(&text).map_err(|e| {
            super::StudyError::dir(root, format!("{}: not a study record: {e}", path.display()))
                .into()
        })
    }

    fn json(&self) -> String {
        serde_json::to_string_pretty(self).expect("the record serialises") + "\n"
    }
}

/// The directory for `record`: created, or one this study wrote before (its record equal);
/// anything else is refused before a file is touched. Then the record, the study file's copy
/// and the design are written (the same bytes as before on a re-run).
pub fn prepare(layout: &Layout, record: &Record, study: &Study) -> Result<(), Error> {
    let root = &layout.root;
    let json = layout.study_json();
    if json.exists() {
        let old = fs::read_to_string(&json).map_err(|e| Error::io("read", &json, e))?;
        let old: serde_json::Value = serde_json::from_str(&old).map_err(|e| {
            super::StudyError::dir(root, format!("{}: not a study record: {e}", json.display()))
        })?;
        let new = serde_json::to_value(record).expect("the record serialises");
        if old != new {
            let differs: Vec<&String> = new
                .as_object()
                .into_iter()
                .flat_map(|m| m.iter())
                .filter(|(k, v)| old.get(k.as_str()) != Some(*v))
                .map(|(k, _)| k)
                .collect();
            let differs: Vec<&str> = differs.iter().map(|s| s.as_str()).collect();
            return Err(super::StudyError::dir(
                root,
                format!(
                    "holds another study (its study.json differs in: {}): give another --out, or \
                     remove the directory to run this study there",
                    differs.join(", ")
                ),
            )
            .into());
        }
    } else if fs::read_dir(root).is_ok_and(|mut d| d.next().is_some()) {
        return Err(super::StudyError::dir(
            root,
            "exists and is not a study's directory (no study.json): give another --out",
        )
        .into());
    }
    fs::create_dir_all(root).map_err(|e| Error::io("create", root, e))?;
    write_atomic(&json, record.json().as_bytes())?;
    write_atomic(&root.join("study.toml"), study.text.as_bytes())?;
    let design = root.join("design.parquet");
    // The extension last: the writer takes the format from it.
    let tmp = root.join(format!("design{TMP}{}.parquet", std::process::id()));
    let mut names = vec!["variant_id".to_string()];
    names.extend(study.parameters.iter().map(|p| p.text.clone()));
    let mut cols = vec![Column::Text(
        record.variants.iter().map(|v| v.id.clone()).collect(),
    )];
    for k in 0..study.parameters.len() {
        cols.push(Column::F64(
            record.variants.iter().map(|v| v.values[k]).collect(),
        ));
    }
    let n = names.len();
    let mut text = vec![false; n];
    text[0] = true;
    write_table(&tmp, &names, &text, &vec![false; n], &[], &cols)?;
    fs::rename(&tmp, &design).map_err(|e| Error::io("rename into place", &design, e))
}

fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let name = path
        .file_name()
        .map_or("file".into(), |n| n.to_string_lossy());
    let tmp = path.with_file_name(format!("{name}{TMP}{}", std::process::id()));
    fs::write(&tmp, bytes).map_err(|e| Error::io("write", &tmp, e))?;
    fs::rename(&tmp, path).map_err(|e| Error::io("rename into place", path, e))
}

/// One table written in one row group (Parquet or CSV by the extension).
pub fn write_table(
    path: &Path,
    names: &[String],
    text: &[bool],
    nullable: &[bool],
    metadata: &[(String, String)],
    cols: &[Column],
) -> Result<(), Error> {
    let schema = Schema {
        names,
        text,
        nullable,
        metadata,
    };
    let io = |e| Error::io("write", path, e);
    let mut w = TableWriter::create(path, Format::of_path(path), &schema).map_err(io)?;
    w.append(cols).map_err(io)?;
    w.finish().map_err(io)
}

/// The columns a summary row has after `variant_id` and the parameters: the outputs, then the
/// run's status and counters; (name, unit, text).
pub fn summary_columns(outputs: &Outputs) -> Vec<(String, &'static str, bool)> {
    let mut c: Vec<(String, &'static str, bool)> = outputs
        .columns()
        .into_iter()
        .map(|(n, u)| (n, u, false))
        .collect();
    for (n, u, t) in [
        ("status", "", true),
        ("error", "", true),
        ("error_class", "", true),
        ("warnings", "", true),
        ("backend", "", true),
        ("t_reached_s", "s", false),
        ("steps", "", false),
        ("rejected_steps", "", false),
        ("rhs_evals", "", false),
    ] {
        c.push((n.to_string(), u, t));
    }
    c
}

/// A finished variant's summary row, beside its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// In [`Outputs::columns`]' order; NaN is null.
    pub outputs: Vec<f64>,
    pub status: RunStatus,
    /// Empty where there is none.
    pub error: String,
    pub error_class: String,
    pub warnings: String,
    /// Which back end ran the variant: `generated` (the built model's code, its free
    /// parameters set) or `interpreted`.
    pub backend: String,
    pub t_reached_s: f64,
    pub steps: f64,
    pub rejected_steps: f64,
    pub rhs_evals: f64,
}

/// `summary.parquet` of variant `v` into `dir`: one row.
pub fn write_summary(dir: &Path, study: &Study, v: &Variant, row: &Row) -> Result<(), Error> {
    let extra = summary_columns(&study.outputs);
    let np = study.parameters.len();
    let mut names = vec!["variant_id".to_string()];
    names.extend(study.parameters.iter().map(|p| p.text.clone()));
    names.extend(extra.iter().map(|c| c.0.clone()));
    let mut text = vec![true];
    text.extend(std::iter::repeat_n(false, np));
    text.extend(extra.iter().map(|c| c.2));
    // Outputs may be null (not resolved, or the variant failed); parameters and counters not.
    let no = study.outputs.columns().len();
    let mut nullable = vec![false; 1 + np];
    nullable.extend(std::iter::repeat_n(true, no));
    nullable.extend(std::iter::repeat_n(false, extra.len() - no));
    let mut metadata: Vec<(String, String)> = extra
        .iter()
        .filter(|c| !c.1.is_empty())
        .map(|c| (format!("unit:{}", c.0), c.1.to_string()))
        .collect();
    metadata.push((
        "washdyn".into(),
        "one variant of a washdyn study: its parameters by path, its outputs (null where not \
         resolved or the variant failed) and its run; wall time in timing/"
            .into(),
    ));
    let mut cols = vec![Column::Text(vec![v.id.clone()])];
    cols.extend(v.values.iter().map(|x| Column::F64(vec![*x])));
    cols.extend(row.outputs.iter().map(|x| Column::F64(vec![*x])));
    cols.push(Column::Text(vec![row.status.name().to_string()]));
    for t in [&row.error, &row.error_class, &row.warnings, &row.backend] {
        cols.push(Column::Text(vec![t.clone()]));
    }
    for x in [
        row.t_reached_s,
        row.steps,
        row.rejected_steps,
        row.rhs_evals,
    ] {
        cols.push(Column::F64(vec![x]));
    }
    write_table(
        &dir.join("summary.parquet"),
        &names,
        &text,
        &nullable,
        &metadata,
        &cols,
    )
}

/// `timing.parquet` of variant `id` into `dir`: its wall time, s.
pub fn write_timing(dir: &Path, id: &str, wall_time_s: f64) -> Result<(), Error> {
    let names = ["variant_id", "wall_time_s"].map(String::from);
    write_table(
        &dir.join("timing.parquet"),
        &names,
        &[true, false],
        &[false, false],
        &[("unit:wall_time_s".into(), "s".into())],
        &[
            Column::Text(vec![id.to_string()]),
            Column::F64(vec![wall_time_s]),
        ],
    )
}
