//! `washdyn`: simulate washing-machine vibrations from the command line.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use washdyn::analysis::{AnalysisOptions, analyse_file};
use washdyn::commands::{
    Backend, RunArgs, RunControl, check_model, resolve_model, run_command_with,
};
use washdyn::results::Format;
use washdyn_runtime::ode::Method;
use washdyn_runtime::run::Guard;

#[derive(Parser)]
#[command(
    name = "washdyn",
    version,
    about = "Vibrations of washing machines as elastic multibody systems"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

/// Settings of a simulation, shared by `run` and `sweep`.
#[derive(clap::Args)]
struct Sim {
    /// End time, s (default: the end of the speed profile).
    #[arg(long)]
    t_end: Option<f64>,
    /// rk4 (fixed step), dopri5 (adaptive, explicit), sdirk4 (L-stable SDIRK), rodas4
    /// (L-stable Rosenbrock), galpha (generalized-alpha on the second-order equations), auto
    /// (dopri5 while not stiff, rodas4 while stiff, switching both ways).
    #[arg(long, default_value = "dopri5")]
    integrator: Method,
    /// Relative tolerance of the adaptive integrators (absolute: 1e-3 x this, in m, m/s and
    /// rad; a modal coordinate in the metres it moves a marker by).
    #[arg(long, default_value_t = 1e-6)]
    tol: f64,
    /// A scene of the model (default: its first scene).
    #[arg(long)]
    scene: Option<String>,
    /// Sampling rate of the sensor file, Hz.
    #[arg(long, default_value_t = 2000.0)]
    sample_rate: f64,
    /// Format of the result files: parquet (columnar, compact) or csv.
    #[arg(long, default_value = "parquet")]
    format: Format,
}

