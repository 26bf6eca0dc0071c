//! washdyn runtime: a back end (the interpreter or generated code) in first-order form
//! (`system`), the static and periodic starts, the run driver with its guards and output, the
//! energy balance along a run, the clearance watch, the linearisation about a rest point and
//! the frequency-domain steady state. Over
//! the model (`washdyn-model`) and the integrators (`washdyn-ode`), which users name directly.
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

// The paths generated code names, and only those: the `machine!` output is compiled in a
// user's crate that may depend on washdyn-runtime and washdyn-macros only, so it reaches the
// model as `::washdyn_runtime::model::...` (plus the runtime's own modules and serde_json).
// Everything else, this crate included, names washdyn_model and washdyn_ode directly
// (tests/tidy.rs holds src/ to it).

/// serde_json, for generated code (`model()` parses the model's embedded JSON).
pub use serde_json;
/// The model, for generated code (`::washdyn_runtime::model::ir::Model`, `...::equations`, ...).
pub use washdyn_model as model;
