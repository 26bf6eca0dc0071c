//! Markers: points fixed on a body, the interface between bodies and force elements. A force
//! element sees only the two markers' states and returns a wrench on each; the body maps the
//! wrench to generalised forces. Elastic bodies later add W q to a marker without touching
//! any element.

use super::TubState;
use crate::geom::{V, f};
use crate::ir::BodyRef;
use crate::scalar::Scalar;

/// A marker's definition: body and rest point (global), with its lever from the tub's reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkerDef {
    pub body: BodyRef,
    pub point: [f64; 3],
    /// point - p0 (used for tub markers).
    pub s: [f64; 3],
}

impl MarkerDef {
    pub fn new(body: BodyRef, point: [f64; 3], p0: [f64; 3]) -> Self {
        MarkerDef {
            body,
            point,
            s: f::sub(point, p0),
        }
    }

    /// Current kinematic state of the marker.
    pub fn state<T: Scalar>(&self, st: &TubState<T>) -> Marker<T> {
        match self.body {
            BodyRef::Tub => {
                let s = V::<T>::c(self.s);
                Marker {
                    pos: V::c(self.point) + st.u + st.alpha.cross(s),
                    vel: st.ud + st.alphad.cross(s),
                    rot: st.alpha,
                    angvel: st.alphad,
                }
            }
            BodyRef::Cabinet => Marker {
                pos: V::c(self.point),
                vel: V::zero(),
                rot: V::zero(),
                angvel: V::zero(),
            },
        }
    }
}

/// Global position and velocity of a marker, and the small rotation and angular velocity of the
/// body's material frame there.
#[derive(Clone, Copy, Debug)]
pub struct Marker<T> {
    pub pos: V<T>,
    pub vel: V<T>,
    pub rot: V<T>,
    pub angvel: V<T>,
}

/// Force and moment acting on a body at a marker, global components.
#[derive(Clone, Copy, Debug)]
pub struct Wrench<T> {
    pub force: V<T>,
    pub moment: V<T>,
}

impl<T: Scalar> Wrench<T> {
    pub fn force(force: V<T>) -> Self {
        Wrench {
            force,
            moment: V::zero(),
        }
    }
    /// The equal and opposite wrench.
    pub fn reaction(self) -> Self {
        Wrench {
            force: -self.force,
            moment: -self.moment,
        }
    }
}
