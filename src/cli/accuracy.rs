//! `washdyn accuracy`: its arguments and what it prints.

use super::{Failure, wrote};
use std::path::PathBuf;
use std::process::ExitCode;
use washdyn::Error;
use washdyn::spec::Field;

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
    /// End of the window of scenes given without one, s.
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
        let mut w = sc.parse::<washdyn::error_class::Window>()?;
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
