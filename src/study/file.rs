//! The study file (TOML): the model, its scene, the run settings, the parameters (paths in
//! `ir::param`'s syntax, each with levels or a range), the design and the outputs to plot
//! against each other. Read with serde (unknown fields refused), then checked against the base
//! model: every problem is reported at its file, line and column, located as a model file's
//! are (`toml_file::locate`). Nothing is written before the whole study is checked.

use super::design::{self, Axis, Design, Kind, Scale};
use super::error::StudyError;
use super::outputs::Outputs;
use crate::error::Error;
use crate::simulation::{RunControl, Simulation, Source};
use crate::spec::{Field, RunSpec, Spelling};
use serde::Deserialize;
use std::path::{Path as FsPath, PathBuf};
use washdyn_model::ir::check::{Path, Seg};
use washdyn_model::ir::modal::from_toml;
use washdyn_model::ir::param::{self, Param};
use washdyn_model::ir::toml_file::{Located, line_col, locate, read_speed_csv};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    /// A built-in model's name, or a model file relative to the study file.
    model: String,
    scene: Option<String>,
    /// `washdyn run`'s specification by its keys (`spec::Field::key`).
    #[serde(default)]
    run: RunSpec,
    #[serde(default, rename = "parameter")]
    parameters: Vec<ParameterTable>,
    design: DesignTable,
    outputs: Option<OutputsTable>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParameterTable {
    path: String,
    /// Speed profile CSV files (time_s, rpm) relative to the study file, with
    /// `path = "speed.profile"`: the design's levels are their indices.
    profiles: Option<Vec<PathBuf>>,
    range: Option<Vec<f64>>,
    levels: Option<Vec<f64>>,
    scale: Option<Scale>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DesignTable {
    kind: Kind,
    samples: Option<usize>,
    seed: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OutputsTable {
    /// Two output columns to plot against each other (stored in study.json).
    pareto: Vec<String>,
}

/// A parameter of the study, resolved on the base model.
#[derive(Clone, Debug)]
pub struct Parameter {
    /// The path as the study file writes it: the summary's and the design's column name.
    pub text: String,
    pub param: Param,
    /// The base model's value there (none for speed profiles).
    pub base: Option<f64>,
    pub axis: Axis,
    /// A speed-profile parameter's tables, the level k being `profiles[k]`; empty for a number.
    pub profiles: Vec<Profile>,
}

/// The path of a parameter whose levels are speed profile files.
pub const PROFILE_PATH: &str = "speed.profile";

/// A speed profile a study varies: its file as the study file names it, and its table.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    pub file: PathBuf,
    pub table: Vec<[f64; 2]>,
}

/// A checked study: the base model, the settings every variant runs with, the parameters, the
/// design and its points, and the columns each variant reports.
#[derive(Debug)]
pub struct Study {
    /// The study file, and its text (copied into the study's directory).
    pub file: PathBuf,
    pub text: String,
    pub source: Source,
    /// The model as the study file names it, and its content as the scene runs it
    /// (`error_class::content_hash`: what a re-run must find unchanged).
    pub model_spec: String,
    pub model_content: String,
    /// The scene's name and the end of the run, s (the profile's end unless `t_end`).
    pub scene: String,
    pub t_end: f64,
    /// The specification every variant runs with (its model the study file's `model`).
    pub spec: RunSpec,
    /// The caller's guard (Ctrl-C); every variant's summary labelled with its id.
    pub control: RunControl,
    pub parameters: Vec<Parameter>,
    pub design: Design,
    /// Design order: one row per variant, one value per parameter.
    pub points: Vec<Vec<f64>>,
    pub outputs: Outputs,
    /// Two output columns for a Pareto plot.
    pub pareto: Option<[String; 2]>,
}

/// Collects the study file's problems, each located.
struct Problems<'a> {
    file: &'a str,
    src: &'a str,
    found: Vec<Located>,
}

impl Problems<'_> {
    fn at(&mut self, path: &Path, message: impl Into<String>) {
        self.at_near(path, path, message);
    }
    /// A problem of `path` located at it, else (absent from the file) at `near`, else at the
    /// file's first line: never at 0:0.
    fn at_near(&mut self, path: &Path, near: &Path, message: impl Into<String>) {
        let (line, column) = match locate(self.src, path) {
            (0, _) => match locate(self.src, near) {
                (0, _) => (1, 1),
                at => at,
            },
            at => at,
        };
        self.found.push(Located {
            file: self.file.to_string(),
            line,
            column,
            message: format!("{path}: {}", message.into()),
        });
    }
    /// The problems so far as the error, if any, in the file's order.
    fn check(&mut self) -> Result<(), Error> {
        if self.found.is_empty() {
            return Ok(());
        }
        self.found.sort_by_key(|e| (e.line, e.column));
        Err(StudyError::File(std::mem::take(&mut self.found)).into())
    }
}

/// Where a field of the specification sits in the study file.
fn field_path(field: Field) -> Path {
    if field.in_run_table() {
        Path::default().key("run").key(field.key())
    } else {
        Path::default().key(field.key())
    }
}

