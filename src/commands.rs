//! The CLI's commands as library functions, so tests drive them without a subprocess.

use crate::error::Error;
pub use crate::error::fe::FeError;
use crate::results::{SensorRecorder, StateRecorder};
use crate::run_dir::RunDir;
pub use crate::simulation::{RunControl, resolve_model};
use crate::simulation::{Simulation, Source};
use crate::spec::Field;
pub use crate::spec::{Backend, RunSpec};
use std::fs;
use std::path::{Path, PathBuf};
use washdyn_model::equations::Equations;
use washdyn_model::ir::modal::ModalData;
use washdyn_model::ir::{DRUM, MOTOR, Model};
use washdyn_runtime::run::{Guard, Progress, Summary};
use washdyn_runtime::system::Interpreter;

/// Outcome of a run: where the files are, and the summary. Until [`RunOutcome::publish`] the
/// files are in the run's own folder beside the target (`run_dir`).
#[derive(Debug)]
pub struct RunOutcome {
    /// The run's folder: its fresh folder until published, then the target.
    pub out_dir: PathBuf,
    /// The sensor file written.
    pub sensors: PathBuf,
    pub summary: Summary,
    /// Why the run stopped early ([`Error::Integration`]); its output up to then is kept.
    pub error: Option<Error>,
    /// Column names and columns (time_s, drum_rpm, channels) when kept in memory.
    pub samples: Option<(Vec<String>, Vec<Vec<f64>>)>,
    /// The model's belt ratio (motor rotor speed / drum speed), for marking motor orders.
    pub motor_ratio: Option<f64>,
    dir: RunDir,
    published: bool,
}

impl RunOutcome {
    /// summary.json again (with what was added after the run: the analysis' order peaks) and
    /// the list of the files written, then the folder renamed into place.
    pub fn publish(&mut self) -> Result<(), Error> {
        if self.published {
            return Ok(());
        }
        self.published = true;
        self.summary.files = files_below(&self.dir.tmp);
        if !self.summary.files.iter().any(|f| f == "summary.json") {
            self.summary.files.push("summary.json".into());
        }
        write_summary(&self.dir.tmp, &self.summary)?;
        let target = self.dir.publish()?;
        if let Some(name) = self.sensors.file_name() {
            self.sensors = target.join(name);
        }
        self.out_dir = target;
        Ok(())
    }
}

