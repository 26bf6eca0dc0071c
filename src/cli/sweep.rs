//! `washdyn sweep`: its arguments; the sweep is a grid design of the study
//! (`washdyn::study::sweep`), run and reported as `study run` does, then collected into one table.

use super::Failure;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use washdyn::spec::RunSpec;
use washdyn::study::{self, Study};

/// `washdyn sweep`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub spec: RunSpec,
    /// Unbalance positions: front, middle, rear (the built-in drums), or axial x in m
    /// (comma-separated).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub positions: Vec<String>,
    /// Unbalance masses, kg (comma-separated).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub masses: Vec<f64>,
    /// Speed profile CSV files (time_s, rpm), comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub profiles: Vec<PathBuf>,
    /// Parallel runs (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
}

pub fn sweep(a: Args) -> Result<ExitCode, Failure> {
    let base = washdyn::simulation::Source::load(&a.spec.model)?;
    let grid = study::sweep::Grid {
        positions: a.positions,
        masses: a.masses,
        profiles: a.profiles,
    };
    let text = study::sweep::study_text(&base, &a.spec, &grid)?;
    let out = study::sweep::out_dir(&a.spec, &base.model);
    let mut s = Study::from_text(&out.join("study.toml"), text)?;
    s.control.guard.interrupt = Some(super::interrupt_flag());
    let code = super::study::run_here(&s, &out, a.jobs)?;
    let c = study::collect(&out)?;
    let _ = writeln!(
        std::io::stdout(),
        "{} variants in one table: {}",
        c.rows,
        out.join("summary.csv").display()
    );
    Ok(code)
}
