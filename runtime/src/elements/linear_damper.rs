//! Linear viscous damper along its current axis, F = c v. A variant of the friction damper for
//! linear studies (e.g. checking the unbalance response against a frequency response).

use crate::equations::{Marker, MarkerDef, Wrench};
use crate::ir;
use crate::scalar::Scalar;

#[derive(Clone, Debug, PartialEq)]
pub struct LinearDamper {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub damping: f64,
}

impl LinearDamper {
    pub fn new(d: &ir::LinearDamper, a: MarkerDef, b: MarkerDef) -> Self {
        LinearDamper {
            name: d.name.clone(),
            a,
            b,
            damping: d.damping,
        }
    }

    pub fn wrenches<T: Scalar>(&self, a: &Marker<T>, b: &Marker<T>) -> (Wrench<T>, Wrench<T>) {
        let d = b.pos - a.pos;
        let l = d.norm();
        let n = d.scale(T::c(1.0) / l);
        let v = n.dot(b.vel - a.vel);
        let fa = n.scale(v * self.damping);
        (Wrench::force(fa), Wrench::force(-fa))
    }
}
