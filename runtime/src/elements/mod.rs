//! Force elements, one file per kind. Each sees only the states of its two markers and returns
//! the wrench on each body (global components), so the same element serves rigid and elastic
//! bodies and both back ends.

mod friction_damper;
mod gasket;
mod linear_damper;
mod spring;

pub use friction_damper::{FrictionDamper, friction_force};
pub use gasket::Gasket;
pub use linear_damper::LinearDamper;
pub use spring::Spring;
