//! `machine!`: a washing machine declared in Rust, checked at compile time by the same checker
//! as the TOML files and compiled by washdyn-runtime's code generator.
//!
//! The shape follows serde_derive: parse -> IR -> check (collecting located errors) -> generate.
//! This crate only reads tokens and places errors; the IR, the checker and the generator live in
//! `washdyn_runtime`, so both front ends fill and check the same model.
//!
//! ```ignore
//! washdyn_macros::machine! {
//!     reference {
//!         gravity: [0.0, 0.0, -9.81],
//!         tub { mass: 55.0, cog: [0.0, 0.0, 0.45], inertia: [[2.6, 0.0, 0.0], [0.0, 2.3, 0.0], [0.0, 0.0, 2.3]] }
//!         rotor drum { axis_point: [0.0, 0.0, 0.45], polar_inertia: 0.49 }
//!         speed { table: [[0.0, 0.0], [5.0, 93.0]] }
//!         spring front { a: { body: tub, point: [0.12, 0.0, 0.62] }, b: { body: cabinet, point: [0.12, 0.0, 0.82] }, stiffness: 4000.0, free_length: 0.1386875 }
//!         scene full { effects: [gyroscopic, unbalance.drum] }
//!     }
//! }
//! // A variant: a base model file (relative to CARGO_MANIFEST_DIR) with changes.
//! washdyn_macros::machine! {
//!     stiffer { base: "data/reference.toml", spring front { stiffness: 5000.0 } }
//! }
//! ```
mod expand;
mod loc;
mod suggest;
mod syntax;
mod tree;

use proc_macro::TokenStream;
use std::path::PathBuf;

/// Declare a machine; expands to `pub mod NAME { pub fn model() -> Model; .. }`.
///
/// Set `WASHDYN_MACRO_TIMING=1` while building to print how long each expansion took.
#[proc_macro]
pub fn machine(input: TokenStream) -> TokenStream {
    let started = std::time::Instant::now();
    let dir = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_default();
    let out = expand::expand(input.into(), &dir);
    if std::env::var_os("WASHDYN_MACRO_TIMING").is_some() {
        eprintln!("machine!: expanded in {:?}", started.elapsed());
    }
    out.into()
}

#[cfg(test)]
mod tests;
