//! washdyn runtime: model IR, the one derivation of the equations of motion, the interpreter back
//! end, integrators, sensors and output.
pub mod ir;
pub mod ode;
