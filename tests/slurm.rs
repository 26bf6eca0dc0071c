//! `washdyn study run --slurm` against a real one-node Slurm that scripts/slurm/up.sh starts in a
//! temporary directory (munged, slurmctld, slurmd; design notes, "A real single-node Slurm"):
//! a study submitted as a job array, one task cancelled while it runs, `study status` from the
//! dataset and from squeue/scontrol, a re-run that submits only the cancelled variant, and the
//! dataset against a local run's to the byte. Slurm's answers are printed as they come, so the
//! test's output (`--nocapture`) is a log of the session.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};
use washdyn::study::slurm::{self, Options};

/// Bounds of the waits, generous: on CI two cores are shared with the ccx-heavy tests.
const START: Duration = Duration::from_secs(120);
const ARRAY: Duration = Duration::from_secs(900);

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A cluster started in a temporary directory, stopped (scripts/slurm/down.sh) when dropped,
/// also when the test fails.
struct Cluster {
    dir: tempfile::TempDir,
    conf: PathBuf,
}

impl Cluster {
    /// None (a skip, a failure under CI) where Slurm is not installed.
    fn up() -> Option<Cluster> {
        let have = [
            "sbatch",
            "squeue",
            "scontrol",
            "slurmctld",
            "slurmd",
            "munged",
        ]
        .iter()
        .all(|t| {
            // The daemons are in /usr/sbin, which up.sh adds to PATH.
            Command::new("sh")
                .args(["-c", &format!("PATH=$PATH:/usr/sbin:/sbin; command -v {t}")])
                .stdout(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        });
        if !common::required_tool(
            have,
            "Slurm and MUNGE",
            "apt-get install slurmctld slurmd slurm-client munge",
        ) {
            return None;
        }
        let dir = tempfile::tempdir().unwrap();
        let cluster = Cluster {
            conf: dir.path().join("slurm.conf"),
            dir,
        };
        let t = Instant::now();
        let o = Command::new("bash")
            .arg(root().join("scripts/slurm/up.sh"))
            .arg(cluster.dir.path())
            .env("UP_TIMEOUT", START.as_secs().to_string())
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "scripts/slurm/up.sh failed:\n{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        let export = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            export.trim(),
            format!("export SLURM_CONF={}", cluster.conf.display())
        );
        println!("up.sh: node idle after {:.2} s", t.elapsed().as_secs_f64());
        Some(cluster)
    }

    /// A Slurm client command against this cluster.
    fn cmd(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.env("SLURM_CONF", &self.conf);
        c
    }

