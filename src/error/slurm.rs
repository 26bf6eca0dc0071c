//! What Slurm's commands refuse or answer (`washdyn study run --slurm`), with the crate's
//! errors so that the error enum reaches no module above it.

use std::path::PathBuf;

/// Tasks listed in a refusal at most; the count says how many more.
const SHOWN: usize = 10;

/// What Slurm's commands refuse or answer, and a task's assignment that does not fit.
#[derive(Debug, thiserror::Error)]
pub enum SlurmError {
    /// A Slurm command that could not be started.
    #[error(
        "cannot run `{command}`: {source} (Slurm's client commands: the Debian package slurm-client)"
    )]
    Missing {
        command: String,
        #[source]
        source: std::io::Error,
    },
    /// A Slurm command that failed: its exit status and what it wrote to stderr.
    #[error("`{command}` failed ({status}): {stderr}{}", conf_hint())]
    Failed {
        command: String,
        status: String,
        stderr: String,
    },
    /// An answer that is not what the command prints.
    #[error("`{command}` answered `{answer}`: {why}")]
    Answer {
        command: String,
        answer: String,
        why: String,
    },
    /// The study's jobs still have tasks queued or running: a new run would remove their tmp
    /// directories under them.
    #[error(
        "{}: tasks of this study are still in Slurm's queue ({}): wait for them (`washdyn study \
         status`) or cancel them (scancel) before running it again",
        dir.display(), listed(tasks)
    )]
    Busy { dir: PathBuf, tasks: Vec<String> },
    /// A path an sbatch script cannot name as it is.
    #[error("{}: {why}", path.display())]
    Path { path: PathBuf, why: String },
    /// A task's assignment: no chunk file for its job, a chunk out of range, or a study that
    /// changed since submission.
    #[error("{}: {message}", path.display())]
    Assignment { path: PathBuf, message: String },
}

pub(crate) fn listed(tasks: &[String]) -> String {
    let mut s = tasks[..tasks.len().min(SHOWN)].join(", ");
    if tasks.len() > SHOWN {
        s += &format!(" and {} more", tasks.len() - SHOWN);
    }
    s
}

/// Without `SLURM_CONF` the client commands look for the cluster in DNS and /etc.
pub(crate) fn conf_hint() -> &'static str {
    if std::env::var_os("SLURM_CONF").is_none() {
        " (SLURM_CONF is not set: export it to the cluster's slurm.conf)"
    } else {
        ""
    }
}
