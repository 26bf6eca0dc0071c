//! `washdyn accuracy`: its arguments, what it prints, its progress (each run's) and what
//! Ctrl-C keeps.

use super::progress::RunLine;
use super::{Failure, wrote};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::{Mutex, PoisonError};
use washdyn_runtime::run::Progress;

/// `washdyn accuracy`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A built-in model or a model file.
    #[arg(long, default_value = "reference")]
    pub model: String,
    /// Scenes and windows: NAME (the whole speed profile) or NAME:T0:T1, repeatable
    /// [default: full and elastic:150:152].
    #[arg(long)]
    pub scene: Vec<String>,
    /// End of the window of scenes given without one, s (checked by the run specification's
    /// rule, as `run`'s).
    #[arg(long)]
    pub t_end: Option<f64>,
    /// Output directory (the repository keeps the study in docs/).
    #[arg(long, default_value = "out/accuracy")]
    pub out: PathBuf,
    /// Two settings a method and looser references: a first look in seconds.
    #[arg(long)]
    pub quick: bool,
}

pub fn accuracy(a: Args) -> Result<ExitCode, Failure> {
    let Args {
        model,
        scene,
        t_end,
        out,
        quick,
    } = a;
    let scenes = if scene.is_empty() {
        vec!["full".to_string(), "elastic:150:152".to_string()]
    } else {
        scene
    };
    let mut windows = Vec::new();
    for sc in &scenes {
        windows.push(sc.parse::<washdyn::error_class::Window>()?);
    }
    let args = washdyn::accuracy::AccuracyArgs {
        model,
        windows,
        t_end,
        out: out.clone(),
        quick,
    };
    let written = out.display().to_string();
    super::progress::on_interrupt(move || {
        format!(
            "nothing written to {written} (accuracy.md and accuracy.json come at the end); the \
             runs finished so far are the lines on stdout"
        )
    });
    let reporter = super::progress::Reporter::new(0);
    let current = Mutex::new((String::new(), RunLine::default()));
    let progress = |label: &str, p: Progress| {
        let mut c = current.lock().unwrap_or_else(PoisonError::into_inner);
        if c.0 != label {
            *c = (label.to_string(), RunLine::default());
        }
        let line = c.1.line(&p, reporter.elapsed_s());
        reporter.set(None, format!("{label}: {line}"));
    };
    let study = washdyn::accuracy::study(&args, &mut |l| println!("{l}"), &progress)?;
    drop(reporter);
    Ok(wrote(washdyn::accuracy::write(&study, &out)?))
}
