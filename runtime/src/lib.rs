//! washdyn runtime: model IR, the one derivation of the equations of motion, the interpreter back
//! end, integrators, sensors and output.
// Index loops over matrix entries read like the formulas they implement.
#![allow(clippy::needless_range_loop)]
pub mod clearance;
pub mod codegen;
pub mod dual;
pub mod elements;
pub mod equations;
pub mod geom;
pub mod harmonic;
pub mod ir;
pub mod linalg;
pub mod ode;
pub mod output;
pub mod periodic;
pub mod run;
pub mod scalar;
pub mod speed;
pub mod statics;
pub mod symbolic;
pub mod system;

/// Re-exported for generated code.
pub use serde_json;