    /// `program args` must succeed: its stdout.
    fn ask(&self, program: &str, args: &[&str]) -> String {
        let o = self.cmd(program).args(args).output().unwrap();
        assert!(
            o.status.success(),
            "{program} {args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8_lossy(&o.stdout).into_owned()
    }

    /// `washdyn args` against this cluster, killed after `limit` (a failure naming the args).
    fn washdyn(&self, args: &[&str], limit: Duration) -> Output {
        let mut child = Command::new(env!("CARGO_BIN_EXE_washdyn"))
            .args(args)
            .env("SLURM_CONF", &self.conf)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let t = Instant::now();
        while child.try_wait().unwrap().is_none() {
            if t.elapsed() > limit {
                let _ = child.kill();
                let o = child.wait_with_output().unwrap();
                panic!(
                    "washdyn {args:?} still running after {limit:?}:\n{}{}",
                    String::from_utf8_lossy(&o.stdout),
                    String::from_utf8_lossy(&o.stderr)
                );
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let o = child.wait_with_output().unwrap();
        for line in String::from_utf8_lossy(&o.stdout).lines() {
            println!("  | {line}");
        }
        for line in String::from_utf8_lossy(&o.stderr).lines() {
            println!("  ! {line}");
        }
        o
    }

    /// `squeue -h -j JOB -r -o '%i %T'`, one task a line.
    fn queue(&self, job: &str) -> Vec<String> {
        self.ask("squeue", &["-h", "-j", job, "-r", "-o", "%i %T"])
            .lines()
            .map(|l| l.trim().to_string())
            .filter(|l| !l.is_empty())
            .collect()
    }

    /// Poll the queue until `job` has left it, printing each new picture of it.
    fn wait_empty(&self, job: &str) {
        let t = Instant::now();
        let mut last = None;
        loop {
            let q = self.queue(job);
            if last.as_ref() != Some(&q) {
                println!(
                    "squeue at {:5.1} s: {}",
                    t.elapsed().as_secs_f64(),
                    if q.is_empty() {
                        "empty".into()
                    } else {
                        q.join(", ")
                    }
                );
                last = Some(q.clone());
            }
            if q.is_empty() {
                return;
            }
            assert!(
                t.elapsed() < ARRAY,
                "job {job} still queued after {ARRAY:?}: {q:?}"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let o = Command::new("bash")
            .arg(root().join("scripts/slurm/down.sh"))
            .arg(self.dir.path())
            .output();
        match o {
            Ok(o) if o.status.success() => {}
            Ok(o) => eprintln!("down.sh: {}", String::from_utf8_lossy(&o.stderr)),
            Err(e) => eprintln!("down.sh did not run: {e}"),
        }
    }
}

/// The study: the rigid reference over 1.5 s of its run-up at 773-785 rpm (as tests/study.rs's
/// grid), the front spring at five stiffnesses. Fixed-step rk4 at 2 us makes each variant
/// 750 000 steps, about 1.5 s of wall time (measured: 1.45 s on generated code, 2 cores): long
/// enough to be seen RUNNING and cancelled (dopri5 ran it in 0.03 s, a task in less time than
/// the poll's round trip to the controller).
const STUDY: &str = "model = \"reference\"\nscene = \"full\"\n\
    [run]\nmethod = \"rk4\"\nstep = 2e-6\nt_start = 100.0\nt_end = 101.5\nstart = \"mean\"\n\
    sample_rate = 200.0\n\
    [[parameter]]\npath = \"springs.spring_front.stiffness\"\n\
    levels = [3000, 3250, 3500, 3750, 4000]\n[design]\nkind = \"grid\"\n";

/// The job id in `submitted slurm job ID: ...`.
fn submitted(stdout: &str) -> String {
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("submitted slurm job "))
        .unwrap_or_else(|| panic!("no submission in:\n{stdout}"));
    line.split(':').next().unwrap().to_string()
}

/// Submit five variants as five tasks (two at a time); a second run is refused while they are
/// queued; cancel task 4 while it is pending and task 2 while its variant is being written
/// (scancel's SIGTERM stops the run between steps as Ctrl-C does, and the run removes its own
/// tmp partition): those variants are missing, nothing of them in place, the others are done;
/// a re-run submits those two alone, and the dataset is a local run's to the byte.
#[test]
fn a_cancelled_task_is_submitted_again_and_the_dataset_is_the_local_runs() {
    let Some(c) = Cluster::up() else {
        return;
    };
    let started = Instant::now();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("springs.toml");
    std::fs::write(&file, STUDY).unwrap();
    let out = dir.path().join("on-slurm");
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());

    println!("$ washdyn study run springs.toml --out on-slurm --slurm --tasks 5 --throttle 2");
    let run = ["study", "run", f, "--out", o, "--slurm"];
    let first = c.washdyn(
        &[&run[..], &["--tasks", "5", "--throttle", "2"]].concat(),
        START,
    );
    assert!(first.status.success(), "the submission failed");
    let stdout = String::from_utf8_lossy(&first.stdout);
    assert!(stdout.contains("5 variants, 5 to run (0 finished before)"));
    assert!(stdout.contains("5 variants in 5 tasks (1 a task), at most 2 at once"));
    let job = submitted(&stdout);
    let script = std::fs::read_to_string(out.join("slurm/job.sh")).unwrap();
    assert!(script.contains("#SBATCH --array=0-4%2\n"), "{script}");
    assert!(script.contains(&format!(
        "study task '{}' --chunk \"$SLURM_ARRAY_TASK_ID\" --chunks 5",
        std::path::absolute(&out).unwrap().display()
    )));

    // While its tasks are queued the study is not run again (a plan would remove their tmp
    // directories): five variants two at a time take seconds, this check milliseconds.
    println!("$ washdyn study run springs.toml --out on-slurm --slurm   (at once)");
    let busy = c.washdyn(&run, START);
    let err = String::from_utf8_lossy(&busy.stderr);
    assert_eq!(busy.status.code(), Some(2), "{err}");
    assert!(
        err.contains("tasks of this study are still in Slurm's queue"),
        "{err}"
    );

    // Task 4 waits behind the throttle for two rounds of runs: cancelled while PENDING it
    // leaves no trace in Slurm (design notes), so status calls it gone.
    let pending = format!("{job}_4");
    let q = c.queue(&job);
    assert!(
        q.contains(&format!("{pending} PENDING")),
        "task 4 not pending behind the throttle: {q:?}"
    );
    println!("$ scancel {pending}   (pending)");
    c.ask("scancel", &[&pending]);

    // Task 2 is cancelled as soon as squeue shows it running.
    let task = format!("{job}_2");
    let t = Instant::now();
    let mut last = Vec::new();
    loop {
        let q = c.queue(&job);
        if q != last {
            println!(
                "squeue at {:5.2} s: {}",
                t.elapsed().as_secs_f64(),
                q.join(", ")
            );
            last = q.clone();
        }
        if q.contains(&format!("{task} RUNNING")) {
            break;
        }
        assert!(
            q.iter().any(|l| l.starts_with(&format!("{task} "))),
            "task {task} left the queue before it was seen running: the variants are too short \
             for this machine (squeue: {q:?})"
        );
        assert!(
            t.elapsed() < ARRAY,
            "{task} not running after {ARRAY:?}: {q:?}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    // ... and once its run has begun writing (its tmp partition made), so the cancel meets a
    // half-written variant.
    let begun = |d: &str| {
        std::fs::read_dir(out.join(d)).is_ok_and(|e| {
            e.flatten().any(|e| {
                e.file_name()
                    .to_string_lossy()
                    .starts_with("variant=0002.tmp-")
            })
        })
    };
    while !begun("variants") {
        let q = c.queue(&job);
        assert!(
            q.contains(&format!("{task} RUNNING")),
            "task {task} stopped running before its tmp partition was seen: {q:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    println!(
        "variants/variant=0002.tmp-* made at {:.2} s",
        t.elapsed().as_secs_f64()
    );
    println!("$ scancel {task}");
    c.ask("scancel", &[&task]);
    c.wait_empty(&job);
    let shown = c.ask("scontrol", &["-o", "show", "job", &job]);
    for l in shown.lines() {
        let f: Vec<&str> = l
            .split_whitespace()
            .filter(|w| {
                ["JobId=", "ArrayTaskId=", "JobState=", "ExitCode="]
                    .iter()
                    .any(|k| w.starts_with(k))
            })
            .collect();
        println!("scontrol: {}", f.join(" "));
    }

    // The dataset: 0002 and 0004 missing, nothing of them in place; Slurm: task 2 CANCELLED,
    // task 4 gone, or still CANCELLED while slurmctld has not yet purged the record of a task
    // cancelled while pending (seen once under load, the suite beside a simulation).
    println!("$ washdyn study status on-slurm");
    let st = c.washdyn(&["study", "status", o], START);
    assert!(st.status.success());
    let st = String::from_utf8_lossy(&st.stdout);
    assert!(
        st.contains("5 variants: 3 done, 0 failed, 2 missing")
            && st.contains("missing: 0002, 0004"),
        "{st}"
    );
    assert!(
        st.contains(&format!("slurm job {job}: 5 tasks: "))
            && st.contains("  task 2 (variants 0002): CANCELLED")
            && (st.contains("  task 4 (variants 0004): gone")
                || st.contains("  task 4 (variants 0004): CANCELLED")),
        "{st}"
    );
    for d in ["variants", "summary", "timing"] {
        for id in ["0002", "0004"] {
            assert!(
                !out.join(d).join(format!("variant={id}")).exists(),
                "{d}/variant={id} in place after the cancel"
            );
        }
    }
    // SIGTERM stops the run between steps as Ctrl-C does (exit code 130): it removes its own
    // tmp partition, so none is left for status to count. (What a SIGKILL leaves, the next run
    // removes: tests/study.rs.)
    assert!(
        !begun("variants"),
        "the cancelled run left its tmp partition"
    );
    assert!(!st.contains("tmp directories of a killed run"), "{st}");

    // The re-run submits the cancelled variants alone and waits for them.
    println!("$ washdyn study run springs.toml --out on-slurm --slurm --wait");
    let again = c.washdyn(&[&run[..], &["--wait"]].concat(), ARRAY);
    let stdout = String::from_utf8_lossy(&again.stdout);
    assert!(again.status.success(), "the re-run failed:\n{stdout}");
    assert!(
        stdout.contains("5 variants, 2 to run (3 finished before)\n"),
        "{stdout}"
    );
    assert!(!begun("variants"), "the tmp partition is still there");
    let job2 = submitted(&stdout);
    assert!(stdout.contains(&format!(
        "submitted slurm job {job2}: 2 variants in 2 tasks (1 a task)"
    )));
    assert!(
        stdout.contains("5 variants: 5 done, 0 failed, 0 missing"),
        "{stdout}"
    );
    let jobs = slurm::jobs(&out).unwrap();
    let recorded: Vec<(&str, usize, usize)> = jobs
        .jobs
        .iter()
        .map(|j| (j.job_id.as_str(), j.tasks, j.variants))
        .collect();
    assert_eq!(recorded, [(job.as_str(), 5, 5), (job2.as_str(), 2, 2)]);
    let a: slurm::Assignment = serde_json::from_str(
        &std::fs::read_to_string(out.join(format!("slurm/job-{job2}.json"))).unwrap(),
    )
    .unwrap();
    assert_eq!(a.chunks, [["0002"], ["0004"]]);

    // The same study run here: the same bytes (wall times and Slurm's files aside).
    let local = dir.path().join("local");
    println!("$ washdyn study run springs.toml --out local");
    let l = c.washdyn(
        &["study", "run", f, "--out", local.to_str().unwrap()],
        ARRAY,
    );
    assert!(l.status.success());
    let (remote, here) = (
        common::dataset_bytes(&out, &["timing", "slurm"]),
        common::dataset_bytes(&local, &["timing", "slurm"]),
    );
    assert_eq!(
        remote.keys().collect::<Vec<_>>(),
        here.keys().collect::<Vec<_>>()
    );
    assert_eq!(remote.len(), 13, "{:?}", remote.keys());
    for (p, b) in &remote {
        assert!(
            here[p] == *b,
            "{} differs from the local run's",
            p.display()
        );
    }
    println!(
        "{} files equal to the local run's; the test took {:.1} s after the cluster was up",
        remote.len(),
        started.elapsed().as_secs_f64()
    );
}

/// The chunks are the to-do list in order, in contiguous pieces differing in size by one at
/// most: a function of the list alone (a task reads its own from the job's chunk file).
#[test]
fn chunks_split_the_todo_list_in_order() {
    let ids: Vec<String> = (0..10).map(|k| format!("{k:04}")).collect();
    let c = slurm::chunks(&ids, 4);
    assert_eq!(c.iter().map(Vec::len).collect::<Vec<_>>(), [2, 3, 2, 3]);
    assert_eq!(c.concat(), ids);
    assert_eq!(slurm::chunks(&ids[..3], 7).len(), 3);
    assert_eq!(slurm::chunks(&ids[..5], 1), [ids[..5].to_vec()]);
}

/// Slurm's array index lists as squeue and scontrol print them (sbatch(1), `--array`).
#[test]
fn array_indices_as_slurm_prints_them() {
    assert_eq!(slurm::indices("3"), Some(vec![3]));
    assert_eq!(slurm::indices("0-3%2"), Some(vec![0, 1, 2, 3]));
    assert_eq!(slurm::indices("1,4-6"), Some(vec![1, 4, 5, 6]));
    assert_eq!(slurm::indices("0-6:3"), Some(vec![0, 3, 6]));
    assert_eq!(slurm::indices("x"), None);
    assert_eq!(slurm::indices("5-2"), None);
}

/// Bad options are refused by name before anything is written or submitted; a directory an
/// sbatch script cannot name is refused; the script holds the options.
#[test]
fn slurm_options_and_paths_are_checked() {
    let bad = Options {
        tasks: Some(0),
        mem: Some("lots".into()),
        time: Some("1:2:3:4".into()),
        partition: Some("a b".into()),
        ..Options::default()
    };
    let e = bad.check().unwrap_err();
    assert_eq!(e.options(), ["--tasks", "--mem", "--time", "--partition"]);
    let good = Options {
        tasks: Some(3),
        throttle: Some(2),
        cpus_per_task: Some(4),
        mem: Some("2G".into()),
        time: Some("1-02:03:04".into()),
        partition: Some("ci".into()),
    };
    good.check().unwrap();
    let s = slurm::script(Path::new("/w/out"), Path::new("/b/washdyn"), 3, &good).unwrap();
    for line in [
        "#SBATCH --array=0-2%2\n",
        "#SBATCH --output=/w/out/slurm/task-%A_%a.out\n",
        "#SBATCH --cpus-per-task=4\n",
        "#SBATCH --mem=2G\n",
        "#SBATCH --time=1-02:03:04\n",
        "#SBATCH --partition=ci\n",
        "exec '/b/washdyn' study task '/w/out' --chunk \"$SLURM_ARRAY_TASK_ID\" --chunks 3\n",
    ] {
        assert!(s.contains(line), "{line} not in\n{s}");
    }
    let e = slurm::script(Path::new("/w/a b"), Path::new("/b/w"), 1, &good).unwrap_err();
    assert!(e.to_string().contains("holds ' '"), "{e}");
}

/// Through the binary, no cluster needed: a refused option writes nothing (exit 2); Slurm
/// options without `--slurm` are clap's usage errors (exit 2); without sbatch on PATH the
/// submission fails naming the command (exit 5); a task of a job never submitted names the
/// missing chunk file (exit 2).
#[test]
fn slurm_refusals_through_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), STUDY).unwrap();
    let o = common::washdyn_in(
        &[
            "study", "run", "s.toml", "--out", "o", "--slurm", "--tasks", "0",
        ],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--tasks must be at least 1"), "{err}");
    assert!(!dir.path().join("o").exists());
    let o = common::washdyn_in(
        &["study", "run", "s.toml", "--out", "o", "--throttle", "2"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--slurm"));
    let o = Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(["study", "run", "s.toml", "--out", "o", "--slurm"])
        .current_dir(dir.path())
        .env("PATH", dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(5), "{err}");
    assert!(
        err.contains("cannot run `sbatch --parsable --hold"),
        "{err}"
    );
    let o = common::washdyn_in(
        &[
            "study", "task", "o", "--chunk", "0", "--chunks", "1", "--job", "77",
        ],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("no chunk file for job 77"), "{err}");
}
