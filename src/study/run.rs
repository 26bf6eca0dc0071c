//! A study run on this machine: [`plan`] checks every variant and prepares the directory
//! (nothing is written before every variant passed), [`execute`] runs the variants not yet
//! finished (missing, or failed before) on `jobs` threads (rayon), each into tmp partitions
//! that are renamed into place when it is done.

use super::dataset::{self, Layout, Record, Row, SUMMARY, State, TIMING, VARIANTS};
use super::file::Study;
use super::variants::{Variant, check_all, variants};
use crate::error::Error;
use crate::results::{Format, SensorRecorder};
use crate::simulation::{Backend, Simulation};
use crate::spec::RunSpec;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;
use washdyn_model::ir::Model;
use washdyn_runtime::run::RunStatus;

/// The back end that runs `variant` of `study`: a built-in model's generated code where the
/// variant differs from it in free parameters only (`Model::free`: one build serves every such
/// variant), else the interpreter, which takes any variant's numbers as data.
pub fn backend_for(study: &Study, variant: &Variant) -> Backend {
    match variant.model(study) {
        Ok(m) => backend_of(study, &m),
        Err(_) => Backend::Interpreted,
    }
}

/// [`backend_for`] of a variant's model, by the fit check alone (`washdyn_models::fits`): the
/// simulation builds the generated system once, where it was built to choose and again to run.
fn backend_of(study: &Study, model: &Model) -> Backend {
    let fits = study
        .source
        .built_in
        .as_deref()
        .and_then(|name| washdyn_models::fits(name, &study.scene, model));
    match fits {
        Some(Ok(())) => Backend::Generated,
        _ => Backend::Interpreted,
    }
}

/// The simulation of `variant`: its model checked, on the back end that fits it
/// ([`backend_for`]), with the study's specification, its summary labelled with the id.
pub fn simulation(study: &Study, variant: &Variant) -> Result<Simulation, Error> {
    let model = variant
        .model(study)
        .map_err(|b| super::StudyError::Variants(vec![b]))?;
    let backend = backend_of(study, &model);
    build(study, variant, model, backend)
}

fn build(study: &Study, v: &Variant, model: Model, backend: Backend) -> Result<Simulation, Error> {
    let spec = RunSpec {
        backend: Some(backend),
        ..study.spec.clone()
    };
    Simulation::new(study.source.variant(model), &spec, &v.control(study))
}

/// What is to run: every variant, and those not finished in the directory.
#[derive(Debug)]
pub struct Plan {
    pub layout: Layout,
    pub variants: Vec<Variant>,
    pub todo: Vec<Variant>,
    /// Tmp directories a killed run left, removed.
    pub removed_tmp: usize,
}

/// Check every variant (refusing the study before anything is written), then prepare `out`
/// (new, or this study's from before), remove a killed run's tmp directories and list the
/// variants to run.
pub fn plan(study: &Study, out: &Path) -> Result<Plan, Error> {
    let vars = variants(study);
    check_all(study, &vars)?;
    let layout = Layout::new(out);
    dataset::prepare(&layout, &Record::new(study, &vars), study)?;
    let removed_tmp = layout.clean_tmp()?;
    let todo = vars
        .iter()
        .filter(|v| layout.state(&v.id) != State::Done)
        .cloned()
        .collect();
    Ok(Plan {
        layout,
        variants: vars,
        todo,
        removed_tmp,
    })
}

/// A variant that ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub id: String,
    /// Interrupted: nothing of it was kept.
    pub status: RunStatus,
    pub error: Option<String>,
    pub warnings: Vec<String>,
    pub wall_time_s: f64,
    pub steps: u64,
    /// Where the variant's time went, for the overhead a study adds to its runs
    /// (benches/study_overhead.rs, examples/study_overhead.rs).
    pub phases: Phases,
}

/// One variant's wall time by phase, s: what the study spends around the run itself.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// The variant's model (parameters set, checked), the back end's choice and the
    /// simulation's set-up (the system built, the settings checked).
    pub setup_s: f64,
    /// The integration (`Simulation::integrate`), the samples kept in memory.
    pub run_s: f64,
    /// The outputs from the samples (peaks, order tracks, cabinet levels).
    pub outputs_s: f64,
    /// Its partitions: the sensors, the summary row and the timing under tmp names, then
    /// renamed into place.
    pub write_s: f64,
}

/// Most parallel runs: each is a thread with its own model, state and output streams; beyond
/// the machine's cores (or the variants) more gain nothing, and 1024 is above any
/// workstation's core count.
pub const MAX_JOBS: usize = 1024;

/// `--jobs` in [1, MAX_JOBS]: checked before [`plan`] writes anything.
pub fn check_jobs(jobs: usize) -> Result<(), Error> {
    if (1..=MAX_JOBS).contains(&jobs) {
        Ok(())
    } else {
        Err(Error::setting(
            "--jobs",
            format!("--jobs must be in [1, {MAX_JOBS}], got {jobs}"),
        ))
    }
}

/// Run the plan's variants on `jobs` threads; `done` is called as each finishes. A variant
/// whose run fails gets its row with the error (the others go on); after an interrupt (the
/// settings' guard flag, Ctrl-C) no variant starts, and the ones stopped keep nothing.
pub fn execute(
    study: &Study,
    plan: &Plan,
    jobs: usize,
    done: &(dyn Fn(&Outcome) + Sync),
) -> Result<Vec<Outcome>, Error> {
    check_jobs(jobs)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build()?;
    let stop = study.control.guard.interrupt.clone();
    let stopped = || stop.as_ref().is_some_and(|f| f.load(Ordering::Relaxed));
    pool.install(|| {
        plan.todo
            .par_iter()
            .filter(|_| !stopped())
            .map(|v| {
                let o = run_variant(study, &plan.layout, v)?;
                done(&o);
                Ok(o)
            })
            .collect()
    })
}