impl Study {
    /// Read and check a study file: the model (built in, or a file relative to the study file),
    /// the scene and settings (`Simulation::new` on the base model), every parameter path on
    /// the base model, the design, and the outputs named for the Pareto plot.
    pub fn load(path: &FsPath) -> Result<Study, Error> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io("read", path, e))?;
        Study::from_text(path, text)
    }

    /// [`Study::load`] of a study file's text (a sweep's, made in memory), as if read from
    /// `path`: relative files are the file's neighbours.
    pub fn from_text(path: &FsPath, text: String) -> Result<Study, Error> {
        let shown = path.display().to_string();
        let parsed: StudyFile = from_toml(&text).map_err(|(span, message)| {
            let at = span.map_or((1, 1), |s| line_col(&text, s.start));
            Error::from(StudyError::at(&shown, at, message))
        })?;
        let mut p = Problems {
            file: &shown,
            src: &text,
            found: Vec::new(),
        };
        let source = load_model(path, &parsed.model, &mut p)?;
        // Every problem at once: the settings, the parameters, the design; then the outputs,
        // which need the scene's channels.
        let spec = RunSpec {
            model: source.spec.clone(),
            scene: parsed.scene.clone(),
            ..parsed.run
        };
        let dir = path.parent().unwrap_or(FsPath::new(""));
        let parameters = parameters(&source, dir, &parsed.parameters, &mut p);
        let control = RunControl::default();
        let base = match Simulation::new(source.variant(source.model.clone()), &spec, &control) {
            Ok(b) => Some(b),
            Err(Error::Settings(refusals)) => {
                for r in refusals {
                    let at = r.field().map_or_else(Path::default, field_path);
                    p.at(&at, r.message(Spelling::File));
                }
                None
            }
            Err(e) => return Err(e),
        };
        let design = Design {
            kind: parsed.design.kind,
            samples: parsed.design.samples,
            seed: parsed.design.seed,
        };
        let axes: Vec<Axis> = parameters.iter().map(|q| q.axis.clone()).collect();
        let points = match design::points(&design, &axes) {
            Ok(points) => points,
            Err(e) => {
                // A parameter refused above has no axis: the design's view of it would mislead.
                // No [[parameter]] at all: shown at the design that has none to vary.
                if parameters.len() == parsed.parameters.len() {
                    p.at_near(&e.at, &Path::default().key("design"), e.message);
                }
                Vec::new()
            }
        };
        p.check()?;
        let base = base.expect("no problems: the base simulation was set up");
        let outputs = Outputs::new(&base);
        let pareto = parsed
            .outputs
            .as_ref()
            .and_then(|o| pareto(&o.pareto, &outputs, &mut p));
        p.check()?;
        Ok(Study {
            file: path.to_path_buf(),
            text: text.clone(),
            model_spec: parsed.model.clone(),
            model_content: crate::error_class::content_hash(&source.model, &base.scene),
            scene: base.scene.name.clone(),
            t_end: base.run.t_end,
            source,
            spec,
            control,
            parameters,
            design,
            points,
            outputs,
            pareto,
        })
    }

    /// Where the study's files go by default: `out/<study file's stem>`.
    pub fn default_out(&self) -> PathBuf {
        let stem = self
            .file
            .file_stem()
            .map_or("study".into(), |s| s.to_string_lossy().to_string());
        PathBuf::from("out").join(stem)
    }
}

/// The two outputs `[outputs] pareto` names, each one of the study's.
fn pareto(names: &[String], outputs: &Outputs, p: &mut Problems) -> Option<[String; 2]> {
    let at = Path::default().key("outputs").key("pareto");
    let [a, b] = names else {
        p.at(
            &at,
            "name two outputs, e.g. [\"peak_door_ring_m\", \"wall_time_s\"]",
        );
        return None;
    };
    if a == b {
        p.at(&at, format!("name two different outputs, not `{a}` twice"));
        return None;
    }
    let known = outputs.plottable();
    let mut ok = true;
    for (i, n) in [a, b].into_iter().enumerate() {
        if !known.contains(n) {
            ok = false;
            p.at(
                &at.clone().idx(i),
                format!(
                    "`{n}` is not an output of this study ({})",
                    outputs.describe()
                ),
            );
        }
    }
    ok.then(|| [a.clone(), b.clone()])
}

/// The base model: a built-in name, else a model file relative to the study file (its own
/// errors at its own lines).
fn load_model(study: &FsPath, spec: &str, p: &mut Problems) -> Result<Source, Error> {
    if washdyn_models::built_in(spec).is_some() {
        return Source::load(spec);
    }
    let path = study.parent().unwrap_or(FsPath::new("")).join(spec);
    if !path.is_file() {
        let shown = std::path::absolute(&path).unwrap_or_else(|_| path.clone());
        p.at(
            &Path::default().key("model"),
            format!(
                "`{spec}` is neither a built-in model ({}) nor a file (no file {})",
                washdyn_models::BUILT_IN.join(", "),
                shown.display()
            ),
        );
        p.check()?;
    }
    Source::load(&path.display().to_string())
}

