//! `washdyn check`: its argument and the report it prints.

use super::Failure;
use std::io::Write;
use std::process::ExitCode;
use washdyn::commands::{check_model, resolve_model};

/// `washdyn check`'s argument.
#[derive(clap::Args)]
pub struct Args {
    /// A built-in model or a model file.
    pub model: String,
}

pub fn check(a: Args) -> Result<ExitCode, Failure> {
    let report = resolve_model(&a.model)
        .and_then(|(m, _)| check_model(&m))
        .map_err(Failure::Quiet)?;
    let _ = writeln!(std::io::stdout(), "{report}");
    Ok(ExitCode::SUCCESS)
}
