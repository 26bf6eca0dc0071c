//! What a study adds to its runs, piece by piece (issue 24, part 5), on the rigid reference
//! (`full`, its seven free suspension parameters: every variant runs on the generated code):
//! a variant's set-up (its model, the back end's choice, the simulation), the writing of its
//! partitions, `plan`, `status` and `collect` over 10, 100 and 1000 finished variants, and what
//! an array task does before its chunk (process start, study load, its plan) for 1, 4 and 16
//! chunks. `cargo bench --bench study_overhead`; the whole study timed inside its own run, and
//! the run-up beside it: examples/study_overhead.rs (docs/study-overhead.md).

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use std::cell::OnceCell;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use washdyn::results::{Format, SensorRecorder};
use washdyn::simulation::{Backend, Simulation};
use washdyn::spec::RunSpec;
use washdyn::study::dataset::{self, Row, SUMMARY, TIMING, VARIANTS};
use washdyn::study::{self, Study, slurm};
use washdyn_runtime::output::SampleSink;

/// The seven free parameters of the reference, +-30 %, a 10 ms window at 100 s (as the example).
fn study_text(n: usize) -> String {
    let mut s = String::from(
        "model = \"reference\"\nscene = \"full\"\n\
         [run]\nt_start = 100.0\nt_end = 100.01\nstart = \"mean\"\n",
    );
    for (path, lo, hi) in [
        ("springs.spring_rear_left.stiffness", 2800.0, 5200.0),
        ("springs.spring_rear_right.stiffness", 2800.0, 5200.0),
        ("springs.spring_front.stiffness", 2800.0, 5200.0),
        ("friction_dampers.damper_front_left.f_max", 52.5, 97.5),
        ("friction_dampers.damper_front_right.f_max", 52.5, 97.5),
        ("friction_dampers.damper_rear_left.f_max", 52.5, 97.5),
        ("friction_dampers.damper_rear_right.f_max", 52.5, 97.5),
    ] {
        s += &format!("[[parameter]]\npath = \"{path}\"\nrange = [{lo}, {hi}]\n");
    }
    s + &format!(
        "[design]\nkind = \"lhs\"\nsamples = {n}\nseed = 1\n\
         [outputs]\npareto = [\"peak_door_ring_m\", \"peak_tub_rotation_rad\"]\n"
    )
}

fn load(dir: &Path, n: usize) -> (PathBuf, Study) {
    let f = dir.join(format!("study{n}.toml"));
    std::fs::write(&f, study_text(n)).unwrap();
    let s = Study::load(&f).unwrap();
    (f, s)
}

/// A variant's set-up: its model (parameters set, checked), the back end's choice, the
/// simulation (the system built). The fit check against the model as the generated code read
/// it at every check before (from its JSON, modal data and all: twice a variant, once to choose
/// the back end by building the system, once to build it for the run) and as it keeps it now
/// (read once); and the build.
fn setup(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let (_, s) = load(dir.path(), 10);
    let vars = study::variants::variants(&s);
    let v = &vars[3];
    let model = v.model(&s).unwrap();
    let mut g = c.benchmark_group("study_setup");
    g.bench_function("variant_model", |b| b.iter(|| v.model(black_box(&s))));
    g.bench_function("fit_check/model_read_each_time", |b| {
        b.iter(|| {
            let base = washdyn_models::reference::model();
            washdyn_model::ir::param::free_values(&base, black_box(&model)).is_ok()
        })
    });
    g.bench_function("fit_check/model_read_once", |b| {
        b.iter(|| {
            washdyn_models::fits("reference", "full", black_box(&model)).is_some_and(|r| r.is_ok())
        })
    });
    g.bench_function("generated_for", |b| {
        b.iter(|| {
            washdyn_models::generated_for("reference", "full", black_box(&model))
                .is_some_and(|r| r.is_ok())
        })
    });
    g.bench_function("backend_for", |b| {
        b.iter(|| study::backend_for(black_box(&s), black_box(v)))
    });
    let spec = RunSpec {
        backend: Some(Backend::Generated),
        ..s.spec.clone()
    };
    let ctl = v.control(&s);
    g.bench_function("simulation_new", |b| {
        b.iter(|| Simulation::new(s.source.variant(model.clone()), &spec, &ctl).unwrap())
    });
    g.finish();
}

/// Directories removed when dropped: criterion drops `iter_batched`'s outputs outside the
/// timing, and removing a directory here costs about 3 ms (more than writing one).
struct Gone(Vec<PathBuf>);

impl Drop for Gone {
    fn drop(&mut self) {
        for p in &self.0 {
            let _ = std::fs::remove_dir_all(p);
        }
    }
}

