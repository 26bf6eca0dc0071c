//! Linear spring: force along its current axis only, F = k (L - L0). Using the current axis keeps
//! the lateral stiffness of the preload (P / L, the pendulum effect of the hanging tub).

use crate::equations::{Marker, MarkerDef, Wrench};
use crate::geom::V;
use crate::ir;
use crate::scalar::Scalar;

#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub stiffness: f64,
    pub free_length: f64,
}

impl Spring {
    pub fn new(s: &ir::Spring, a: MarkerDef, b: MarkerDef) -> Self {
        Spring {
            name: s.name.clone(),
            a,
            b,
            stiffness: s.stiffness,
            free_length: s.free_length,
        }
    }

    /// Wrenches on the bodies at a and b.
    pub fn wrenches<T: Scalar>(&self, a: &Marker<T>, b: &Marker<T>) -> (Wrench<T>, Wrench<T>) {
        let d = b.pos - a.pos;
        let l = d.norm();
        // f n with n = d / l: tension pulls a towards b.
        let f_over_l = (l - self.free_length) * self.stiffness / l;
        let fa: V<T> = d.scale(f_over_l);
        (Wrench::force(fa), Wrench::force(-fa))
    }
}
