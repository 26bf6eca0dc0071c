//! Linear viscous damper along its current axis, F = c v. A variant of the friction damper for
//! linear studies (e.g. checking the unbalance response against a frequency response).

use super::Element;
use crate::equations::{Drive, Marker, MarkerDef, Wrench, rest_axis};
use crate::geom::V;
use crate::ir;
use crate::scalar::Scalar;

#[derive(Clone, Debug, PartialEq)]
pub struct LinearDamper {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub damping: f64,
    pub n0: [f64; 3],
}

impl LinearDamper {
    pub fn new(d: &ir::LinearDamper, a: MarkerDef, b: MarkerDef) -> Self {
        LinearDamper {
            name: d.name.clone(),
            n0: rest_axis(a.point, b.point),
            a,
            b,
            damping: d.damping,
        }
    }
}

impl Element for LinearDamper {
    const ELASTIC: bool = false;
    const DISSIPATIVE: bool = true;

    fn name(&self) -> &str {
        &self.name
    }

    fn markers(&self) -> (&MarkerDef, &MarkerDef) {
        (&self.a, &self.b)
    }

    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        exact: bool,
        _d: &Drive<T>,
        _z: &[T],
    ) -> (Wrench<T>, Wrench<T>) {
        let n = if exact {
            let d = b.pos - a.pos;
            d.scale(T::c(1.0) / d.norm())
        } else {
            V::c(self.n0)
        };
        let v = n.dot(b.vel - a.vel);
        let fa = n.scale(v * self.damping);
        (Wrench::force(fa), Wrench::force(-fa))
    }
}
