//! `washdyn analyse`: its arguments and what it prints.

use super::Failure;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use washdyn::Error;
use washdyn::analysis::{AnalysisOptions, analyse_signals, read_signals};
use washdyn::results::Format;

/// `washdyn analyse`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Parquet or CSV with columns time_s, drum_rpm, then one column per channel.
    pub file: PathBuf,
    /// Output directory (default: beside the file, <stem>-analysis).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Belt ratio (motor speed / drum speed) for marking the motor orders.
    #[arg(long, default_value_t = 11.25)]
    pub motor_ratio: f64,
    /// Format of the spectra and order-track tables: parquet or csv.
    #[arg(long, default_value = "parquet")]
    pub format: Format,
    /// Also write every plot as SVG (PNG always).
    #[arg(long)]
    pub svg: bool,
}

pub fn analyse(a: Args) -> Result<ExitCode, Failure> {
    let Args {
        file,
        out,
        motor_ratio,
        format,
        svg,
    } = a;
    let dir = out.unwrap_or_else(|| {
        let stem = file
            .file_stem()
            .map_or("signals".into(), |s| s.to_string_lossy().to_string());
        file.with_file_name(format!("{stem}-analysis"))
    });
    let opts = AnalysisOptions {
        motor_ratio,
        format,
        svg,
        ..AnalysisOptions::default()
    };
    opts.validate().map_err(Error::from)?;
    // A run's sensor file beside its summary.json: the two must be one run's.
    if let Some(run) = file.parent() {
        washdyn::run_dir::check_same_run(run, &file).map_err(Error::from)?;
    }
    let signals = read_signals(&file).map_err(Error::from)?;
    // A file shorter than a block is analysed in one block over all of it (down to the
    // analysis' shortest block), as `washdyn run` does.
    let fitted = opts
        .fit_to(signals.len(), signals.sample_rate)
        .map_err(Error::from)?;
    if fitted.block_length_s < opts.block_length_s {
        eprintln!(
            "note: {} spans {} s, shorter than the analysis' {} s blocks: analysed in one block \
             of it",
            file.display(),
            washdyn_ode::Rounded(fitted.block_length_s),
            opts.block_length_s
        );
    }
    let r = analyse_signals(&signals, &dir, &fitted).map_err(Error::from)?;
    let _ = writeln!(
        std::io::stdout(),
        "{r}\nplots and spectra in {}",
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}
