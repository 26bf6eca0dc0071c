//! `washdyn sweep`: a grid design of the study over the drum's unbalance (its axial position
//! and mass) and the speed profile. The sweep's options become the study file they stand for
//! (written into the sweep's directory as `study.toml`, as any study's), and the study runs it:
//! every variant checked before anything runs, the same dataset, re-run, `status` and
//! `collect`. The options a study does not take are refused here, at their option.

use crate::error::Error;
use crate::simulation::{RunControl, Simulation, Source};
use crate::spec::{Field, RunSpec};
use serde::Serialize;
use std::path::PathBuf;
use washdyn_model::ir::Model;
use washdyn_model::ir::toml_file::read_speed_csv;

use super::file::PROFILE_PATH;

/// Named axial unbalance positions (x, m) of the built-in machines' drum
/// (docs/reference-machine.md): front, middle, rear. Other models have other drums: give them
/// positions in m.
pub const POSITIONS: &[(&str, f64)] = &[("front", 0.15), ("middle", 0.0), ("rear", -0.12)];

/// Models whose drum the named positions describe.
const NAMED_POSITION_MODELS: &[&str] = &["reference", "compact"];

/// What a sweep varies; an empty list keeps the model's own value (with none at all, the sweep
/// is the base model alone: its own mass as the one level).
#[derive(Clone, Debug, Default)]
pub struct Grid {
    /// Names from [`POSITIONS`], or axial positions in m.
    pub positions: Vec<String>,
    /// kg of the drum's unbalance.
    pub masses: Vec<f64>,
    /// Speed profile CSV files (time_s, rpm).
    pub profiles: Vec<PathBuf>,
}

/// The study file of a sweep, as serde writes it (the study reads it back by its own rules).
#[derive(Serialize)]
struct SweepFile<'a> {
    model: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    scene: Option<&'a str>,
    run: &'a RunSpec,
    parameter: Vec<Parameter>,
    design: Design,
}

#[derive(Serialize)]
struct Parameter {
    path: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    levels: Option<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    profiles: Option<Vec<PathBuf>>,
}

#[derive(Serialize)]
struct Design {
    kind: &'static str,
}

/// The sweep's directory: the specification's, else `out/<model>-sweep`.
pub fn out_dir(spec: &RunSpec, base: &Model) -> PathBuf {
    spec.out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(format!("{}-sweep", base.name)))
}

/// The study file a sweep of `base` stands for. Refuses, at its option, what `run` would
/// refuse of `spec` (the settings' rules on the base model), what a study does not take (a
/// back end, CSV, energy or states: run such a variant with `washdyn run`), and a position,
/// mass or profile that is no level (unknown, not finite, unreadable, given twice).
pub fn study_text(base: &Source, spec: &RunSpec, grid: &Grid) -> Result<String, Error> {
    if spec.speed.is_some() {
        return Err(Error::setting(
            Field::Speed,
            "a sweep varies the speed with --profiles (files of the same format)",
        ));
    }
    let unsupported = [
        (Field::Backend, spec.backend.is_some()),
        (
            Field::Format,
            spec.format != crate::results::Format::Parquet,
        ),
        (Field::Energy, spec.energy),
        (Field::States, spec.states),
        (Field::Force, spec.force),
    ];
    if let Some((f, _)) = unsupported.iter().find(|(_, given)| *given) {
        return Err(Error::setting(
            *f,
            format!(
                "a sweep is a study: its variants run on the back end that fits each and write \
                 the sensors as Parquet only; run one variant with `washdyn run {} {}`",
                spec.model,
                f.option()
            ),
        ));
    }
    Simulation::new(
        base.variant(base.model.clone()),
        spec,
        &RunControl::default(),
    )?;
    let unbalance = drum_unbalance(&base.model, grid)?;
    let mut parameter = Vec::new();
    let positions = positions(&base.model, &grid.positions)?;
    if !positions.is_empty() {
        parameter.push(Parameter {
            path: format!("unbalances.{}.position.0", unbalance.name),
            levels: Some(positions),
            profiles: None,
        });
    }
    if !grid.masses.is_empty() || grid.positions.is_empty() && grid.profiles.is_empty() {
        let masses = match grid.masses.is_empty() {
            true => vec![unbalance.mass],
            false => levels("--masses", &grid.masses)?,
        };
        parameter.push(Parameter {
            path: format!("unbalances.{}.mass", unbalance.name),
            levels: Some(masses),
            profiles: None,
        });
    }
    if !grid.profiles.is_empty() {
        parameter.push(Parameter {
            path: PROFILE_PATH.into(),
            levels: None,
            profiles: Some(profiles(&grid.profiles)?),
        });
    }
    let model = match washdyn_models::built_in(&spec.model) {
        Some(_) => spec.model.clone(),
        None => absolute(&PathBuf::from(&spec.model)).display().to_string(),
    };
    let file = SweepFile {
        model,
        scene: spec.scene.as_deref(),
        run: spec,
        parameter,
        design: Design { kind: "grid" },
    };
    // Strings, numbers and tables only: TOML writes every value of them.
    let text = toml::to_string(&file).expect("a sweep's study file serialises");
    Ok(format!(
        "# The study `washdyn sweep` ran (a grid design): `washdyn study run` of this file \
         completes it.\n{text}"
    ))
}

