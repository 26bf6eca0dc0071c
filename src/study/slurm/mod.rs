//! A study on a Slurm cluster (`washdyn study run --slurm`): the variants still to run at
//! submission split into N chunks, one array task a chunk, each task `washdyn study task DIR
//! --chunk K --chunks N`, which runs its chunk through [`execute`](super::execute), so the files
//! are the local run's to the byte. Under `DIR/slurm/`:
//!
//! ```text
//! job.sh              the last submission's sbatch script
//! jobs.json           every submission: job id, tasks, variants (a study is resubmitted until done)
//! job-<id>.json       that job's chunks: the variant ids of each task, and the study file
//! task-<id>_<k>.out   each task's stdout (.err: stderr)
//! ```
//!
//! The job is submitted held, its chunk file written under its id, then released: a task reads
//! the list fixed at submission, never a plan of a directory other tasks are writing into.
//! Slurm's view is read from `squeue` and `scontrol` only: clusters without accounting have no
//! `sacct`, and a task that left the controller's memory is reported gone, not as an error.

use super::dataset::{Layout, Record};
use super::file::Study;
use super::run::Plan;
use super::variants::variants;
use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The folder under the study's directory.
pub const SLURM: &str = "slurm";

mod queue;
pub use queue::{GONE, JobView, StateCount, TaskView, check_idle, indices, queue, view, wait};

/// Array tasks a submission makes at most by default: Slurm's default `MaxArraySize` (1001)
/// allows indices up to 1000.
pub const DEFAULT_MAX_TASKS: usize = 1000;

pub use crate::error::slurm::SlurmError;

/// The submission's options (`washdyn study run --slurm`); None leaves Slurm's default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    /// Array tasks (default: one a variant still to run, at most [`DEFAULT_MAX_TASKS`]); more
    /// than there are variants to run makes one a variant.
    pub tasks: Option<usize>,
    /// Tasks running at once (`--array=...%K`).
    pub throttle: Option<usize>,
    pub cpus_per_task: Option<usize>,
    /// sbatch's `--mem`: a number with an optional unit K, M, G or T.
    pub mem: Option<String>,
    /// sbatch's `--time`: minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS.
    pub time: Option<String>,
    pub partition: Option<String>,
}

impl Options {
    /// Every refused option at once, before anything is written or submitted.
    pub fn check(&self) -> Result<(), Error> {
        let mut refusals = Vec::new();
        let mut refuse = |option: &'static str, message: String| {
            refusals.push(crate::error::Refusal::plain(option, message));
        };
        for (option, v) in [
            ("--tasks", self.tasks),
            ("--throttle", self.throttle),
            ("--cpus-per-task", self.cpus_per_task),
        ] {
            if v == Some(0) {
                refuse(option, format!("{option} must be at least 1, got 0"));
            }
        }
        if let Some(m) = &self.mem
            && !mem_ok(m)
        {
            refuse(
                "--mem",
                format!(
                    "--mem `{m}`: expected a number of megabytes or a number with K, M, G or T"
                ),
            );
        }
        if let Some(t) = &self.time
            && !time_ok(t)
        {
            refuse(
                "--time",
                format!(
                    "--time `{t}`: expected minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS"
                ),
            );
        }
        if let Some(p) = &self.partition
            && (p.is_empty()
                || !p
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c)))
        {
            refuse(
                "--partition",
                format!("--partition `{p}`: expected a partition's name (letters, digits, _ - .)"),
            );
        }
        if refusals.is_empty() {
            Ok(())
        } else {
            Err(Error::Settings(refusals))
        }
    }
}

fn digits(s: &str) -> bool {
    !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit())
}

fn mem_ok(m: &str) -> bool {
    let n = m.strip_suffix(['K', 'M', 'G', 'T']).unwrap_or(m);
    digits(n) && n.bytes().any(|b| b != b'0')
}

/// Slurm's time formats (sbatch(1), `--time`).
fn time_ok(t: &str) -> bool {
    let parts = |s: &str, n: std::ops::RangeInclusive<usize>| {
        let p: Vec<&str> = s.split(':').collect();
        n.contains(&p.len()) && p.iter().all(|x| digits(x))
    };
    match t.split_once('-') {
        Some((d, rest)) => digits(d) && parts(rest, 1..=3),
        None => parts(t, 1..=3),
    }
}

/// `DIR/slurm/jobs.json`: every submission of the study, oldest first.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Jobs {
    pub jobs: Vec<Job>,
}

/// One submission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Job {
    pub job_id: String,
    pub tasks: usize,
    /// Variants it runs (those not finished at submission).
    pub variants: usize,
}

/// `DIR/slurm/job-<id>.json`: what each task of a job runs, fixed at submission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Assignment {
    pub job_id: String,
    /// The study file, absolute: a task loads it (its model file is relative to it) and checks
    /// it is still the study of the directory.
    pub study_file: PathBuf,
    /// Per task, its variants' ids.
    pub chunks: Vec<Vec<String>>,
}

