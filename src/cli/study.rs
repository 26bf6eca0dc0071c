//! `washdyn study run | status | collect | task`: their arguments, the study's progress and
//! report on the terminal; the study itself is `washdyn::study` (on Slurm:
//! `washdyn::study::slurm`).

use super::progress::duration;
use super::{Failure, interrupt_flag, wrote};
use clap::Subcommand;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use washdyn::Error;
use washdyn::study::{self, Study, slurm};
use washdyn_runtime::run::{RunError, RunStatus};

/// `washdyn study`'s arguments: one of its commands.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub cmd: StudyCmd,
}

#[derive(Subcommand)]
pub enum StudyCmd {
    /// Check every variant, then run those not finished in DIR (missing or failed):
    /// DIR/variants/variant=<id>/sensors.parquet, DIR/summary/variant=<id>/summary.parquet,
    /// DIR/timing/variant=<id>/timing.parquet, with the study and its design beside them.
    Run {
        /// The study file.
        study: PathBuf,
        /// The study's directory (default: out/<study file's stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Parallel runs (default: all cores).
        #[arg(long, conflicts_with = "slurm")]
        jobs: Option<usize>,
        #[command(flatten)]
        slurm: SlurmArgs,
    },
    /// How many variants are done, failed (and why) and missing; with a study submitted to
    /// Slurm, each job's tasks as `squeue` and `scontrol` see them.
    Status {
        /// The study's directory.
        dir: PathBuf,
    },
    /// Every summary row in variant order with its wall time: DIR/summary.parquet and
    /// DIR/summary.csv.
    Collect {
        /// The study's directory.
        dir: PathBuf,
    },
    /// Internal: one array task of `study run --slurm` (DIR/slurm/job.sh runs it), the
    /// variants of chunk K as its job's chunk file lists them.
    #[command(hide = true)]
    Task {
        /// The study's directory.
        dir: PathBuf,
        /// This task's chunk (SLURM_ARRAY_TASK_ID).
        #[arg(long)]
        chunk: usize,
        /// The job's chunks.
        #[arg(long)]
        chunks: usize,
        /// The job (default: SLURM_ARRAY_JOB_ID).
        #[arg(long)]
        job: Option<String>,
        /// Parallel runs (default: SLURM_CPUS_PER_TASK, else 1).
        #[arg(long)]
        jobs: Option<usize>,
    },
}

/// `washdyn study run --slurm`'s options: the variants still to run as one Slurm job array.
#[derive(clap::Args)]
pub struct SlurmArgs {
    /// Submit to Slurm (sbatch; SLURM_CONF names the cluster) instead of running here: the
    /// variants still to run in N chunks, one array task each (DIR/slurm/job.sh), recorded in
    /// DIR/slurm/jobs.json; prints the job id.
    #[arg(long)]
    pub slurm: bool,
    /// Array tasks, N (default: one a variant still to run, at most 1000).
    #[arg(long, requires = "slurm")]
    pub tasks: Option<usize>,
    /// Tasks running at once, K (`--array=0-(N-1)%K`; default: Slurm's).
    #[arg(long, requires = "slurm")]
    pub throttle: Option<usize>,
    /// CPUs of each task (its variants run on as many threads).
    #[arg(long, requires = "slurm")]
    pub cpus_per_task: Option<usize>,
    /// Memory of each task, sbatch's --mem (`500M`, `2G`).
    #[arg(long, requires = "slurm")]
    pub mem: Option<String>,
    /// Time limit of each task, sbatch's --time (`30`, `1:00:00`, `1-00:00`).
    #[arg(long, requires = "slurm")]
    pub time: Option<String>,
    /// Partition, sbatch's --partition.
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// Wait for the array to end (polling squeue), then report as `study status` does.
    #[arg(long, requires = "slurm")]
    pub wait: bool,
}

/// Variants whose warnings or errors are printed at most; the rest are counted.
const SHOWN: usize = 10;

/// How often `--wait` asks squeue.
const POLL: std::time::Duration = std::time::Duration::from_secs(1);

/// `washdyn study run | status | collect | task`.
pub fn study(a: Args) -> Result<ExitCode, Failure> {
    match a.cmd {
        StudyCmd::Run {
            study: file,
            out,
            jobs,
            slurm,
        } => {
            let mut s = Study::load(&file)?;
            s.control.guard.interrupt = Some(interrupt_flag());
            let out = out.unwrap_or_else(|| s.default_out());
            if slurm.slurm {
                return submit(&s, &out, &slurm);
            }
            run_here(&s, &out, jobs)
        }
        StudyCmd::Task {
            dir,
            chunk,
            chunks,
            job,
            jobs,
        } => task(&dir, chunk, chunks, job, jobs),
        StudyCmd::Status { dir } => {
            status(&dir)?;
            Ok(ExitCode::SUCCESS)
        }
        StudyCmd::Collect { dir } => {
            let c = study::collect(&dir)?;
            let mut out = std::io::stdout();
            let _ = writeln!(out, "{} rows in variant order", c.rows);
            if !c.missing.is_empty() {
                let _ = writeln!(
                    out,
                    "not in the table (no summary yet): {}",
                    c.missing.join(", ")
                );
            }
            Ok(wrote(c.files))
        }
    }
}