/// The unbalance on the rotor named `drum`, which the sweep varies.
fn drum_unbalance<'a>(
    base: &'a Model,
    grid: &Grid,
) -> Result<&'a washdyn_model::ir::Unbalance, Error> {
    let drum = base.drum().map(|r| r.name.as_str());
    base.unbalances
        .iter()
        .find(|u| Some(u.rotor.as_str()) == drum)
        .ok_or_else(|| {
            let what = match grid.masses.is_empty() {
                true => "--positions",
                false => "--masses",
            };
            Error::setting(
                what,
                "the model has no unbalance on a rotor named `drum` to vary",
            )
        })
}

/// Axial positions, m: a name of [`POSITIONS`] (the built-in drums only) or a number.
fn positions(base: &Model, given: &[String]) -> Result<Vec<f64>, Error> {
    let refuse = |m: String| Error::setting("--positions", m);
    let mut out = Vec::new();
    for p in given {
        let x = match p.parse::<f64>() {
            Ok(x) if x.is_finite() => x,
            Ok(_) => return Err(refuse(format!("position `{p}` must be a finite x in m"))),
            Err(_) => {
                let &(_, x) = POSITIONS.iter().find(|(n, _)| n == p).ok_or_else(|| {
                    refuse(format!(
                        "unknown position `{p}` (front, middle, rear, or an axial x in m)"
                    ))
                })?;
                if !NAMED_POSITION_MODELS.contains(&base.name.as_str()) {
                    return Err(refuse(format!(
                        "position `{p}` is defined for the built-in drums ({}) only; give model \
                         `{}` its axial unbalance position in m, e.g. --positions 0.1,-0.1",
                        NAMED_POSITION_MODELS.join(", "),
                        base.name
                    )));
                }
                x
            }
        };
        out.push(x);
    }
    levels("--positions", &out)
}

/// Numbers as a study's levels: finite, each once (two variants alike would be one).
fn levels(option: &'static str, xs: &[f64]) -> Result<Vec<f64>, Error> {
    for (k, x) in xs.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::setting(
                option,
                format!("{option}: {x} is not a finite number"),
            ));
        }
        if xs[..k].contains(x) {
            return Err(Error::setting(
                option,
                format!("{option}: {x} given twice: two variants would be the same"),
            ));
        }
    }
    Ok(xs.to_vec())
}

/// The profiles as absolute paths (the study file lives elsewhere), each read once here so
/// that a bad one is refused at `--profiles`.
fn profiles(given: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let mut out: Vec<PathBuf> = Vec::new();
    for p in given {
        read_speed_csv(p).map_err(|e| Error::setting("--profiles", e.to_string()))?;
        let a = absolute(p);
        if out.contains(&a) {
            return Err(Error::setting(
                "--profiles",
                format!(
                    "`{}` given twice: two variants would be the same",
                    p.display()
                ),
            ));
        }
        out.push(a);
    }
    Ok(out)
}

fn absolute(p: &std::path::Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}
