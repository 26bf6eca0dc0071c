//! washdyn's model: the IR (`ir`: structures, checker, TOML loader, modal data), the one
//! derivation of the equations of motion (`equations`, `elements`), and the code generator the
//! `machine!` macro runs at compile time (`symbolic`, `codegen`). Nothing here integrates: the
//! macro builds this crate, not the integrators (`washdyn-ode`) or the run driver
//! (`washdyn-runtime`).
// Index loops over matrix entries read like the formulas they implement.
#![allow(clippy::needless_range_loop)]
pub mod codegen;
pub mod dual;
pub mod elements;
pub mod equations;
pub mod geom;
pub mod ir;
pub mod linalg;
pub mod scalar;
pub mod speed;
pub mod symbolic;
