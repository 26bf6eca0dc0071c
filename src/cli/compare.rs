//! `washdyn compare`: its arguments and what it prints. Two runs of one speed profile are
//! compared in time; a run and a measurement file, or two runs with `--over-speed`, at equal
//! drum speed.

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
    /// The second run's directory (B), or a measured signal file (CSV or Parquet with
    /// `time_s`, `drum_rpm` and channels named like the run's sensors): then compared over
    /// speed.
    #[arg(value_name = "RUN_B|MEASUREMENT")]
    pub run_b: PathBuf,
    /// Compare two runs at equal drum speed instead of equal time (runs of different speed
    /// profiles); a measurement file is always compared so.
    #[arg(long)]
    pub over_speed: bool,
    /// Over speed: multiply B by the constant factor that matches its order 1 to A's (always
    /// computed and reported; applied only with this).
    #[arg(long)]
    pub calibrate: bool,
    /// Over speed: edges of the speed ranges of the dB table, rpm (default 400,800,1400).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub speed_ranges: Option<Vec<f64>>,
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
        over_speed,
        calibrate,
        speed_ranges,
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
    // A file, or a path named like one that is missing (then its read says so), is a measurement.
    let ext = run_b
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let measured =
        !run_b.is_dir() && (run_b.is_file() || matches!(ext.as_deref(), Some("csv" | "parquet")));
    if over_speed || measured {
        if let Some(t) = until {
            let m = format!("--until {t} compares in time; over speed every common speed counts");
            return Err(Error::setting("--until", m).into());
        }
        let speed_ranges =
            speed_ranges.unwrap_or_else(|| washdyn::compare::speed::DEFAULT_RANGE_EDGES.to_vec());
        if washdyn::compare::check_edges(&speed_ranges).is_err() {
            let m = format!(
                "--speed-ranges must be positive, finite, increasing rpm, got {speed_ranges:?}"
            );
            return Err(Error::setting("--speed-ranges", m).into());
        }
        let labels = if measured {
            [
                label_a.unwrap_or_else(|| "simulation".into()),
                label_b.unwrap_or_else(|| "measurement".into()),
            ]
        } else {
            [name(&run_a, label_a), name(&run_b, label_b)]
        };
        let args = washdyn::compare::SpeedArgs {
            run: run_a,
            other: run_b,
            labels,
            out,
            motor_ratio,
            svg,
            calibrate,
            range_edges: speed_ranges,
        };
        let (_, files) = washdyn::compare::compare_over_speed(&args).map_err(Error::from)?;
        return Ok(wrote(files));
    }
    for (given, option) in [
        (calibrate, "--calibrate"),
        (speed_ranges.is_some(), "--speed-ranges"),
    ] {
        if given {
            let m =
                format!("{option} is for a comparison over speed (a measurement, or --over-speed)");
            return Err(Error::setting(option, m).into());
        }
    }
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
