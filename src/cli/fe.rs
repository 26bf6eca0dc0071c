//! `washdyn fe solve | write | deck | modal | reference`: their arguments and what they print.

use super::progress::{Reporter, duration};
use super::{Failure, wrote};
use clap::Subcommand;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;
use washdyn::Error;
use washdyn::commands::FeError;
use washdyn_fe::ccx::Event;

/// `washdyn fe`'s arguments: one of its commands.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub cmd: FeCmd,
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
        /// Only these bodies (comma-separated: tub, drum, cabinet, tub_bare).
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

/// On Ctrl-C (SIGTERM, SIGHUP) during `fe deck`, `modal` or `reference`, say what is kept:
/// `out_kept` (what `--out` holds by then), the decks and ccx's files so far in `work`; exit
/// 130. ccx, in the same process group, takes the terminal's Ctrl-C itself.
fn interrupted_keeps(out_kept: String, work: &std::path::Path) {
    let work = work.to_path_buf();
    let said = ctrlc::set_handler(move || {
        eprintln!(
            "interrupted: {out_kept}; the decks and ccx's files so far are in {}",
            work.display()
        );
        std::process::exit(130);
    });
    if let Err(e) = said {
        eprintln!("warning: Ctrl-C will not say what was kept: {e}");
    }
}

/// The progress of the ccx solves below a command: a line when each starts and ends, and while
/// one runs `ccx still running on <deck>, <elapsed>` (every interval when not on a terminal).
/// The observer holds it weakly: the command's end drops it.
fn ccx_progress() -> Arc<Reporter> {
    let reporter = Arc::new(Reporter::new(0));
    let weak = Arc::downgrade(&reporter);
    washdyn_fe::ccx::observe(move |e| {
        let Some(r) = weak.upgrade() else { return };
        match e {
            Event::Started { deck } => {
                r.say(&format!("ccx started on {}", deck.display()));
                let name = deck.file_stem().unwrap_or_default().to_string_lossy();
                let name = name.into_owned();
                let start = Instant::now();
                r.live(move || {
                    format!(
                        "ccx still running on {name}, {}",
                        duration(start.elapsed().as_secs_f64())
                    )
                });
            }
            Event::Finished { deck, wall_s } => {
                r.say(&format!(
                    "ccx finished on {} in {}",
                    deck.display(),
                    duration(wall_s)
                ));
                let start = Instant::now();
                r.live(move || {
                    format!(
                        "between ccx solves, {} since the last",
                        duration(start.elapsed().as_secs_f64())
                    )
                });
            }
        }
    });
    reporter
}

pub fn fe(a: Args) -> Result<ExitCode, Failure> {
    let _progress = matches!(
        a.cmd,
        FeCmd::Deck { .. } | FeCmd::Modal { .. } | FeCmd::Reference { .. }
    )
    .then(ccx_progress);
    match a.cmd {
        FeCmd::Write { out } => {
            washdyn::commands::fe_write(&out).map_err(Error::from)?;
            Ok(ExitCode::SUCCESS)
        }
        FeCmd::Deck { spec, out, work } => {
            // The modal data are written only once checked.
            interrupted_keeps("no modal data written".into(), &work);
            washdyn::commands::fe_deck(&spec, &out, &work).map_err(Error::from)?;
            Ok(ExitCode::SUCCESS)
        }
        FeCmd::Modal { out, work, only } => {
            // Each body's modal data are written as its solve ends; report.txt at the end.
            let kept = format!(
                "the bodies solved so far have their <body>.modal.toml in {} (report.txt not \
                 updated)",
                out.display()
            );
            interrupted_keeps(kept, &work);
            washdyn::commands::fe_modal(&out, &work, &only).map_err(Error::from)?;
            Ok(ExitCode::SUCCESS)
        }
        FeCmd::Reference {
            model,
            out,
            work,
            modes,
            speeds,
            no_convergence,
            ccx_results,
        } => {
            // The study's files are written at its end.
            interrupted_keeps(format!("nothing written to {}", out.display()), &work);
            let args = washdyn::full_mesh::Args {
                model,
                modes,
                speeds_rpm: speeds,
                spec: washdyn_fe::assembly::LinearSpec::default(),
                work,
                convergence: !no_convergence,
                committed: ccx_results,
            };
            let study =
                washdyn::full_mesh::study(&args, &mut |l| println!("{l}")).map_err(Error::from)?;
            Ok(wrote(
                washdyn::full_mesh::write(&study, &out).map_err(Error::from)?,
            ))
        }
        FeCmd::Solve { deck } => {
            let run = washdyn_fe::ccx::run(&deck)
                .map_err(|e| Error::from(FeError::from(washdyn_fe::Error::from(e))))?;
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
    }
}
