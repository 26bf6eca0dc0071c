//! The crate's errors: one enum per boundary (the deck reader's [`InpError`], the user spec's
//! [`SpecError`], ccx's [`CcxError`], its result files' [`ResultsError`], the full-mesh
//! deck's [`AssemblyError`], the pipeline's own checks [`PipelineError`]) and [`Error`], which
//! wraps them for the public API. The Display texts are the messages users and tests read.

use crate::subspace::GroupFit;
use std::path::PathBuf;

pub use crate::assembly::AssemblyError;
pub use crate::ccx::CcxError;
pub use crate::inp::{InpError, InpProblem};
pub use crate::user::{SpecError, SpecProblem};

/// Any error of washdyn-fe.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Inp(#[from] InpError),
    #[error(transparent)]
    Spec(#[from] SpecError),
    #[error(transparent)]
    Ccx(#[from] CcxError),
    #[error(transparent)]
    Results(#[from] ResultsError),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// The model file a user spec names.
    #[error(transparent)]
    Model(#[from] washdyn_model::ir::toml_file::ModelFileError),
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// An I/O error of a file ccx wrote, as the OS words it.
    #[error(transparent)]
    CcxFile(#[from] std::io::Error),
    /// `source` in `context` (a body, a job, a file ccx wrote).
    #[error("{context}: {source}")]
    In { context: String, source: Box<Error> },
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Error {
        let path = path.into();
        move |source| Error::Io { path, source }
    }
    /// This error in `context`: `context: self`.
    pub(crate) fn within(self, context: impl Into<String>) -> Error {
        Error::In {
            context: context.into(),
            source: Box::new(self),
        }
    }
    /// The error under the contexts [`Error::within`] added.
    pub fn innermost(&self) -> &Error {
        match self {
            Error::In { source, .. } => source.innermost(),
            e => e,
        }
    }
}

/// Put an error in context: `context: error`.
pub(crate) trait Within<T> {
    fn within(self, context: impl FnOnce() -> String) -> Result<T, Error>;
}

impl<T, E: Into<Error>> Within<T> for Result<T, E> {
    fn within(self, context: impl FnOnce() -> String) -> Result<T, Error> {
        self.map_err(|e| e.into().within(context()))
    }
}

/// What is wrong in a file ccx wrote (`.frd`, `.dat`) or in a field file.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    #[error("line {line}: {what} in `{text}`")]
    Record {
        line: usize,
        what: &'static str,
        text: String,
    },
    #[error("line {line}: {what}")]
    Line { line: usize, what: &'static str },
    #[error("line {line}: no frequency in `{text}`")]
    NoFrequency { line: usize, text: String },
    #[error("line {line}: not a {what} print: `{text}`")]
    NotAPrint {
        line: usize,
        what: &'static str,
        text: String,
    },
    #[error("{}: not a washdyn field file", path.display())]
    NotAField { path: PathBuf },
    #[error("{}: truncated header", path.display())]
    TruncatedHeader { path: PathBuf },
    #[error("{}: header: {source}", path.display())]
    Header {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("{}: {values} values, expected {expected}", path.display())]
    FieldSize {
        path: PathBuf,
        values: usize,
        expected: usize,
    },
    #[error(transparent)]
    Encode(#[from] serde_json::Error),
    #[error("the field of `{body}` has {field} modes, its modal data {data} ({how})")]
    FieldModes {
        body: String,
        field: usize,
        data: usize,
        how: Regenerate,
    },
    #[error("the field of `{body}` has a point `{point}` its modal data lacks ({how})")]
    FieldPoint {
        body: String,
        point: String,
        how: Regenerate,
    },
    #[error(
        "the field of `{body}`: point `{point}` has {field} values, its modal data {data} \
         ({how})"
    )]
    FieldValues {
        body: String,
        point: String,
        field: usize,
        data: usize,
        how: Regenerate,
    },
    #[error(
        "the field of `{body}` has other mode shapes than its modal data: {} ({frequency:.6} Hz) \
         at the data's {points} points: largest principal angle sin {:.1e}, residual after the \
         best rotation {:.1e} (allowed {:e}; a turn or sign flip within a group of \
         equal frequencies is re-projected, not refused; {how})",
        modes_of(fit), fit.sin_angle, fit.residual, crate::subspace::SUBSPACE_TOLERANCE
    )]
    FieldShapes {
        body: String,
        fit: GroupFit,
        frequency: f64,
        points: usize,
        how: Regenerate,
    },
}

/// How a field and its modal data that disagree are made one again: by the command that made
/// them, read from the modal data's `source` (`user::deck_source` marks a user's deck's).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Regenerate {
    /// A built-in body: `washdyn fe modal`.
    BuiltIn,
    /// A user's deck: `washdyn fe deck` with the spec it was made from (as it was named then).
    Deck { spec: String },
}

impl Regenerate {
    /// The command behind modal data of this `source`.
    pub fn of(source: &str) -> Regenerate {
        match source.split_once(crate::user::DECK_SOURCE) {
            Some((_, spec)) => Regenerate::Deck {
                spec: spec.trim().to_string(),
            },
            None => Regenerate::BuiltIn,
        }
    }
}

impl std::fmt::Display for Regenerate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Regenerate::BuiltIn => f.write_str("regenerate both with `washdyn fe modal`"),
            Regenerate::Deck { spec } => {
                write!(f, "regenerate both with `washdyn fe deck {spec}`")
            }
        }
    }
}

fn modes_of(g: &GroupFit) -> String {
    if g.modes.len() == 1 {
        format!("mode {}", g.modes.start + 1)
    } else {
        format!("modes {}-{}", g.modes.start + 1, g.modes.end)
    }
}

