//! `washdyn`'s command line: a module per command with its arguments (clap) and what it prints;
//! the commands' work is the library's (`washdyn::*`). `main.rs` dispatches and maps errors to
//! exit codes.

pub mod accuracy;
pub mod analyse;
pub mod campbell;
pub mod check;
pub mod compare;
pub mod fe;
pub mod fields;
pub mod modes;
pub mod progress;
pub mod run;
pub mod study;
pub mod sweep;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use washdyn::Error;
use washdyn_runtime::run::Guard;

/// The exit codes, shown by `washdyn --help`; the README's table is this text (tidy holds it).
const EXIT_CODES: &str = "Exit codes (by the cause, whichever command meets it):
  0    success
  1    a run stopped early (its output up to then is kept), or a sweep's or study's variant
       failed
  2    a setting refused before anything was written (an option or its value, clap's usage
       errors, a study file or a measurement's mapping file at its line, a study directory
       that is another study's or has tasks in Slurm's queue)
  3    a model refused, under every command that takes one: it does not load, fails the
       checker (also a study's variant), lacks the scene, or is neither built in nor a file
  4    a file or directory that cannot be read or written (also an --out that is a file)
  5    other refused data: a signal or measured file the analysis cannot take (also after a
       run; a tacho without pulses, channels of two sample rates), runs
       that cannot be compared or files of two runs, FE or field input, a Slurm command that
       failed
  130  interrupted (Ctrl-C, SIGTERM, SIGHUP); summary.json says so and the output is kept";

#[derive(Parser)]
#[command(
    name = "washdyn",
    version,
    about = "Vibrations of washing machines as elastic multibody systems",
    after_help = EXIT_CODES
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Cmd,
}

#[derive(Subcommand)]
pub enum Cmd {
    /// Simulate a run-up: writes DIR/sensors.parquet and DIR/summary.json.
    Run(run::Args),
    /// Displacement fields on the FE meshes from a run's states (`run --states`), as VTK grids
    /// with a .pvd collection per body (ParaView).
    Fields(fields::Args),
    /// Order analysis of a signal file (time_s, drum_rpm, channels...): order plots, cascades,
    /// speed plots, spectra and order tracks.
    Analyse(analyse::Args),
    /// Compare two finished runs of one speed profile (directories written by `washdyn run`):
    /// per channel and order the peaks over the run and their difference in dB (B against A),
    /// the RMS differences, each run's cost; compare.md, compare.json and per channel the two
    /// order plots side by side and the order tracks overlaid. A run against a measurement
    /// file (or `--over-speed`: runs of different profiles) is compared at equal drum speed:
    /// dB per speed range, resonance speeds, a calibration factor (`--calibrate` applies it).
    Compare(compare::Args),
    /// FE models with CalculiX: `solve DECK.inp` runs ccx on a deck (errors with the deck's
    /// line) and lists its eigenfrequencies.
    Fe(fe::Args),
    /// Check a model file and list its scenes.
    Check(check::Args),
    /// What accuracy costs in time: every method over a sweep of tolerances against a
    /// confirmed reference, modal truncation, scenes, back ends. Writes accuracy.md,
    /// accuracy.json and a work-precision plot per scene (PNG, SVG).
    Accuracy(accuracy::Args),
    /// The spinning drum's frequencies over speed from its modal data (rotating frame:
    /// Coriolis, spin softening, stress stiffening), with the excitation orders: campbell.csv
    /// and campbell.png (.svg).
    Campbell(campbell::Args),
    /// The rigid modes of the suspended tub (at rest, friction released) with each damper's
    /// stroke per mode, as markdown on stdout and in DIR/modes.md.
    Modes(modes::Args),
    /// Run variants (unbalance position, mass, speed profile) on all cores with `run`'s
    /// simulation options: a grid design of the study (DIR/study.toml), its dataset in DIR and
    /// one table of every variant, DIR/summary.csv.
    Sweep(sweep::Args),
    /// Variant studies: a design over a model's parameters (a study file, TOML; README,
    /// "Variant studies"), every variant checked before any runs, run on all cores (or as a
    /// Slurm job array, `run --slurm`) into one hive-partitioned Parquet dataset; a re-run
    /// completes it.
    Study(study::Args),
}

/// The guard of `run` and `sweep` beyond the specification's: Ctrl-C.
pub fn guard() -> Guard {
    Guard {
        interrupt: Some(interrupt_flag()),
        ..Guard::default()
    }
}

/// The Ctrl-C flag, also set by SIGTERM and SIGHUP (ctrlc's `termination`: a batch system's
/// time limit, a closed session): a run stops between steps, its summary's status
/// `interrupted`, its sensor file closed and readable.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = interrupt.clone();
    if let Err(e) = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)) {
        eprintln!("warning: Ctrl-C will not write a summary: {e}");
    }
    interrupt
}

/// How a command failed: an error to print as `error: ...`, one printed as it is (`check`'s
/// report), or one already reported.
pub enum Failure {
    Error(Error),
    Quiet(Error),
    Printed(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Failure {
        Failure::Error(e)
    }
}

/// Prints the files a command wrote.
pub fn wrote(files: Vec<PathBuf>) -> ExitCode {
    for f in files {
        println!("wrote {}", f.display());
    }
    ExitCode::SUCCESS
}
