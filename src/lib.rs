//! washdyn: the command-line tool's library: model resolution, one simulation set-up
//! (`simulation`) for `run`, `sweep`, `study` and `accuracy`, their typed errors (`Error`), and
//! post-processing.
pub mod accuracy;
pub mod basis;
pub mod campbell;
pub mod commands;
pub mod compare;
pub mod error;
pub mod error_class;
pub mod fields;
pub mod full_mesh;
pub mod measured;
pub mod modes;
pub mod run_dir;
pub mod simulation;
pub mod spec;
pub mod study;
pub mod vtk;

pub use error::Error;
/// Result files and the order analysis live in `washdyn-analysis`; here under their old paths.
pub use washdyn_analysis::{self as analysis, results};