/// Every `[[parameter]]` resolved on the base model, with its levels or range checked.
fn parameters(
    source: &Source,
    dir: &FsPath,
    tables: &[ParameterTable],
    p: &mut Problems,
) -> Vec<Parameter> {
    let mut out: Vec<Parameter> = Vec::new();
    for (i, t) in tables.iter().enumerate() {
        let at = |k: &str| Path::default().key("parameter").idx(i).key(k);
        if t.profiles.is_some() || t.path.trim() == PROFILE_PATH {
            if out.iter().any(|o| o.text == PROFILE_PATH) {
                p.at(&at("path"), format!("`{PROFILE_PATH}` given twice"));
            } else if let Some(q) = profile_parameter(dir, t, &at, p) {
                out.push(q);
            }
            continue;
        }
        let param = match param::resolve(&source.model, &t.path) {
            Ok(q) => q,
            Err(e) => {
                p.at(&at("path"), e.message);
                continue;
            }
        };
        if let Some(other) = out.iter().find(|o| o.param.path == param.path) {
            p.at(
                &at("path"),
                format!(
                    "`{}` names the same number as `{}` ({})",
                    t.path, other.text, param.path
                ),
            );
            continue;
        }
        let axis = match (&t.levels, &t.range) {
            (Some(_), Some(_)) | (None, None) => {
                p.at(
                    &at("path"),
                    format!(
                        "`{}`: give either `levels = [..]` or `range = [lo, hi]`",
                        t.path
                    ),
                );
                continue;
            }
            (Some(levels), None) => {
                if t.scale.is_some() {
                    p.at(
                        &at("scale"),
                        "`scale` maps a range; levels are taken as given",
                    );
                }
                if levels.is_empty() {
                    p.at(&at("levels"), "no levels");
                } else if let Some(x) = levels.iter().find(|x| !x.is_finite()) {
                    p.at(&at("levels"), format!("level {x} is not a finite number"));
                } else if let Some((k, x)) = levels
                    .iter()
                    .enumerate()
                    .find(|(k, x)| levels[..*k].contains(x))
                {
                    p.at(
                        &at("levels").idx(k),
                        format!("level {x} given twice: two variants would be the same"),
                    );
                }
                Axis::Levels(levels.clone())
            }
            (None, Some(range)) => {
                let scale = t.scale.unwrap_or_default();
                match range[..] {
                    [lo, hi] if lo.is_finite() && hi.is_finite() && lo < hi => {
                        if scale == Scale::Log && lo <= 0.0 {
                            p.at(
                                &at("range"),
                                format!("a log scale needs a positive range, got [{lo}, {hi}]"),
                            );
                        }
                        Axis::Range { lo, hi, scale }
                    }
                    _ => {
                        p.at(
                            &at("range"),
                            format!(
                                "range must be [lo, hi] with finite lo < hi, got {:?}",
                                range
                            ),
                        );
                        continue;
                    }
                }
            }
        };
        out.push(Parameter {
            text: t.path.trim().to_string(),
            base: Some(param::get(&source.model, &param)),
            param,
            axis,
            profiles: Vec::new(),
        });
    }
    out
}

/// A `speed.profile` parameter: its files (relative to the study file) read as speed tables,
/// each refused at its place; its levels their indices.
fn profile_parameter(
    dir: &FsPath,
    t: &ParameterTable,
    at: &dyn Fn(&str) -> Path,
    p: &mut Problems,
) -> Option<Parameter> {
    let Some(files) = t
        .profiles
        .as_ref()
        .filter(|_| t.path.trim() == PROFILE_PATH)
    else {
        p.at(
            &at("path"),
            format!(
                "speed profile files go with `path = \"{PROFILE_PATH}\"` and `profiles = [..]`"
            ),
        );
        return None;
    };
    if t.levels.is_some() || t.range.is_some() || t.scale.is_some() {
        p.at(
            &at("profiles"),
            "a profile parameter's levels are its files: no levels, range or scale",
        );
    }
    if files.is_empty() {
        p.at(&at("profiles"), "no profiles");
        return None;
    }
    let mut profiles = Vec::new();
    for (k, f) in files.iter().enumerate() {
        if files[..k].contains(f) {
            p.at(
                &at("profiles").idx(k),
                format!(
                    "`{}` given twice: two variants would be the same",
                    f.display()
                ),
            );
            continue;
        }
        match read_speed_csv(&dir.join(f)) {
            Ok(table) => profiles.push(Profile {
                file: f.clone(),
                table,
            }),
            Err(e) => p.at(&at("profiles").idx(k), e.to_string()),
        }
    }
    (profiles.len() == files.len()).then(|| Parameter {
        text: PROFILE_PATH.to_string(),
        param: Param {
            text: PROFILE_PATH.to_string(),
            path: Path::default().key("speed").key("table"),
        },
        base: None,
        axis: Axis::Levels((0..profiles.len()).map(|k| k as f64).collect()),
        profiles,
    })
}

/// Whether a parameter changes the speed profile: the settings' rules read it (the window's
/// end, a periodic start's constant speed), so such variants are set up before anything runs.
pub fn touches_speed(p: &Parameter) -> bool {
    matches!(p.param.path.0.first(), Some(Seg::Key(k)) if k == "speed")
}