/// One variant's partitions as `run_variant` writes them: its sensors (the 10 ms window's 21
/// samples of 24 channels), summary row and timing under tmp names, then renamed into place
/// (each iteration another id, so no older partition is replaced).
fn write(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let (_, s) = load(dir.path(), 10);
    let out = dir.path().join("out");
    let plan = study::plan(&s, &out).unwrap();
    let v = &plan.variants[0];
    let sim = Simulation::new(
        s.source.variant(v.model(&s).unwrap()),
        &s.spec,
        &v.control(&s),
    )
    .unwrap();
    let kept_dir = dir.path().join("kept");
    std::fs::create_dir(&kept_dir).unwrap();
    let mut kept = SensorRecorder::deferred(&kept_dir, Format::Parquet);
    let (summary, _) = sim.integrate(&mut kept, &mut |_| {});
    let channels: Vec<String> = kept.names[2..].to_vec();
    let rows = kept.memory[0].len();
    let row = Row {
        outputs: s.outputs.none(),
        status: summary.status,
        error: String::new(),
        error_class: String::new(),
        warnings: String::new(),
        backend: "generated".into(),
        t_reached_s: summary.t_reached,
        steps: summary.steps as f64,
        rejected_steps: 0.0,
        rhs_evals: summary.rhs_evals as f64,
    };
    let layout = &plan.layout;
    let mut values = vec![0.0; channels.len()];
    let mut sensors = |id: &str| {
        let dir = layout.tmp(VARIANTS, id).unwrap();
        let mut sink = SensorRecorder::deferred(&dir, Format::Parquet);
        sink.header(&channels).unwrap();
        for i in 0..rows {
            for (x, col) in values.iter_mut().zip(&kept.memory[2..]) {
                *x = col[i];
            }
            sink.sample(kept.memory[0][i], kept.memory[1][i], &values)
                .unwrap();
        }
        sink.finish().unwrap();
        dir
    };
    let summary = |id: &str| {
        let sd = layout.tmp(SUMMARY, id).unwrap();
        dataset::write_summary(&sd, &s, v, &row).unwrap();
        let td = layout.tmp(TIMING, id).unwrap();
        dataset::write_timing(&td, id, 0.01).unwrap();
        (sd, td)
    };
    let mut k = 0usize;
    let mut next = || {
        k += 1;
        format!("bench{k}")
    };
    let mut g = c.benchmark_group("study_write");
    g.bench_function("sensors", |b| {
        b.iter_batched(
            &mut next,
            |id| Gone(vec![sensors(&id)]),
            BatchSize::SmallInput,
        )
    });
    g.bench_function("summary_and_timing", |b| {
        b.iter_batched(
            &mut next,
            |id| {
                let (sd, td) = summary(&id);
                Gone(vec![sd, td])
            },
            BatchSize::SmallInput,
        )
    });
    g.bench_function("variant", |b| {
        b.iter_batched(
            &mut next,
            |id| {
                let p = sensors(&id);
                let (sd, td) = summary(&id);
                for (p, d) in [(p, VARIANTS), (td, TIMING), (sd, SUMMARY)] {
                    layout.publish(&p, d, &id).unwrap();
                }
                Gone(
                    [VARIANTS, TIMING, SUMMARY]
                        .map(|d| layout.partition(d, &id))
                        .to_vec(),
                )
            },
            BatchSize::SmallInput,
        )
    });
    g.finish();
}

/// `plan` (a re-run of a finished study: it checks every variant and reads every summary),
/// `status` and `collect` over studies of 10, 100 and 1000 finished variants.
fn by_variants(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let mut g = c.benchmark_group("study_by_variants");
    g.sample_size(10);
    for n in [10, 100, 1000] {
        // Run only when one of the three is selected (criterion calls a closure only then).
        let done = OnceCell::new();
        let finished = || {
            done.get_or_init(|| {
                let (_, s) = load(dir.path(), n);
                let out = dir.path().join(format!("out{n}"));
                let plan = study::plan(&s, &out).unwrap();
                study::execute(&s, &plan, 2, &|_| {}).unwrap();
                (s, out)
            })
        };
        g.bench_with_input(BenchmarkId::new("replan", n), &n, |b, _| {
            let (s, out) = finished();
            b.iter(|| study::plan(s, out).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("status", n), &n, |b, _| {
            let (_, out) = finished();
            b.iter(|| study::status(out).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("collect", n), &n, |b, _| {
            let (_, out) = finished();
            b.iter(|| study::collect(out).unwrap())
        });
    }
    g.finish();
}

/// What an array task does before its chunk: start the process, load the study and plan its
/// chunk (`slurm::task_plan`: the chunk file, the study against `study.json`), for a job of 1,
/// 4 and 16 chunks over 1000 variants; and the process alone.
fn task_start(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let (file, s) = load(dir.path(), 1000);
    let out = dir.path().join("out");
    let plan = study::plan(&s, &out).unwrap();
    let ids: Vec<String> = plan.todo.iter().map(|v| v.id.clone()).collect();
    let mut g = c.benchmark_group("study_task_start");
    g.sample_size(20);
    g.bench_function("process", |b| {
        b.iter(|| {
            let o = Command::new(env!("CARGO_BIN_EXE_washdyn"))
                .arg("--version")
                .output()
                .unwrap();
            assert!(o.status.success());
        })
    });
    for n in [1, 4, 16] {
        let job = format!("{n}");
        slurm::assign(
            &out,
            &slurm::Assignment {
                job_id: job.clone(),
                study_file: std::fs::canonicalize(&file).unwrap(),
                chunks: slurm::chunks(&ids, n),
            },
        )
        .unwrap();
        g.bench_with_input(BenchmarkId::new("load_and_plan", n), &n, |b, _| {
            b.iter(|| slurm::task_plan(&out, &job, n - 1, n).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, setup, write, by_variants, task_start);
criterion_main!(benches);
