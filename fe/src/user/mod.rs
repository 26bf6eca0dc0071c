//! A user's body: their CalculiX deck (`inp/mod.rs`) and a short spec (TOML) naming what the
//! machine needs of it (kind and support, the points, the modes and the correction loads, the
//! drum's spin), turned into the same [`BodySpec`] the built-in bodies are, and built by the
//! same pipeline. With a `model`, the points the model attaches to the body come from it
//! (`points.rs`), so the spec lists only what the model does not say. After the build, the result is checked against the deck: ccx's own mass and
//! centre of gravity (EMAS) against the mass the modal data integrates, the rigid-body modes a
//! free body must have, and the mass normalisation of the kept modes.

mod check;
mod error;
mod points;

pub use error::{SpecError, SpecProblem, UnitsReading};

use crate::error::{Error, PipelineError};
use crate::inp::{self, Units};
use crate::lumping::continuum_mass_props;
use crate::modal::Keep;
use crate::pipeline::{BodySpec, Report, Spin, build};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use washdyn_model::ir::BodyRef;
use washdyn_model::ir::attachments::{Attachment, attachments};
use washdyn_model::ir::modal::{ElasticBodyKind, LoadCase, ModalData, Support};
use washdyn_model::ir::toml_file::load_file_unresolved;

/// The spec file, as written (SI units, whatever the deck's).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UserSpec {
    /// File stem of the outputs: `<name>.modal.toml`, `<name>.field.bin`.
    pub name: String,
    /// The deck, relative to the spec file.
    pub deck: PathBuf,
    /// The deck's units: "SI" or "mm-t-s".
    pub units: Units,
    /// tub, drum or cabinet.
    pub body: ElasticBodyKind,
    /// free_free, clamped or on_springs.
    pub support: Support,
    /// Eigenmodes ccx computes (a free body's 6 rigid ones included).
    pub solve_modes: usize,
    pub keep: KeepSpec,
    /// The machine's model file (TOML, relative to the spec): every point it attaches to the
    /// body becomes a point of the body (its modal data is not read: this makes it).
    pub model: Option<PathBuf>,
    /// Points besides the model's, or the deck's node set a model point is read on: a node
    /// set of the deck (its centroid is the point) or a position (the nodes near it form the
    /// set). Without a model, every point a force element, sensor or mount attaches to.
    #[serde(default)]
    pub points: Vec<PointSpec>,
    /// Unit loads whose static response becomes correction modes (non-spinning bodies).
    #[serde(default)]
    pub correction: Vec<LoadCase>,
    /// Krylov blocks of the correction modes (1: static give; 2: also K^-1 M of it).
    #[serde(default = "one")]
    pub correction_order: usize,
    /// The drum's spin: axis and the speed of the prestress.
    pub spin: Option<SpinSpec>,
    /// Also write `<name>.field.bin` for `washdyn fields`.
    #[serde(default = "yes")]
    pub recovery: bool,
}

fn yes() -> bool {
    true
}

fn one() -> usize {
    1
}

#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeepSpec {
    /// Modes below this, Hz, are rigid-body modes (free bodies; 0 otherwise).
    #[serde(default)]
    pub rigid_below_hz: f64,
    pub max_hz: f64,
    pub max_modes: usize,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// The node set's name; a model item's name (any case) makes this the model's point.
    pub name: String,
    /// A node set of the deck.
    pub nset: Option<String>,
    /// Where the point is, m: with `nset`, where the set is read (default the model's point,
    /// or else the set's centroid); alone, the nodes near it become the set.
    pub at: Option<[f64; 3]>,
}

#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpinSpec {
    pub axis_point: [f64; 3],
    pub axis: [f64; 3],
    /// The speed of the prestress, rpm (the top of the run-up).
    pub reference_rpm: f64,
}

/// The spec file's line of a byte offset.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

