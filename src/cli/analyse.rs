//! `washdyn analyse`: its arguments and what it prints. A signal file (CSV/Parquet) is read as
//! it is; a mapping file (`.toml`) or a UFF file (with `--tacho` or `--rpm`) goes through
//! `washdyn::measured`, whose report (speed source, tacho quality, unit conversions) is printed
//! before the analysis.

use super::Failure;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use washdyn::Error;
use washdyn::analysis::{AnalysisOptions, Signals, analyse_signals, read_signals};
use washdyn::measured::{self, ChannelMap, Mapping, Measured, SpeedMap, Spots, TachoMap};
use washdyn::results::Format;

/// Belt ratio (motor speed / drum speed) of the built-in machines: the motor orders' default.
const MOTOR_RATIO: f64 = 11.25;
/// Most points of a speed table `--speed-table` writes.
const SPEED_TABLE_POINTS: usize = 5000;

/// `washdyn analyse`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Parquet or CSV with columns time_s, drum_rpm, then one column per channel; a mapping
    /// file (measurement.toml, docs/validation.md); or a UFF 58/58b file (.uff, .unv, .58)
    /// with --tacho or --rpm.
    pub file: PathBuf,
    /// Output directory (default: beside the file, <stem>-analysis).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Belt ratio (motor speed / drum speed) for marking the motor orders (default 11.25);
    /// with --tacho, the tacho is on the motor shaft and this is its ratio to the drum.
    #[arg(long)]
    pub motor_ratio: Option<f64>,
    /// Format of the spectra and order-track tables: parquet or csv.
    #[arg(long, default_value = "parquet")]
    pub format: Format,
    /// Also write every plot as SVG (PNG always).
    #[arg(long)]
    pub svg: bool,
    /// A UFF file's tacho channel (its name as the file gives it) for the drum speed.
    #[arg(long, value_name = "CHANNEL", conflicts_with = "rpm")]
    pub tacho: Option<String>,
    /// The tacho's pulses per revolution of its shaft.
    #[arg(long, default_value_t = 1, requires = "tacho")]
    pub ppr: u32,
    /// A UFF file's drum speed channel (rpm).
    #[arg(long, value_name = "CHANNEL")]
    pub rpm: Option<String>,
    /// Also write the measured drum speed as a speed table (CSV time_s,drum_rpm) for
    /// `washdyn run --speed`.
    #[arg(long, value_name = "FILE")]
    pub speed_table: Option<PathBuf>,
}

/// How the file is read.
enum Input {
    Signals,
    Mapping,
    Uff,
}

fn input(file: &Path) -> Input {
    let ext = file
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "toml" => Input::Mapping,
        "uff" | "unv" | "58" | "uf" => Input::Uff,
        _ => Input::Signals,
    }
}

pub fn analyse(a: Args) -> Result<ExitCode, Failure> {
    let dir = a.out.clone().unwrap_or_else(|| {
        let stem = a
            .file
            .file_stem()
            .map_or("signals".into(), |s| s.to_string_lossy().to_string());
        a.file.with_file_name(format!("{stem}-analysis"))
    });
    let opts = AnalysisOptions {
        motor_ratio: a.motor_ratio.unwrap_or(MOTOR_RATIO),
        format: a.format,
        svg: a.svg,
        ..AnalysisOptions::default()
    };
    opts.validate().map_err(Error::from)?;
    let kind = input(&a.file);
    if !matches!(kind, Input::Uff) {
        for (given, option) in [(a.tacho.is_some(), "--tacho"), (a.rpm.is_some(), "--rpm")] {
            if given {
                return Err(Error::setting(
                    option,
                    "applies to a UFF file; a mapping file names its speed source, a CSV or \
                     Parquet file has drum_rpm",
                )
                .into());
            }
        }
    }
    let signals = match kind {
        Input::Signals => {
            // A run's sensor file beside its summary.json: the two must be one run's.
            if let Some(run) = a.file.parent() {
                washdyn::run_dir::check_same_run(run, &a.file).map_err(Error::from)?;
            }
            if a.speed_table.is_some() {
                return Err(Error::setting(
                    "--speed-table",
                    "applies to a measurement (a mapping or UFF file)",
                )
                .into());
            }
            read_signals(&a.file).map_err(Error::from)?
        }
        Input::Mapping => measurement(measured::load(&a.file).map_err(Error::from)?, &a)?,
        Input::Uff => measurement(uff_direct(&a)?, &a)?,
    };
    analyse_loaded(&signals, &a.file, &dir, &opts)
}

/// Print what loading did, write the speed table if asked; the signals to analyse.
fn measurement(m: Measured, a: &Args) -> Result<Signals, Failure> {
    let _ = write!(std::io::stdout(), "{m}");
    if let Some(path) = &a.speed_table {
        let table = measured::speed_table(&m, SPEED_TABLE_POINTS);
        measured::write_speed_csv(path, &table).map_err(Error::from)?;
        println!(
            "speed table ({} points) in {} (washdyn run --speed)",
            table.len(),
            path.display()
        );
    }
    Ok(m.signals)
}

/// A UFF file with the speed's source from the options: every other channel analysed under
/// its own name.
fn uff_direct(a: &Args) -> Result<Measured, Failure> {
    let raw = washdyn::analysis::uff58::read(&a.file)
        .map_err(|e| Error::from(measured::MeasuredError::from(e)))?;
    let speed_name = a.tacho.as_ref().or(a.rpm.as_ref());
    let Some(speed_name) = speed_name else {
        let names: Vec<String> = raw.iter().map(|c| format!("`{}`", c.name)).collect();
        return Err(Error::setting(
            "--tacho",
            format!(
                "a UFF file needs the drum speed's source: --tacho CHANNEL [--ppr N] \
                 [--motor-ratio R] or --rpm CHANNEL; its channels: {}",
                names.join(", ")
            ),
        )
        .into());
    };
    let channels = raw
        .iter()
        .filter(|c| &c.name != speed_name)
        .map(|c| ChannelMap {
            measured: Some(c.name.clone()),
            sensor: c.name.clone(),
            ..ChannelMap::default()
        })
        .collect();
    let tacho = a.tacho.as_ref().map(|t| TachoMap {
        channel: t.clone(),
        pulses_per_rev: a.ppr,
        edge: "rising".into(),
        side: if a.motor_ratio.is_some() {
            "motor"
        } else {
            "drum"
        }
        .into(),
        ratio: a.motor_ratio,
        threshold: None,
        hysteresis: None,
        smoothing_s: None,
    });
    let file = a.file.file_name().map(PathBuf::from).unwrap_or_default();
    let dir = a
        .file
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let mapping = Mapping {
        files: vec![file],
        channels,
        speed: SpeedMap {
            tacho,
            rpm: a.rpm.clone(),
        },
    };
    Ok(measured::load_mapping(&mapping, &Spots::command_line(dir)).map_err(Error::from)?)
}

/// The analysis of loaded signals, as for every input.
fn analyse_loaded(
    signals: &Signals,
    file: &Path,
    dir: &Path,
    opts: &AnalysisOptions,
) -> Result<ExitCode, Failure> {
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
    let r = analyse_signals(signals, dir, &fitted).map_err(Error::from)?;
    let _ = writeln!(
        std::io::stdout(),
        "{r}\nplots and spectra in {}",
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}
