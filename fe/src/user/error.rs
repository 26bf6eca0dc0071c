//! What the user's spec refuses, typed: where in the spec file (its line, where the field or
//! point is found) and what. The Display texts are the messages users and tests read.

use std::path::PathBuf;
use washdyn_model::ir::attachments::Attachment;
use washdyn_model::ir::modal::{ElasticBodyKind, POINT_TOLERANCE, Support};

/// A spec error: the spec file, the line where known, and what.
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {problem}", file.display(), line.map_or(String::new(), |l| format!(":{l}")))]
pub struct SpecError {
    pub file: PathBuf,
    pub line: Option<usize>,
    pub problem: SpecProblem,
}

/// What is wrong at a [`SpecError`]'s place.
#[derive(Debug, thiserror::Error)]
pub enum SpecProblem {
    #[error("cannot read: {0}")]
    Read(#[source] std::io::Error),
    /// The TOML parser's or the spec schema's message.
    #[error("{0}")]
    Toml(String),
    #[error("need 0 < keep.max_modes ({keep}) <= solve_modes ({solve})")]
    ModeCounts { keep: usize, solve: usize },
    #[error("keep.max_hz must be positive")]
    MaxHz,
    #[error("correction_order is 1 (the static give) or 2 (also K^-1 M of it), not {order}")]
    CorrectionOrder { order: usize },
    #[error(
        "a {body:?} is held {support:?} and {} (tub: free_free; drum: clamped, with [spin]; \
         cabinet: on_springs or clamped)",
        if *spins { "spins" } else { "does not spin" }
    )]
    Support {
        body: ElasticBodyKind,
        support: Support,
        spins: bool,
    },
    #[error(
        "correction: no point `{point}` in `points`{}",
        if *with_model { " or the model's" } else { "" }
    )]
    NoCorrectionPoint { point: String, with_model: bool },
    #[error("spin: needs a nonzero axis and a positive reference_rpm")]
    SpinAxis,
    #[error(
        "spin: the axis through axis_point {:?} m along {:?} passes {off:.3} m from \
         the body's centre of gravity {cog:.3?} m, {:.0} % of the body's reach from it (at most \
         {:.0} %: a drum turns about its own axis); the spec is in SI units (m), whatever the \
         deck's",
        spin.axis_point,
        spin.axis,
        100.0 * off / reach,
        100.0 * super::AXIS_OFF_COG
    )]
    AxisOffCog {
        spin: Box<crate::pipeline::Spin>,
        off: f64,
        cog: [f64; 3],
        reach: f64,
    },
    #[error(
        "the model {} attaches nothing to the {body} where a scene makes it elastic \
         (`elastic.{body}`)",
        model.display()
    )]
    AttachesNothing { model: PathBuf, body: &'static str },
    #[error("point `{point}`: `at` is not finite")]
    PointNotFinite { point: String },
    #[error("point `{point}`: the deck {} has no node set `{set}`", deck.display())]
    PointSet {
        point: String,
        deck: PathBuf,
        set: String,
    },
    #[error("point `{point}`: give nset, or a finite `at`, or both")]
    PointUnplaced { point: String },
    #[error(
        "point `{point}` at {at:?} is {:.1} mm from where the model puts it ({}, \
         `{}`: {:?}); the model checker matches within {} mm",
        off * 1e3,
        model.what,
        model.path,
        model.point,
        POINT_TOLERANCE * 1e3
    )]
    PointOff {
        point: String,
        at: [f64; 3],
        off: f64,
        model: Box<Attachment>,
    },
    #[error(
        "the model's {} (`{}`) at {:?} is {off:.3} m from the deck's nearest \
         structural node: a patch there would not be the part it attaches to; map \
         it to a node set of the deck, {{ name = \"{}\", nset = \"...\" }}",
        model.what,
        model.path,
        model.point,
        model.name
    )]
    FarFromStructure { model: Box<Attachment>, off: f64 },
}
