//! washdyn runtime: model IR, the one derivation of the equations of motion, the interpreter back
//! end, integrators, sensors and output.
pub mod elements;
pub mod equations;
pub mod geom;
pub mod ir;
pub mod linalg;
pub mod ode;
pub mod scalar;
pub mod speed;
pub mod system;
pub mod output;
pub mod run;
pub mod statics;
pub mod codegen;

/// Re-exported for generated code.
pub use serde_json;
