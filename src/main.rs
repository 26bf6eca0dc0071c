//! `washdyn`: simulate washing-machine vibrations from the command line. Every command's
//! error is a `washdyn::Error`; [`exit_code`] maps it to the process's exit code.

mod cli;
mod study_cli;

use clap::Parser;
use cli::{Cli, Cmd, FeCmd};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use washdyn::Error;
use washdyn::analysis::{AnalysisError, AnalysisOptions, analyse_file};
use washdyn::commands::{RunControl, check_model, resolve_model, run_command_with};
use washdyn::spec::{Field, RunSpec};
use washdyn::study::StudyError;
use washdyn::study::slurm::SlurmError;
use washdyn_runtime::run::RunError;

/// The exit code of an error: the one mapping (the table is `cli::EXIT_CODES`, shown by
/// `washdyn --help`, and docs/commands.md).
fn exit_code(e: &Error) -> ExitCode {
    ExitCode::from(match e {
        Error::Integration {
            source: RunError::Interrupted { .. },
            ..
        } => 130,
        Error::Integration { .. } => 1,
        Error::Settings(_)
        | Error::Analysis(AnalysisError::InvalidOptions(_))
        | Error::Study(
            StudyError::File(_)
            | StudyError::Directory { .. }
            | StudyError::Slurm(
                SlurmError::Busy { .. } | SlurmError::Path { .. } | SlurmError::Assignment { .. },
            ),
        ) => 2,
        Error::Model(_)
        | Error::Check { .. }
        | Error::Scene { .. }
        | Error::UnknownModel { .. }
        | Error::Study(StudyError::Variants(_)) => 3,
        Error::Io { .. } | Error::File { .. } | Error::Analysis(AnalysisError::Io { .. }) => 4,
        Error::Analysis(_)
        | Error::Compare(_)
        | Error::Refused { .. }
        | Error::Study(StudyError::Slurm(
            SlurmError::Missing { .. } | SlurmError::Failed { .. } | SlurmError::Answer { .. },
        )) => 5,
    })
}

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

fn main() -> ExitCode {
    let cli = Cli::parse();
    match command(cli.cmd) {
        Ok(code) => code,
        Err(Failure::Printed(e)) => exit_code(&e),
        Err(Failure::Quiet(e)) => {
            eprintln!("{e}");
            exit_code(&e)
        }
        Err(Failure::Error(e)) => {
            eprintln!("error: {e}");
            exit_code(&e)
        }
    }
}

