//! Recovery on the FE mesh after a run (`washdyn fields`): the stored states (`states.parquet`)
//! and each body's mode shapes on its mesh (`<body>.field.bin`, from `washdyn fe modal`) give
//! the nodal displacements, rigid motion + W q in the global frame, written as VTK grids with a
//! `.pvd` collection per body. It reads what the run wrote and never touches the run.
//!
//! Kinematics (linearised, as the equations): a tub node x moves u + alpha x (x - p0) + W q_tub;
//! the drum is drawn turned by its ratio x phi about its axis, p = B + R(ratio phi)(x - B), and
//! moves with the tub's material frame at its mount B (translation d_B, rotation theta_B) plus
//! its own modes: d_B + theta_B x (p - B) + R(ratio phi) W q_drum; a cabinet node moves W q_cab.
//!
//! This file holds the command (which run, which model, what to write); the concepts it joins
//! have a file each: the stored states and the instants asked for (`states.rs`), the field
//! files' modes against the scene's (`projection.rs`), the recovery of displacements and
//! stresses on a body's mesh (`recovery.rs`), the VTK grids (`grids.rs`) and the drum's front
//! edge over a run (`drum_edge.rs`).

use std::path::Path;
use washdyn_model::equations::Equations;
use washdyn_model::ir::BodyRef;
use washdyn_model::ir::files::FileHash;

mod drum_edge;
mod grids;
mod projection;
mod recovery;
mod states;

pub use crate::error::fields::FieldsError;
pub use drum_edge::{EdgeRow, drum_edge, write_drum_edge};
pub use grids::{Written, write_fields, write_fields_with};
pub use recovery::{BodyField, NodeStresses, Recovery};
pub use states::{MAX_FRAMES, REVOLUTION_FRAMES, States, Times, check_times};

/// What `washdyn fields` makes.
pub enum Request {
    /// Grids at these instants.
    Fields(Times),
    /// The drum's front edge over the run, every `stride`-th sample (`svg`: also SVG).
    DrumEdge { stride: usize, svg: bool },
}

/// `washdyn fields`: the run in `run_dir` (its summary names model and scene; `model` overrides
/// the model, for model files), into `out` (default `run_dir/fields`).
pub fn fields_command(
    run_dir: &Path,
    model: Option<&str>,
    request: &Request,
    fe_dir: &Path,
    out: Option<&Path>,
) -> Result<Written, FieldsError> {
    fields_command_with(run_dir, model, request, fe_dir, out, &mut |_, _, _| {})
}

/// [`fields_command`], telling `frame` of each grid written ([`write_fields_with`]).
pub fn fields_command_with(
    run_dir: &Path,
    model: Option<&str>,
    request: &Request,
    fe_dir: &Path,
    out: Option<&Path>,
    frame: &mut dyn FnMut(usize, usize, &Path),
) -> Result<Written, FieldsError> {
    // The states must be the summary's run's before anything is read of either.
    crate::run_dir::check_same_run(run_dir, &run_dir.join("states.parquet"))?;
    let summary = std::fs::read_to_string(run_dir.join("summary.json")).map_err(|source| {
        FieldsError::NoSummary {
            dir: run_dir.to_path_buf(),
            source,
        }
    })?;
    let summary: serde_json::Value =
        serde_json::from_str(&summary).map_err(FieldsError::Summary)?;
    let text = |k: &'static str| {
        summary[k]
            .as_str()
            .map(str::to_string)
            .ok_or(FieldsError::SummaryKey(k))
    };
    // The run's model: `--model`, else the file the summary names (refused if it or a data
    // file it names changed since), else the built-in model of the summary's name.
    let files: Vec<FileHash> = match summary.get("model_files") {
        Some(v) => serde_json::from_value(v.clone()).map_err(FieldsError::ModelFiles)?,
        None => Vec::new(),
    };
    let spec = match (model, files.first()) {
        (Some(m), _) => m.to_string(),
        (None, Some(first)) => {
            for f in &files {
                f.unchanged()
                    .map_err(|message| FieldsError::ModelChanged { message })?;
            }
            first.path.clone()
        }
        (None, None) => text("model")?,
    };
    let (model, _) = crate::commands::resolve_model(&spec)?;
    let scene = model
        .scene(Some(&text("scene")?))
        .map_err(FieldsError::Scene)?;
    let eq = Equations::new(&model, &scene);
    let rec = Recovery::new(&eq, fe_dir).map_err(|e| match e {
        FieldsError::NoFieldFiles { .. } => Recovery::no_field_for(&model, &scene.name, fe_dir),
        e => e,
    })?;
    let states =
        States::read(&run_dir.join("states.parquet")).map_err(|e| FieldsError::NoStates {
            source: Box::new(e),
        })?;
    let out = out.map_or_else(|| run_dir.join("fields"), Path::to_path_buf);
    match request {
        Request::Fields(times) => {
            let instants = states.instants(times)?;
            write_fields_with(&rec, &states, &instants, &out, frame)
        }
        Request::DrumEdge { stride, svg } => {
            let start = std::time::Instant::now();
            let rows = drum_edge(&rec, &states, *stride)?;
            let files = write_drum_edge(&rows, &out, *svg)?;
            let top = rows.iter().max_by(|a, b| a.max_m.total_cmp(&b.max_m));
            let peak = rows
                .iter()
                .filter_map(|r| r.peak.map(|p| (p, r.t)))
                .max_by(|a, b| a.0.0.total_cmp(&b.0.0));
            Ok(Written {
                bytes: files
                    .iter()
                    .filter_map(|f| std::fs::metadata(f).ok())
                    .map(|m| m.len())
                    .sum(),
                files,
                seconds: start.elapsed().as_secs_f64(),
                largest: top.map(|r| ("drum front edge".into(), r.max_m, r.node, r.t)),
                peak_stress: peak.map(|((pa, node), t)| (BodyRef::Drum.name().into(), pa, node, t)),
                notes: rec.notes.clone(),
            })
        }
    }
}

#[cfg(test)]
mod tests;