/// The files below `dir`, relative to it, sorted.
fn files_below(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if let Ok(rel) = p.strip_prefix(dir) {
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    out.sort();
    out
}

/// The summary's order peaks from the analysis: per channel and tracked order, its largest
/// amplitude (SI units) and the drum speed there; orders never resolved are left out.
pub fn order_peaks(r: &crate::analysis::AnalysisReport) -> Vec<washdyn_runtime::run::OrderPeak> {
    r.channels
        .iter()
        .flat_map(|c| {
            c.orders.iter().filter_map(|o| {
                Some(washdyn_runtime::run::OrderPeak {
                    channel: c.name.clone(),
                    order: o.order,
                    level: o.max_amplitude?,
                    unit: c.quantity.si_unit().to_string(),
                    rpm: o.rpm_at_max?,
                })
            })
        })
        .collect()
}

/// Motor speed / drum speed: the ratio of a rotor named `motor`, else of the fastest rotor
/// that is not the drum.
pub fn motor_ratio(model: &Model) -> Option<f64> {
    let drum = model.drum().map_or(1.0, |r| r.ratio);
    model
        .rotor(MOTOR)
        .or_else(|| {
            model
                .rotors
                .iter()
                .filter(|r| r.name != DRUM)
                .max_by(|a, b| a.ratio.total_cmp(&b.ratio))
        })
        .map(|r| r.ratio / drum)
}

/// `DIR/summary.json`, written for finished and failed runs alike.
pub fn write_summary(dir: &Path, summary: &Summary) -> Result<(), Error> {
    let json = serde_json::to_string_pretty(summary).expect("summary serialises");
    let path = dir.join("summary.json");
    fs::write(&path, json + "\n").map_err(|e| Error::io("write", path, e))
}

/// [`run_command_with`] with the default [`RunControl`], published.
pub fn run_command(
    spec: &RunSpec,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutcome, Error> {
    let mut o = run_command_with(spec, &RunControl::default(), progress)?;
    o.publish()?;
    Ok(o)
}

/// The simulation `washdyn run` sets up for `spec` (every setting checked; nothing written).
pub fn run_simulation(spec: &RunSpec, ctl: &RunControl) -> Result<Simulation, Error> {
    let source = Source::load(&spec.model)?;
    let source = match &spec.speed {
        Some(file) => with_speed(source, file)?,
        None => source,
    };
    Simulation::new(source, spec, ctl)
}

/// The model with its speed table replaced by `file`'s (`--speed`), read as a study's
/// profiles are and held to the model checker's speed rules (times increasing, rpm finite
/// and >= 0). A changed model: the interpreter runs it.
fn with_speed(source: Source, file: &Path) -> Result<Source, Error> {
    let refuse = |m: String| Error::setting(Field::Speed, format!("{}: {m}", file.display()));
    let table = washdyn_model::ir::toml_file::read_speed_csv(file)
        .map_err(|e| Error::setting(Field::Speed, e.to_string()))?;
    let mut model = source.model.clone();
    model.speed.table = table;
    model.speed.csv = None;
    if let Err(errors) = washdyn_model::ir::check::check(&model) {
        let speed: Vec<String> = errors
            .iter()
            .filter(|e| {
                e.path.0.first() == Some(&washdyn_model::ir::check::Seg::Key("speed".into()))
            })
            .map(|e| e.to_string())
            .collect();
        let all = || errors.iter().map(|e| e.to_string()).collect();
        let shown: Vec<String> = if speed.is_empty() { all() } else { speed };
        return Err(refuse(shown.join("; ")));
    }
    Ok(source.variant(model))
}

/// `washdyn run`: validate every setting (nothing is written before), integrate, stream
/// `sensors.parquet` (or `.csv`), write `summary.json`. A failed integration still writes both
/// and reports the error with its time. The samples stay in memory for the analysis when
/// `ctl` asks for one.
pub fn run_command_with(
    spec: &RunSpec,
    ctl: &RunControl,
    progress: &mut dyn FnMut(Progress),
) -> Result<RunOutcome, Error> {
    let sim = run_simulation(spec, ctl)?;
    let target = spec
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&sim.model().name));
    let id = crate::run_dir::new_run_id();
    let dir = RunDir::claim(&target, &id, spec.force)?;
    let out_dir = dir.tmp.clone();
    let motor_ratio = motor_ratio(sim.model());
    let keep_samples = ctl.analysis_band_hz.is_some();
    let mut sink = SensorRecorder::new(&out_dir, spec.format, keep_samples);
    sink.run_id = Some(id.clone());
    sink.states = spec.states.then(|| {
        let mut r = StateRecorder::new(&out_dir);
        r.run_id = Some(id.clone());
        r
    });
    sink.energy = spec.energy.then(|| {
        let mut r = crate::results::EnergyRecorder::new(&out_dir, spec.format);
        r.run_id = Some(id.clone());
        r
    });
    let verdict = crate::error_class::Verdict::of(&sim);
    let (mut summary, error) = sim.integrate(&mut sink, progress);
    verdict.apply(&mut summary, error.is_none());
    summary.run_id = Some(id);
    let mut written = sink
        .finish()
        .map_err(|e| Error::io("write", sink.path(), e));
    if let (Ok(()), Some(e)) = (&written, &sink.energy) {
        let (t, lines) = e.lines();
        let opts = crate::analysis::AnalysisOptions::default();
        written = crate::analysis::plot::energy_plot(&t, &lines, &opts, &out_dir.join("energy"))
            .map(drop)
            .map_err(Error::from);
    }
    // The summary says what the exit code will: a file the run could not write fails it.
    if let (Err(e), None) = (&written, &error) {
        summary.status = washdyn_runtime::run::RunStatus::Failed;
        summary.error = Some(e.to_string());
    }
    write_summary(&out_dir, &summary)?;
    written?;
    let samples = keep_samples.then(|| (sink.names.clone(), std::mem::take(&mut sink.memory)));
    Ok(RunOutcome {
        out_dir,
        sensors: sink.path().to_path_buf(),
        summary,
        error,
        samples,
        motor_ratio,
        dir,
        published: false,
    })
}

