//! Massless friction damper (seed paper, "Friction damper"): one axial DOF with friction, and a
//! rubber bearing at each end acting as a rotary spring-damper M = C dphi + D domega about the
//! two axes normal to the rod (no torsion about the rod). The bearing moments bend the massless
//! rod; its equilibrium gives the transverse end forces, so force and moment balance hold
//! exactly for the element.
//!
//! The axial law (`ir::FrictionLaw`): the paper's F = 2 Fmax / pi atan(s v), stateless, or the
//! damper as built, the slider in series with the end bushings' axial stiffness k: an
//! elasto-plastic presliding law (Dupont, Hayward, Armstrong and Altpeter, IEEE TAC 47(5),
//! 2002, without the micro-viscous term, which would bring back the dashpot) whose state is the
//! bushings' deflection z, F = k z, z' = v (1 - alpha(z, v) z / z_ss), z_ss = Fmax / k. Our
//! alpha makes alpha z / z_ss = clamp((|z| - z_ba) / (z_ss - z_ba), 0, 1) while loading (v z >
//! 0) and 0 while unloading: elastic below the breakaway deflection z_ba and on every reversal,
//! an exponential approach to Fmax over (z_ss - z_ba) of stroke above it, so every branch of
//! the hysteresis loop has a closed form (the tests hold the law to it). Rate independent; no
//! drift under small vibration (purely elastic below z_ba); stuck, a spring; sliding, Coulomb.

use super::Element;
use crate::equations::{Drive, Marker, MarkerDef, Wrench, rest_axis};
use crate::geom::V;
use crate::geom::f;
use crate::ir;
use crate::scalar::Scalar;
use std::f64::consts::PI;

/// The axial law as the element evaluates it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Axial {
    /// 2 Fmax / pi atan(slope v).
    Arctan { slope: f64 },
    /// The elasto-plastic law: bushings' stiffness (N/m), breakaway as a fraction of the sliding
    /// deflection Fmax / k; `state` is the index of z among the system's element states.
    ElastoPlastic {
        stiffness: f64,
        breakaway: f64,
        state: usize,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct FrictionDamper {
    pub name: String,
    pub a: MarkerDef,
    pub b: MarkerDef,
    pub f_max: f64,
    pub law: Axial,
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

/// The elasto-plastic law's rate z' at bushing deflection z and axial velocity v (positive:
/// extension), for sliding deflection z_ss = Fmax / k and breakaway fraction b < 1. Written with
/// `max` only, so it traces (codegen) and differentiates (dual numbers) as it evaluates; z_ss
/// is a scalar so that Fmax can be a free parameter of generated code.
pub fn ep_rate<T: Scalar>(z_ss: T, breakaway: f64, z: T, v: T) -> T {
    let s = z.max(-z);
    // alpha z / z_ss in magnitude: 0 below z_ba = b z_ss, 1 from z_ss.
    let ramp = ((s - z_ss * breakaway) / (z_ss * (1.0 - breakaway))).max(T::zero());
    let g = T::c(1.0) - (T::c(1.0) - ramp).max(T::zero());
    // sgn z where it matters (g = 0 near z = 0).
    let sgn = z / s.max(z_ss * 1e-9);
    let loading = (sgn * v).max(T::zero());
    v - g * sgn * loading
}

impl FrictionDamper {
    /// The damper on `law` (the scene's); an elasto-plastic one keeps its deflection at
    /// element state `state`.
    pub fn new(
        d: &ir::FrictionDamper,
        law: ir::FrictionLaw,
        state: usize,
        a: MarkerDef,
        b: MarkerDef,
    ) -> Self {
        let law = match law {
            ir::FrictionLaw::Arctan => Axial::Arctan { slope: d.slope },
            ir::FrictionLaw::ElastoPlastic => Axial::ElastoPlastic {
                stiffness: d.axial_stiffness.expect("checked: the law's stiffness"),
                breakaway: d.breakaway.unwrap_or(ir::DEFAULT_BREAKAWAY),
                state,
            },
        };
        FrictionDamper {
            name: d.name.clone(),
            n0: rest_axis(a.point, b.point),
            l0: f::norm(f::sub(b.point, a.point)),
            a,
            b,
            f_max: d.f_max,
            law,
            bearing_stiffness: d.bearing_stiffness,
            bearing_damping: d.bearing_damping,
        }
    }

    /// The rod's axis, a -> b: current (exact geometry) or at rest.
    fn axis<T: Scalar>(&self, a: &Marker<T>, b: &Marker<T>, exact: bool) -> V<T> {
        if exact {
            let r = b.pos - a.pos;
            r.scale(T::c(1.0) / r.dot(r).sqrt())
        } else {
            V::<T>::c(self.n0)
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

    fn state(&self) -> Option<usize> {
        match self.law {
            Axial::ElastoPlastic { state, .. } => Some(state),
            Axial::Arctan { .. } => None,
        }
    }

    fn state_rate<T: Scalar>(&self, a: &Marker<T>, b: &Marker<T>, exact: bool, z: &[T]) -> T {
        let Axial::ElastoPlastic {
            stiffness,
            breakaway,
            state,
        } = self.law
        else {
            return T::zero();
        };
        let n = self.axis(a, b, exact);
        let z_ss = T::c(self.f_max) * (1.0 / stiffness);
        let z = z.get(state).copied().unwrap_or(T::zero());
        ep_rate(z_ss, breakaway, z, n.dot(b.vel - a.vel))
    }

    fn state_dissipation(
        &self,
        a: &Marker<f64>,
        b: &Marker<f64>,
        exact: bool,
        z: &[f64],
        zd: &[f64],
    ) -> f64 {
        let Axial::ElastoPlastic {
            stiffness, state, ..
        } = self.law
        else {
            return 0.0;
        };
        let v = self.axis(a, b, exact).dot(b.vel - a.vel);
        -stiffness * z[state] * (v - zd[state])
    }

    fn wrenches<T: Scalar>(
        &self,
        a: &Marker<T>,
        b: &Marker<T>,
        exact: bool,
        _d: &Drive<T>,
        z: &[T],
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
        let f = match self.law {
            Axial::Arctan { slope } => friction_force(self.f_max, slope, n.dot(rd)),
            // A state beyond `z` (an evaluation without states): the assembly state, z = 0.
            Axial::ElastoPlastic {
                stiffness, state, ..
            } => z.get(state).map_or(T::zero(), |&z| z * stiffness),
        };
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

#[cfg(test)]
#[path = "presliding_tests.rs"]
mod tests;
