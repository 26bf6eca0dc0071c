//! Why `washdyn campbell` draws no diagram: its source, its speeds, the eigenvalues on the way,
//! the files it writes. Here with the crate's errors so that the error enum reaches no module
//! above it.

use super::{Error, FileError, PlotError};
use washdyn_fe::error::PipelineError;

#[derive(Debug, thiserror::Error)]
pub enum CampbellError {
    /// A modal data file that cannot be read (the reader's message names the file and field).
    #[error("{0}")]
    ModalFile(String),
    /// A modal data file the modal checker refuses.
    #[error("{file}: {}", problems.join("; "))]
    Problems { file: String, problems: Vec<String> },
    /// The model cannot be resolved.
    #[error(transparent)]
    Model(Box<Error>),
    /// A model without an elastic drum.
    #[error("model `{model}` has no elastic drum")]
    NoElasticDrum { model: String },
    /// `--max-rpm` outside (0, MAX_RPM].
    #[error(
        "--max-rpm must be in (0, {}], got {rpm}",
        washdyn_model::ir::check::MAX_RPM
    )]
    MaxRpm { rpm: f64 },
    /// The motor ratio (`what`: the option or the model's rotor) outside (0, `max`].
    #[error("{what} must be in (0, {max}], got {ratio}")]
    MotorRatio {
        what: &'static str,
        ratio: f64,
        max: f64,
    },
    /// Modal data without geometric stiffness.
    #[error("the modal data has no geometric stiffness: not a spinning body (the drum)")]
    NotSpinning,
    /// The eigenvalue iteration did not converge at `rpm`.
    #[error("at {rpm:.0} rpm: {source} (geometric_stiffness, elementary.g)")]
    Eigen {
        rpm: f64,
        #[source]
        source: PipelineError,
    },
    /// Modes that do not oscillate at `rpm` (past a divergence speed, or spurious pairs).
    #[error(
        "at {rpm:.0} rpm {oscillating} of the {modes} modes oscillate: diag(omega_0^2) + \
         Omega^2 (K_G - S_perp) is not positive definite there \
         (geometric_stiffness.per_omega2)"
    )]
    NotOscillating {
        rpm: f64,
        oscillating: usize,
        modes: usize,
    },
    /// A file or directory that cannot be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// A plot that cannot be drawn or written.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

impl From<Error> for CampbellError {
    fn from(e: Error) -> CampbellError {
        CampbellError::Model(Box::new(e))
    }
}
