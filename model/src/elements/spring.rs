//! Linear spring: force along its current axis only, F = k (L - L0) (+ an optional quadratic
//! term about the rest length). The current axis keeps the lateral stiffness of the preload
//! (P / L, the pendulum effect of the hanging tub). Linearised: rest axis plus that same lateral
//! stiffness, so both variants share the rest-state stiffness.

use super::Element;
use crate::equations::{Drive, Marker, MarkerDef, Wrench, rest_axis};
use crate::geom::{V, f};
use crate::ir;
use crate::scalar::Scalar;

#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub stiffness: f64,
    pub quadratic_stiffness: f64,
    pub free_length: f64,
    /// Length and axis (a -> b) at rest.
    pub rest_length: f64,
    pub n0: [f64; 3],
}

impl Spring {
    pub fn new(s: &ir::Spring, a: MarkerDef, b: MarkerDef) -> Self {
        Spring {
            name: s.name.clone(),
            rest_length: f::norm(f::sub(b.point, a.point)),
            n0: rest_axis(a.point, b.point),
            a,
            b,
            stiffness: s.stiffness,
            quadratic_stiffness: s.quadratic_stiffness,
            free_length: s.free_length,
        }
    }

    fn law<T: Scalar>(&self, l: T) -> T {
        let dr = l - self.rest_length;
        (l - self.free_length) * self.stiffness + dr * dr * self.quadratic_stiffness
    }
}

impl Element for Spring {
    const ELASTIC: bool = true;
    const DISSIPATIVE: bool = false;

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
        let d = b.pos - a.pos;
        let fa: V<T> = if exact {
            // f n with n = d / l: tension pulls a towards b.
            let l = d.norm();
            d.scale(self.law(l) / l)
        } else {
            let n0 = V::<T>::c(self.n0);
            let du = d - V::c(self.b.point) + V::c(self.a.point);
            let stretch = n0.dot(du);
            let p = self.law(T::c(self.rest_length));
            let lateral = du.reject(n0).scale(p / self.rest_length);
            n0.scale(p + stretch * self.stiffness + stretch * stretch * self.quadratic_stiffness)
                + lateral
        };
        (Wrench::force(fa), Wrench::force(-fa))
    }
}
