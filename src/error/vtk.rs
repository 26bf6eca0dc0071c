//! `.vtu` and `.pvd` files (the `vtk` module) that could not be written.

use super::FileError;
use std::path::PathBuf;

/// Why a grid or a collection was not written.
#[derive(Debug, thiserror::Error)]
pub enum VtkError {
    /// The file cannot be written.
    #[error(transparent)]
    Io(#[from] FileError),
    /// Data whose length is not `components` per point (or cell).
    #[error("{}: {name} has {values} values for {count} x {components}", path.display())]
    Length {
        path: PathBuf,
        name: String,
        values: usize,
        count: usize,
        components: usize,
    },
}
