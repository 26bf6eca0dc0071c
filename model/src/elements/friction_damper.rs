//! Massless friction damper (seed paper, "Friction damper"): one axial DOF with arctan-regularised
//! Coulomb friction F = 2 Fmax / pi atan(s v), and a rubber bearing at each end acting as a rotary
//! spring-damper M = C dphi + D domega about the two axes normal to the rod (no torsion about
//! the rod). The bearing moments bend the massless rod; its equilibrium gives the transverse end
//! forces, so force and moment balance hold exactly for the element.

use super::Element;
use crate::equations::{Drive, Marker, MarkerDef, Wrench, rest_axis};
use crate::geom::V;
use crate::geom::f;
use crate::ir;
use crate::scalar::Scalar;
use std::f64::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct FrictionDamper {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub f_max: f64,
    pub slope: f64,
    pub bearing_stiffness: f64,
    pub bearing_damping: f64,
    /// Rod direction and length at rest, a -> b.
    pub n0: [f64; 3],
    pub l0: f64,
}

/// The friction law alone: force opposing a relative velocity v (positive: extension).
pub fn friction_force<T: Scalar>(f_max: f64, slope: f64, v: T) -> T {
    // f_max as a scalar of its own, so that it can be a free parameter of generated code
    // (folded, the two constants are one literal).
    (v * slope).atan() * (T::c(f_max) * (2.0 / PI))
}

impl FrictionDamper {
    pub fn new(d: &ir::FrictionDamper, a: MarkerDef, b: MarkerDef) -> Self {
        FrictionDamper {
            name: d.name.clone(),
            n0: rest_axis(a.point, b.point),
            l0: f::norm(f::sub(b.point, a.point)),
            a,
            b,
            f_max: d.f_max,
            slope: d.slope,
            bearing_stiffness: d.bearing_stiffness,
            bearing_damping: d.bearing_damping,
        }
    }
}

impl Element for FrictionDamper {
    const ELASTIC: bool = true;
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
    ) -> (Wrench<T>, Wrench<T>) {
        let rd = b.vel - a.vel;
        // Linearised: rod axis, length and lever fixed at rest; only the friction law bends.
        let (r, l2, n) = if exact {
            let r = b.pos - a.pos;
            let l2 = r.dot(r);
            (r, l2, r.scale(T::c(1.0) / l2.sqrt()))
        } else {
            let n0 = V::<T>::c(self.n0);
            (n0.scale(T::c(self.l0)), T::c(self.l0 * self.l0), n0)
        };
        // Axial friction: resists extension, pulling a towards b.
        let f = friction_force(self.f_max, self.slope, n.dot(rd));
        // Rod rotation from rest (small angle) and its angular velocity normal to the rod.
        let tilt = if exact {
            V::<T>::c(self.n0).cross(n)
        } else {
            let du = b.pos - a.pos - V::c(self.b.point) + V::c(self.a.point);
            V::<T>::c(self.n0).cross(du).scale(T::c(1.0 / self.l0))
        };
        let w_rod = r.cross(rd).scale(T::c(1.0) / l2);
        let bearing = |m: &Marker<T>| {
            let dphi = (tilt - m.rot).reject(n);
            let dw = (w_rod - m.angvel).reject(n);
            dphi * self.bearing_stiffness + dw * self.bearing_damping
        };
        // Moment each bearing exerts on its body (the rod feels the opposite).
        let ma = bearing(a);
        let mb = bearing(b);
        // Massless rod: r x F_b = M_a + M_b fixes the transverse force at b on the rod.
        let ft = (ma + mb).cross(r).scale(T::c(1.0) / l2);
        let wa = Wrench {
            force: n.scale(f) + ft,
            moment: ma,
        };
        let wb = Wrench {
            force: -(n.scale(f) + ft),
            moment: mb,
        };
        (wa, wb)
    }
}