/// Read the spec and its deck into a [`BodySpec`]. Errors name the file and line (spec or
/// deck) and the set or field.
pub fn load(spec_path: &Path) -> Result<BodySpec, Error> {
    let err = |line, problem| SpecError {
        file: spec_path.to_path_buf(),
        line,
        problem,
    };
    let text = std::fs::read_to_string(spec_path).map_err(|e| err(None, SpecProblem::Read(e)))?;
    let spec: UserSpec = washdyn_model::ir::modal::from_toml(&text).map_err(|(span, m)| {
        let line = span.map(|s| line_of(&text, s.start));
        err(line, SpecProblem::Toml(m))
    })?;
    // Where a field stands in the spec, for errors found after parsing.
    let bad = |needle: &str, problem| err(text.find(needle).map(|i| line_of(&text, i)), problem);
    let dir = spec_path.parent().unwrap_or(Path::new("."));
    let deck = dir.join(&spec.deck);
    let mut mesh = inp::read(&deck, spec.units)?;
    check_counts(&spec).map_err(|(needle, problem)| bad(needle, problem))?;
    // The rules of the modal data that need no solve, before ccx (`check.rs`).
    let refuse = |(line, problem)| err(line, problem);
    check::units(&text, &spec, &mesh).map_err(refuse)?;
    check::positions(&text, &spec, &mesh).map_err(refuse)?;
    let attachments = match &spec.model {
        Some(file) => model_attachments(&dir.join(file), spec.body, &bad)?,
        None => Vec::new(),
    };
    let points = points::points(&spec.points, &attachments, &mut mesh, &deck, &bad)?;
    for c in &spec.correction {
        if !points.iter().any(|(n, _)| *n == c.point) {
            let problem = SpecProblem::NoCorrectionPoint {
                point: c.point.clone(),
                with_model: spec.model.is_some(),
            };
            return Err(bad(&format!("\"{}\"", c.point), problem).into());
        }
    }
    check::placed(&text, &spec, &mesh, &points).map_err(refuse)?;
    let spin = match spec.spin {
        Some(s) => {
            let n = s.axis.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !(n.is_finite() && n > 0.0 && s.reference_rpm > 0.0) {
                return Err(bad("[spin]", SpecProblem::SpinAxis).into());
            }
            let spin = Spin {
                axis_point: s.axis_point,
                axis: s.axis.map(|v| v / n),
                reference_speed: s.reference_rpm * std::f64::consts::PI / 30.0,
            };
            axis_through_the_body(&mesh, &spin).map_err(|m| bad("axis_point", m))?;
            Some(spin)
        }
        None => None,
    };
    check::spin(&text, &spec).map_err(refuse)?;
    Ok(BodySpec {
        name: spec.name,
        kind: spec.body,
        support: spec.support,
        mesh,
        solve_modes: spec.solve_modes,
        keep: Keep {
            rigid_below_hz: spec.keep.rigid_below_hz,
            max_hz: spec.keep.max_hz,
            max_modes: spec.keep.max_modes,
        },
        points,
        spin,
        correction: spec.correction,
        correction_order: spec.correction_order,
        recovery: spec.recovery,
    })
}

/// The spec's counts, frequencies and kind of body against each other: the field's needle
/// in the spec and what is wrong.
fn check_counts(spec: &UserSpec) -> Result<(), (&'static str, SpecProblem)> {
    let (keep, solve) = (spec.keep.max_modes, spec.solve_modes);
    if solve == 0 || keep == 0 || keep > solve {
        return Err(("solve_modes", SpecProblem::ModeCounts { keep, solve }));
    }
    if !(spec.keep.max_hz > 0.0 && spec.keep.rigid_below_hz >= 0.0) {
        return Err(("max_hz", SpecProblem::MaxHz));
    }
    if !(1..=2).contains(&spec.correction_order) {
        let order = spec.correction_order;
        return Err(("correction_order", SpecProblem::CorrectionOrder { order }));
    }
    let free = spec.support == Support::FreeFree;
    if free != (spec.body == ElasticBodyKind::Tub)
        || (spec.spin.is_some()) != (spec.body == ElasticBodyKind::Drum)
    {
        let problem = SpecProblem::Support {
            body: spec.body,
            support: spec.support,
            spins: spec.spin.is_some(),
        };
        return Err(("body", problem));
    }
    Ok(())
}

/// Farthest the body's centre of gravity may lie from the spin axis, as a fraction of the
/// body's reach from the axis (its farthest node): a drum turns about its own axis, balanced
/// (the laundry's unbalance is the model's, not the FE body's). A gross mistake passes far
/// off: the axis point written in the deck's mm (measured 1.0 of the reach on the drum of
/// the unit tests, tests/user_spinning.rs's), the axis through the origin instead of the
/// drum's centre (0.72), the wrong axis direction (0.26). Such an axis made modal data that
/// `campbell` then refused (mm), or a Campbell diagram of the wrong body without a word
/// (through the origin: 103.4 Hz for the lowest mode at 1400 rpm where ccx has 97.4).
pub(crate) const AXIS_OFF_COG: f64 = 0.1;

/// The spin axis passes through the body's centre of gravity, within `AXIS_OFF_COG` of the
/// body's reach from it.
fn axis_through_the_body(mesh: &crate::mesh::Mesh, spin: &Spin) -> Result<(), SpecProblem> {
    let off = |p: [f64; 3]| washdyn_model::geom::f::off_line(p, spin.axis_point, spin.axis);
    let cog = crate::lumping::consistent_mass_props(mesh).cog;
    let reach = mesh.nodes.iter().map(|p| off(*p)).fold(0.0f64, f64::max);
    let d = off(cog);
    if d.is_finite() && d <= AXIS_OFF_COG * reach {
        return Ok(());
    }
    Err(SpecProblem::AxisOffCog {
        spin: Box::new(spin.clone()),
        off: d,
        cog,
        reach,
    })
}

