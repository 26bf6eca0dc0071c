//! `washdyn compare`: its arguments and what it prints.

use super::{Failure, wrote};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use washdyn::Error;

/// `washdyn compare`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// The first run's directory (A: the reference of the differences).
    #[arg(value_name = "RUN_A")]
    pub run_a: PathBuf,
    /// The second run's directory (B).
    #[arg(value_name = "RUN_B")]
    pub run_b: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/compare")]
    pub out: PathBuf,
    /// Name of run A in tables and plots (default: its directory's name).
    #[arg(long)]
    pub label_a: Option<String>,
    /// Name of run B in tables and plots (default: its directory's name).
    #[arg(long)]
    pub label_b: Option<String>,
    /// Belt ratio (motor speed / drum speed) of the motor order tracked.
    #[arg(long, default_value_t = 11.25)]
    pub motor_ratio: f64,
    /// Also write the plots as SVG (PNG always).
    #[arg(long)]
    pub svg: bool,
    /// Compare up to this time only, s (both runs must reach it): a run that stopped early
    /// against a longer one, or a stretch of a run-up.
    #[arg(long, allow_hyphen_values = true)]
    pub until: Option<f64>,
}

pub fn compare(a: Args) -> Result<ExitCode, Failure> {
    let Args {
        run_a,
        run_b,
        out,
        label_a,
        label_b,
        motor_ratio,
        svg,
        until,
    } = a;
    let name = |p: &Path, l: Option<String>| {
        l.unwrap_or_else(|| {
            p.file_name()
                .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
        })
    };
    let args = washdyn::compare::CompareArgs {
        labels: [name(&run_a, label_a), name(&run_b, label_b)],
        runs: [run_a, run_b],
        out,
        motor_ratio,
        svg,
        until,
    };
    let (c, files) = washdyn::compare::compare(&args).map_err(Error::from)?;
    if let Some(n) = &c.note {
        eprintln!("note: {n}");
    }
    Ok(wrote(files))
}