/// `study run` on this machine (and `sweep`): check and plan, run the variants still to run on
/// `jobs` threads (default: all cores) with its progress (`study_line`), report.
pub fn run_here(s: &Study, out: &Path, jobs: Option<usize>) -> Result<ExitCode, Failure> {
    let jobs = jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
    study::check_jobs(jobs)?;
    // Tasks of an earlier submission still running would lose their tmp directories.
    slurm::check_idle(out)?;
    let plan = study::plan(s, out)?;
    planned(out, &plan);
    let reporter = super::progress::Reporter::new(plan.todo.len() as u64);
    let counts = Arc::new([AtomicUsize::new(0), AtomicUsize::new(0)]);
    reporter.live(study_line(plan.todo.len(), counts.clone()));
    let done = |o: &study::Outcome| {
        let n = counts[0].fetch_add(1, Ordering::Relaxed) + 1;
        if o.status == RunStatus::Failed {
            counts[1].fetch_add(1, Ordering::Relaxed);
        }
        reporter.position(n as u64);
    };
    let res = study::execute(s, &plan, jobs, &done)?;
    drop(reporter);
    report(s, &plan, &res, out)
}

/// A study's progress line from its counts (variants finished, failed): `variants 3 / 10
/// done (1 failed), 2 min 10 s wall, projected end in 4 min 53 s`, the end projected from the
/// mean wall time a variant took so far (the jobs in parallel included).
fn study_line(total: usize, counts: Arc<[AtomicUsize; 2]>) -> impl Fn() -> String + Send + 'static {
    let start = std::time::Instant::now();
    move || {
        let (done, failed) = (
            counts[0].load(Ordering::Relaxed),
            counts[1].load(Ordering::Relaxed),
        );
        let wall = start.elapsed().as_secs_f64();
        let end = match done {
            0 => "not yet known".to_string(),
            n => format!("in {}", duration(wall / n as f64 * (total - n) as f64)),
        };
        format!(
            "variants {done} / {total} done ({failed} failed), {} wall, projected end {end}",
            duration(wall)
        )
    }
}

/// The plan's first line: what is to run.
fn planned(out: &Path, plan: &study::Plan) {
    println!(
        "{}: {} variants, {} to run ({} finished before){}",
        out.display(),
        plan.variants.len(),
        plan.todo.len(),
        plan.variants.len() - plan.todo.len(),
        match plan.removed_tmp {
            0 => String::new(),
            n => format!("; removed {n} tmp directories of a killed run"),
        }
    );
}

