//! What a study costs beside its runs (issue 24, part 5), on the rigid reference machine
//! (`full`, its seven free suspension parameters, so every variant runs on the generated code):
//! per variant the set-up (the plan's check, the variant's model and simulation), the writing
//! of its partitions and `collect`, for 10, 100 and 1000 variants of a 10 ms window, one
//! thread; the start of a Slurm array task (`washdyn study task`, run here one after the other
//! without Slurm) for 1, 4 and 16 tasks over the same 64 variants; and one whole run-up through
//! the same code for the run itself. Writes docs/study-overhead.md (or the file given):
//! `cargo build --release && cargo run --release --example study_overhead`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use washdyn::study::{self, Outcome, Phases, Study, slurm};

/// The seven free parameters of the reference (models/data/reference.toml), +-30 %.
const PARAMETERS: &str = "\
[[parameter]]\npath = \"springs.spring_rear_left.stiffness\"\nrange = [2800, 5200]\n\
[[parameter]]\npath = \"springs.spring_rear_right.stiffness\"\nrange = [2800, 5200]\n\
[[parameter]]\npath = \"springs.spring_front.stiffness\"\nrange = [2800, 5200]\n\
[[parameter]]\npath = \"friction_dampers.damper_front_left.f_max\"\nrange = [52.5, 97.5]\n\
[[parameter]]\npath = \"friction_dampers.damper_front_right.f_max\"\nrange = [52.5, 97.5]\n\
[[parameter]]\npath = \"friction_dampers.damper_rear_left.f_max\"\nrange = [52.5, 97.5]\n\
[[parameter]]\npath = \"friction_dampers.damper_rear_right.f_max\"\nrange = [52.5, 97.5]\n";

/// The short window every overhead variant runs: 10 ms at 100 s (773 rpm), from the mean-load
/// rest, so the run is small beside what the study adds.
const SHORT: &str = "[run]\nt_start = 100.0\nt_end = 100.01\nstart = \"mean\"\n";

const PARETO: &str = "[outputs]\npareto = [\"peak_door_ring_m\", \"peak_tub_rotation_rad\"]\n";

fn secs(t: Instant) -> f64 {
    t.elapsed().as_secs_f64()
}

fn write_study(dir: &Path, name: &str, body: &str) -> PathBuf {
    let f = dir.join(name);
    let text = format!("model = \"reference\"\nscene = \"full\"\n{body}");
    std::fs::write(&f, text).expect("write the study file");
    f
}

fn lhs(n: usize) -> String {
    format!("{SHORT}{PARAMETERS}[design]\nkind = \"lhs\"\nsamples = {n}\nseed = 1\n{PARETO}")
}

fn sum(outcomes: &[Outcome]) -> Phases {
    let mut s = Phases::default();
    for o in outcomes {
        s.setup_s += o.phases.setup_s;
        s.run_s += o.phases.run_s;
        s.outputs_s += o.phases.outputs_s;
        s.write_s += o.phases.write_s;
    }
    s
}

/// One study of `n` short variants: each step's wall time, s.
struct Scaled {
    n: usize,
    load: f64,
    plan: f64,
    execute: f64,
    phases: Phases,
    replan: f64,
    status: f64,
    collect: f64,
    backend: String,
}

fn scaled(work: &Path, n: usize) -> Scaled {
    let file = write_study(work, &format!("lhs{n}.toml"), &lhs(n));
    let out = work.join(format!("lhs{n}"));
    let t = Instant::now();
    let s = Study::load(&file).expect("the study loads");
    let load = secs(t);
    let t = Instant::now();
    let plan = study::plan(&s, &out).expect("the study plans");
    let plan_s = secs(t);
    let backend = study::backend_for(&s, &plan.variants[0]).name().to_string();
    let t = Instant::now();
    let outcomes = study::execute(&s, &plan, 1, &|_| {}).expect("the study runs");
    let execute = secs(t);
    assert!(
        outcomes
            .iter()
            .all(|o| o.status == washdyn_runtime::run::RunStatus::Ok),
        "every variant runs"
    );
    let t = Instant::now();
    let again = study::plan(&s, &out).expect("the study plans again");
    let replan = secs(t);
    assert!(again.todo.is_empty(), "a finished study has nothing to run");
    let t = Instant::now();
    let st = study::status(&out).expect("status");
    let status = secs(t);
    assert_eq!(st.done, n);
    let t = Instant::now();
    let c = study::collect(&out).expect("collect");
    let collect = secs(t);
    assert_eq!(c.rows, n);
    Scaled {
        n,
        load,
        plan: plan_s,
        execute,
        phases: sum(&outcomes),
        replan,
        status,
        collect,
        backend,
    }
}

