//! The FE front end: FE model -> modal data -> IR. Writes CalculiX decks, runs `ccx` and reads
//! its results. Like the TOML loader it is a front end: the CLI uses it, the step loop never
//! does. So far: the deck writer, the ccx runner with its error detection, and the closed-form
//! check decks; the machine's bodies and the modal-data import are to come (issue 8).

// Index loops read as the formulas they implement (sums over axes and modes).
#![allow(clippy::needless_range_loop)]

pub mod assembly;
pub mod bodies;
pub mod ccx;
pub mod consistent;
pub mod correction;
pub mod curves;
pub mod dat;
pub mod deck;
pub mod error;
pub mod field;
pub mod frd;
pub mod inp;
pub mod lumping;
pub mod mesh;
pub mod modal;
pub mod pipeline;
pub mod prestress;
pub mod rotating;
pub mod stress;
pub mod subspace;
pub mod user;

pub use error::Error;
