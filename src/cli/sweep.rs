//! `washdyn sweep`: its arguments and what it prints.

use super::Failure;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use washdyn::spec::RunSpec;

/// `washdyn sweep`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub spec: RunSpec,
    /// Unbalance positions: front, middle, rear (comma-separated).
    #[arg(long, value_delimiter = ',')]
    pub positions: Vec<String>,
    /// Unbalance masses, kg (comma-separated).
    #[arg(long, value_delimiter = ',')]
    pub masses: Vec<f64>,
    /// Speed profile CSV files (time_s, rpm), comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub profiles: Vec<PathBuf>,
    /// Parallel runs (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
}

pub fn sweep(a: Args) -> Result<ExitCode, Failure> {
    let Args {
        spec,
        positions,
        masses,
        profiles,
        jobs,
    } = a;
    let base = washdyn::simulation::Source::load(&spec.model)?;
    let (method, tol) = spec.solver(&base.model);
    let cfg = washdyn::sweep::SweepRun {
        spec,
        control: washdyn::simulation::RunControl {
            guard: super::guard(),
            ..Default::default()
        },
        jobs: jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get())),
    };
    washdyn::sweep::check_settings(&base, &cfg)?;
    let spec = washdyn::sweep::SweepSpec {
        positions,
        masses,
        profiles,
    };
    let vars = washdyn::sweep::variants(&base.model, &spec)?;
    let bar = ProgressBar::new(vars.len() as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} variants [{elapsed_precise}, ETA {eta}] {msg}",
        )
        .expect("valid template"),
    );
    let done = |r: &washdyn::sweep::VariantResult| {
        bar.inc(1);
        bar.set_message(format!("{}: {}", r.name, r.summary.status));
    };
    let res = washdyn::sweep::run_sweep(&base, vars, &cfg, &done)?;
    bar.finish_and_clear();
    let failed = res
        .iter()
        .filter(|r| r.summary.status != washdyn_runtime::run::RunStatus::Ok)
        .count();
    // The set-up's own warning (a loose tolerance) is every variant's: said once.
    let common = washdyn::error_class::tolerance_warning(method, tol);
    if let Some(w) = &common {
        eprintln!("warning: {w}");
    }
    for r in &res {
        for w in r
            .summary
            .warnings
            .iter()
            .filter(|w| Some(*w) != common.as_ref())
        {
            eprintln!("warning: {}: {w}", r.name);
        }
    }
    let _ = writeln!(
        std::io::stdout(),
        "{} variants ({} failed); table: {}/sweep.csv",
        res.len(),
        failed,
        cfg.out(&base.model).display()
    );
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
