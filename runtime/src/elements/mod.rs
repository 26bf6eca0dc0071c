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

use crate::equations::{Marker, MarkerDef, Wrench};
use crate::scalar::Scalar;

/// What the derivation needs of every force element.
pub trait Element {
    /// The two attachment markers (a, b).
    fn markers(&self) -> (&MarkerDef, &MarkerDef);
    /// Wrenches on the bodies at a and b. `exact`: current geometry; otherwise kinematics
    /// linearised about the rest position (scene effect `element_geometry` off).
    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        exact: bool,
    ) -> (Wrench<T>, Wrench<T>);
}