#[derive(Subcommand)]
enum Cmd {
    /// Simulate a run-up: writes DIR/sensors.csv and DIR/summary.json.
    Run {
        /// A built-in model (`reference`, `compact`) or a model file (.toml).
        model: String,
        #[command(flatten)]
        sim: Sim,
        /// Output directory (default: out/<model name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Fixed step of rk4, s (default 1e-4).
        #[arg(long)]
        step: Option<f64>,
        /// Also write the energy balance by category (DIR/energy.parquet and energy.png): the
        /// drive's work, gravity, each body's modal strain and damping, each element's stored
        /// and dissipated energy, and the kinetic energy, every 10 ms.
        #[arg(long)]
        energy: bool,
        /// galpha's spectral radius at infinity, in [0, 1] (default 0.8): 1 keeps the
        /// unresolved high modes undamped, 0 removes them in one step.
        #[arg(long)]
        rho_inf: Option<f64>,
        /// generated (default for built-in models) or interpreted (default for model files).
        #[arg(long)]
        backend: Option<Backend>,
        /// Skip the analysis: order plots, cascades, speed plots, spectra and order tracks
        /// (DIR/analysis/).
        #[arg(long)]
        no_plots: bool,
        /// Also write every plot as SVG (PNG always).
        #[arg(long)]
        svg: bool,
        /// Also write cascades (time spectra over speed) and the spectra table.
        #[arg(long)]
        cascades: bool,
        /// Step budget; the run stops with an error (keeping its output) when it is spent.
        #[arg(long)]
        max_steps: Option<u64>,
        /// Keep running when the tub motion exceeds 5 x the small-motion bounds (30 mm, 0.05 rad).
        #[arg(long)]
        no_validity_stop: bool,
        /// Write sensor output beyond the 2 GB limit.
        #[arg(long)]
        allow_large_output: bool,
        /// Also write the state at every sample (drum angle, q) to DIR/states.parquet, for
        /// `washdyn fields`.
        #[arg(long)]
        states: bool,
        /// How the run starts: `static` (equilibrium under every load at t = 0, a rotating
        /// unbalance's centrifugal force included as if it stood still), `mean` (at rest
        /// under gravity and the mean loads at the start speed) or `periodic` (on the
        /// periodic steady state by shooting; constant speed only).
        #[arg(long, default_value = "static")]
        start: washdyn_runtime::run::Start,
    },
    /// Displacement fields on the FE meshes from a run's states (`run --states`), as VTK grids
    /// with a .pvd collection per body (ParaView).
    Fields {
        /// The run's output directory (summary.json, states.parquet).
        run: PathBuf,
        /// The model, when the run's was a file (default: the summary's model).
        #[arg(long)]
        model: Option<String>,
        /// Instants, s (comma-separated).
        #[arg(long, value_delimiter = ',')]
        times: Option<Vec<f64>>,
        /// FROM:TO:STEP, s.
        #[arg(long)]
        range: Option<String>,
        /// One drum revolution from this time, s (36 frames).
        #[arg(long)]
        revolution: Option<f64>,
        /// Instead of grids: the drum's front-edge deformation over the run against speed
        /// (drum_edge.csv, .png), every STRIDE-th stored sample.
        #[arg(long, value_name = "STRIDE")]
        drum_edge: Option<usize>,
        /// Also write the drum-edge plot as SVG.
        #[arg(long)]
        svg: bool,
        /// Where `washdyn fe modal` left the field files (<body>.field.bin).
        #[arg(long, default_value = "out/fe/work")]
        fe: PathBuf,
        /// Output directory (default: RUN/fields).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Order analysis of a signal file (time_s, drum_rpm, channels...): order plots, cascades,
    /// speed plots, spectra and order tracks.
    Analyse {
        /// Parquet or CSV with columns time_s, drum_rpm, then one column per channel.
        file: PathBuf,
        /// Output directory (default: beside the file, <stem>-analysis).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Belt ratio (motor speed / drum speed) for marking the motor orders.
        #[arg(long, default_value_t = 11.25)]
        motor_ratio: f64,
        /// Format of the spectra and order-track tables: parquet or csv.
        #[arg(long, default_value = "parquet")]
        format: Format,
        /// Also write every plot as SVG (PNG always).
        #[arg(long)]
        svg: bool,
    },
    /// Compare two finished runs of one speed profile (directories written by `washdyn run`):
    /// per channel and order the peaks over the run and their difference in dB (B against A),
    /// the RMS differences, each run's cost; compare.md, compare.json and per channel the two
    /// order plots side by side and the order tracks overlaid.
    Compare {
        /// The first run's directory (A: the reference of the differences).
        #[arg(value_name = "RUN_A")]
        run_a: PathBuf,
        /// The second run's directory (B).
        #[arg(value_name = "RUN_B")]
        run_b: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out/compare")]
        out: PathBuf,
        /// Name of run A in tables and plots (default: its directory's name).
        #[arg(long)]
        label_a: Option<String>,
        /// Name of run B in tables and plots (default: its directory's name).
        #[arg(long)]
        label_b: Option<String>,
        /// Belt ratio (motor speed / drum speed) of the motor order tracked.
        #[arg(long, default_value_t = 11.25)]
        motor_ratio: f64,
        /// Also write the plots as SVG (PNG always).
        #[arg(long)]
        svg: bool,
    },
    /// FE models with CalculiX: `solve DECK.inp` runs ccx on a deck (errors with the deck's
    /// line) and lists its eigenfrequencies.
    Fe {
        #[command(subcommand)]
        cmd: FeCmd,
    },
    /// Check a model file and list its scenes.
    Check { model: String },
    /// What accuracy costs in time: every method over a sweep of tolerances against a
    /// confirmed reference, modal truncation, scenes, back ends. Writes accuracy.md,
    /// accuracy.json and a work-precision plot per scene (PNG, SVG).
    Accuracy {
        /// A built-in model or a model file.
        #[arg(long, default_value = "reference")]
        model: String,
        /// Scenes and windows: NAME (the whole speed profile) or NAME:T0:T1, repeatable
        /// [default: full and elastic:150:152].
        #[arg(long)]
        scene: Vec<String>,
        /// End of the window of scenes given without one, s.
        #[arg(long)]
        t_end: Option<f64>,
        /// Output directory (the repository keeps the study in docs/).
        #[arg(long, default_value = "out/accuracy")]
        out: PathBuf,
        /// Two settings a method and looser references: a first look in seconds.
        #[arg(long)]
        quick: bool,
    },
    /// The spinning drum's frequencies over speed from its modal data (rotating frame:
    /// Coriolis, spin softening, stress stiffening), with the excitation orders: campbell.csv
    /// and campbell.png (.svg).
    Campbell {
        /// A model (built-in name or model file) with an elastic drum, or the drum's modal data
        /// file (e.g. models/fe/drum.modal.toml).
        source: String,
        /// Highest drum speed, rpm [default: the model's top speed, else 1400].
        #[arg(long)]
        max_rpm: Option<f64>,
        /// Motor/drum speed ratio for the motor order line [default: the model's rotor `motor`,
        /// else 11.25].
        #[arg(long)]
        motor_ratio: Option<f64>,
        /// Output directory.
        #[arg(long, default_value = "out/campbell")]
        out: PathBuf,
        /// Also write the plot as SVG.
        #[arg(long)]
        svg: bool,
    },
    /// The rigid modes of the suspended tub (at rest, friction released) with each damper's
    /// stroke per mode, as markdown on stdout and in DIR/modes.md.
    Modes {
        /// A built-in model or a model file.
        model: String,
        /// A scene of the model (default: its first scene); elastic bodies are taken rigid.
        #[arg(long)]
        scene: Option<String>,
        /// Output directory (default: out/<model name>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Run variants (unbalance position, mass, speed profile) on all cores: one folder each
    /// and a comparison table DIR/sweep.csv.
    Sweep {
        /// A built-in model or a model file.
        model: String,
        /// Unbalance positions: front, middle, rear (comma-separated).
        #[arg(long, value_delimiter = ',')]
        positions: Vec<String>,
        /// Unbalance masses, kg (comma-separated).
        #[arg(long, value_delimiter = ',')]
        masses: Vec<f64>,
        /// Speed profile CSV files (time_s, rpm), comma-separated.
        #[arg(long, value_delimiter = ',')]
        profiles: Vec<PathBuf>,
        #[command(flatten)]
        sim: Sim,
        /// Output directory (default: out/<model>-sweep).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Parallel runs (default: all cores).
        #[arg(long)]
        jobs: Option<usize>,
    },
}

#[derive(Subcommand)]
enum FeCmd {
    /// Run ccx on a deck (`<job>.inp`; results beside it) and list the frequencies it found.
    Solve { deck: PathBuf },
    /// Write the built-in FE models (tub, drum, cabinet) as CalculiX decks.
    Write {
        /// Output directory.
        #[arg(long, default_value = "out/fe")]
        out: PathBuf,
    },
    /// Modal data from your own CalculiX deck: a spec (TOML: the deck and its units, the body
    /// kind and support, the points, the modes, correction loads, the drum's spin; see
    /// docs/modal-data.md) is solved like the built-in bodies and checked against the deck
    /// (ccx's mass and centre of gravity, rigid-body modes, mass normalisation); writes
    /// `<name>.modal.toml` (and `<name>.field.bin` with recovery) to `--out`.
    Deck {
        /// The spec file.
        spec: PathBuf,
        /// Where the modal data (and field) files go.
        #[arg(long, default_value = "out/fe")]
        out: PathBuf,
        /// Scratch directory for decks and ccx results.
        #[arg(long, default_value = "out/fe/work")]
        work: PathBuf,
    },
    /// Solve the built-in FE models with ccx and write their modal data
    /// (`<body>.modal.toml`) and a report; the decks and ccx's files go to `--work`.
    Modal {
        /// Where the modal data files go (the repository keeps them in models/fe).
        #[arg(long, default_value = "out/fe")]
        out: PathBuf,
        /// Scratch directory for decks and ccx results.
        #[arg(long, default_value = "out/fe/work")]
        work: PathBuf,
        /// Only these bodies (comma-separated: tub, drum, cabinet).
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
    },
    /// The full-mesh reference: the linear machine assembled from the tub's and the cabinet's
    /// meshes in CalculiX (`*STEADY STATE DYNAMICS`, drum order 1) against washdyn's Ritz model
    /// of it, every sensor channel; writes full-mesh.md and full-mesh.json.
    Reference {
        /// A built-in model or a model file.
        #[arg(long, default_value = "reference")]
        model: String,
        /// Output directory (the repository keeps the study in docs/).
        #[arg(long, default_value = "out/full-mesh")]
        out: PathBuf,
        /// Scratch directory for the deck and ccx's files.
        #[arg(long, default_value = "out/full-mesh/work")]
        work: PathBuf,
        /// ccx's mode counts (comma-separated, ascending; the last is the reference).
        #[arg(long, value_delimiter = ',', default_values_t = washdyn::full_mesh::MODES)]
        modes: Vec<usize>,
        /// Drum speeds, rpm (comma-separated).
        #[arg(long, value_delimiter = ',', default_values_t = washdyn::full_mesh::SPEEDS_RPM)]
        speeds: Vec<f64>,
        /// Skip the table of the Ritz model's convergence with its mode counts.
        #[arg(long)]
        no_convergence: bool,
    },
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
    match cli.cmd {
        Cmd::Run {
            model,
            sim:
                Sim {
                    t_end,
                    integrator,
                    tol,
                    scene,
                    sample_rate,
                    format,
                },
            out,
            step,
            energy,
            rho_inf,
            backend,
            no_plots,
            svg,
            cascades,
            max_steps,
            no_validity_stop,
            allow_large_output,
            states,
            start,
        } => {
            let args = RunArgs {
                model,
                t_end,
                out,
                integrator,
                tol,
                step,
                rho_inf,
                backend,
                scene,
                sample_rate,
                max_steps,
                format,
                keep_samples: !no_plots,
                states,
                energy,
                start,
            };
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
            // Ctrl-C stops the run between steps; the normal failure path then flushes the
            // samples and writes summary.json with status "interrupted".
            let interrupt = Arc::new(AtomicBool::new(false));
            let flag = interrupt.clone();
            if let Err(e) = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)) {
                eprintln!("warning: Ctrl-C will not write a summary: {e}");
            }
            let ctl = RunControl {
                guard: Guard {
                    stop_factor: if no_validity_stop {
                        None
                    } else {
                        Guard::default().stop_factor
                    },
                    interrupt: Some(interrupt),
                    ..Guard::default()
                },
                allow_large_output,
                analysis_band_hz: (!no_plots).then_some(ANALYSIS_BAND_HZ),
            };
            let outcome = run_command_with(&args, &ctl, &mut progress);
            bar.finish_and_clear();
            match outcome {
                Ok(o) => {
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
                    if let Some(samples) = o.samples.filter(|_| s.samples > 1 && o.error.is_none())
                    {
                        let dir = o.out_dir.join("analysis");
                        let opts = AnalysisOptions {
                            motor_ratio: o.motor_ratio.unwrap_or(11.25),
                            format,
                            svg,
                            cascades,
                            ..AnalysisOptions::default()
                        };
                        match analyse_run(samples, sample_rate, &dir, opts) {
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
                        return ExitCode::FAILURE;
                    }
                    if let Some(e) = failed_analysis {
                        eprintln!("error: analysis failed: {e}");
                        return ExitCode::FAILURE;
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Cmd::Sweep {
            model,
            positions,
            masses,
            profiles,
            sim:
                Sim {
                    t_end,
                    integrator,
                    tol,
                    scene,
                    sample_rate,
                    format,
                },
            out,
            jobs,
        } => {
            let result = (|| {
                if let Some(j) = jobs
                    && !(1..=washdyn::sweep::MAX_JOBS).contains(&j)
                {
                    return Err(format!(
                        "--jobs must be in [1, {}], got {j}",
                        washdyn::sweep::MAX_JOBS
                    ));
                }
                let (m, _) = resolve_model(&model)?;
                washdyn::commands::validate_sweep(
                    &m,
                    scene.as_deref(),
                    integrator,
                    tol,
                    t_end,
                    sample_rate,
                )?;
                let spec = washdyn::sweep::SweepSpec {
                    positions,
                    masses,
                    profiles,
                };
                let vars = washdyn::sweep::variants(&m, &spec)?;
                let cfg = washdyn::sweep::SweepRun {
                    out: out
                        .unwrap_or_else(|| PathBuf::from("out").join(format!("{}-sweep", m.name))),
                    t_end,
                    method: integrator,
                    tol,
                    scene,
                    sample_rate,
                    format,
                    jobs: jobs.unwrap_or_else(|| {
                        std::thread::available_parallelism().map_or(2, |n| n.get())
                    }),
                };
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
                let res = washdyn::sweep::run_sweep(vars, &cfg, &done)?;
                bar.finish_and_clear();
                Ok::<_, String>((cfg.out, res))
            })();
            match result {
                Ok((dir, res)) => {
                    let failed = res.iter().filter(|r| r.summary.status != "ok").count();
                    let _ = writeln!(
                        std::io::stdout(),
                        "{} variants ({failed} failed); table: {}/sweep.csv",
                        res.len(),
                        dir.display()
                    );
                    if failed > 0 {
                        ExitCode::FAILURE
                    } else {
                        ExitCode::SUCCESS
                    }
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
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
            match analyse_file(&file, &dir, &opts) {
                Ok(r) => {
                    let _ = writeln!(
                        std::io::stdout(),
                        "{r}\nplots and spectra in {}",
                        dir.display()
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Cmd::Compare {
            run_a,
            run_b,
            out,
            label_a,
            label_b,
            motor_ratio,
            svg,
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
            };
            wrote(
                washdyn::compare::compare(&args)
                    .map(|(_, files)| files)
                    .map_err(|e| e.to_string()),
            )
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
                    .map(|()| Request::Fields(Times::List(t))),
                (None, Some(r), None, None) => parse_range(&r).map(Request::Fields),
                (None, None, Some(t), None) => washdyn::fields::check_times("--revolution", &[t])
                    .map(|()| Request::Fields(Times::Revolution(t))),
                (None, None, None, Some(0)) => {
                    Err("--drum-edge: the stride must be at least 1".into())
                }
                (None, None, None, Some(stride)) => Ok(Request::DrumEdge { stride, svg }),
                _ => Err(
                    "give exactly one of --times, --range, --revolution, --drum-edge".to_string(),
                ),
            };
            match request.and_then(|r| {
                washdyn::fields::fields_command(&run, model.as_deref(), &r, &fe, out.as_deref())
            }) {
                Ok(w) => {
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
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Cmd::Accuracy {
            model,
            scene,
            t_end,
            out,
            quick,
        } => {
            if let Some(t) = t_end
                && !(t > 0.0 && t <= washdyn::validate::T_END_MAX)
            {
                eprintln!(
                    "error: --t-end must be > 0 and at most {} s, got {t}",
                    washdyn::validate::T_END_MAX
                );
                return ExitCode::from(2);
            }
            let scenes = if scene.is_empty() {
                vec!["full".to_string(), "elastic:150:152".to_string()]
            } else {
                scene
            };
            let mut windows = Vec::new();
            for sc in &scenes {
                match sc.parse::<washdyn::accuracy::Window>() {
                    Ok(mut w) => {
                        if let (true, Some(t)) = (w.t1.is_nan(), t_end) {
                            w.t1 = t;
                        }
                        windows.push(w)
                    }
                    Err(e) => {
                        eprintln!("error: --scene {e}");
                        return ExitCode::from(2);
                    }
                }
            }
            let args = washdyn::accuracy::AccuracyArgs {
                model,
                windows,
                out: out.clone(),
                quick,
            };
            let study = washdyn::accuracy::study(&args, &mut |l| println!("{l}"));
            wrote(study.and_then(|s| washdyn::accuracy::write(&s, &out)))
        }
        Cmd::Modes { model, scene, out } => {
            wrote(washdyn::modes::run(&model, scene.as_deref(), out.as_deref()).map(|f| vec![f]))
        }
        Cmd::Campbell {
            source,
            max_rpm,
            motor_ratio,
            out,
            svg,
        } => wrote(washdyn::campbell::run(
            &source,
            max_rpm,
            motor_ratio,
            &out,
            svg,
        )),
        Cmd::Fe {
            cmd: FeCmd::Write { out },
        } => match fe_write(&out) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Cmd::Fe {
            cmd: FeCmd::Deck { spec, out, work },
        } => match fe_deck(&spec, &out, &work) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Cmd::Fe {
            cmd: FeCmd::Modal { out, work, only },
        } => match fe_modal(&out, &work, &only) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Cmd::Fe {
            cmd:
                FeCmd::Reference {
                    model,
                    out,
                    work,
                    modes,
                    speeds,
                    no_convergence,
                },
        } => {
            let args = washdyn::full_mesh::Args {
                model,
                modes,
                speeds_rpm: speeds,
                spec: washdyn_fe::assembly::LinearSpec::default(),
                work,
                convergence: !no_convergence,
            };
            wrote(
                washdyn::full_mesh::study(&args, &mut |l| println!("{l}"))
                    .and_then(|s| washdyn::full_mesh::write(&s, &out)),
            )
        }
        Cmd::Fe {
            cmd: FeCmd::Solve { deck },
        } => match washdyn_fe::ccx::run(&deck) {
            Ok(run) => {
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
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Cmd::Check { model } => match resolve_model(&model).and_then(|(m, _)| check_model(&m)) {
            Ok(report) => {
                let _ = writeln!(std::io::stdout(), "{report}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("{e}");
                ExitCode::from(2)
            }
        },
    }
}

/// A command that writes files: list them, or print its error (exit code 2).
fn wrote(r: Result<Vec<PathBuf>, String>) -> ExitCode {
    match r {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `washdyn fe write`: the built-in decks (frequency decks, and the drum's prestressed one).
fn fe_write(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    for (name, text) in washdyn_fe::bodies::decks() {
        let p = out.join(name);
        std::fs::write(&p, &text).map_err(|e| format!("{}: {e}", p.display()))?;
        println!("{} ({} kB)", p.display(), text.len() / 1024);
    }
    Ok(())
}

/// `washdyn fe modal`: solve the built-in bodies and write their modal data and a report.
fn fe_modal(out: &Path, work: &Path, only: &[String]) -> Result<(), String> {
    let bodies = washdyn_fe::bodies::builtin();
    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    if let Some(bad) = only.iter().find(|o| !names.contains(&o.as_str())) {
        return Err(format!(
            "--only: no built-in body `{bad}`; the bodies are {}",
            names.join(", ")
        ));
    }
    for d in [out, work] {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let order: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    let mut sections = Vec::new();
    for b in bodies {
        if !only.is_empty() && !only.contains(&b.name) {
            continue;
        }
        let (data, r) = washdyn_fe::pipeline::build(&b, work)?;
        let p = out.join(format!("{}.modal.toml", b.name));
        let text = format!(
            "# Modal data of the {} (docs/modal-data.md), written by `washdyn fe modal`.\n{}",
            b.name,
            data.to_toml()
        );
        std::fs::write(&p, &text).map_err(|e| format!("{}: {e}", p.display()))?;
        let line = format!(
            "{r}  {} modes kept, {:.2} to {:.2} Hz; {} ({} kB)\n",
            data.modes(),
            data.frequencies[0],
            data.frequencies[data.modes() - 1],
            p.display(),
            text.len() / 1024
        );
        print!("{line}");
        sections.push((b.name.clone(), line));
    }
    // With --only, the other bodies' sections of an existing report stay.
    let p = out.join("report.txt");
    let old = std::fs::read_to_string(&p).unwrap_or_default();
    let report = washdyn::commands::merge_report(&old, &sections, &order);
    std::fs::write(&p, report).map_err(|e| format!("{}: {e}", p.display()))
}

/// `washdyn fe deck`: a user's deck and spec to checked modal data (and field).
fn fe_deck(spec: &Path, out: &Path, work: &Path) -> Result<(), String> {
    let body = washdyn_fe::user::load(spec)?;
    for d in [out, work] {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let (data, report, c) = washdyn_fe::user::build_checked(&body, work)?;
    let p = out.join(format!("{}.modal.toml", body.name));
    let text = format!(
        "# Modal data of `{}` from {} (washdyn fe deck).\n{}",
        body.name,
        spec.display(),
        data.to_toml()
    );
    std::fs::write(&p, &text).map_err(|e| format!("{}: {e}", p.display()))?;
    print!("{report}");
    println!(
        "  checked against the deck: mass {:.1e} off ccx's, CoG {:.1e} m, {} rigid-body modes, \
         normalisation {:.1e}",
        c.mass, c.cog, c.rigid_modes, c.normalisation
    );
    println!(
        "  {} modes kept, {:.2} to {:.2} Hz; wrote {}",
        data.modes(),
        data.frequencies[0],
        data.frequencies[data.modes() - 1],
        p.display()
    );
    if body.recovery {
        let field = format!("{}.field.bin", body.name);
        std::fs::copy(work.join(&field), out.join(&field))
            .map_err(|e| format!("{}: {e}", out.join(&field).display()))?;
        println!("  wrote {}", out.join(&field).display());
    }
    Ok(())
}

/// `FROM:TO:STEP` of `washdyn fields --range`.
fn parse_range(r: &str) -> Result<washdyn::fields::Times, String> {
    let v: Vec<f64> = r
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--range `{r}`: expected FROM:TO:STEP in seconds"))?;
    match v[..] {
        [a, b, dt] => Ok(washdyn::fields::Times::Range(a, b, dt)),
        _ => Err(format!("--range `{r}`: expected FROM:TO:STEP in seconds")),
    }
}
