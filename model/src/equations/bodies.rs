//! Inertia terms of subsystem 1: the tub's weight, the rotors' spin and the rotating
//! unbalances. The tub's constant mass blocks (rigid, or FE with its attached parts) are
//! assembled once in `Equations::new`.

use super::kinematics::{MarkerDef, ModalRows, Wrench};
use super::{BodyState, Drive};
use crate::geom::{V, f};
use crate::ir::{Rotor, Unbalance};
use crate::scalar::Scalar;

/// The tub's own weight: the rigid tub (its rest CoG p0 is the reference point), or the FE tub
/// with its CoG offset and its modes' weight sums.
#[derive(Clone, Debug, PartialEq)]
pub struct TubDef {
    pub mass: f64,
    pub p0: [f64; 3],
    /// Inertia about the CoG (the rigid tub; informational for the elastic one).
    pub inertia: [[f64; 3]; 3],
    /// CoG - p0.
    pub cog_offset: [f64; 3],
    /// The tub's modes: first index in q and sum dm W_k per mode (zero for free-free modes up to
    /// the lumping error; kept, not assumed).
    pub modal_weight: Option<(usize, Vec<[f64; 3]>)>,
}

impl TubDef {
    /// Weight: m g on the translation; the moment of the CoG offset seen from the tilted tub,
    /// (m c) x (g - alpha x g), plus the modes' shift of the weight, (C q) x g; on the modes
    /// C^T (g - alpha x g).
    pub fn add<T: Scalar>(&self, b: &BodyState<T>, g: V<T>, h: &mut [T]) {
        (g * self.mass).add_to(h, 0);
        let gt = g - b.tub.alpha.cross(g);
        let mut m = V::<T>::c(self.cog_offset).scale(T::c(self.mass)).cross(gt);
        if let Some((start, c)) = &self.modal_weight {
            let mut cq = V::<T>::zero();
            for (k, ck) in c.iter().enumerate() {
                cq = cq + V::scaled(*ck, b.q[start + k]);
                h[start + k] += gt.dot_c(*ck);
            }
            m = m + cq.cross(g);
        }
        m.add_to(h, 3);
    }
}

/// A rotor's spin: polar inertia about an axis fixed in the tub at its mount, speed `ratio` x
/// drum speed.
#[derive(Clone, Debug, PartialEq)]
pub struct RotorDef {
    pub name: String,
    pub axis: [f64; 3],
    pub axis_point: [f64; 3],
    pub ratio: f64,
    pub polar_inertia: f64,
    /// The tub point carrying the rotor (with the tub's modes there when the tub is elastic).
    pub mount: MarkerDef,
}

impl RotorDef {
    pub fn new(r: &Rotor, mount: MarkerDef) -> Self {
        RotorDef {
            name: r.name.clone(),
            axis: f::unit(r.axis),
            axis_point: r.axis_point,
            ratio: r.ratio,
            polar_inertia: r.polar_inertia,
            mount,
        }
    }

    /// Rate of change of the spin angular momentum Jp theta' e in tub components:
    /// Jp (theta'' e + beta' x theta' e), beta' the angular velocity of the mount (alpha' plus
    /// the tub's elastic rotation there). The first term is the spin-up reaction, the second
    /// the gyroscopic moment; both act on the tub at the mount.
    pub fn add<T: Scalar>(&self, b: &BodyState<T>, d: &Drive<T>, h: &mut [T]) {
        let e = V::<T>::c(self.axis);
        let jp = self.polar_inertia * self.ratio;
        let mut betad = self.mount.frame_rotation(b).1;
        if let Some(r) = &self.mount.modal {
            betad = betad + r.motion(b.qd).1;
        }
        let dh = e.scale(d.omega_dot * jp) + betad.cross(e).scale(d.omega * jp);
        let z = V::zero();
        self.mount.apply(
            b,
            &Wrench {
                force: z,
                moment: -dh,
            },
            z,
            h,
        );
    }
}

/// A point mass on a rotor. Its position turns with the rotor angle, so it adds an
/// angle-dependent part to M1 and centrifugal, tangential and Coriolis terms to h. The rotor's
/// frame rides on its mount (the tub's elastic displacement and rotation there); on the
/// elastic drum the mass also moves with the drum's modes at its point.
#[derive(Clone, Debug, PartialEq)]
pub struct UnbalanceDef {
    pub name: String,
    pub mass: f64,
    pub ratio: f64,
    pub axis: [f64; 3],
    pub mount: MarkerDef,
    /// Component of (position - mount) along the axis.
    pub rho_axial: [f64; 3],
    /// Component normal to the axis at angle 0.
    pub rho_radial: [f64; 3],
    /// The drum's modes at the mass (drum frame), when the drum is elastic.
    pub drum: Option<ModalRows>,
}

/// Rotation by angle th about the unit axis e (Rodrigues), and its transpose.
pub fn rotate<T: Scalar>(e: V<T>, c: T, s: T, v: V<T>) -> V<T> {
    v.scale(c) + e.cross(v).scale(s) + e.scale(e.dot(v) * (T::c(1.0) - c))
}

impl UnbalanceDef {
    pub fn new(u: &Unbalance, r: &RotorDef, drum: Option<ModalRows>) -> Self {
        let e = r.axis;
        let rho = f::sub(u.position, r.mount.point);
        let along = rho[0] * e[0] + rho[1] * e[1] + rho[2] * e[2];
        let rho_axial = [along * e[0], along * e[1], along * e[2]];
        UnbalanceDef {
            name: u.name.clone(),
            mass: u.mass,
            ratio: r.ratio,
            axis: e,
            mount: r.mount.clone(),
            rho_axial,
            rho_radial: f::sub(rho, rho_axial),
            drum,
        }
    }