/// After a run (local, or one Slurm task): the warnings, the failures, the exit code.
fn report(
    s: &Study,
    plan: &study::Plan,
    res: &[study::Outcome],
    out: &Path,
) -> Result<ExitCode, Failure> {
    // The set-up's own warning (a loose tolerance) is every variant's: said once.
    let (method, tol) = s.spec.solver(&s.source.model);
    let common = washdyn::error_class::tolerance_warning(method, tol);
    if let Some(w) = &common {
        eprintln!("warning: {w}");
    }
    // A study's variants often warn alike: the first few here, all in the summaries.
    let warned: Vec<&study::Outcome> = res
        .iter()
        .filter(|o| o.status != RunStatus::Interrupted)
        .filter(|o| o.warnings.iter().any(|w| Some(w) != common.as_ref()))
        .collect();
    for o in warned.iter().take(SHOWN) {
        for w in o.warnings.iter().filter(|w| Some(*w) != common.as_ref()) {
            eprintln!("warning: variant {}: {w}", o.id);
        }
    }
    if warned.len() > SHOWN {
        eprintln!(
            "warning: {} more variants warned (the summaries' `warnings` column)",
            warned.len() - SHOWN
        );
    }
    let failed: Vec<&study::Outcome> = res
        .iter()
        .filter(|o| o.status == RunStatus::Failed)
        .collect();
    for o in failed.iter().take(SHOWN) {
        eprintln!(
            "variant {} failed: {}",
            o.id,
            o.error.as_deref().unwrap_or("")
        );
    }
    let interrupted =
        res.len() < plan.todo.len() || res.iter().any(|o| o.status == RunStatus::Interrupted);
    println!(
        "ran {} variants ({} failed); summaries: {}/summary (washdyn study collect {} for one \
         table)",
        res.iter()
            .filter(|o| o.status != RunStatus::Interrupted)
            .count(),
        failed.len(),
        out.display(),
        out.display()
    );
    if interrupted {
        let e = Error::integration(RunError::Interrupted { t: 0.0 });
        let kept = res
            .iter()
            .filter(|o| o.status != RunStatus::Interrupted)
            .count();
        eprintln!(
            "interrupted: {kept} variants finished here and {} before are kept in {}; run the \
             study again to complete it",
            plan.variants.len() - plan.todo.len(),
            out.display()
        );
        return Err(Failure::Printed(e));
    }
    Ok(if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// `study run --slurm`: plan as a local run does, submit the variants still to run, and with
/// `--wait` wait for the array and report as `status`.
fn submit(s: &Study, out: &Path, a: &SlurmArgs) -> Result<ExitCode, Failure> {
    let opts = slurm::Options {
        tasks: a.tasks,
        throttle: a.throttle,
        cpus_per_task: a.cpus_per_task,
        mem: a.mem.clone(),
        time: a.time.clone(),
        partition: a.partition.clone(),
    };
    opts.check()?;
    let exe = std::env::current_exe()
        .map_err(|e| Error::io("find the path of", "the running washdyn", e))?;
    slurm::check_idle(out)?;
    let plan = study::plan(s, out)?;
    planned(out, &plan);
    let Some(sub) = slurm::submit(s, &plan, &opts, &exe)? else {
        println!("nothing to submit: every variant has finished");
        return status(out);
    };
    let sizes: Vec<usize> = sub.chunks.iter().map(|c| c.len()).collect();
    let (lo, hi) = (sizes.iter().min(), sizes.iter().max());
    println!(
        "submitted slurm job {}: {} variants in {} tasks ({} a task){} ({})",
        sub.job_id,
        plan.todo.len(),
        sub.chunks.len(),
        if lo == hi {
            format!("{}", lo.unwrap_or(&0))
        } else {
            format!("{}-{}", lo.unwrap_or(&0), hi.unwrap_or(&0))
        },
        a.throttle
            .map_or(String::new(), |k| format!(", at most {k} at once")),
        sub.script.display()
    );
    if !a.wait {
        return Ok(ExitCode::SUCCESS);
    }
    slurm::wait(&sub.job_id, POLL, &mut |counts| {
        let c: Vec<String> = counts.iter().map(|(s, n)| format!("{n} {s}")).collect();
        match c.is_empty() {
            true => println!("slurm job {}: no task in the queue", sub.job_id),
            false => println!("slurm job {}: {}", sub.job_id, c.join(", ")),
        }
    })?;
    status(out)
}

/// `study task`: one array task's chunk, run as a local run runs it.
fn task(
    dir: &Path,
    chunk: usize,
    chunks: usize,
    job: Option<String>,
    jobs: Option<usize>,
) -> Result<ExitCode, Failure> {
    let Some(job) = job.or_else(|| std::env::var("SLURM_ARRAY_JOB_ID").ok()) else {
        return Err(Error::setting(
            "--job",
            "no --job and no SLURM_ARRAY_JOB_ID: `study task` is the task of a job `study run \
             --slurm` submitted",
        )
        .into());
    };
    let jobs = match (jobs, std::env::var("SLURM_CPUS_PER_TASK")) {
        (Some(j), _) => j,
        (None, Ok(c)) => c.trim().parse().map_err(|_| {
            Error::setting(
                "--jobs",
                format!("SLURM_CPUS_PER_TASK `{c}` is no count: give --jobs"),
            )
        })?,
        (None, Err(_)) => 1,
    };
    study::check_jobs(jobs)?;
    let (mut s, plan) = slurm::task_plan(dir, &job, chunk, chunks)?;
    s.control.guard.interrupt = Some(interrupt_flag());
    let ids: Vec<&str> = plan.todo.iter().map(|v| v.id.as_str()).collect();
    println!(
        "slurm job {job} task {chunk} of {chunks}: variants {} on {jobs} threads",
        ids.join(", ")
    );
    let done = |o: &study::Outcome| {
        println!(
            "variant {}: {} ({:.2} s, {} steps)",
            o.id, o.status, o.wall_time_s, o.steps
        );
    };
    let res = study::execute(&s, &plan, jobs, &done)?;
    report(&s, &plan, &res, dir)
}

/// `study status`: the dataset's standing, then each Slurm job's tasks where the study was
/// submitted. Exit code 1 while a variant failed or is missing.
fn status(dir: &Path) -> Result<ExitCode, Failure> {
    let st = study::status(dir)?;
    println!(
        "{}: {} variants: {} done, {} failed, {} missing",
        dir.display(),
        st.total,
        st.done,
        st.failed.len(),
        st.missing.len()
    );
    for (id, e) in &st.failed {
        println!("failed {id}: {e}");
    }
    if !st.missing.is_empty() {
        println!("missing: {}", st.missing.join(", "));
    }
    if st.tmp > 0 {
        println!(
            "{} tmp directories of a killed run (the next `washdyn study run` removes them)",
            st.tmp
        );
    }
    for j in slurm::view(dir)? {
        println!("{j}");
        let odd: Vec<&slurm::TaskView> =
            j.tasks.iter().filter(|t| t.state != "COMPLETED").collect();
        for t in odd.iter().take(SHOWN) {
            println!(
                "  task {} (variants {}): {}",
                t.index,
                t.variants.join(", "),
                t.state
            );
        }
        if odd.len() > SHOWN {
            println!("  and {} more tasks not completed", odd.len() - SHOWN);
        }
    }
    Ok(if st.failed.is_empty() && st.missing.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
