//! What a study refuses: its file (each problem at its file, line and column), variants the
//! checker refuses (nothing runs then), and an output directory that is not this study's.
//! Part of `washdyn::Error` (`Error::Study`; re-exported as `washdyn::study::StudyError`), so `washdyn`'s exit code maps it with the rest.

use std::fmt;
use std::path::PathBuf;
use washdyn_model::ir::toml_file::Located;

/// A variant the model refuses: its id, its parameter values, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct BadVariant {
    pub id: String,
    /// (path as the study file writes it, value); the parameter the finding names first.
    pub values: Vec<(String, f64)>,
    /// The checker's findings, or why the value could not be set.
    pub message: String,
}

impl fmt::Display for BadVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let values: Vec<String> = self
            .values
            .iter()
            .map(|(p, v)| format!("{p} = {v}"))
            .collect();
        write!(
            f,
            "variant {} ({}): {}",
            self.id,
            values.join(", "),
            self.message
        )
    }
}

/// Variants listed in a refusal at most; the count says how many more.
const SHOWN: usize = 10;

#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The study file: every problem found, each at its file, line and column.
    #[error("{}", .0.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("\n"))]
    File(Vec<Located>),
    /// Variants whose model the checker refuses (or that cannot take their values): the study
    /// is refused before anything runs or is written.
    #[error("{}", variants(.0))]
    Variants(Vec<BadVariant>),
    /// The study's directory: not a study's, another study's, or one whose files disagree.
    #[error("{}: {message}", dir.display())]
    Directory { dir: PathBuf, message: String },
    /// A run on Slurm: its commands failing, tasks still queued, a task's assignment.
    #[error(transparent)]
    Slurm(#[from] super::slurm::SlurmError),
}

fn variants(bad: &[BadVariant]) -> String {
    let mut lines = vec![format!(
        "the study is refused, nothing ran: {} variant{} the model checker refuses",
        bad.len(),
        if bad.len() == 1 { "" } else { "s" }
    )];
    lines.extend(bad.iter().take(SHOWN).map(|b| format!("  {b}")));
    if bad.len() > SHOWN {
        lines.push(format!("  and {} more", bad.len() - SHOWN));
    }
    lines.join("\n")
}

impl StudyError {
    /// One problem of the study file `file` at (line, column).
    pub fn at(file: &str, (line, column): (usize, usize), message: impl Into<String>) -> Self {
        StudyError::File(vec![Located {
            file: file.to_string(),
            line,
            column,
            message: message.into(),
        }])
    }

    /// A directory refused, with why.
    pub fn dir(dir: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        StudyError::Directory {
            dir: dir.into(),
            message: message.into(),
        }
    }
}