/// `washdyn check`: the model's own checks (done on loading), then what a run needs of each
/// scene: a static equilibrium at t = 0 (a model without springs has none) and a rest position
/// inside the small-motion bounds of [`Guard`].
pub fn check_model(model: &Model) -> Result<String, Error> {
    let guard = Guard::default();
    let mut lines = vec![format!(
        "{}: ok; scenes: {}",
        model.name,
        model.scene_names().join(", ")
    )];
    let mut errors = Vec::new();
    for name in model.scene_names() {
        let scene = model
            .scene(Some(&name))
            .map_err(|m| Error::setting(Field::Scene, m))?;
        let mut sys = Interpreter::new(model, &scene);
        match washdyn_runtime::statics::static_equilibrium(&mut sys, 0.0) {
            Ok(q) => {
                let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
                let (u, a) = Equations::new(model, &scene).bodies.rigid_motion(&q);
                let (u, a) = (norm(u), norm(a));
                let spec = RunSpec {
                    scene: Some(name.clone()),
                    ..RunSpec::default()
                };
                let (method, tol) = spec.solver(model);
                let msg = format!(
                    "scene `{name}` (default: {method} at {tol:e}): static rest position at \
                     t = 0: tub translation {:.2} mm, rotation {a:.2e} rad",
                    u * 1e3
                );
                // A NaN compares false: test finiteness first, then the bounds negated.
                if !(q.iter().all(|x| x.is_finite()) && u.is_finite() && a.is_finite()) {
                    errors.push(format!("{msg}: not a number (non-finite model data)"));
                } else if !(u <= guard.translation_m && a <= guard.rotation_rad) {
                    errors.push(format!(
                        "{msg}: beyond the small-motion bounds ({} mm, {} rad); a spring pulling \
                         the wrong way or too soft?",
                        guard.translation_m * 1e3,
                        guard.rotation_rad
                    ));
                } else {
                    lines.push(msg);
                }
            }
            Err(e) => errors.push(format!("scene `{name}` cannot run: {e}")),
        }
    }
    if errors.is_empty() {
        Ok(lines.join("\n"))
    } else {
        Err(Error::Scene {
            model: model.name.clone(),
            problems: errors,
        })
    }
}

/// `washdyn fe modal`'s report: the sections of `old` (one per body, starting with a line
/// `NAME: ...` at column 0) with those in `new` replaced or added, in the bodies' `order`.
pub fn merge_report(old: &str, new: &[(String, String)], order: &[String]) -> String {
    let mut sections: Vec<(String, String)> = Vec::new();
    for line in old.lines() {
        let head = line
            .split_once(": ")
            .filter(|_| !line.starts_with(' '))
            .map(|(n, _)| n.to_string());
        match (head, sections.last_mut()) {
            (Some(name), _) => sections.push((name, format!("{line}\n"))),
            (None, Some((_, text))) => {
                text.push_str(line);
                text.push('\n');
            }
            (None, None) => {}
        }
    }
    for (name, text) in new {
        match sections.iter_mut().find(|(n, _)| n == name) {
            Some(s) => s.1 = text.clone(),
            None => sections.push((name.clone(), text.clone())),
        }
    }
    let rank = |n: &str| order.iter().position(|o| o == n).unwrap_or(order.len());
    sections.sort_by_key(|(n, _)| rank(n));
    sections.into_iter().map(|(_, t)| t).collect()
}

/// An I/O failure on `path`, as `washdyn fe` words it (`path: error`).
fn fe_io(path: &Path) -> impl FnOnce(std::io::Error) -> FeError {
    crate::error::FileError::at(path)
}

/// `washdyn fe write`: the built-in decks (frequency decks, and the drum's prestressed one).
pub fn fe_write(out: &Path) -> Result<(), FeError> {
    std::fs::create_dir_all(out).map_err(fe_io(out))?;
    for (name, text) in washdyn_fe::bodies::decks() {
        let p = out.join(name);
        std::fs::write(&p, &text).map_err(fe_io(&p))?;
        println!("{} ({} kB)", p.display(), text.len() / 1024);
    }
    Ok(())
}

