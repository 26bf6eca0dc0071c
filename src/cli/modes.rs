//! `washdyn modes`: its arguments and what it prints.

use super::{Failure, wrote};
use std::path::PathBuf;
use std::process::ExitCode;
use washdyn::Error;

/// `washdyn modes`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A built-in model or a model file.
    pub model: String,
    /// A scene of the model (default: its first scene); elastic bodies are taken rigid.
    #[arg(long)]
    pub scene: Option<String>,
    /// Output directory (default: out/<model name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn modes(a: Args) -> Result<ExitCode, Failure> {
    let Args { model, scene, out } = a;
    let file =
        washdyn::modes::run(&model, scene.as_deref(), out.as_deref()).map_err(Error::from)?;
    Ok(wrote(vec![file]))
}
