//! What the user's spec refuses, typed: where in the spec file (its line, where the field or
//! point is found) and what. The Display texts are the messages users and tests read.

use crate::inp::Units;
use std::path::PathBuf;
use washdyn_model::ir::attachments::Attachment;
use washdyn_model::ir::check::MAX_RPM;
use washdyn_model::ir::modal::{
    ElasticBodyKind, MAX_EXTENT, MAX_SUPPORT_STIFFNESS, POINT_TOLERANCE, Support, UNIT_TOLERANCE,
};

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

    // Found before ccx starts (`check.rs`): what the modal data's rules would refuse after it.
    #[error("{}", units_message(read, fits))]
    Units {
        read: UnitsReading,
        /// The other unit systems the deck would be a machine part in.
        fits: Vec<UnitsReading>,
    },
    #[error(
        "point `{point}` at {at:?} m is {off:.3} m outside the deck's nodes ({:.3?} to \
         {:.3?} m, with {:.2} m to spare): the spec is in SI units (m), whatever the deck's",
        bounds[0],
        bounds[1],
        super::points::FAR
    )]
    PointOffMesh {
        point: String,
        at: [f64; 3],
        off: f64,
        /// The nodes' bounding box: lowest and highest coordinates.
        bounds: Box<[[f64; 3]; 2]>,
    },
    #[error(
        "point `{point}` is named twice (each point of the modal data has its own name): rename \
         or drop one"
    )]
    DuplicatePoint { point: String },
    #[error("correction[{index}] at `{point}`: direction {direction:?} {}", direction_remedy(*direction))]
    CorrectionDirection {
        index: usize,
        point: String,
        direction: [f64; 3],
    },
    #[error(
        "correction[{index}]: a moment at `{point}`, whose node set has {nodes} node(s), which \
         turn with no rotation of the point; read the point on a set of 3 or more nodes, or \
         load it with a force"
    )]
    MomentOnFewNodes {
        index: usize,
        point: String,
        nodes: usize,
    },
    #[error(
        "spin: reference_rpm {rpm} is above the machine's top speed, {MAX_RPM} rpm (the prestress \
         is taken at the top of the run-up)"
    )]
    SpinSpeed { rpm: f64 },
    #[error(
        "spin: axis_point {at:?} is more than {MAX_EXTENT} m from the origin; the spec is in SI \
         units (m), whatever the deck's"
    )]
    SpinAxisPoint { at: [f64; 3] },
    #[error(
        "the deck's spring to the ground in `{part}` at {at:?} m is at no point of its own, \
         while others are: add a point on that one node (as the cabinet's FOOT_k, a node set of \
         the spring's node)"
    )]
    LoneSpring { part: String, at: [f64; 3] },
    #[error(
        "the deck's springs to the ground at `{point}` are {stiffness:?} N/m, beyond \
         {MAX_SUPPORT_STIFFNESS:e} N/m (a rigid support: hold the body clamped), or the deck's \
         *SPRING values are in other units than `units`"
    )]
    SupportStiffness { point: String, stiffness: [f64; 3] },
}

/// The deck's mass and the distance of its centre of gravity from the origin as read in some
/// units, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitsReading {
    pub units: Units,
    /// kg.
    pub mass: f64,
    /// m.
    pub cog: f64,
}

impl std::fmt::Display for UnitsReading {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} kg, centre of gravity {} m from the origin",
            sig(self.mass),
            sig(self.cog)
        )
    }
}

/// `v` to 4 significant digits, without an exponent in the range of a machine's parts.
fn sig(v: f64) -> String {
    if !(1e-4..1e6).contains(&v.abs()) {
        return format!("{v:.3e}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

/// The units refusal: what the deck is read in `read`'s units, what a machine part is, and the
/// units it would be one in (or that none make it one).
fn units_message(read: &UnitsReading, fits: &[UnitsReading]) -> String {
    let (lo, hi) = super::check::BODY_MASS;
    let mut m = format!(
        "units = \"{}\": read in these units the deck weighs {read}, where a washing machine's \
         tub, drum or cabinet weighs {lo} to {hi} kg within {MAX_EXTENT} m of the origin",
        read.units
    );
    if fits.is_empty() {
        let all: Vec<&str> = Units::ALL.iter().map(|u| u.name()).collect();
        m += &format!(
            "; no units washdyn reads ({}) make it one: check the deck's *DENSITY and *MASS \
             values and its node coordinates",
            all.join(", ")
        );
    }
    for f in fits {
        m += &format!(
            "; read as {} it weighs {f}: if the deck is in {0}, write units = \"{0}\"",
            f.units
        );
    }
    m
}

/// What a correction load's direction that is no unit vector should be.
fn direction_remedy(d: [f64; 3]) -> String {
    let n = d.iter().map(|v| v * v).sum::<f64>().sqrt();
    if n.is_finite() && n > 0.0 {
        let u = d.map(|v| v / n);
        format!(
            "has length {n}, not 1 (within {UNIT_TOLERANCE:e}): write the unit vector, \
             {u:?}"
        )
    } else {
        "is no direction: give the load's unit vector, e.g. [0.0, 0.0, 1.0]".into()
    }
}
