//! Standard test problems with known or published solutions, one a file. They implement
//! [`OdeSystem`](super::OdeSystem) with analytic Jacobians and are public so integration tests
//! and benchmarks can use them.

pub mod blowup;
pub mod exponential;
pub mod harmonic;
pub mod hires;
pub mod stiff_decay;
pub mod vdpol;

pub use blowup::Blowup;
pub use exponential::Exponential;
pub use harmonic::Harmonic;
pub use hires::Hires;
pub use stiff_decay::StiffDecay;
pub use vdpol::{VanDerPol, VanDerPolClassic};