/// The points `model` attaches to the body of kind `kind`, its modal data unread; errors name
/// the model file and line.
fn model_attachments(
    model: &Path,
    kind: ElasticBodyKind,
    bad: points::Bad,
) -> Result<Vec<Attachment>, Error> {
    let m = load_file_unresolved(model)?;
    let body = match kind {
        ElasticBodyKind::Tub => BodyRef::Tub,
        ElasticBodyKind::Drum => BodyRef::Drum,
        ElasticBodyKind::Cabinet => BodyRef::Cabinet,
    };
    let found = attachments(&m, body);
    if found.is_empty() {
        let problem = SpecProblem::AttachesNothing {
            model: model.to_path_buf(),
            body: body.name(),
        };
        return Err(bad("model =", problem).into());
    }
    Ok(found)
}

/// What a user's modal data's `source` ends with, then the spec: the advice on a field that
/// disagrees with its data names the command that remakes them (`error::Regenerate`).
pub const DECK_SOURCE: &str = "; made by washdyn fe deck ";

/// The `source` of modal data made from a user's deck by `spec`.
pub fn deck_source(source: &str, spec: &Path) -> String {
    format!("{source}{DECK_SOURCE}{}", spec.display())
}

/// What the checks after the build measured.
#[derive(Clone, Debug)]
pub struct Checked {
    /// |m_ccx / m_ours - 1| (ccx's EMAS over the deck's elements against our integration).
    pub mass: f64,
    /// |cog_ccx - cog_ours|, m.
    pub cog: f64,
    /// ccx's modes below `rigid_below_hz` (a free body must have 6).
    pub rigid_modes: usize,
    /// max |W^T M W - I| of the kept modes.
    pub normalisation: f64,
}

/// Build the body in `work` and check it against the deck; the bounds: mass within 2e-5 (ccx
/// prints 7 digits; the built-in bodies measure 1.2e-6 to 4.0e-6), CoG within 1e-4 m, 6 rigid modes on a
/// free body, normalisation within 5e-3 (the built-in bodies measure 3.8e-5 to 1.2e-3
/// (models/fe/report.txt): ccx expands S8R shells to 3-D bricks, whose mass the mid-surface
/// integral does not hold exactly).
pub fn build_checked(spec: &BodySpec, work: &Path) -> Result<(ModalData, Report, Checked), Error> {
    let (data, report) = build(spec, work)?;
    let e = report.emas.ok_or_else(|| PipelineError::NoEmas {
        body: spec.name.clone(),
    })?;
    let ours = continuum_mass_props(&spec.mesh);
    let cog = (0..3)
        .map(|i| (e.cog[i] - ours.cog[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    let checked = Checked {
        mass: (e.mass / ours.mass - 1.0).abs(),
        cog,
        rigid_modes: report
            .all_frequencies
            .iter()
            .filter(|f| **f < spec.keep.rigid_below_hz)
            .count(),
        normalisation: report.mass_error,
    };
    let mut wrong = Vec::new();
    if checked.mass > 2e-5 {
        wrong.push(format!(
            "mass: ccx {} kg, integrated {} kg",
            e.mass, ours.mass
        ));
    }
    if checked.cog > 1e-4 {
        wrong.push(format!("centre of gravity {cog:.2e} m off ccx's"));
    }
    if spec.support == Support::FreeFree && checked.rigid_modes != 6 {
        wrong.push(format!(
            "{} modes below {} Hz where a free body has 6 rigid-body modes (a loose part, or \
             keep.rigid_below_hz too high or low)",
            checked.rigid_modes, spec.keep.rigid_below_hz
        ));
    }
    if checked.normalisation > 5e-3 {
        wrong.push(format!(
            "mass normalisation off by {:.1e}",
            checked.normalisation
        ));
    }
    wrong.extend(refused(&data));
    if !wrong.is_empty() {
        let (body, failures) = (spec.name.clone(), wrong);
        return Err(PipelineError::Checks { body, failures }.into());
    }
    Ok((data, report, checked))
}

/// What `check`, `run` and `campbell` would refuse in the modal data (`modal::problems`): found
/// here, before the file is written, not when it is read.
fn refused(data: &ModalData) -> Vec<String> {
    washdyn_model::ir::modal::problems(data)
        .into_iter()
        .map(|p| format!("the modal data's {p}"))
        .collect()
}

#[cfg(test)]
mod tests;