    /// Position, velocity and acceleration relative to the mount in tub components, given the
    /// drive, and the rotor angle's cosine and sine.
    pub fn motion<T: Scalar>(&self, d: &Drive<T>) -> (V<T>, V<T>, V<T>, T, T) {
        let e = V::<T>::c(self.axis);
        let th = d.phi * self.ratio;
        let (c, s) = (th.cos(), th.sin());
        let r0 = V::<T>::c(self.rho_radial);
        let radial = r0.scale(c) + e.cross(r0).scale(s);
        let pos = V::c(self.rho_axial) + radial;
        let thd = d.omega * self.ratio;
        let thdd = d.omega_dot * self.ratio;
        let tangential = e.cross(radial);
        let vel = tangential.scale(thd);
        let acc = tangential.scale(thdd) - radial.scale(thd * thd);
        (pos, vel, acc, c, s)
    }

    /// Generalised forces (first order in the small quantities; see the module doc of
    /// `equations`) and, as a mass, the M1 update m J^T J with J the mass's velocity Jacobian.
    #[allow(clippy::too_many_arguments)]
    pub fn add<T: Scalar>(
        &self,
        b: &BodyState<T>,
        d: &Drive<T>,
        g: V<T>,
        inertia: bool,
        m1: Option<&mut [T]>,
        n1: usize,
        h: &mut [T],
    ) {
        let m = self.mass;
        let e = V::<T>::c(self.axis);
        let (y, yd, ydd, c, s) = self.motion(d);
        let rot = |v: V<T>| rotate(e, c, s, v);
        let rot_t = |v: V<T>| rotate(e, c, -s, v);
        let f0 = (g - ydd) * m;
        if !inertia {
            // A prescribed rotating load, a function of time only: centrifugal, tangential and
            // weight. (Keeping the weight's tilt with the tub, alpha x W at the turning lever,
            // would be a parametric term feeding even orders.)
            let w = Wrench {
                force: f0,
                moment: y.cross(f0),
            };
            self.mount.apply(b, &w, V::zero(), h);
            if let Some(r) = &self.drum {
                r.add_force(rot_t(f0), h);
            }
            return;
        }
        let (alpha, alphad) = self.mount.frame_rotation(b);
        let (mut beta, mut betad) = (alpha, alphad);
        let mut theta = V::zero();
        if let Some(r) = &self.mount.modal {
            theta = r.motion(b.q).1;
            beta = beta + theta;
            betad = betad + r.motion(b.qd).1;
        }
        let (mut rw, mut rwd) = (V::zero(), V::zero());
        if let Some(r) = &self.drum {
            rw = rot(r.motion(b.q).0);
            rwd = rot(r.motion(b.qd).0);
        }
        let om = d.omega * self.ratio;
        let omd = d.omega_dot * self.ratio;
        // Acceleration beyond y'' and the M1 terms: the centrifugal field tilting with the
        // frame, the frame's Coriolis, and the elastic displacement turning with the rotor.
        let extra = beta.cross(ydd)
            + betad.cross(yd).scale(T::c(2.0))
            + e.cross(rw).scale(omd)
            + e.cross(e.cross(rw)).scale(om * om)
            + e.cross(rwd).scale(om * T::c(2.0));
        let force = f0 - extra * m;
        let f_t = force - alpha.cross(f0);
        let m_b = y.cross(f_t) + (theta.cross(y) + rw).cross(f0);
        self.mount.apply(b, &Wrench { force, moment: m_b }, f0, h);
        if let Some(r) = &self.drum {
            r.add_force(rot_t(force - beta.cross(f0)), h);
        }
        let Some(m1) = m1 else { return };
        // M1 += m J^T J over the columns that move the mass: u, alpha, the tub's modes at the
        // mount (with the lever y) and the drum's modes at the mass (turned by the rotor).
        // Columns are recomputed per pair instead of collected: the interpreter must not
        // allocate, and the tracer shares the repeated subexpressions anyway.
        let rho = V::<T>::c(self.mount.s) + y;
        let nt = self.mount.modal.as_ref().map_or(0, |r| r.w.len());
        let nd = self.drum.as_ref().map_or(0, |r| r.w.len());
        let col = |x: usize| -> (usize, V<T>) {
            if x < 6 {
                let mut ea = [0.0; 3];
                ea[x % 3] = 1.0;
                if x < 3 {
                    (x, V::c(ea))
                } else {
                    (x, V::<T>::c(ea).cross(rho))
                }
            } else if x < 6 + nt {
                let r = self.mount.modal.as_ref().expect("nt > 0");
                let k = x - 6;
                (
                    r.start + k,
                    V::<T>::c(r.w[k]) + V::<T>::c(r.phi[k]).cross(y),
                )
            } else {
                let r = self.drum.as_ref().expect("nd > 0");
                let k = x - 6 - nt;
                (r.start + k, rot(V::c(r.w[k])))
            }
        };
        let count = 6 + nt + nd;
        for x in 0..count {
            let (i, vi) = col(x);
            for z in x..count {
                let (j, vj) = col(z);
                let v = vi.dot(vj) * m;
                m1[i * n1 + j] += v;
                if i != j {
                    m1[j * n1 + i] += v;
                }
            }
        }
    }
}
