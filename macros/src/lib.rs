//! `machine!`: a washing machine declared in Rust, checked at compile time by the same checker
//! as the TOML files and compiled by washdyn-model's code generator.
//!
//! The shape follows serde_derive: parse -> IR -> check (collecting located errors) -> generate.
//! This crate only reads tokens and places errors; the IR, the checker and the generator live in
//! `washdyn_model` (this crate builds no integrator), so both front ends fill and check the same
//! model. The calling crate needs `washdyn-runtime` as a dependency (the generated code names
//! `::washdyn_runtime`, and the model through its facade `::washdyn_runtime::model`).
//!
//! # Syntax
//!
//! ```ignore
//! washdyn_macros::machine! {
//!     /// Doc comments before the name document the generated module.
//!     reference {
//!         gravity: [0.0, 0.0, -9.81],                       // top-level field
//!         tub { mass: 55.0, cog: [0.0, 0.0, 0.45], inertia: [[2.6, 0.0, 0.0], [0.0, 2.3, 0.0], [0.0, 0.0, 2.3]] }
//!         speed { table: [[0.0, 0.0], [5.0, 93.0]] }      // or { csv: "data/run.csv" }
//!         rotor drum { axis_point: [0.0, 0.0, 0.45], polar_inertia: 0.49 }
//!         unbalance test_mass { rotor: drum, mass: 0.6, position: [0.15, 0.0, 0.69] }
//!         spring front {
//!             a: { body: tub, point: [0.12, 0.0, 0.62] },
//!             b: { body: cabinet, point: [0.12, 0.0, 0.82] },
//!             stiffness: 4000.0,
//!             free_length: 0.1386875,
//!         }
//!         sensor tub1 { body: tub, point: [0.30, 0.0, 0.70], kind: acceleration }
//!         scene full { effects: [gyroscopic, unbalance.drum] }
//!     }
//! }
//! ```
//!
//! - The first identifier names the model and the generated module `pub mod NAME`, which holds
//!   what `washdyn_model::codegen::generate` emits (`model()`, `MODEL_JSON`, ...).
//! - Inside: `key: value` fields (`gravity`, `base`), blocks `tub`, `cabinet`, `speed`, and
//!   items `KIND NAME { .. }` with KIND one of rotor, unbalance, spring, damper,
//!   friction_damper, gasket, sensor, scene; each item is one element of the IR's list of that
//!   kind with `name` = NAME (an identifier, or a string for other names). Commas between blocks
//!   and items are optional, between fields required; trailing commas are fine.
//! - Values: numbers (float or integer literals, optional leading `-`, no suffix but `f64`),
//!   strings, bare or dotted identifiers (`tub`, `unbalance.drum`; read as strings), arrays
//!   `[..]` and objects `{ key: value, .. }`. Field names are the IR's (serde's) names.
//! - `//` comments and doc comments anywhere document the declaration; other attributes are
//!   errors.
//!
//! # Variants
//!
//! `compact { base: "data/reference.toml", spring spring_front { stiffness: 5000.0 } }` loads
//! the base model file (relative to the calling crate's `CARGO_MANIFEST_DIR`) with the TOML
//! front end, then applies the declarations: a field or block replaces the fields it gives
//! (objects merge key by key); an item whose name is a base item of that kind changes the
//! fields it gives; any other name adds a complete new item. Errors about inherited values point
//! at the `base` literal (or at the redeclared item's name).
//!
//! # Errors
//!
//! Every finding is reported at once, in source order, at the token to fix: the checker's
//! `springs[1].stiffness` at that value, an unknown field at its key, a missing field at the
//! item's name, a bad file at its string literal. Set `WASHDYN_MACRO_TIMING=1` while building to
//! print each expansion's time.
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
    let input = proc_macro2::TokenStream::from(input);
    // The first top-level identifier is the machine's name (doc comments are `#[..]`).
    let name = input.clone().into_iter().find_map(|t| match t {
        proc_macro2::TokenTree::Ident(i) => Some(i.to_string()),
        _ => None,
    });
    let out = expand::expand(input, &dir);
    if std::env::var_os("WASHDYN_MACRO_TIMING").is_some() {
        eprintln!(
            "machine! {}: expanded in {:?}",
            name.unwrap_or_default(),
            started.elapsed()
        );
    }
    out.into()
}

#[cfg(test)]
mod tests;
