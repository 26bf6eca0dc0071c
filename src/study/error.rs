//! What a study refuses: the types live with the crate's errors (`crate::error::study`), so
//! the error enum reaches no module above it.

pub use crate::error::study::{BadVariant, StudyError};
