//! washdyn: the command-line tool's library: model resolution, the `run` command and
//! post-processing.
pub mod accuracy;
pub mod analysis;
pub mod basis;
pub mod campbell;
pub mod commands;
pub mod compare;
pub mod fields;
pub mod full_mesh;
pub mod modes;
pub mod results;
pub mod sweep;
pub mod validate;
pub mod vtk;
