//! Parallel variant studies: unbalance position and mass, speed profile. Each variant is a copy
//! of the model's IR with those fields changed, checked by the one checker and run by the
//! interpreter (generated code bakes the base model's numbers in), on all cores (rayon).
//! A variant that fails its check or its run gets a row with the reason; the others go on.

use crate::analysis::{AnalysisOptions, Channel, RunUp, Signals};
use crate::commands::{motor_ratio, write_summary};
use crate::error::Error;
use crate::results::{EnergyRecorder, SensorRecorder, StateRecorder};
use crate::simulation::{Backend, RunControl, Simulation, Source};
use crate::spec::RunSpec;
use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};
use washdyn_model::ir::Model;
use washdyn_model::ir::check::{CheckError, check};
use washdyn_model::ir::toml_file::read_speed_csv;
use washdyn_runtime::run::{Labels, Summary};

/// Named axial unbalance positions (x, m) of the built-in machines' drum
/// (docs/reference-machine.md): front, middle, rear. Other models have other drums: give them
/// positions in m.
pub const POSITIONS: &[(&str, f64)] = &[("front", 0.15), ("middle", 0.0), ("rear", -0.12)];

/// Models whose drum the named positions describe.
const NAMED_POSITION_MODELS: &[&str] = &["reference", "compact"];

/// One variant of a sweep: its model, or the checker's findings on it.
#[derive(Clone, Debug)]
pub struct Variant {
    pub name: String,
    pub model: Result<Model, Vec<CheckError>>,
}

impl Variant {
    /// The model, or [`Error::Check`] with the findings.
    pub fn checked(&self) -> Result<&Model, Error> {
        self.model.as_ref().map_err(|errors| Error::Check {
            model: self.name.clone(),
            errors: errors.clone(),
        })
    }
}

/// What to vary; an empty list keeps the model's own value.
#[derive(Clone, Debug, Default)]
pub struct SweepSpec {
    /// Names from `POSITIONS`.
    pub positions: Vec<String>,
    /// kg of the drum's first unbalance.
    pub masses: Vec<f64>,
    /// Speed profile CSV files (time_s, rpm).
    pub profiles: Vec<PathBuf>,
}

/// The cartesian product of the spec over the base model. Errors name the offending value.
pub fn variants(base: &Model, spec: &SweepSpec) -> Result<Vec<Variant>, Error> {
    let ui = base
        .unbalances
        .iter()
        .position(|u| base.drum().is_some_and(|r| r.name == u.rotor))
        .ok_or_else(|| {
            let what = if spec.masses.is_empty() {
                "--positions"
            } else {
                "--masses"
            };
            Error::setting(
                what,
                "the model has no unbalance on a rotor named `drum` to vary",
            )
        })?;
    let positions: Vec<Option<(String, f64)>> = if spec.positions.is_empty() {
        vec![None]
    } else {
        spec.positions
            .iter()
            .map(|p| {
                if let Ok(x) = p.parse::<f64>() {
                    return if x.is_finite() {
                        Ok(Some((format!("x{x}"), x)))
                    } else {
                        Err(Error::setting(
                            "--positions",
                            format!("position `{p}` must be a finite x in m"),
                        ))
                    };
                }
                let &(n, x) = POSITIONS.iter().find(|(n, _)| n == p).ok_or_else(|| {
                    Error::setting(
                        "--positions",
                        format!(
                            "unknown position `{p}` (front, middle, rear, or an axial x in m)"
                        ),
                    )
                })?;
                if !NAMED_POSITION_MODELS.contains(&base.name.as_str()) {
                    return Err(Error::setting("--positions", format!(
                        "position `{p}` is defined for the built-in drums ({}) only; give model                          `{}` its axial unbalance position in m, e.g. --positions 0.1,-0.1",
                        NAMED_POSITION_MODELS.join(", "),
                        base.name
                    )));
                }
                Ok(Some((n.to_string(), x)))
            })
            .collect::<Result<_, _>>()?
    };
    let masses: Vec<Option<f64>> = if spec.masses.is_empty() {
        vec![None]
    } else {
        spec.masses.iter().map(|&m| Some(m)).collect()
    };
    let profiles: Vec<Option<(String, Vec<[f64; 2]>)>> = if spec.profiles.is_empty() {
        vec![None]
    } else {
        spec.profiles
            .iter()
            .map(|p| {
                let stem = p
                    .file_stem()
                    .map_or("profile".into(), |s| s.to_string_lossy().to_string());
                read_speed_csv(p)
                    .map(|t| Some((stem, t)))
                    .map_err(|e| Error::setting("--profiles", e.to_string()))
            })
            .collect::<Result<_, _>>()?
    };
    let mut out = Vec::new();
    let mut used = HashSet::new();
    for pos in &positions {
        for mass in &masses {
            for prof in &profiles {
                let mut m = base.clone();
                let mut parts = Vec::new();
                if let Some((n, x)) = pos {
                    m.unbalances[ui].position[0] = *x;
                    parts.push(n.to_string());
                }
                if let Some(kg) = mass {
                    m.unbalances[ui].mass = *kg;
                    parts.push(format!("{kg}kg"));
                }
                if let Some((stem, table)) = prof {
                    m.speed.table = table.clone();
                    m.speed.csv = None;
                    parts.push(stem.clone());
                }
                let stem = if parts.is_empty() {
                    "base".into()
                } else {
                    parts.join("_")
                };
                // Every variant its own folder, even where two are given alike.
                let mut name = stem.clone();
                let mut k = 2;
                while !used.insert(name.clone()) {
                    name = format!("{stem}_{k}");
                    k += 1;
                }
                let model = check(&m).map(|_| m);
                out.push(Variant { name, model });
            }
        }
    }
    Ok(out)
}

