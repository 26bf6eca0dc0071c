//! `washdyn run`: its arguments (the run's specification, `washdyn::spec::RunSpec`, and the
//! analysis after it), the progress bar, the summary on stdout and the warnings on stderr.

use super::Failure;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::process::ExitCode;
use washdyn::analysis::AnalysisOptions;
use washdyn::commands::{RunControl, run_command_with};
use washdyn::spec::RunSpec;

/// Post-processing of a run from the samples it kept in memory: channels that are identically
/// zero (a fixed cabinet's) are left out, and spectra stop at 300 Hz (motor order 1 at 1400 rpm
/// is 262.5 Hz), so a full run-up's output stays small.
const ANALYSIS_BAND_HZ: f64 = 300.0;

fn analyse_run(
    samples: (Vec<String>, Vec<Vec<f64>>),
    sample_rate: f64,
    dir: &std::path::Path,
    opts: AnalysisOptions,
) -> Result<washdyn::analysis::AnalysisReport, washdyn::analysis::AnalysisError> {
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
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} t = {msg} [{elapsed_precise}, ETA {eta}]")
            .expect("valid template"),
    );
    let mut progress = |p: washdyn_runtime::run::Progress| {
        bar.set_position((1000.0 * p.t / p.t_end) as u64);
        bar.set_message(match p.start {
            // The periodic start iterates before t moves: say how far it is.
            Some((k, r)) => format!(
                "{:.2} s, periodic start at {:.0} rpm: {k} periods, residual {r:.1e} x tolerance",
                p.t, p.rpm
            ),
            None => format!("{:.2} / {:.2} s, drum {:.0} rpm", p.t, p.t_end, p.rpm),
        });
    };
    let ctl = RunControl {
        guard: super::guard(),
        analysis_band_hz: (!c.no_plots).then_some(ANALYSIS_BAND_HZ),
        variant: None,
    };
    let outcome = run_command_with(spec, &ctl, &mut progress);
    bar.finish_and_clear();
    let mut o = outcome?;
    // The analysis into the run's folder before it goes into place; its order peaks join the
    // summary.
    let mut analysis = None;
    let samples = o.samples.take();
    if let Some(samples) = samples.filter(|_| o.summary.samples > 1 && o.error.is_none()) {
        let dir = o.out_dir.join("analysis");
        let opts = AnalysisOptions {
            motor_ratio: o.motor_ratio.unwrap_or(11.25),
            format: spec.format,
            svg: c.svg,
            cascades: c.cascades,
            ..AnalysisOptions::default()
        };
        let r = analyse_run(samples, spec.sample_rate, &dir, opts);
        if let Ok(r) = &r {
            o.summary.order_peaks = washdyn::commands::order_peaks(r);
        }
        analysis = Some(r);
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
    let mut failed_analysis = None;
    match analysis {
        Some(Ok(r)) => {
            let _ = writeln!(out, "{r}");
            let _ = writeln!(
                out,
                "plots and tables in {}",
                o.out_dir.join("analysis").display()
            );
        }
        Some(Err(e)) => failed_analysis = Some(e),
        None => {}
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
