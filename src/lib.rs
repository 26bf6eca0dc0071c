//! washdyn: the command-line tool's library: model resolution, the `run` command and
//! post-processing.
pub mod analysis;
pub mod campbell;
pub mod commands;
pub mod results;
pub mod sweep;
pub mod validate;