/// A finished (or failed) variant: its summary and, per channel, the largest amplitude of
/// drum order 1 over the run (its run-up envelope) with the drum speed where it occurs.
#[derive(Debug)]
pub struct VariantResult {
    pub name: String,
    pub summary: Summary,
    /// Why the variant failed: its model or settings refused, its run stopped early.
    pub error: Option<Error>,
    pub peaks: Vec<(String, f64, f64)>,
}

/// What every variant runs with: `run`'s specification (its back end by default the
/// interpreter, as for any variant; its output directory the sweep's), the caller's control
/// and the sweep's parallel runs.
#[derive(Clone, Debug)]
pub struct SweepRun {
    pub spec: RunSpec,
    pub control: RunControl,
    pub jobs: usize,
}

impl SweepRun {
    /// The sweep's directory: the specification's, else `out/<model>-sweep`.
    pub fn out(&self, base: &Model) -> PathBuf {
        self.spec
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join(format!("{}-sweep", base.name)))
    }
}

/// Most parallel runs of a sweep: each is a thread with its own model, state and output
/// streams; beyond the machine's cores (or the variants) more gain nothing, and 1024 is above
/// any workstation's core count.
pub const MAX_JOBS: usize = 1024;

/// The settings' rules on the base model, before anything is written: what `run` would refuse
/// of these settings, the sweep refuses (a variant's own profile is checked again when it runs).
pub fn check_settings(base: &Source, cfg: &SweepRun) -> Result<(), Error> {
    if !(1..=MAX_JOBS).contains(&cfg.jobs) {
        return Err(Error::setting(
            "--jobs",
            format!("--jobs must be in [1, {MAX_JOBS}], got {}", cfg.jobs),
        ));
    }
    Simulation::new(base.variant(base.model.clone()), &cfg.spec, &cfg.control).map(|_| ())
}

/// The simulation of variant `v` of `base`: `run`'s specification, the summary's model
/// labelled `<model>/<variant>`.
pub fn simulation(base: &Source, v: &Variant, cfg: &SweepRun) -> Result<Simulation, Error> {
    let model = v.checked()?;
    let ctl = RunControl {
        variant: Some(v.name.clone()),
        ..cfg.control.clone()
    };
    Simulation::new(base.variant(model.clone()), &cfg.spec, &ctl)
}

/// Run every variant of `base` on `jobs` threads; `done` is called as each finishes. Writes
/// `<out>/<variant>/{sensors.<format>, summary.json}` and `<out>/sweep.csv`.
pub fn run_sweep(
    base: &Source,
    vars: Vec<Variant>,
    cfg: &SweepRun,
    done: &(dyn Fn(&VariantResult) + Sync),
) -> Result<Vec<VariantResult>, Error> {
    use rayon::prelude::*;
    let out = cfg.out(&base.model);
    fs::create_dir_all(&out).map_err(|e| Error::io("create", &out, e))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(cfg.jobs.max(1))
        .build()
        .map_err(|e| Error::refused("sweep", e.to_string()))?;
    let results: Vec<VariantResult> = pool.install(|| {
        vars.par_iter()
            .map(|v| {
                let r = run_one(base, v, cfg, &out).unwrap_or_else(|e| failed(base, v, cfg, e));
                done(&r);
                r
            })
            .collect()
    });
    write_table(&out.join("sweep.csv"), &results)?;
    Ok(results)
}

/// The row of a variant that could not run.
fn failed(base: &Source, v: &Variant, cfg: &SweepRun, error: Error) -> VariantResult {
    let model = v.model.as_ref().map_or(&base.model.name, |m| &m.name);
    let s = &cfg.spec;
    let labels = Labels {
        model: format!("{model}/{}", v.name),
        scene: s.scene.clone().unwrap_or_default(),
        backend: s.backend.unwrap_or(Backend::Interpreted).name().into(),
    };
    let (method, tol) = s.solver(&base.model);
    let mut summary = crate::simulation::unstarted_summary(
        &labels,
        method,
        &s.options(method, tol),
        (s.t_start, s.t_end.unwrap_or(f64::NAN)),
    );
    summary.model_files = base.files.clone();
    summary.status = washdyn_runtime::run::RunStatus::Failed;
    summary.error = Some(error.to_string());
    VariantResult {
        name: v.name.clone(),
        summary,
        error: Some(error),
        peaks: Vec::new(),
    }
}

