//! Why `washdyn fe` (solve, write, modal, deck) and the full-mesh reference (`fe reference`)
//! stop: washdyn-fe's own errors as their source, the files they write, the committed answer
//! they refuse. Here with the crate's errors so that the error enum reaches no module above it.

use super::{Error, FileError};
use std::path::PathBuf;
use washdyn_runtime::harmonic::HarmonicError;

/// `washdyn fe solve | write | modal | deck`.
#[derive(Debug, thiserror::Error)]
pub enum FeError {
    /// `--only` names no built-in body.
    #[error("--only: no built-in body `{name}`; the bodies are {}", bodies.join(", "))]
    NoBody { name: String, bodies: Vec<String> },
    /// The deck, the spec, ccx or the pipeline's checks.
    #[error(transparent)]
    Fe(Box<washdyn_fe::Error>),
    /// A file or directory that cannot be written.
    #[error(transparent)]
    Io(#[from] FileError),
}

/// `washdyn fe reference`: the full-mesh study.
#[derive(Debug, thiserror::Error)]
pub enum FullMeshError {
    /// The model cannot be resolved.
    #[error(transparent)]
    Model(Box<Error>),
    /// The linear machine lacks the study's scene (the model's message).
    #[error("{0}")]
    Scene(String),
    /// No ccx mode count asked for.
    #[error("no mode count given")]
    NoModes,
    /// A built-in body the assembly needs is missing.
    #[error("no built-in body {0}")]
    NoBody(String),
    /// washdyn's frequency-domain answer.
    #[error(transparent)]
    Harmonic(#[from] HarmonicError),
    /// The assembly or ccx's solve.
    #[error(transparent)]
    Fe(Box<washdyn_fe::Error>),
    /// A file or directory that cannot be read or written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The committed answer is no JSON of its kind.
    #[error("{}: {source}", path.display())]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    /// The study or the answer does not serialise.
    #[error("{0}")]
    Serialise(#[source] serde_json::Error),
    /// The committed answer is for another deck than the code writes now.
    #[error(
        "{}: ccx's answer is for the deck {committed}, the code writes {now} now (mesh, model \
         or deck writer changed): {}",
        path.display(),
        regenerate(*modes)
    )]
    OtherDeck {
        path: PathBuf,
        committed: String,
        now: String,
        modes: usize,
    },
    /// The committed answer is for other mode counts or speeds.
    #[error(
        "{}: {found_modes} modes at {found_rpm:?} rpm, asked for {modes} at {rpm:?}: {}",
        path.display(),
        regenerate(*modes)
    )]
    OtherSettings {
        path: PathBuf,
        found_modes: usize,
        found_rpm: Vec<f64>,
        modes: usize,
        rpm: Vec<f64>,
    },
    /// The committed answer's channels are not `speeds` x `channels` (an edited file).
    #[error(
        "{}: `channels` is not {speeds} speeds of {channels} channels: {}",
        path.display(),
        regenerate(*modes)
    )]
    Channels {
        path: PathBuf,
        speeds: usize,
        channels: usize,
        modes: usize,
    },
}

/// How to make a committed answer that fits.
fn regenerate(modes: usize) -> String {
    format!(
        "regenerate it with `washdyn fe reference --modes {modes} --no-convergence` and copy \
         its full-mesh.ccx.json there"
    )
}

impl From<Error> for FullMeshError {
    fn from(e: Error) -> FullMeshError {
        FullMeshError::Model(Box::new(e))
    }
}

/// Boxed: washdyn-fe's error is large, and `washdyn::Error` carries this one.
impl From<washdyn_fe::Error> for FeError {
    fn from(e: washdyn_fe::Error) -> FeError {
        FeError::Fe(Box::new(e))
    }
}

/// Boxed: washdyn-fe's error is large, and `washdyn::Error` carries this one.
impl From<washdyn_fe::Error> for FullMeshError {
    fn from(e: washdyn_fe::Error) -> FullMeshError {
        FullMeshError::Fe(Box::new(e))
    }
}
