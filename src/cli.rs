//! `washdyn`'s command line (clap): the commands and their options, and the guard (validity
//! stop, Ctrl-C) the simulation options give.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use washdyn::commands::Backend;
use washdyn::results::Format;
use washdyn_ode::Method;
use washdyn_runtime::run::{Guard, Start};

/// The exit codes (docs/commands.md), shown by `washdyn --help`.
const EXIT_CODES: &str = "Exit codes:
  0    success
  1    a run stopped early (its output up to then is kept), or a sweep's or study's variant
       failed
  2    a setting refused before anything was written (an option or its value, a study file
       at its line, a study directory that is another study's or has tasks in Slurm's queue)
  3    a model refused: it does not load, fails the checker (also a study's variant), a scene
       cannot run, or it is neither built in nor a file
  4    a file or directory that cannot be read or written
  5    other refused data: a signal file the analysis cannot take (also after a run), runs
       that cannot be compared, FE or field input, a Slurm command that failed
  130  interrupted (Ctrl-C); summary.json says so";

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

/// Settings of a simulation, shared by `run` and `sweep`.
#[derive(clap::Args)]
pub struct Sim {
    /// End time, s (default: the end of the speed profile).
    #[arg(long)]
    pub t_end: Option<f64>,
    /// rk4 (fixed step), dopri5 (adaptive, explicit), sdirk4 (L-stable SDIRK), rodas4
    /// (L-stable Rosenbrock), galpha (generalized-alpha on the second-order equations), imex
    /// (the modal bodies' own terms implicit, the elements explicit: ARK4(3)6L[2]SA), auto
    /// (dopri5 while not stiff, rodas4 while stiff, switching both ways). Default: the scene's
    /// own (`washdyn check` lists them; the reference's `damper_mass`: galpha), else dopri5.
    #[arg(long)]
    pub integrator: Option<Method>,
    /// Relative tolerance of the adaptive integrators (absolute: 1e-3 x this, in m, m/s and
    /// rad; a modal coordinate in the metres it moves a marker by). 1e-2 or looser warns: no
    /// error class covers it. Default: the scene's own with its method, else 1e-6.
    #[arg(long)]
    pub tol: Option<f64>,
    /// Fixed step of rk4, s (default 1e-4).
    #[arg(long)]
    pub step: Option<f64>,
    /// galpha's spectral radius at infinity, in [0, 1] (default 0.8): 1 keeps the
    /// unresolved high modes undamped, 0 removes them in one step.
    #[arg(long)]
    pub rho_inf: Option<f64>,
    /// Step budget; the run stops with an error (keeping its output) when it is spent.
    #[arg(long)]
    pub max_steps: Option<u64>,
    /// A scene of the model (default: its first scene).
    #[arg(long)]
    pub scene: Option<String>,
    /// Sampling rate of the sensor file, Hz.
    #[arg(long, default_value_t = 2000.0)]
    pub sample_rate: f64,
    /// Format of the result files: parquet (columnar, compact) or csv.
    #[arg(long, default_value = "parquet")]
    pub format: Format,
    /// How the run starts: `static` (equilibrium under every load at t = 0, a rotating
    /// unbalance's centrifugal force included as if it stood still), `mean` (at rest
    /// under gravity and the mean loads at the start speed) or `periodic` (on the
    /// periodic steady state by shooting; constant speed only).
    #[arg(long, default_value = "static")]
    pub start: Start,
    /// Keep running when the tub motion exceeds 5 x the small-motion bounds (30 mm, 0.05 rad).
    #[arg(long)]
    pub no_validity_stop: bool,
    /// Write sensor output beyond the 2 GB limit.
    #[arg(long)]
    pub allow_large_output: bool,
    /// The progress guard: a run whose recent rate projects the rest of it beyond this many
    /// seconds of wall time stops (keeping its output). Raise it for a run meant to take hours.
    /// `inf` never stops.
    #[arg(long, default_value_t = Guard::default().max_projected_s)]
    pub max_projected_wall: f64,
}

impl Sim {
    /// The guard of `run` and `sweep`: the validity stop unless `--no-validity-stop`, and Ctrl-C.
    pub fn guard(&self) -> Guard {
        Guard {
            stop_factor: if self.no_validity_stop {
                None
            } else {
                Guard::default().stop_factor
            },
            interrupt: Some(interrupt_flag()),
            max_projected_s: self.max_projected_wall,
            ..Guard::default()
        }
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

#[derive(Subcommand)]
pub enum Cmd {
    /// Simulate a run-up: writes DIR/sensors.parquet and DIR/summary.json.
    Run {
        /// A built-in model (`reference`, `compact`) or a model file (.toml).
        model: String,
        #[command(flatten)]
        sim: Sim,
        /// Output directory (default: out/<model name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write the energy balance by category (DIR/energy.parquet and energy.png): the
        /// drive's work, gravity, each body's modal strain and damping, each element's stored
        /// and dissipated energy, and the kinetic energy, every 10 ms.
        #[arg(long)]
        energy: bool,
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
        /// Also write the state at every sample (drum angle, q) to DIR/states.parquet, for
        /// `washdyn fields`.
        #[arg(long)]
        states: bool,
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
        /// Compare up to this time only, s (both runs must reach it): a run that stopped early
        /// against a longer one, or a stretch of a run-up.
        #[arg(long)]
        until: Option<f64>,
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
    /// Run variants (unbalance position, mass, speed profile) on all cores with the
    /// interpreter and `run`'s simulation options: one folder each and a comparison table
    /// DIR/sweep.csv.
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
    /// Variant studies: a design over a model's parameters (a study file, TOML; README,
    /// "Variant studies"), every variant checked before any runs, run on all cores (or as a
    /// Slurm job array, `run --slurm`) into one hive-partitioned Parquet dataset; a re-run
    /// completes it.
    Study {
        #[command(subcommand)]
        cmd: StudyCmd,
    },
}

#[derive(Subcommand)]
pub enum StudyCmd {
    /// Check every variant, then run those not finished in DIR (missing or failed):
    /// DIR/variants/variant=<id>/sensors.parquet, DIR/summary/variant=<id>/summary.parquet,
    /// DIR/timing/variant=<id>/timing.parquet, with the study and its design beside them.
    Run {
        /// The study file.
        study: PathBuf,
        /// The study's directory (default: out/<study file's stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Parallel runs (default: all cores).
        #[arg(long, conflicts_with = "slurm")]
        jobs: Option<usize>,
        #[command(flatten)]
        slurm: SlurmArgs,
    },
    /// How many variants are done, failed (and why) and missing; with a study submitted to
    /// Slurm, each job's tasks as `squeue` and `scontrol` see them.
    Status {
        /// The study's directory.
        dir: PathBuf,
    },
    /// Every summary row in variant order with its wall time: DIR/summary.parquet and
    /// DIR/summary.csv.
    Collect {
        /// The study's directory.
        dir: PathBuf,
    },
    /// Internal: one array task of `study run --slurm` (DIR/slurm/job.sh runs it), the
    /// variants of chunk K as its job's chunk file lists them.
    #[command(hide = true)]
    Task {
        /// The study's directory.
        dir: PathBuf,
        /// This task's chunk (SLURM_ARRAY_TASK_ID).
        #[arg(long)]
        chunk: usize,
        /// The job's chunks.
        #[arg(long)]
        chunks: usize,
        /// The job (default: SLURM_ARRAY_JOB_ID).
        #[arg(long)]
        job: Option<String>,
        /// Parallel runs (default: SLURM_CPUS_PER_TASK, else 1).
        #[arg(long)]
        jobs: Option<usize>,
    },
}

/// `washdyn study run --slurm`'s options: the variants still to run as one Slurm job array.
#[derive(clap::Args)]
pub struct SlurmArgs {
    /// Submit to Slurm (sbatch; SLURM_CONF names the cluster) instead of running here: the
    /// variants still to run in N chunks, one array task each (DIR/slurm/job.sh), recorded in
    /// DIR/slurm/jobs.json; prints the job id.
    #[arg(long)]
    pub slurm: bool,
    /// Array tasks, N (default: one a variant still to run, at most 1000).
    #[arg(long, requires = "slurm")]
    pub tasks: Option<usize>,
    /// Tasks running at once, K (`--array=0-(N-1)%K`; default: Slurm's).
    #[arg(long, requires = "slurm")]
    pub throttle: Option<usize>,
    /// CPUs of each task (its variants run on as many threads).
    #[arg(long, requires = "slurm")]
    pub cpus_per_task: Option<usize>,
    /// Memory of each task, sbatch's --mem (`500M`, `2G`).
    #[arg(long, requires = "slurm")]
    pub mem: Option<String>,
    /// Time limit of each task, sbatch's --time (`30`, `1:00:00`, `1-00:00`).
    #[arg(long, requires = "slurm")]
    pub time: Option<String>,
    /// Partition, sbatch's --partition.
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// Wait for the array to end (polling squeue), then report as `study status` does.
    #[arg(long, requires = "slurm")]
    pub wait: bool,
}

#[derive(Subcommand)]
pub enum FeCmd {
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
        /// Take ccx's answer for the last mode count from this file (a full-mesh.ccx.json an
        /// earlier run wrote, e.g. the committed models/fe/full-mesh.ccx.json) instead of
        /// solving; refused unless it came from the deck the code writes now.
        #[arg(long)]
        ccx_results: Option<PathBuf>,
    },
}

/// `FROM:TO:STEP` of `washdyn fields --range`.
pub fn parse_range(r: &str) -> Result<washdyn::fields::Times, String> {
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
