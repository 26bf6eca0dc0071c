//! The FE front end: FE model -> modal data -> IR. Writes the CalculiX decks of the elastic
//! bodies, runs `ccx`, and imports its results into the modal data the IR carries. Like the TOML
//! loader it is a front end: the CLI uses it, the step loop never does.

pub mod bodies;
pub mod ccx;
pub mod dat;
pub mod deck;
pub mod frd;
pub mod import;
pub mod lumping;
pub mod modal_file;
