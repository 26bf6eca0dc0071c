//! washdyn: the command-line tool's library: run driver glue and post-processing.
pub mod analysis;
