//! Force elements, one file per kind. Each sees only the states of its two markers and returns
//! the wrench on each body (global components), so the same element serves rigid and elastic
//! bodies and both back ends.

pub mod bolted_joint;
mod contact;
mod damper_joint;
mod friction_damper;
mod gasket;
mod linear_damper;
mod spring;

pub use bolted_joint::BoltedJoint;
pub use contact::Contact;
pub use damper_joint::{Axial, DamperJoint};
pub use friction_damper::{FrictionDamper, friction_force};
pub use gasket::{Gasket, OMEGA_FLOOR, reference_speed};
pub use linear_damper::LinearDamper;
pub use spring::Spring;

use crate::equations::{Drive, Marker, MarkerDef, Wrench};
use crate::scalar::Scalar;

/// What the derivation needs of every force element.
pub trait Element {
    /// Stores energy at rest velocity (a spring, the bearings' and the gasket's stiffness).
    const ELASTIC: bool;
    /// Dissipates through its velocity terms (friction, dampers, the gasket's damping).
    const DISSIPATIVE: bool;
    /// The element's name in the model (energy balance, reports).
    fn name(&self) -> &str;
    /// The two attachment markers (a, b).
    fn markers(&self) -> (&MarkerDef, &MarkerDef);
    /// Wrenches on the bodies at a and b. `exact`: current geometry; otherwise kinematics
    /// linearised about the rest position (scene effect `element_geometry` off). `d`: the drum's
    /// motion, for elements whose law follows the excitation (the hysteretic gasket). `z`: the
    /// system's element states (an element with a state past its end reads its assembly value).
    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        exact: bool,
        d: &Drive<T>,
        z: &[T],
    ) -> (Wrench<T>, Wrench<T>);
    /// The index of the element's own state among the system's element states (a presliding
    /// friction law's deflection), if it has one.
    fn state(&self) -> Option<usize> {
        None
    }
    /// The rate of the element's state (zero for an element without one).
    fn state_rate<T: Scalar>(&self, _a: &Marker<T>, _b: &Marker<T>, _exact: bool, _z: &[T]) -> T {
        T::zero()
    }
    /// The power the element's state dissipates (a presliding slider's -k z (v - z'), never
    /// positive), for the energy balance's dissipated category.
    fn state_dissipation(
        &self,
        _a: &Marker<f64>,
        _b: &Marker<f64>,
        _exact: bool,
        _z: &[f64],
        _zd: &[f64],
    ) -> f64 {
        0.0
    }
}
