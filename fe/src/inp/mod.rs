//! Reading a user's CalculiX (Abaqus-format) input deck into a [`Mesh`]: nodes, elements,
//! node and element sets, materials, sections, point masses, ground springs, rigid bodies and
//! the boundary. The model part only: the deck's own steps are skipped (the pipeline writes
//! the analyses it needs). Units: SI, or mm-t-s as CalculiX users often write them, converted
//! to SI on reading. What the pipeline cannot integrate (other element types, orthotropic
//! materials, constraints) is refused with the file and line, never dropped.
//!
//! The syntax (cards, `*INCLUDE`, numbers and sets) is in `cards.rs`, the unit systems in
//! `units.rs`, the errors in `error.rs`; `keywords.rs` gives the cards their meaning, this
//! file the order of the passes.

mod cards;
mod error;
mod keywords;
mod units;

pub use error::{InpError, InpProblem};
pub use units::{Units, in_units};

use crate::mesh::Mesh;
use cards::cards;
use keywords::Reader;
use std::path::Path;

/// Node sets the deck writer (`Mesh::model_deck`) writes itself: not read into the mesh.
const RESERVED: [&str; 2] = ["NALL", "WD_PRINT"];

/// Keywords of analysis set-up the model part may hold and the pipeline replaces: skipped.
const SKIPPED: [&str; 3] = ["*HEADING", "*AMPLITUDE", "*PHYSICAL CONSTANTS"];

/// Read a deck (and its includes) in `units` into a [`Mesh`] in SI. Node ids are renumbered
/// 1..n in the order the deck defines them (the pipeline's meshes number densely).
pub fn read(path: &Path, units: Units) -> Result<Mesh, InpError> {
    let mut all = Vec::new();
    cards(path, &mut all, 0)?;
    let mut r = Reader::new(&all, units, path);
    r.model_cards()?;
    r.sections()?;
    r.node_sets()?;
    r.rigid_bodies()?;
    r.boundaries()?;
    if r.mesh.parts.is_empty() {
        return Err(InpError {
            file: path.to_path_buf(),
            line: 0,
            problem: InpProblem::NoParts,
        });
    }
    Ok(r.mesh)
}

#[cfg(test)]
mod tests;
