//! Slurm's view of a study's jobs, from `squeue` and `scontrol` alone (clusters without
//! accounting have no `sacct`): the tasks still queued, each task's state, the wait for an
//! array to end, and the refusal to run a study whose tasks are still queued.

use super::{Assignment, Error, SlurmError, assignment_file, jobs, read_json, slurm};
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

/// A query of a job that may have left the controller's memory: empty then.
fn query(program: &str, args: &[&str]) -> Result<String, SlurmError> {
    match slurm(program, args) {
        Err(SlurmError::Failed { stderr, .. }) if stderr.contains("Invalid job id") => {
            Ok(String::new())
        }
        r => r,
    }
}

/// Refuse while tasks of the study's recorded jobs are queued or running (a run's plan removes
/// tmp directories, theirs too). Nothing to ask without `slurm/jobs.json`.
pub fn check_idle(dir: &Path) -> Result<(), Error> {
    let mut busy = Vec::new();
    for j in jobs(dir)?.jobs {
        busy.extend(queue(&j.job_id)?.into_iter().map(|(k, s)| match k {
            Some(k) => format!("{}_{k} {s}", j.job_id),
            None => format!("{} {s}", j.job_id),
        }));
    }
    if busy.is_empty() {
        Ok(())
    } else {
        Err(SlurmError::Busy {
            dir: dir.to_path_buf(),
            tasks: busy,
        }
        .into())
    }
}

/// A job's tasks in the queue (pending, running, completing): (index, state) from
/// `squeue -h -j ID -r -o '%i %T'`; index None for a job that is no array.
pub fn queue(job: &str) -> Result<Vec<(Option<usize>, String)>, Error> {
    let args = ["-h", "-j", job, "-r", "-o", "%i %T"];
    let out = query("squeue", &args)?;
    let mut tasks = Vec::new();
    for line in out.lines().filter(|l| !l.trim().is_empty()) {
        let bad = |why: &str| SlurmError::Answer {
            command: format!("squeue {}", args.join(" ")),
            answer: line.into(),
            why: why.into(),
        };
        let (id, state) = line
            .trim()
            .split_once(' ')
            .ok_or_else(|| bad("expected `ID STATE`"))?;
        match id.split_once('_') {
            None => tasks.push((None, state.to_string())),
            Some((_, k)) => {
                let ks = indices(k.trim_start_matches('[').trim_end_matches(']'))
                    .ok_or_else(|| bad("expected JOB_INDEX or JOB_[RANGES]"))?;
                tasks.extend(ks.into_iter().map(|k| (Some(k), state.to_string())));
            }
        }
    }
    Ok(tasks)
}

/// Slurm's array indices: `3`, `0-5`, `1,4-6`, `0-9:2`, with an optional `%K` throttle.
pub fn indices(s: &str) -> Option<Vec<usize>> {
    let s = s.split('%').next()?;
    let mut out = Vec::new();
    for part in s.split(',') {
        let (range, step) = match part.split_once(':') {
            Some((r, st)) => (r, st.parse::<usize>().ok().filter(|&x| x > 0)?),
            None => (part, 1),
        };
        let (a, b): (usize, usize) = match range.split_once('-') {
            Some((a, b)) => (a.parse().ok()?, b.parse().ok()?),
            None => {
                let a = range.parse().ok()?;
                (a, a)
            }
        };
        if b < a {
            return None;
        }
        out.extend((a..=b).step_by(step));
    }
    Some(out)
}

/// Task states from `scontrol -o show job ID` (one line a task, finished ones too while the
/// controller keeps them: `MinJobAge`).
fn controller(job: &str) -> Result<BTreeMap<usize, String>, Error> {
    let out = query("scontrol", &["-o", "show", "job", job])?;
    let mut states = BTreeMap::new();
    for line in out.lines() {
        let field = |key: &str| {
            line.split_whitespace()
                .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
        };
        if field("ArrayJobId") != Some(job) {
            continue;
        }
        let (Some(ks), Some(state)) = (field("ArrayTaskId"), field("JobState")) else {
            continue;
        };
        let ks = indices(ks).ok_or_else(|| SlurmError::Answer {
            command: format!("scontrol -o show job {job}"),
            answer: line.into(),
            why: "ArrayTaskId is no list of indices".into(),
        })?;
        for k in ks {
            states.insert(k, state.to_string());
        }
    }
    Ok(states)
}

/// One array task as Slurm sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskView {
    pub index: usize,
    /// Slurm's state (PENDING, RUNNING, COMPLETED, CANCELLED, FAILED, ...), or [`GONE`].
    pub state: String,
    pub variants: Vec<String>,
}

/// A task neither `squeue` nor `scontrol` knows: finished and forgotten (`MinJobAge`), or
/// cancelled while pending (which leaves no trace). The dataset tells whether it ran.
pub const GONE: &str = "gone";

/// A state and how many tasks are in it.
pub type StateCount = (String, usize);

/// (state, tasks) in order of first appearance.
fn count_states<'a>(states: impl Iterator<Item = &'a str>) -> Vec<StateCount> {
    let mut c: Vec<StateCount> = Vec::new();
    for s in states {
        match c.iter_mut().find(|(x, _)| x == s) {
            Some((_, n)) => *n += 1,
            None => c.push((s.to_string(), 1)),
        }
    }
    c
}

/// One recorded job as Slurm sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct JobView {
    pub job_id: String,
    pub tasks: Vec<TaskView>,
}

impl JobView {
    /// Tasks by state.
    pub fn counts(&self) -> Vec<StateCount> {
        count_states(self.tasks.iter().map(|t| t.state.as_str()))
    }
}

impl fmt::Display for JobView {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let counts: Vec<String> = self
            .counts()
            .iter()
            .map(|(s, n)| format!("{n} {s}"))
            .collect();
        write!(
            f,
            "slurm job {}: {} tasks: {}",
            self.job_id,
            self.tasks.len(),
            counts.join(", ")
        )
    }
}

/// Slurm's view of every job recorded in `dir`, oldest first (empty without `slurm/jobs.json`).
pub fn view(dir: &Path) -> Result<Vec<JobView>, Error> {
    let mut out = Vec::new();
    for j in jobs(dir)?.jobs {
        let a: Assignment = read_json(&assignment_file(dir, &j.job_id))?;
        let queued: BTreeMap<usize, String> = queue(&j.job_id)?
            .into_iter()
            .filter_map(|(k, s)| Some((k?, s)))
            .collect();
        // The controller's answer is the later one: it wins where both know a task.
        let known = controller(&j.job_id)?;
        let tasks = a
            .chunks
            .iter()
            .enumerate()
            .map(|(k, ids)| TaskView {
                index: k,
                state: known
                    .get(&k)
                    .or(queued.get(&k))
                    .cloned()
                    .unwrap_or_else(|| GONE.to_string()),
                variants: ids.clone(),
            })
            .collect();
        out.push(JobView {
            job_id: j.job_id,
            tasks,
        });
    }
    Ok(out)
}

/// Poll the queue every `every` until none of `job`'s tasks is in it; `changed` gets the
/// queue's (state, tasks) counts whenever they change.
pub fn wait(
    job: &str,
    every: std::time::Duration,
    changed: &mut dyn FnMut(&[StateCount]),
) -> Result<(), Error> {
    let mut last = None;
    loop {
        let q = queue(job)?;
        let counts = count_states(q.iter().map(|(_, s)| s.as_str()));
        if last.as_ref() != Some(&counts) {
            changed(&counts);
            last = Some(counts);
        }
        if q.is_empty() {
            return Ok(());
        }
        std::thread::sleep(every);
    }
}
