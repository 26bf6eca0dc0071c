//! washdyn runtime: a back end (the interpreter or generated code) in first-order form
//! (`system`), the static and periodic starts, the run driver with its guards and output, the
//! energy balance along a run, the clearance watch, the linearisation about a rest point and
//! the frequency-domain steady state. The model (`washdyn-model`) and the integrators
//! (`washdyn-ode`) are re-exported under their old paths, which generated code and users name.
// Index loops over matrix entries read like the formulas they implement.
#![allow(clippy::needless_range_loop)]
pub mod clearance;
pub mod energy;
pub mod harmonic;
pub mod linearise;
pub mod mass;
pub mod output;
pub mod periodic;
pub mod run;
pub mod statics;
pub mod system;

pub use washdyn_model::{
    codegen, dual, elements, equations, geom, ir, linalg, scalar, speed, symbolic,
};
pub use washdyn_ode as ode;

/// Re-exported for generated code.
pub use serde_json;
