//! Why `washdyn modes` lists no rigid modes. Here with the crate's errors so that the error
//! enum reaches no module above it.

use super::Error;

#[derive(Debug, thiserror::Error)]
pub enum ModesError {
    /// The model cannot be resolved.
    #[error(transparent)]
    Model(Box<Error>),
    /// Not a scene of the model (the model's message).
    #[error("{0}")]
    Scene(String),
    /// No rest position to linearise about (the runtime's message).
    #[error("{0}")]
    Rest(String),
    /// The table cannot be written.
    #[error(transparent)]
    Io(super::ActionError),
}

impl From<Error> for ModesError {
    fn from(e: Error) -> ModesError {
        ModesError::Model(Box::new(e))
    }
}
