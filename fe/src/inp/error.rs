//! What the deck reader refuses, typed: where (file and line) and what (the keyword, field or
//! id at fault). The Display texts are the reader's messages users and tests read.

use std::path::PathBuf;

/// A deck error: where, and what.
#[derive(Debug, thiserror::Error)]
#[error("{}:{line}: {problem}", file.display())]
pub struct InpError {
    pub file: PathBuf,
    /// 1-based; 0 where the error is the file's (it cannot be read, it lacks something).
    pub line: usize,
    pub problem: InpProblem,
}

/// What is wrong at an [`InpError`]'s place.
#[derive(Debug, thiserror::Error)]
pub enum InpProblem {
    // The syntax (`cards.rs`).
    #[error("cannot read: {0}")]
    Read(#[source] std::io::Error),
    #[error("*INCLUDE nested deeper than 8 (a cycle?)")]
    IncludeTooDeep,
    #[error("data before the first keyword")]
    DataBeforeKeyword,
    #[error("{keyword} needs {key}=")]
    NeedsParameter { keyword: String, key: String },
    #[error("{keyword} has no data line")]
    NoData { keyword: String },
    #[error("{keyword}: missing {what}")]
    MissingField { keyword: String, what: String },
    #[error("{keyword}: {what} `{text}` is not a number")]
    NotANumber {
        keyword: String,
        what: String,
        text: String,
    },
    #[error("{keyword}: {what} is {value}")]
    NotFinite {
        keyword: String,
        what: String,
        value: f64,
    },
    #[error("{keyword}: {what} `{text}` is not an integer")]
    NotAnInteger {
        keyword: String,
        what: String,
        text: String,
    },
    #[error("GENERATE needs first <= last and a positive step")]
    BadGenerate,
    #[error("{keyword}: no set `{set}` defined above")]
    SetNotAbove { keyword: String, set: String },

    // What the pipeline cannot take.
    #[error(
        "{keyword} is not supported in the model part (supported: *NODE, *ELEMENT, \
             *NSET, *ELSET, *MATERIAL, *ELASTIC, *DENSITY, *SHELL SECTION, *SOLID \
             SECTION, *BEAM SECTION, *MASS, *SPRING, *RIGID BODY, *BOUNDARY, \
             *INCLUDE; steps are skipped)"
    )]
    UnsupportedKeyword { keyword: String },
    #[error(
        "element type {kind} is not supported (supported: {}); \
         the pipeline integrates the mass of these only",
        supported.join(", ")
    )]
    UnsupportedElement {
        kind: String,
        supported: Vec<&'static str>,
    },
    #[error("{keyword}: temperature-dependent data is not supported")]
    TemperatureDependent { keyword: String },
    #[error("*ELASTIC, TYPE={kind}: only isotropic materials are supported")]
    Anisotropic { kind: String },
    #[error("shell offsets and composites are not supported")]
    ShellOffset,
    #[error("*BEAM SECTION, SECTION={shape}: only RECT is supported")]
    BeamShape { shape: String },
    #[error("*BOUNDARY: prescribed values are not supported")]
    PrescribedValue,

    // Values out of range.
    #[error("*ELASTIC: E = {e} Pa, nu = {nu} is not a material")]
    NotAMaterial { e: f64, nu: f64 },
    #[error("*DENSITY: {rho} kg/m^3")]
    Density { rho: f64 },
    #[error("{keyword}: {what} must be positive, got {value}")]
    NotPositive {
        keyword: String,
        what: &'static str,
        value: f64,
    },
    #[error("*SPRING: dof {dof}, not 1, 2 or 3")]
    SpringDof { dof: i64 },
    #[error("*BOUNDARY: dofs {first} to {last}")]
    BoundaryDofs { first: i64, last: i64 },

    // Cards out of place or incomplete.
    #[error("{keyword} outside a *MATERIAL")]
    OutsideMaterial { keyword: String },
    #[error("{keyword} needs {what}")]
    MissingLine {
        keyword: &'static str,
        what: &'static str,
    },
    #[error("*RIGID BODY needs {key}= (the pipeline reads the part's rotation there)")]
    RigidBodyNeeds { key: &'static str },
    #[error("element {id}: {kind} has {nodes} nodes, the line gives {given}")]
    NodeCount {
        id: i64,
        kind: String,
        nodes: usize,
        given: usize,
    },
    #[error("{what} {id} defined twice")]
    DefinedTwice { what: &'static str, id: i64 },

    // References to what is not defined.
    #[error("node {id} is not defined")]
    NoNode { id: i64 },
    #[error("no material `{name}` defined")]
    NoMaterial { name: String },
    #[error("material `{name}` has no {card}")]
    MaterialLacks { name: String, card: &'static str },
    #[error("no element set `{set}` with elements defined")]
    NoElementSet { set: String },
    #[error("element set `{set}`: element {id} is not defined")]
    SetElementUndefined { set: String, id: i64 },
    #[error("node set `{set}`: node {id} is not defined")]
    SetNodeUndefined { set: String, id: i64 },
    #[error("no node set `{set}` defined")]
    NoNodeSet { set: String },

    // Sections.
    #[error("element {id} ({kind}) in `{set}` does not take {keyword}")]
    WrongSection {
        id: i64,
        kind: String,
        set: String,
        keyword: String,
    },
    #[error("element {id} already has a section (line {first})")]
    SecondSection { id: i64, first: usize },
    #[error("element {id} ({kind}) has no section")]
    NoSection { id: i64, kind: String },
    #[error("the deck defines no elements with sections")]
    NoParts,
}