/// `washdyn` beside this example (target/release/examples/..).
fn washdyn() -> PathBuf {
    let exe = std::env::current_exe().expect("this example's path");
    let bin = exe
        .parent()
        .and_then(Path::parent)
        .expect("target/<profile>/examples")
        .join("washdyn");
    assert!(
        bin.is_file(),
        "{} is missing: `cargo build --release` first",
        bin.display()
    );
    bin
}

/// Wall time of one run of a command, s.
fn spawn(cmd: &mut Command) -> f64 {
    let t = Instant::now();
    let out = cmd.output().expect("start washdyn");
    assert!(
        out.status.success(),
        "{cmd:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    secs(t)
}

/// The same `variants` run as `tasks` array tasks, each its own `washdyn study task` process,
/// one after the other: the sum of their wall times, s.
fn tasks(work: &Path, exe: &Path, variants: usize, tasks: usize) -> f64 {
    let file = write_study(work, &format!("tasks{tasks}.toml"), &lhs(variants));
    let out = work.join(format!("tasks{tasks}"));
    let s = Study::load(&file).expect("the study loads");
    let plan = study::plan(&s, &out).expect("the study plans");
    let ids: Vec<String> = plan.todo.iter().map(|v| v.id.clone()).collect();
    let chunks = slurm::chunks(&ids, tasks);
    slurm::assign(
        &out,
        &slurm::Assignment {
            job_id: "1".into(),
            study_file: std::fs::canonicalize(&file).expect("the study file"),
            chunks,
        },
    )
    .expect("the chunk file");
    let total = (0..tasks)
        .map(|k| {
            spawn(
                Command::new(exe)
                    .args(["study", "task"])
                    .arg(&out)
                    .args(["--chunk", &k.to_string(), "--chunks", &tasks.to_string()])
                    .args(["--job", "1", "--jobs", "1"]),
            )
        })
        .sum();
    assert_eq!(study::status(&out).expect("status").done, variants);
    total
}

/// One whole run-up (the profile's 178 s, the run's default start) at the base values.
fn run_up(work: &Path) -> (Outcome, String) {
    let file = write_study(
        work,
        "runup.toml",
        "[[parameter]]\npath = \"springs.spring_front.stiffness\"\nlevels = [4000.0]\n\
         [design]\nkind = \"grid\"\n",
    );
    let s = Study::load(&file).expect("the study loads");
    let plan = study::plan(&s, &work.join("runup")).expect("the study plans");
    let backend = study::backend_for(&s, &plan.variants[0]).name().to_string();
    let mut o = study::execute(&s, &plan, 1, &|_| {}).expect("the run-up runs");
    (o.remove(0), backend)
}

fn ms(x: f64) -> String {
    format!("{:.2}", 1e3 * x)
}

/// What the example measured.
struct Measured {
    commit: String,
    /// /proc/loadavg at the start.
    load: String,
    /// The whole run-up and its back end.
    whole: Outcome,
    whole_backend: String,
    /// The studies of 10, 100 and 1000 short variants.
    rows: Vec<Scaled>,
    /// `washdyn --version`'s wall time, s.
    start: f64,
    /// Variants of the task study, and (tasks, the sum of their wall times, s).
    variants: usize,
    task_rows: Vec<(usize, f64)>,
}

fn measure() -> Measured {
    let exe = washdyn();
    let work = tempfile::tempdir().expect("a scratch directory");
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let commit = Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    let (whole, whole_backend) = run_up(work.path());
    eprintln!("run-up: {:?}", whole.phases);
    let rows: Vec<Scaled> = [10, 100, 1000]
        .into_iter()
        .map(|n| {
            let r = scaled(work.path(), n);
            eprintln!("{n} variants: execute {:.2} s", r.execute);
            r
        })
        .collect();
    let start: f64 = (0..20)
        .map(|_| spawn(Command::new(&exe).arg("--version")))
        .sum::<f64>()
        / 20.0;
    let variants = 64;
    let task_rows: Vec<(usize, f64)> = [1, 4, 16]
        .into_iter()
        .map(|n| (n, tasks(work.path(), &exe, variants, n)))
        .collect();
    Measured {
        commit,
        load,
        whole,
        whole_backend,
        rows,
        start,
        variants,
        task_rows,
    }
}

/// The report's header and the run-up's section.
fn run_up_section(md: &mut String, m: &Measured) {
    let Measured {
        commit,
        load,
        whole,
        whole_backend,
        rows,
        ..
    } = m;
    let p = &whole.phases;
    let _ = write!(
        md,
        "# What a study costs beside its runs\n\n\
         Written by `cargo build --release && cargo run --release --example study_overhead` \
         (examples/study_overhead.rs; commit {commit}, load average at the start {}, 2 cores). \
         The rigid reference machine, scene `full`, its seven free suspension parameters \
         (3 spring rates, 4 damper friction forces) +-30 % by a Latin hypercube, so every \
         variant runs on the generated code (back end: {}). One thread (`--jobs 1`); the \
         plan's check of every variant runs on rayon's threads (both cores). The split per \
         variant is `washdyn::study::Phases`, timed inside the study's own `run_variant`. \
         Before the fit check (`washdyn_models::fits`; this example at commit ac9bda0) a \
         variant's set-up took 22.8 to 23.6 ms: the generated system was built to choose the \
         back end and again to run, each build reading the model from its JSON with its modal \
         data. `cargo bench --bench study_overhead` times the pieces one by one.\n\n\
         ## The run-up itself\n\n\
         One whole run-up at the base values through the study (0 to 178.375 s, dopri5 1e-6, \
         back end {whole_backend}): set-up {} ms, run {:.2} s, outputs (order tracks, cabinet \
         levels) {} ms, writing its partitions (357 k samples of 24 channels) {} ms. The \
         outputs cost as much as the run: each channel's order tracks resample it to the drum \
         angle (`analysis::angle`); in a 10 ms window below they are the kernel's set-up, \
         once a channel.\n\n",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" "),
        rows[0].backend,
        ms(p.setup_s),
        p.run_s,
        ms(p.outputs_s),
        ms(p.write_s),
    );
}