/// `washdyn fe modal`: solve the built-in bodies and write their modal data and a report.
pub fn fe_modal(out: &Path, work: &Path, only: &[String]) -> Result<(), FeError> {
    let bodies = washdyn_fe::bodies::builtin();
    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    if let Some(bad) = only.iter().find(|o| !names.contains(&o.as_str())) {
        return Err(FeError::NoBody {
            name: bad.clone(),
            bodies: names.iter().map(|n| n.to_string()).collect(),
        });
    }
    for d in [out, work] {
        std::fs::create_dir_all(d).map_err(fe_io(d))?;
    }
    let order: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    let mut sections = Vec::new();
    for b in bodies {
        if !only.is_empty() && !only.contains(&b.name) {
            continue;
        }
        let (data, r) = washdyn_fe::pipeline::build(&b, work)?;
        let header = format!(
            "the {} (docs/modal-data.md), written by `washdyn fe modal`",
            b.name
        );
        let line = format!("{r}{}\n", write_modal(out, &b.name, &header, &data)?);
        print!("{line}");
        sections.push((b.name.clone(), line));
    }
    // With --only, the other bodies' sections of an existing report stay.
    let p = out.join("report.txt");
    let old = std::fs::read_to_string(&p).unwrap_or_default();
    let report = merge_report(&old, &sections, &order);
    std::fs::write(&p, report).map_err(fe_io(&p))
}

/// `<out>/<name>.modal.toml` with a comment line saying whose data it is; returns the
/// report's line for it (modes kept, their range, the file and its size).
fn write_modal(out: &Path, name: &str, header: &str, data: &ModalData) -> Result<String, FeError> {
    let p = out.join(format!("{name}.modal.toml"));
    let text = format!("# Modal data of {header}.\n{}", data.to_toml());
    fs::write(&p, &text).map_err(fe_io(&p))?;
    Ok(format!(
        "  {} modes kept, {:.2} to {:.2} Hz; {} ({} kB)",
        data.modes(),
        data.frequencies[0],
        data.frequencies[data.modes() - 1],
        p.display(),
        text.len() / 1024
    ))
}

/// `washdyn fe deck`: a user's deck and spec to checked modal data (and field).
pub fn fe_deck(spec: &Path, out: &Path, work: &Path) -> Result<(), FeError> {
    let body = washdyn_fe::user::load(spec)?;
    for d in [out, work] {
        fs::create_dir_all(d).map_err(fe_io(d))?;
    }
    let (mut data, report, c) = washdyn_fe::user::build_checked(&body, work)?;
    data.source = washdyn_fe::user::deck_source(&data.source, spec);
    let header = format!("`{}` from {} (washdyn fe deck)", body.name, spec.display());
    let line = write_modal(out, &body.name, &header, &data)?;
    print!("{report}");
    let names: Vec<&str> = body.points.iter().map(|(n, _)| n.as_str()).collect();
    println!("  points: {}", names.join(", "));
    println!(
        "  checked against the deck: mass {:.1e} off ccx's, CoG {:.1e} m, {} rigid-body modes, \
         normalisation {:.1e}",
        c.mass, c.cog, c.rigid_modes, c.normalisation
    );
    println!("{line}");
    if body.recovery {
        let field = format!("{}.field.bin", body.name);
        fs::copy(work.join(&field), out.join(&field)).map_err(fe_io(&out.join(&field)))?;
        println!("  wrote {}", out.join(&field).display());
    }
    Ok(())
}

#[cfg(test)]
mod report_tests {
    use super::merge_report;

    #[test]
    fn only_the_solved_bodies_sections_change() {
        let old = "cabinet: 3 nodes\n  lumped mass 1 kg\ntub: 1 nodes\n  old tub\n";
        let order = ["tub", "drum", "cabinet"].map(String::from);
        let new = vec![("tub".to_string(), "tub: 2 nodes\n  new tub\n".to_string())];
        assert_eq!(
            merge_report(old, &new, &order),
            "tub: 2 nodes\n  new tub\ncabinet: 3 nodes\n  lumped mass 1 kg\n"
        );
        assert_eq!(merge_report("", &new, &order), "tub: 2 nodes\n  new tub\n");
    }
}