fn run_one(base: &Source, v: &Variant, cfg: &SweepRun, out: &Path) -> Result<VariantResult, Error> {
    let sim = simulation(base, v, cfg)?;
    let dir = out.join(&v.name);
    fs::create_dir_all(&dir).map_err(|e| Error::io("create", &dir, e))?;
    let motor = motor_ratio(sim.model());
    let rate = sim.run.sample_rate;
    let mut sink = SensorRecorder::new(&dir, cfg.spec.format, true);
    sink.states = cfg.spec.states.then(|| StateRecorder::new(&dir));
    sink.energy = cfg
        .spec
        .energy
        .then(|| EnergyRecorder::new(&dir, cfg.spec.format));
    let verdict = crate::error_class::Verdict::of(&sim);
    let (mut summary, error) = sim.integrate(&mut sink, &mut |_| {});
    verdict.apply(&mut summary, error.is_none());
    let finished = sink.finish();
    write_summary(&dir, &summary)?;
    finished.map_err(|e| Error::io("write", sink.path(), e))?;
    let peaks = order_one_peaks(std::mem::take(&mut sink.memory), &sink.names, rate, motor)?;
    Ok(VariantResult {
        name: v.name.clone(),
        summary,
        error,
        peaks,
    })
}

/// Per channel, the largest drum-order-1 amplitude over the run from the order tracks, and the
/// drum speed there. Unlike a raw maximum it does not catch start-up transients or other
/// orders. Channels that are zero throughout (a fixed cabinet) and runs too short for one
/// analysis block give none.
fn order_one_peaks(
    mut cols: Vec<Vec<f64>>,
    names: &[String],
    sample_rate: f64,
    motor: Option<f64>,
) -> Result<Vec<(String, f64, f64)>, Error> {
    if cols.len() < 3 || cols[0].len() < 2 {
        return Ok(Vec::new());
    }
    let data = cols.split_off(2);
    let rpm = cols.pop().unwrap_or_default();
    let t0 = cols[0][0];
    let channels: Vec<Channel> = names
        .iter()
        .skip(2)
        .zip(data)
        .map(|(n, d)| Channel::new(n.clone(), d))
        .collect();
    let signals = Signals::from_uniform(t0, sample_rate, rpm, channels)?;
    // 4 s blocks: 6 revolutions at the 93 rpm distribution speed, so order 1 is resolved from
    // there on (the tracks follow the drum angle and do not smear at higher speed).
    let opts = AnalysisOptions {
        motor_ratio: motor.unwrap_or(11.25),
        block_length_s: 4.0,
        track_orders: vec![1.0],
        cascades: false,
        ..AnalysisOptions::default()
    };
    let mut out = Vec::new();
    for c in &signals.channels {
        if c.data.iter().all(|v| *v == 0.0) {
            continue;
        }
        let Ok(run) = RunUp::analyse(&signals, c, &opts) else {
            continue;
        };
        let best = run
            .tracks
            .iter()
            .find(|t| t.order == 1.0)
            .and_then(|t| t.max(&run.blocks));
        if let Some((a, r)) = best {
            out.push((c.name.clone(), a, r));
        }
    }
    Ok(out)
}

fn write_table(path: &Path, results: &[VariantResult]) -> Result<(), Error> {
    let e = |e: csv::Error| Error::io("write", path, e.into());
    let mut w = csv::Writer::from_path(path).map_err(e)?;
    let mut channels: Vec<String> = Vec::new();
    for r in results {
        for (c, _, _) in &r.peaks {
            if !channels.contains(c) {
                channels.push(c.clone());
            }
        }
    }
    let mut header: Vec<String> = [
        "variant",
        "status",
        "t_reached_s",
        "steps",
        "rhs_evals",
        "wall_time_s",
        "error",
    ]
    .map(String::from)
    .to_vec();
    for c in &channels {
        header.push(format!("{c}_order1_peak"));
        header.push(format!("{c}_order1_peak_rpm"));
    }
    w.write_record(&header).map_err(e)?;
    for r in results {
        let m = &r.summary;
        let mut row = vec![
            r.name.clone(),
            m.status.name().to_string(),
            m.t_reached.to_string(),
            m.steps.to_string(),
            m.rhs_evals.to_string(),
            format!("{:.3}", m.wall_time_s),
            m.error.clone().unwrap_or_default(),
        ];
        for c in &channels {
            match r.peaks.iter().find(|p| &p.0 == c) {
                Some((_, p, rpm)) => {
                    row.push(format!("{p:.6e}"));
                    row.push(format!("{rpm:.1}"));
                }
                None => {
                    row.push(String::new());
                    row.push(String::new());
                }
            }
        }
        w.write_record(&row).map_err(e)?;
    }
    w.flush().map_err(|e| Error::io("write", path, e))
}