/// What the pipeline's own checks refuse: its solves' results disagreeing with the mesh or
/// with each other, numerics that failed.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    // The modal solve and its readings (`modal.rs`, `field.rs`).
    #[error("the .dat prints nodes for {dat} modes, the .frd has {frd}")]
    PrintCount { dat: usize, frd: usize },
    #[error("no node set {set}")]
    NoNodeSet { set: String },
    #[error("node set {set}: no node has a mode shape")]
    NoShapeInSet { set: String },
    #[error("node {node} has no mode shape")]
    NoShape { node: usize },
    #[error("modal data without points")]
    NoPoints,

    // The build (`pipeline.rs`, `user`).
    #[error("{body}: no mode kept")]
    NoModeKept { body: String },
    #[error("{body}: the eigen solve kept no 3-D shapes")]
    No3dShapes { body: String },
    #[error("{body}: {kept} eigenmodes kept, {shapes} shapes")]
    KeptShapes {
        body: String,
        kept: usize,
        shapes: usize,
    },
    #[error("{body}: a free spinning body with correction modes")]
    FreeSpinning { body: String },
    #[error("{body}: the shapes and their 3-D basis differ in number")]
    BasisCount { body: String },
    #[error(
        "{part}: the spring to the ground at node {node} is at no one-node point, while \
         others are (add a point there, as FOOT_k)"
    )]
    LoneSpring { part: String, node: usize },
    #[error("{body}: the solve wrote no 3-D output")]
    No3dOutput { body: String },
    #[error("{body}: no EMAS totals in ccx's .dat")]
    NoEmas { body: String },
    /// The checks of a user's body against its deck (`user::build_checked`), each as worded.
    #[error("{body}: {}", failures.join("; "))]
    Checks { body: String, failures: Vec<String> },

    // Stress recovery (`stress.rs`).
    #[error("ccx element {element} is not in the mesh")]
    UnknownElement { element: usize },
    #[error("expanded node {node} has no coordinates")]
    NoCoordinates { node: usize },
    #[error("{blocks} stress blocks for {cases} {what} (not a 3-D solve?)")]
    StressBlocks {
        blocks: usize,
        cases: usize,
        what: &'static str,
    },
    #[error("no mode at {hz} Hz in the solve")]
    NoModeAt { hz: f64 },

    // The consistent mass (`consistent`).
    #[error("node {node} has mass but no mode shape")]
    NoShapeAtMass { node: usize },
    #[error("no rotation printed for ROT NODE {node}")]
    NoRotation { node: usize },
    #[error("no displacement for REF NODE {node}")]
    NoReference { node: usize },

    // Correction modes (`correction.rs`).
    #[error("the body's inertia is singular")]
    SingularInertia,
    #[error("a 3-2-1 support needs three structural nodes")]
    FewNodes,
    #[error("the structural nodes are collinear: no 3-2-1 support")]
    Collinear,
    #[error("no 3-2-1 support fixes the rigid motions (det {det:.1e})")]
    NoSupport { det: f64 },
    #[error("load case at `{point}`: no such point")]
    NoLoadPoint { point: String },
    #[error("{job}: ccx wrote {results} static results for {cases} load cases")]
    StaticCount {
        job: String,
        results: usize,
        cases: usize,
    },
    #[error(
        "{job}: the 3-2-1 support carries {worst:.1e} of the largest load: the relieved \
         loads are not in equilibrium"
    )]
    NotInEquilibrium { job: String, worst: f64 },

    // The prestress and geometric stiffness (`prestress`).
    #[error("no stresses of set {set} in the .dat")]
    NoPrestress { set: &'static str },
    #[error(
        "element {element}: ccx solved it as no 20-node brick (the geometric \
         stiffness takes C3D20, C3D20R and the shells and beams ccx expands into them)"
    )]
    NotABrick { element: usize },
    #[error("element {element}: {points} integration points (C3D20R has 8, C3D20 27)")]
    IntegrationPoints { element: usize, points: usize },
    #[error("element {element}: no material in the mesh")]
    NoMaterial { element: usize },
    #[error("the .frd lacks coordinates of some bricks' nodes")]
    LacksCoordinates,
    #[error("the .frd has no static displacements")]
    NoStatics,
    #[error("the .frd lacks static displacements of some bricks' nodes")]
    LacksStatics,
    #[error("{what}: ccx expanded element {element} otherwise than in the prestress solve")]
    OtherExpansion { what: String, element: usize },
    #[error("shape {shape} has no displacement at ccx's node {node:?}")]
    NoDisplacement { shape: usize, node: Option<usize> },
    #[error("element {element}: det J <= 0")]
    Jacobian { element: usize },
    #[error("a mode has no rotation of rigid part {set} (ROT NODE)")]
    NoRigidRotation { set: String },
    #[error("no mode shape at point mass node {node}")]
    NoShapeAtPointMass { node: usize },

    // Characteristic curves (`curves`).
    #[error(
        "{file}: fit.{field} = {residual:.2e} is above fit.bound = {bound:.2e}: the polynomial \
         does not reproduce ccx's nonlinear static solutions (smaller load levels, or more modes)"
    )]
    CurveFit {
        file: String,
        field: &'static str,
        residual: f64,
        bound: f64,
    },
    #[error("{job}: ccx wrote no static result")]
    NoStaticResult { job: String },
    #[error("{body}: chosen mode {mode} is not among the {modes} modes solved, or chosen twice")]
    NoSuchMode {
        body: String,
        mode: usize,
        modes: usize,
    },

    // The rotating body's eigenvalues (`rotating.rs`).
    #[error("the reduced matrices are not finite")]
    NotFinite,
    #[error("the eigenvalue iteration did not converge")]
    NoConvergence,
}