/// How a command failed: an error to print as `error: ...`, one printed as it is (`check`'s
/// report), or one already reported.
enum Failure {
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
fn wrote(files: Vec<PathBuf>) -> ExitCode {
    for f in files {
        println!("wrote {}", f.display());
    }
    ExitCode::SUCCESS
}

/// A command whose errors are still text.
fn text<T>(command: &'static str, r: Result<T, String>) -> Result<T, Error> {
    r.map_err(|m| Error::refused(command, m))
}

fn command(cmd: Cmd) -> Result<ExitCode, Failure> {
    match cmd {
        Cmd::Run {
            spec,
            no_plots,
            svg,
            cascades,
        } => run(RunCli {
            spec,
            no_plots,
            svg,
            cascades,
        }),
        Cmd::Sweep {
            spec,
            positions,
            masses,
            profiles,
            jobs,
        } => {
            let base = washdyn::simulation::Source::load(&spec.model)?;
            let (method, tol) = spec.solver(&base.model);
            let cfg = washdyn::sweep::SweepRun {
                spec,
                control: washdyn::simulation::RunControl {
                    guard: cli::guard(),
                    ..Default::default()
                },
                jobs: jobs
                    .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get())),
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
            let common = washdyn::accuracy::class::tolerance_warning(method, tol);
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
        Cmd::Study { cmd } => study_cli::study(cmd),
        Cmd::Analyse {
            file,
            out,
            motor_ratio,
            format,
            svg,
        } => {
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
            let r = analyse_file(&file, &dir, &opts).map_err(Error::from)?;
            let _ = writeln!(
                std::io::stdout(),
                "{r}\nplots and spectra in {}",
                dir.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Compare {
            run_a,
            run_b,
            out,
            label_a,
            label_b,
            motor_ratio,
            svg,
            until,
        } => {
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
            let (_, files) = washdyn::compare::compare(&args).map_err(Error::from)?;
            Ok(wrote(files))
        }
        Cmd::Fields {
            run,
            model,
            times,
            range,
            revolution,
            drum_edge,
            svg,
            fe,
            out,
        } => {
            use washdyn::fields::{Request, Times};
            let request = match (times, range, revolution, drum_edge) {
                (Some(t), None, None, None) => washdyn::fields::check_times("--times", &t)
                    .map(|()| Request::Fields(Times::List(t)))
                    .map_err(|m| Error::setting("--times", m)),
                (None, Some(r), None, None) => cli::parse_range(&r)
                    .map(Request::Fields)
                    .map_err(|m| Error::setting("--range", m)),
                (None, None, Some(t), None) => washdyn::fields::check_times("--revolution", &[t])
                    .map(|()| Request::Fields(Times::Revolution(t)))
                    .map_err(|m| Error::setting("--revolution", m)),
                (None, None, None, Some(0)) => Err(Error::setting(
                    "--drum-edge",
                    "--drum-edge: the stride must be at least 1",
                )),
                (None, None, None, Some(stride)) => Ok(Request::DrumEdge { stride, svg }),
                _ => Err(Error::setting(
                    "--times",
                    "give exactly one of --times, --range, --revolution, --drum-edge",
                )),
            }?;
            let w = text(
                "fields",
                washdyn::fields::fields_command(
                    &run,
                    model.as_deref(),
                    &request,
                    &fe,
                    out.as_deref(),
                ),
            )?;
            for n in &w.notes {
                eprintln!("note: {n}");
            }
            println!(
                "wrote {} files, {:.1} MB in {:.2} s",
                w.files.len(),
                w.bytes as f64 / 1e6,
                w.seconds
            );
            if let Some((body, m, node, t)) = w.largest {
                println!(
                    "largest displacement {:.4} mm: {body} node {node} at t = {t:.3} s",
                    m * 1e3
                );
            }
            if let Some((body, pa, node, t)) = w.peak_stress {
                println!(
                    "peak von Mises stress {:.2} MPa: {body} node {node} at t = {t:.3} s",
                    pa * 1e-6
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Accuracy {
            model,
            scene,
            t_end,
            out,
            quick,
        } => {
            if let Some(t) = t_end
                && !(t > 0.0 && t <= washdyn::spec::T_END_MAX)
            {
                return Err(Error::setting(
                    Field::TEnd,
                    format!(
                        "--t-end must be > 0 and at most {} s, got {t}",
                        washdyn::spec::T_END_MAX
                    ),
                )
                .into());
            }
            let scenes = if scene.is_empty() {
                vec!["full".to_string(), "elastic:150:152".to_string()]
            } else {
                scene
            };
            let mut windows = Vec::new();
            for sc in &scenes {
                let mut w = sc.parse::<washdyn::accuracy::Window>()?;
                if let (true, Some(t)) = (w.t1.is_nan(), t_end) {
                    w.t1 = t;
                }
                windows.push(w);
            }
            let args = washdyn::accuracy::AccuracyArgs {
                model,
                windows,
                out: out.clone(),
                quick,
            };
            let study = washdyn::accuracy::study(&args, &mut |l| println!("{l}"))?;
            Ok(wrote(washdyn::accuracy::write(&study, &out)?))
        }
        Cmd::Modes { model, scene, out } => Ok(wrote(vec![text(
            "modes",
            washdyn::modes::run(&model, scene.as_deref(), out.as_deref()),
        )?])),
        Cmd::Campbell {
            source,
            max_rpm,
            motor_ratio,
            out,
            svg,
        } => Ok(wrote(text(
            "campbell",
            washdyn::campbell::run(&source, max_rpm, motor_ratio, &out, svg),
        )?)),
        Cmd::Fe {
            cmd: FeCmd::Write { out },
        } => {
            text("fe", washdyn::commands::fe_write(&out))?;
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Fe {
            cmd: FeCmd::Deck { spec, out, work },
        } => {
            text("fe", washdyn::commands::fe_deck(&spec, &out, &work))?;
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Fe {
            cmd: FeCmd::Modal { out, work, only },
        } => {
            text("fe", washdyn::commands::fe_modal(&out, &work, &only))?;
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Fe {
            cmd:
                FeCmd::Reference {
                    model,
                    out,
                    work,
                    modes,
                    speeds,
                    no_convergence,
                    ccx_results,
                },
        } => {
            let args = washdyn::full_mesh::Args {
                model,
                modes,
                speeds_rpm: speeds,
                spec: washdyn_fe::assembly::LinearSpec::default(),
                work,
                convergence: !no_convergence,
                committed: ccx_results,
            };
            let study = text(
                "fe",
                washdyn::full_mesh::study(&args, &mut |l| println!("{l}")),
            )?;
            Ok(wrote(text("fe", washdyn::full_mesh::write(&study, &out))?))
        }
        Cmd::Fe {
            cmd: FeCmd::Solve { deck },
        } => {
            let run = text("fe", washdyn_fe::ccx::run(&deck).map_err(|e| e.to_string()))?;
            let dat = std::fs::read_to_string(run.dat()).unwrap_or_default();
            let f = washdyn_fe::ccx::frequencies(&dat);
            let mut out = std::io::stdout();
            let _ = writeln!(
                out,
                "{}: solved in {:.2} s; {} eigenfrequencies (Hz):",
                deck.display(),
                run.wall_s,
                f.len()
            );
            for (i, hz) in f.iter().enumerate() {
                let _ = writeln!(out, "{:4} {hz:.6}", i + 1);
            }
            Ok(ExitCode::SUCCESS)
        }
        Cmd::Check { model } => {
            let report = resolve_model(&model)
                .and_then(|(m, _)| check_model(&m))
                .map_err(Failure::Quiet)?;
            let _ = writeln!(std::io::stdout(), "{report}");
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// `washdyn run`'s own options beside the specification: the analysis after the run.
struct RunCli {
    spec: RunSpec,
    no_plots: bool,
    svg: bool,
    cascades: bool,
}

/// `washdyn run`: the run, its summary on stdout and warnings on stderr, then the analysis.
fn run(c: RunCli) -> Result<ExitCode, Failure> {
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
        guard: cli::guard(),
        analysis_band_hz: (!c.no_plots).then_some(ANALYSIS_BAND_HZ),
        variant: None,
    };
    let outcome = run_command_with(spec, &ctl, &mut progress);
    bar.finish_and_clear();
    let o = outcome?;
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
    if let Some(samples) = o.samples.filter(|_| s.samples > 1 && o.error.is_none()) {
        let dir = o.out_dir.join("analysis");
        let opts = AnalysisOptions {
            motor_ratio: o.motor_ratio.unwrap_or(11.25),
            format: spec.format,
            svg: c.svg,
            cascades: c.cascades,
            ..AnalysisOptions::default()
        };
        match analyse_run(samples, spec.sample_rate, &dir, opts) {
            Ok(r) => {
                let _ = writeln!(out, "{r}");
                let _ = writeln!(out, "plots and tables in {}", dir.display());
            }
            Err(e) => failed_analysis = Some(e),
        }
    }
    if let Some(e) = o.error {
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
