//! `washdyn campbell`: its arguments and what it prints.

use super::{Failure, wrote};
use std::path::PathBuf;
use std::process::ExitCode;
use washdyn::Error;

/// `washdyn campbell`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A model (built-in name or model file) with an elastic drum, or the drum's modal data
    /// file (e.g. models/fe/drum.modal.toml).
    pub source: String,
    /// Highest drum speed, rpm [default: the model's top speed, else 1400].
    #[arg(long)]
    pub max_rpm: Option<f64>,
    /// Motor/drum speed ratio for the motor order line [default: the model's rotor `motor`,
    /// else 11.25].
    #[arg(long)]
    pub motor_ratio: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out/campbell")]
    pub out: PathBuf,
    /// Also write the plot as SVG.
    #[arg(long)]
    pub svg: bool,
}

pub fn campbell(a: Args) -> Result<ExitCode, Failure> {
    let Args {
        source,
        max_rpm,
        motor_ratio,
        out,
        svg,
    } = a;
    let files =
        washdyn::campbell::run(&source, max_rpm, motor_ratio, &out, svg).map_err(Error::from)?;
    Ok(wrote(files))
}