/// Tmp partitions of one variant, removed unless published.
struct Tmp<'a> {
    layout: &'a Layout,
    id: &'a str,
    dirs: Vec<(&'static str, PathBuf)>,
}

impl Tmp<'_> {
    fn dir(&mut self, dataset: &'static str) -> Result<PathBuf, Error> {
        let p = self.layout.tmp(dataset, self.id)?;
        self.dirs.push((dataset, p.clone()));
        Ok(p)
    }
    /// Into place in the order made, the summary last (it marks the variant finished); a
    /// sensors partition without its file (a run that never started) replaces an older one by
    /// nothing.
    fn publish(mut self) -> Result<(), Error> {
        self.dirs.sort_by_key(|(d, _)| *d == SUMMARY);
        for (d, p) in std::mem::take(&mut self.dirs) {
            if d == VARIANTS && !p.join("sensors.parquet").is_file() {
                let old = self.layout.partition(VARIANTS, self.id);
                for q in [&p, &old] {
                    if q.exists() {
                        std::fs::remove_dir_all(q).map_err(|e| Error::io("remove", q, e))?;
                    }
                }
                continue;
            }
            self.layout.publish(&p, d, self.id)?;
        }
        Ok(())
    }
}

impl Drop for Tmp<'_> {
    fn drop(&mut self) {
        for (_, p) in &self.dirs {
            let _ = std::fs::remove_dir_all(p);
        }
    }
}

/// Seconds since the last lap.
struct Lap(Instant);

impl Lap {
    fn next(&mut self) -> f64 {
        let now = Instant::now();
        (now - std::mem::replace(&mut self.0, now)).as_secs_f64()
    }
}

/// One variant: its model and simulation, the run into its tmp partitions, its outputs, then
/// its partitions into place. A variant refused at its set-up gets a failed row.
fn run_variant(study: &Study, layout: &Layout, v: &Variant) -> Result<Outcome, Error> {
    let mut lap = Lap(Instant::now());
    let mut phases = Phases::default();
    let mut tmp = Tmp {
        layout,
        id: &v.id,
        dirs: Vec::new(),
    };
    let model = v.model(study).map_err(|b| b.to_string());
    let backend = model
        .as_ref()
        .map_or(Backend::Interpreted, |m| backend_of(study, m));
    let sim = model.and_then(|m| build(study, v, m, backend).map_err(|e| e.to_string()));
    phases.setup_s = lap.next();
    let (row, wall, warnings) = match sim {
        Err(e) => {
            tmp.dir(VARIANTS)?;
            (failed_row(study, e, backend), 0.0, Vec::new())
        }
        Ok(sim) => {
            let rate = sim.run.sample_rate;
            let mut sink = SensorRecorder::deferred(&tmp.dir(VARIANTS)?, Format::Parquet);
            phases.write_s = lap.next();
            let verdict = crate::error_class::Verdict::of(&sim);
            let (mut summary, error) = sim.integrate(&mut sink, &mut |_| {});
            verdict.apply(&mut summary, error.is_none());
            phases.run_s = lap.next();
            sink.finish()
                .map_err(|e| Error::io("write", sink.path(), e))?;
            phases.write_s += lap.next();
            if summary.status == RunStatus::Interrupted {
                return Ok(Outcome {
                    id: v.id.clone(),
                    status: summary.status,
                    error: summary.error,
                    warnings: summary.warnings,
                    wall_time_s: summary.wall_time_s,
                    steps: summary.steps,
                    phases,
                });
            }
            let outputs = match error {
                None => study
                    .outputs
                    .values(&summary, &sink.names, &sink.memory, rate),
                Some(_) => study.outputs.none(),
            };
            phases.outputs_s = lap.next();
            let row = Row {
                outputs,
                status: summary.status,
                error: summary.error.clone().unwrap_or_default(),
                error_class: summary.error_class.clone().unwrap_or_default(),
                warnings: summary.warnings.join("\n"),
                backend: backend.name().into(),
                t_reached_s: summary.t_reached,
                steps: summary.steps as f64,
                rejected_steps: summary.rejected_steps as f64,
                rhs_evals: summary.rhs_evals as f64,
            };
            (row, summary.wall_time_s, summary.warnings)
        }
    };
    dataset::write_summary(&tmp.dir(SUMMARY)?, study, v, &row)?;
    dataset::write_timing(&tmp.dir(TIMING)?, &v.id, wall)?;
    let mut outcome = Outcome {
        id: v.id.clone(),
        status: row.status,
        error: (!row.error.is_empty()).then(|| row.error.clone()),
        warnings,
        wall_time_s: wall,
        steps: row.steps as u64,
        phases,
    };
    tmp.publish()?;
    outcome.phases.write_s += lap.next();
    Ok(outcome)
}

/// The row of a variant refused at its set-up.
fn failed_row(study: &Study, error: String, backend: Backend) -> Row {
    Row {
        outputs: study.outputs.none(),
        status: RunStatus::Failed,
        error,
        error_class: String::new(),
        warnings: String::new(),
        backend: backend.name().into(),
        t_reached_s: study.spec.t_start,
        steps: 0.0,
        rejected_steps: 0.0,
        rhs_evals: 0.0,
    }
}
