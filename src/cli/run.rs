//! `washdyn run`: its arguments (the run's specification, `washdyn::spec::RunSpec`, and the
//! analysis after it), its progress (`progress::RunLine`), the summary on stdout and the
//! warnings on stderr.

use super::Failure;
use std::io::Write;
use std::process::ExitCode;
use washdyn::analysis::{AnalysisError, AnalysisOptions, AnalysisReport};
use washdyn::commands::{RunControl, run_command_with};
use washdyn::spec::RunSpec;
use washdyn_ode::Rounded;
use washdyn_runtime::run::{AnalysisStatus, RunStatus};

/// Post-processing of a run from the samples it kept in memory: channels that are identically
/// zero (a fixed cabinet's) are left out, and spectra stop at 300 Hz (motor order 1 at 1400 rpm
/// is 262.5 Hz), so a full run-up's output stays small.
const ANALYSIS_BAND_HZ: f64 = 300.0;

fn analyse_run(
    samples: (Vec<String>, Vec<Vec<f64>>),
    sample_rate: f64,
    dir: &std::path::Path,
    opts: AnalysisOptions,
) -> Result<AnalysisReport, AnalysisError> {
    let (names, mut cols) = samples;
    let data = cols.split_off(2.min(cols.len()));
    let rpm = cols.pop().unwrap_or_default();
    let t0 = cols.first().and_then(|t| t.first()).copied().unwrap_or(0.0);
    let channels = names
        .into_iter()
        .skip(2)
        .zip(data)
        .filter(|(_, d)| d.iter().any(|v| *v != 0.0))
        .map(|(n, d)| washdyn::analysis::Channel::new(n, d))
        .collect();
    let signals = washdyn::analysis::Signals::from_uniform(t0, sample_rate, rpm, channels)?;
    let opts = AnalysisOptions {
        max_frequency_hz: Some(ANALYSIS_BAND_HZ),
        ..opts
    };
    washdyn::analysis::analyse_signals(&signals, dir, &opts)
}

/// The analysis after the run and what it did (for summary.json): skipped, with the reason, for
/// a run that failed or kept fewer samples than the shortest block
/// ([`washdyn::analysis::MIN_BLOCK_LENGTH_S`]); else done, in one block over the whole run where
/// it is shorter than the default block (with a note saying so). `Err`: the analysis failed.
fn analyse_after(
    o: &mut washdyn::commands::RunOutcome,
    spec: &RunSpec,
    c: &Args,
    dir: &std::path::Path,
) -> Result<(AnalysisStatus, Option<AnalysisReport>), AnalysisError> {
    let skipped = |note: String| Ok((AnalysisStatus::Skipped { note }, None));
    let samples = o.samples.take();
    if o.error.is_some() {
        return skipped("no analysis: the run stopped before its end (its error)".into());
    }
    let Some(samples) = samples else {
        return skipped("no analysis: the run kept no samples".into());
    };
    let defaults = AnalysisOptions {
        motor_ratio: o.motor_ratio.unwrap_or(11.25),
        format: spec.format,
        svg: c.svg,
        cascades: c.cascades,
        ..AnalysisOptions::default()
    };
    let n = samples.1.first().map_or(0, Vec::len);
    let opts = match defaults.fit_to(n, spec.sample_rate) {
        Ok(opts) => opts,
        Err(e) => return skipped(format!("no analysis: {e}")),
    };
    let block = opts.block_length_s;
    let note = (block < defaults.block_length_s).then(|| {
        format!(
            "the run's {n} samples ({} s) are fewer than the analysis' {} s block: analysed in \
             one block of them (frequency resolution {:.3} Hz)",
            Rounded(block),
            defaults.block_length_s,
            1.0 / block
        )
    });
    let report = analyse_run(samples, spec.sample_rate, dir, opts)?;
    let status = AnalysisStatus::Done {
        block_length_s: block,
        note,
    };
    Ok((status, Some(report)))
}

/// `washdyn run`'s arguments: the run's specification and the analysis after it.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub spec: RunSpec,
    /// Skip the analysis: order plots, cascades, speed plots, spectra and order tracks
    /// (DIR/analysis/).
    #[arg(long)]
    pub no_plots: bool,
    /// Also write every plot as SVG (PNG always).
    #[arg(long)]
    pub svg: bool,
    /// Also write cascades (time spectra over speed) and the spectra table.
    #[arg(long)]
    pub cascades: bool,
}

/// `washdyn run`: the run, its summary on stdout and warnings on stderr, then the analysis.
pub fn run(c: Args) -> Result<ExitCode, Failure> {
    let spec = &c.spec;
    let reporter = super::progress::Reporter::new(1000);
    let mut line = super::progress::RunLine::default();
    let mut progress = |p: washdyn_runtime::run::Progress| {
        let position = (1000.0 * p.t / p.t_end) as u64;
        reporter.set(Some(position), line.line(&p, reporter.elapsed_s()));
    };
    let ctl = RunControl {
        guard: super::guard(),
        analysis_band_hz: (!c.no_plots).then_some(ANALYSIS_BAND_HZ),
        variant: None,
    };
    let outcome = run_command_with(spec, &ctl, &mut progress);
    drop(reporter);
    let mut o = outcome?;
    // The analysis into the run's folder before it goes into place: its status and order
    // peaks join the summary that publishing writes.
    let mut report = None;
    let mut failed_analysis = None;
    if !c.no_plots {
        let dir = o.out_dir.join("analysis");
        let status = match analyse_after(&mut o, spec, &c, &dir) {
            Ok((status, r)) => {
                if let Some(r) = &r {
                    o.summary.order_peaks = washdyn::commands::order_peaks(r);
                }
                report = r;
                status
            }
            Err(e) => {
                // The run's status says what the exit code says: failed, with the analysis' error.
                o.summary.status = RunStatus::Failed;
                o.summary.error = Some(format!("analysis failed: {e}"));
                let error = e.to_string();
                failed_analysis = Some(e);
                AnalysisStatus::Failed { error }
            }
        };
        if let AnalysisStatus::Done { note: Some(n), .. } | AnalysisStatus::Skipped { note: n } =
            &status
        {
            eprintln!("note: {n}");
        }
        o.summary.analysis = Some(status);
    }
    o.publish()?;
    let s = &o.summary;
    // A closed stdout (e.g. `| head`) must not turn a finished run into a panic.
    let mut out = std::io::stdout();
    let _ = writeln!(
        out,
        "{} / {} / {} / {}: t = {} s, {} steps ({} rejected), {} rhs evals, {:.2} s wall",
        s.model,
        s.scene,
        s.backend,
        s.integrator,
        s.t_reached,
        s.steps,
        s.rejected_steps,
        s.rhs_evals,
        s.wall_time_s
    );
    if let Some(c) = &s.error_class {
        let _ = writeln!(out, "error class: {c}");
    }
    let _ = writeln!(out, "wrote {} and summary.json", o.sensors.display());
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(r) = report {
        let _ = writeln!(out, "{r}");
        let _ = writeln!(
            out,
            "plots and tables in {}",
            o.out_dir.join("analysis").display()
        );
    }
    if let Some(e) = o.error.take() {
        eprintln!(
            "error: {e}; the output up to then is in {}",
            o.out_dir.display()
        );
        return Err(Failure::Printed(e));
    }
    if let Some(e) = failed_analysis {
        eprintln!("error: analysis failed: {e}");
        return Err(Failure::Printed(e.into()));
    }
    Ok(ExitCode::SUCCESS)
}
