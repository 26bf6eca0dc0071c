//! Inertia terms of subsystem 1: the rigid tub, the rotors' spin and the rotating unbalances.

use super::{Drive, TubState};
use crate::geom::{V, f};
use crate::ir::{Rotor, Tub, Unbalance};
use crate::scalar::Scalar;

/// The suspended tub assembly as a rigid body; its rest CoG p0 is the reference point.
#[derive(Clone, Debug, PartialEq)]
pub struct TubDef {
    pub mass: f64,
    pub p0: [f64; 3],
    pub inertia: [[f64; 3]; 3],
}

impl TubDef {
    pub fn new(t: &Tub) -> Self {
        TubDef {
            mass: t.mass,
            p0: t.cog,
            inertia: t.inertia,
        }
    }

    /// Constant mass block and weight. About its CoG the blocks decouple and gravity has no
    /// moment.
    pub fn add<T: Scalar>(&self, _st: &TubState<T>, g: V<T>, m1: &mut [T], n1: usize, h: &mut [T]) {
        for i in 0..3 {
            m1[i * n1 + i] += T::c(self.mass);
            for j in 0..3 {
                m1[(3 + i) * n1 + 3 + j] += T::c(self.inertia[i][j]);
            }
        }
        (g * self.mass).add_to(h, 0);
    }
}

/// A rotor's spin: polar inertia about an axis fixed in the tub, speed `ratio` x drum speed.
#[derive(Clone, Debug, PartialEq)]
pub struct RotorDef {
    pub name: String,
    pub axis: [f64; 3],
    pub axis_point: [f64; 3],
    pub ratio: f64,
    pub polar_inertia: f64,
}

impl RotorDef {
    pub fn new(r: &Rotor, _p0: [f64; 3]) -> Self {
        RotorDef {
            name: r.name.clone(),
            axis: f::unit(r.axis),
            axis_point: r.axis_point,
            ratio: r.ratio,
            polar_inertia: r.polar_inertia,
        }
    }

    /// Rate of change of the spin angular momentum Jp theta' e in tub components:
    /// Jp (theta'' e + omega x theta' e). The first term is the spin-up reaction on the tub, the
    /// second the gyroscopic moment (omega = alpha' to first order).
    pub fn add<T: Scalar>(&self, st: &TubState<T>, d: &Drive<T>, h: &mut [T]) {
        let e = V::<T>::c(self.axis);
        let jp = self.polar_inertia * self.ratio;
        let dh = e.scale(d.omega_dot * jp) + st.alphad.cross(e).scale(d.omega * jp);
        (-dh).add_to(h, 3);
    }
}

/// A point mass on a rotor. Its position in the tub frame turns with the rotor angle, so it adds
/// an angle-dependent part to M1 and centrifugal, tangential and Coriolis terms to h.
#[derive(Clone, Debug, PartialEq)]
pub struct UnbalanceDef {
    pub name: String,
    pub mass: f64,
    pub ratio: f64,
    pub axis: [f64; 3],
    /// Axis point relative to p0.
    pub c: [f64; 3],
    /// Component of (position - axis point) along the axis.
    pub rho_axial: [f64; 3],
    /// Component normal to the axis at angle 0.
    pub rho_radial: [f64; 3],
}

impl UnbalanceDef {
    pub fn new(u: &Unbalance, r: &super::RotorDef, p0: [f64; 3]) -> Self {
        let e = r.axis;
        let rho = f::sub(u.position, r.axis_point);
        let along = rho[0] * e[0] + rho[1] * e[1] + rho[2] * e[2];
        let rho_axial = [along * e[0], along * e[1], along * e[2]];
        UnbalanceDef {
            name: u.name.clone(),
            mass: u.mass,
            ratio: r.ratio,
            axis: e,
            c: f::sub(r.axis_point, p0),
            rho_axial,
            rho_radial: f::sub(rho, rho_axial),
        }
    }

    /// Position, velocity and acceleration relative to p0 in tub components, given the drive.
    pub fn motion<T: Scalar>(&self, d: &Drive<T>) -> (V<T>, V<T>, V<T>) {
        let e = V::<T>::c(self.axis);
        let th = d.phi * self.ratio;
        let (c, s) = (th.cos(), th.sin());
        let r0 = V::<T>::c(self.rho_radial);
        let radial = r0.scale(c) + e.cross(r0).scale(s);
        let pos = V::c(self.c) + V::c(self.rho_axial) + radial;
        let thd = d.omega * self.ratio;
        let thdd = d.omega_dot * self.ratio;
        let tangential = e.cross(radial);
        let vel = tangential.scale(thd);
        let acc = tangential.scale(thdd) - radial.scale(thd * thd);
        (pos, vel, acc)
    }

    #[allow(clippy::too_many_arguments)]
    pub fn add<T: Scalar>(
        &self,
        st: &TubState<T>,
        d: &Drive<T>,
        g: V<T>,
        inertia: bool,
        m1: &mut [T],
        n1: usize,
        h: &mut [T],
    ) {
        let m = self.mass;
        let (s, sd, sdd) = self.motion(d);
        let weight = g * m;
        if !inertia {
            // A prescribed rotating load, a function of time only: centrifugal, tangential and
            // weight. (Keeping the weight's tilt with the tub, alpha x W at the turning lever,
            // would be a parametric term feeding even orders.)
            (weight - sdd * m).add_to(h, 0);
            (s.cross(weight) - s.cross(sdd) * m).add_to(h, 3);
            return;
        }
        let sv = s.0;
        let ss = s.dot(s);
        for i in 0..3 {
            m1[i * n1 + i] += T::c(m);
            m1[(3 + i) * n1 + 3 + i] += ss * m;
            for j in 0..3 {
                m1[(3 + i) * n1 + 3 + j] -= sv[i] * sv[j] * m;
            }
        }
        // -m s~ in the (u, alpha) block, +m s~ in (alpha, u).
        let sk = skew(s);
        for i in 0..3 {
            for j in 0..3 {
                m1[i * n1 + 3 + j] -= sk[i][j] * m;
                m1[(3 + i) * n1 + j] += sk[i][j] * m;
            }
        }
        let cor = st.alphad.cross(sd).scale(T::c(2.0));
        // Translation (global): the centrifugal load turns with the tub (alpha x s'').
        let fu = weight - (sdd + st.alpha.cross(sdd) + cor) * m;
        fu.add_to(h, 0);
        // Rotation (tub components): gravity seen from the tilted tub.
        let mr = s.cross(weight - st.alpha.cross(weight)) - s.cross(sdd + cor) * m;
        mr.add_to(h, 3);
    }
}

/// Skew matrix s~ with s~ x = s x x.
pub fn skew<T: Scalar>(s: V<T>) -> [[T; 3]; 3] {
    let [x, y, z] = s.0;
    let o = T::zero();
    [[o, -z, y], [z, o, -x], [-y, x, o]]
}