/// Per variant, by study size.
fn sizes_section(md: &mut String, m: &Measured) {
    let (rows, p) = (&m.rows, &m.whole.phases);
    let _ = write!(
        md,
        "## Per variant, by study size\n\n\
         Each variant a 10 ms window at 100 s (from the mean-load rest), so that the run is \
         small beside the overhead. ms per variant; `plan` checks every variant and prepares the \
         directory, `re-plan` is `study run` on the finished study (it reads every summary), \
         `status` and `collect` read every partition (`collect` also draws the Pareto plot).\n\n\
         | variants | plan | set-up | run | outputs | write | execute, all | re-plan | status | collect | study load, ms |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        let n = r.n as f64;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.n,
            ms(r.plan / n),
            ms(r.phases.setup_s / n),
            ms(r.phases.run_s / n),
            ms(r.phases.outputs_s / n),
            ms(r.phases.write_s / n),
            ms(r.execute / n),
            ms(r.replan / n),
            ms(r.status / n),
            ms(r.collect / n),
            ms(r.load),
        );
    }
    let big = rows.last().expect("three sizes");
    let n = big.n as f64;
    let overhead = (big.plan + big.phases.setup_s + big.phases.write_s + big.collect) / n;
    let _ = write!(
        md,
        "\nAt {} variants the study adds {} ms a variant (plan, set-up, write, collect) to a \
         run-up of {:.2} s: {:.2} %.\n\n",
        big.n,
        ms(overhead),
        p.run_s,
        100.0 * overhead / p.run_s,
    );
}

/// Per task, by task count.
fn tasks_section(md: &mut String, m: &Measured) {
    let (variants, start, task_rows) = (m.variants, m.start, &m.task_rows);
    let _ = write!(
        md,
        "## Per task, by task count\n\n\
         The same {variants} variants as 1, 4 and 16 array tasks (`washdyn study task DIR \
         --chunk K --chunks N --job 1 --jobs 1`, the chunk file written as `study run --slurm` \
         writes it), each task a process of its own, run one after the other without Slurm (its \
         scheduling adds to this). A task starts the process, loads the study (the reference's \
         TOML and modal data), checks it against `study.json`, then runs its chunk. The process \
         alone (`washdyn --version`): {} ms.\n\n\
         | tasks | all tasks, s | per task, s | start per extra task, ms |\n|---|---|---|---|\n",
        ms(start)
    );
    let one = task_rows[0].1;
    for &(k, t) in task_rows {
        let extra = if k > 1 {
            ms((t - one) / (k - 1) as f64)
        } else {
            "-".into()
        };
        let _ = writeln!(md, "| {k} | {t:.2} | {:.3} | {extra} |", t / k as f64);
    }
}

fn main() {
    let target = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("docs/study-overhead.md"), PathBuf::from);
    let m = measure();
    let mut md = String::new();
    run_up_section(&mut md, &m);
    sizes_section(&mut md, &m);
    tasks_section(&mut md, &m);
    std::fs::write(&target, &md).expect("write the report");
    print!("{md}");
    eprintln!("wrote {}", target.display());
}