/// `todo` in `n` contiguous chunks of sizes differing by one at most (the larger first), in
/// order: a function of the list alone, so a job's tasks split it one way.
pub fn chunks(todo: &[String], n: usize) -> Vec<Vec<String>> {
    let n = n.clamp(1, todo.len().max(1));
    (0..n)
        .map(|k| todo[k * todo.len() / n..(k + 1) * todo.len() / n].to_vec())
        .collect()
}

fn slurm_dir(dir: &Path) -> PathBuf {
    dir.join(SLURM)
}

fn jobs_file(dir: &Path) -> PathBuf {
    slurm_dir(dir).join("jobs.json")
}

fn assignment_file(dir: &Path, job: &str) -> PathBuf {
    slurm_dir(dir).join(format!("job-{job}.json"))
}

/// The submissions recorded in `dir` (none without `slurm/jobs.json`).
pub fn jobs(dir: &Path) -> Result<Jobs, Error> {
    let path = jobs_file(dir);
    if !path.exists() {
        return Ok(Jobs::default());
    }
    read_json(&path)
}

fn read_json<T: for<'a> Deserialize<'a>>(path: &Path) -> Result<T, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io("read", path, e))?;
    serde_json::from_str(&text).map_err(|e| {
        SlurmError::Assignment {
            path: path.to_path_buf(),
            message: format!("not washdyn's: {e}"),
        }
        .into()
    })
}

fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let tmp = path.with_extension(format!("tmp-{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| Error::io("write", &tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| Error::io("rename into place", path, e))
}

/// Run a Slurm command: its stdout, or why not.
fn slurm(program: &str, args: &[&str]) -> Result<String, SlurmError> {
    let command = std::iter::once(program)
        .chain(args.iter().copied())
        .collect::<Vec<_>>()
        .join(" ");
    let out = Command::new(program)
        .args(args)
        .output()
        .map_err(|source| SlurmError::Missing {
            command: command.clone(),
            source,
        })?;
    if !out.status.success() {
        return Err(SlurmError::Failed {
            command,
            status: out.status.to_string(),
            stderr: String::from_utf8_lossy(&out.stderr).trim().to_string(),
        });
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// A path an sbatch script names: characters that survive its `#SBATCH` lines, Slurm's `%`
/// patterns and the shell's single quotes.
fn nameable(path: &Path) -> Result<String, SlurmError> {
    let s = path.to_str().ok_or_else(|| SlurmError::Path {
        path: path.to_path_buf(),
        why: "not UTF-8: an sbatch script cannot name it".into(),
    })?;
    if let Some(c) = s
        .chars()
        .find(|c| c.is_whitespace() || c.is_control() || "%'\"\\$`".contains(*c))
    {
        return Err(SlurmError::Path {
            path: path.to_path_buf(),
            why: format!(
                "holds {c:?}, which an sbatch script's options or Slurm's file patterns would \
                 change: give a path without it"
            ),
        });
    }
    Ok(s.to_string())
}

/// The sbatch script: an array of `tasks` tasks, each `exe study task DIR --chunk K --chunks N`.
pub fn script(dir: &Path, exe: &Path, tasks: usize, opts: &Options) -> Result<String, Error> {
    let d = nameable(dir)?;
    let exe = nameable(exe)?;
    let mut s = format!(
        "#!/bin/sh\n\
         # Written by `washdyn study run --slurm`: task K runs chunk K of the variants that were\n\
         # still to run at submission ({d}/slurm/job-<job id>.json lists them).\n\
         #SBATCH --job-name=washdyn-study\n\
         #SBATCH --array=0-{}{}\n\
         #SBATCH --output={d}/slurm/task-%A_%a.out\n\
         #SBATCH --error={d}/slurm/task-%A_%a.err\n",
        tasks - 1,
        opts.throttle.map_or(String::new(), |k| format!("%{k}"))
    );
    for (key, v) in [
        ("cpus-per-task", opts.cpus_per_task.map(|c| c.to_string())),
        ("mem", opts.mem.clone()),
        ("time", opts.time.clone()),
        ("partition", opts.partition.clone()),
    ] {
        if let Some(v) = v {
            s += &format!("#SBATCH --{key}={v}\n");
        }
    }
    s += &format!(
        "exec '{exe}' study task '{d}' --chunk \"$SLURM_ARRAY_TASK_ID\" --chunks {tasks}\n"
    );
    Ok(s)
}

/// A submission.
#[derive(Clone, Debug, PartialEq)]
pub struct Submitted {
    pub job_id: String,
    pub chunks: Vec<Vec<String>>,
    pub script: PathBuf,
}

/// Submit the plan's variants still to run as one job array (none: nothing to run). `exe` is
/// the washdyn the tasks run (the running one). Held until its chunk file is written under its
/// id, then released; a failure in between cancels it.
pub fn submit(
    study: &Study,
    plan: &Plan,
    opts: &Options,
    exe: &Path,
) -> Result<Option<Submitted>, Error> {
    opts.check()?;
    if plan.todo.is_empty() {
        return Ok(None);
    }
    let dir = std::path::absolute(&plan.layout.root)
        .map_err(|e| Error::io("resolve", &plan.layout.root, e))?;
    let study_file =
        std::fs::canonicalize(&study.file).map_err(|e| Error::io("resolve", &study.file, e))?;
    let todo: Vec<String> = plan.todo.iter().map(|v| v.id.clone()).collect();
    let n = opts.tasks.unwrap_or(DEFAULT_MAX_TASKS).min(todo.len());
    let chunks = chunks(&todo, n);
    let text = script(&dir, exe, chunks.len(), opts)?;
    let sd = slurm_dir(&dir);
    std::fs::create_dir_all(&sd).map_err(|e| Error::io("create", &sd, e))?;
    let mut record = jobs(&dir)?;
    let path = sd.join("job.sh");
    write_atomic(&path, text.as_bytes())?;
    let p = path.to_string_lossy();
    let out = slurm("sbatch", &["--parsable", "--hold", &p])?;
    let answer = out.trim();
    let id = answer.split(';').next().unwrap_or_default();
    if !digits(id) {
        return Err(SlurmError::Answer {
            command: format!("sbatch --parsable --hold {p}"),
            answer: answer.into(),
            why: "expected a job id".into(),
        }
        .into());
    }
    let release = || -> Result<(), Error> {
        assign(
            &dir,
            &Assignment {
                job_id: id.into(),
                study_file,
                chunks: chunks.clone(),
            },
        )?;
        record.jobs.push(Job {
            job_id: id.into(),
            tasks: chunks.len(),
            variants: todo.len(),
        });
        let json = serde_json::to_string_pretty(&record).expect("jobs serialise") + "\n";
        write_atomic(&jobs_file(&dir), json.as_bytes())?;
        slurm("scontrol", &["release", id])?;
        Ok(())
    };
    if let Err(e) = release() {
        let _ = slurm("scancel", &[id]);
        return Err(e);
    }
    Ok(Some(Submitted {
        job_id: id.into(),
        chunks,
        script: path,
    }))
}

/// Write job `a.job_id`'s chunk file into `dir`: what its tasks run. `submit` writes it while
/// the job is held; the overhead bench writes one for tasks it starts itself, without Slurm.
pub fn assign(dir: &Path, a: &Assignment) -> Result<(), Error> {
    let sd = slurm_dir(dir);
    std::fs::create_dir_all(&sd).map_err(|e| Error::io("create", &sd, e))?;
    let json = serde_json::to_string_pretty(a).expect("an assignment serialises") + "\n";
    write_atomic(&assignment_file(dir, &a.job_id), json.as_bytes())
}

/// What task `chunk` of `chunks` of `job` runs in `dir`: the study (from the file recorded at
/// submission, which must still be the directory's study) and a plan of its chunk's variants.
/// Nothing is removed or rewritten: other tasks are writing into the directory.
pub fn task_plan(
    dir: &Path,
    job: &str,
    chunk: usize,
    chunks: usize,
) -> Result<(Study, Plan), Error> {
    let path = assignment_file(dir, job);
    if !path.is_file() {
        return Err(SlurmError::Assignment {
            path,
            message: format!("no chunk file for job {job}: not a job `washdyn study run --slurm` submitted for this directory"),
        }
        .into());
    }
    let a: Assignment = read_json(&path)?;
    let bad = |message: String| -> Error {
        SlurmError::Assignment {
            path: path.clone(),
            message,
        }
        .into()
    };
    if a.chunks.len() != chunks {
        return Err(bad(format!(
            "job {job} has {} chunks, the task was told {chunks}",
            a.chunks.len()
        )));
    }
    let Some(ids) = a.chunks.get(chunk) else {
        return Err(bad(format!(
            "chunk {chunk} out of range: job {job} has chunks 0 to {}",
            chunks - 1
        )));
    };
    let study = Study::load(&a.study_file)?;
    let vars = variants(&study);
    if Record::new(&study, &vars) != Record::read(dir)? {
        return Err(bad(format!(
            "{} is no longer the study of this directory (changed since submission)",
            a.study_file.display()
        )));
    }
    let todo = ids
        .iter()
        .map(|id| {
            vars.iter()
                .find(|v| &v.id == id)
                .cloned()
                .ok_or_else(|| bad(format!("variant {id} is not in the study")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let plan = Plan {
        layout: Layout::new(dir),
        variants: vars,
        todo,
        removed_tmp: 0,
    };
    Ok((study, plan))
}

impl From<SlurmError> for Error {
    fn from(e: SlurmError) -> Error {
        Error::Study(e.into())
    }
}
