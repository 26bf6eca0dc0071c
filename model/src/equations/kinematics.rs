//! Markers: points fixed on a body, the interface between bodies and force elements (Exudyn's
//! `MarkerData`). A marker carries its Jacobian over the body's coordinates: the rigid columns
//! of the floating frame it rides on (u, alpha at a lever) and the mode-shape rows of the
//! body's modes there. Force elements, sensors, rotors and unbalances see a marker's motion and
//! give it a wrench; `MarkerDef::apply` maps the wrench to generalised forces (J^T w plus the
//! linearised tilt terms). None of them asks which body the marker is on: the body layer
//! (equations/body.rs) builds the marker, and its structure is all the derivation reads.

use super::BodyState;
use crate::geom::{V, f};
use crate::ir::BodyRef;
use crate::scalar::Scalar;

/// A marker's definition: body and rest point (global), the floating frame it rides on, and
/// on an elastic body its mode-shape rows.
#[derive(Clone, Debug, PartialEq)]
pub struct MarkerDef {
    /// The body it is on: for reports and the recovery; the derivation never branches on it.
    pub body: BodyRef,
    pub point: [f64; 3],
    /// The first of the six rigid coordinates (u, alpha) of the floating frame the point rides
    /// on; `None` on a fixed frame (the cabinet on its feet, or the ground).
    pub frame: Option<usize>,
    /// point - p0, the lever from the floating frame's reference (zero on a fixed frame).
    pub s: [f64; 3],
    /// The body's modes at this point (and, on a body spinning on a mount, the parent's modes
    /// at the mount carried to the point), when the scene makes them elastic.
    pub modal: Option<ModalRows>,
}

/// Translation W and rotation Phi per unit modal coordinate at a marker; the body's modal
/// coordinates start at `start` in q. Built by `new`, which also lays the rows out as the two
/// constant tables every projection goes through (`Scalar::mat_vec`).
#[derive(Clone, Debug, PartialEq)]
pub struct ModalRows {
    pub start: usize,
    pub w: Vec<[f64; 3]>,
    pub phi: Vec<[f64; 3]>,
    /// [W; Phi] (6 x n, column-major): the point's motion from the modal coordinates.
    motion: Vec<f64>,
    /// [W^T Phi^T] (n x 6, column-major): the modal forces of a force and a moment there.
    load: Vec<f64>,
}

impl ModalRows {
    pub fn new(start: usize, w: Vec<[f64; 3]>, phi: Vec<[f64; 3]>) -> Self {
        assert_eq!(w.len(), phi.len(), "W and Phi per mode");
        let motion = w
            .iter()
            .zip(&phi)
            .flat_map(|(a, b)| a.iter().chain(b))
            .copied()
            .collect();
        let load = (0..6)
            .flat_map(|c| (0..w.len()).map(move |k| (c, k)))
            .map(|(c, k)| if c < 3 { w[k][c] } else { phi[k][c - 3] })
            .collect();
        ModalRows {
            start,
            w,
            phi,
            motion,
            load,
        }
    }

    /// Number of modes.
    pub fn n(&self) -> usize {
        self.w.len()
    }

    /// sum_k W_k x_k and sum_k Phi_k x_k over the body's slice of `x`.
    pub fn motion<T: Scalar>(&self, x: &[T]) -> (V<T>, V<T>) {
        let mut y = [T::zero(); 6];
        T::mat_vec(&self.motion, &x[self.start..self.start + self.n()], &mut y);
        (V([y[0], y[1], y[2]]), V([y[3], y[4], y[5]]))
    }

    /// h += W^T f + Phi^T m on the body's modal rows.
    pub fn add_load<T: Scalar>(&self, f: V<T>, m: V<T>, h: &mut [T]) {
        let x = [f.0[0], f.0[1], f.0[2], m.0[0], m.0[1], m.0[2]];
        T::mat_vec(&self.load, &x, &mut h[self.start..self.start + self.n()]);
    }

    /// h += W^T f on the body's modal rows.
    pub fn add_force<T: Scalar>(&self, f: V<T>, h: &mut [T]) {
        T::mat_vec(
            &self.load[..3 * self.n()],
            &f.0,
            &mut h[self.start..self.start + self.n()],
        );
    }

    /// The rows of a point rigidly attached at `r` (m, global) from this one: W + Phi x r.
    pub fn moved(&self, r: [f64; 3]) -> ModalRows {
        ModalRows::new(
            self.start,
            self.w
                .iter()
                .zip(&self.phi)
                .map(|(w, p)| f::add(*w, f::cross(*p, r)))
                .collect(),
            self.phi.clone(),
        )
    }
}

/// Velocity Jacobian of a point on a floating frame whose rigid coordinates start at `start`
/// (lever `s` from its reference, the frame's mode rows there if it is elastic): for each
/// column j of q1, the translation and the rotation per unit q_j'. Other columns stay zero.
pub fn frame_point_jacobian(
    start: usize,
    s: [f64; 3],
    rows: Option<&ModalRows>,
    n1: usize,
) -> Vec<([f64; 3], [f64; 3])> {
    let mut j = vec![([0.0; 3], [0.0; 3]); n1];
    for a in 0..3 {
        let mut e = [0.0; 3];
        e[a] = 1.0;
        j[start + a].0 = e;
        j[start + 3 + a] = (f::cross(e, s), e);
    }
    if let Some(r) = rows {
        for k in 0..r.w.len() {
            j[r.start + k] = (r.w[k], r.phi[k]);
        }
    }
    j
}

/// M1 += T^T diag(m E, J) T: a rigid part of mass `mass` and inertia `inertia` (about its CoG,
/// global axes) whose CoG moves with the velocity Jacobian `jac` (constant: folds at compile
/// time).
pub fn add_rigid_mass(
    m1: &mut [f64],
    n1: usize,
    mass: f64,
    inertia: [[f64; 3]; 3],
    jac: &[([f64; 3], [f64; 3])],
) {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for i in 0..n1 {
        for j in 0..n1 {
            let ((vi, wi), (vj, wj)) = (jac[i], jac[j]);
            let mut v = mass * dot(vi, vj);
            for a in 0..3 {
                v += wi[a] * dot(inertia[a], wj);
            }
            m1[i * n1 + j] += v;
        }
    }
}

impl MarkerDef {
    /// A point on a floating frame (rigid coordinates from `start`, reference `p0`).
    pub fn floating(body: BodyRef, point: [f64; 3], start: usize, p0: [f64; 3]) -> Self {
        MarkerDef {
            body,
            point,
            frame: Some(start),
            s: f::sub(point, p0),
            modal: None,
        }
    }

    /// A point on a fixed frame: it moves with the body's modes only.
    pub fn fixed(body: BodyRef, point: [f64; 3]) -> Self {
        MarkerDef {
            body,
            point,
            frame: None,
            s: [0.0; 3],
            modal: None,
        }
    }

    /// The marker's velocity Jacobian over q1 (constant: folds at compile time); `None` on a
    /// fixed frame, whose modes live in subsystem 2.
    pub fn jacobian(&self, n1: usize) -> Option<Vec<([f64; 3], [f64; 3])>> {
        self.frame
            .map(|c| frame_point_jacobian(c, self.s, self.modal.as_ref(), n1))
    }

    /// The frame's small rotation and its rate at state b (zero on a fixed frame).
    pub fn frame_rotation<T: Scalar>(&self, b: &BodyState<T>) -> (V<T>, V<T>) {
        match self.frame {
            Some(c) => (
                V::from_slice(&b.q[c + 3..c + 6]),
                V::from_slice(&b.qd[c + 3..c + 6]),
            ),
            None => (V::zero(), V::zero()),
        }
    }

    /// h += J^T w at this marker, with the linearised tilt terms: force `w.force` (global)
    /// whose turning with the frame is taken from `f_tilt` (the rest load when linearised,
    /// zero for loads of first order), and moment `w.moment` in the frame's components. The
    /// one way every element, unbalance, rotor and reaction reaches the generalised forces.
    pub fn apply<T: Scalar>(&self, b: &BodyState<T>, w: &Wrench<T>, f_tilt: V<T>, h: &mut [T]) {
        let wq = self.modal.as_ref().map(|r| r.motion(b.q).0);
        let alpha = self.frame_rotation(b).0;
        self.scatter(&self.load(alpha, wq, w, f_tilt), h);
    }

    /// The load of `apply` at the marker's ports, from the frame's rotation and the marker's
    /// elastic displacement `w` (W q). On a floating frame: rigid rows f and
    /// s x (f - alpha x f_tilt) + (W q) x f_tilt + m (the lever grows with the elastic
    /// displacement); modal rows W^T (f - alpha x f_tilt) + Phi^T m (the modes live in the
    /// frame). On a fixed frame: W^T f + Phi^T m.
    pub fn load<T: Scalar>(
        &self,
        alpha: V<T>,
        w: Option<V<T>>,
        wr: &Wrench<T>,
        f_tilt: V<T>,
    ) -> Load<T> {
        if self.frame.is_none() {
            return Load {
                force: V::zero(),
                moment: V::zero(),
                modal_force: wr.force,
                modal_moment: wr.moment,
            };
        }
        let f_frame = wr.force - alpha.cross(f_tilt);
        let mut m = V::<T>::c(self.s).cross(f_frame) + wr.moment;
        if let Some(w) = w {
            m = m + w.cross(f_tilt);
        }
        Load {
            force: wr.force,
            moment: m,
            modal_force: f_frame,
            modal_moment: wr.moment,
        }
    }

    /// h += the load through the marker's constant maps: the floating frame's rigid rows
    /// (force, moment), and on an elastic body W^T modal_force + Phi^T modal_moment.
    pub fn scatter<T: Scalar>(&self, l: &Load<T>, h: &mut [T]) {
        if let Some(c) = self.frame {
            l.force.add_to(h, c);
        }
        if let Some(r) = &self.modal {
            r.add_load(l.modal_force, l.modal_moment, h);
        }
        if let Some(c) = self.frame {
            l.moment.add_to(h, c + 3);
        }
    }

    /// The marker's local coordinates at state b.
    pub fn local<T: Scalar>(&self, b: &BodyState<T>) -> Local<T> {
        let mut l = match self.frame {
            Some(c) => Local {
                u: V::from_slice(&b.q[c..c + 3]),
                alpha: V::from_slice(&b.q[c + 3..c + 6]),
                ud: V::from_slice(&b.qd[c..c + 3]),
                alphad: V::from_slice(&b.qd[c + 3..c + 6]),
                w: V::zero(),
                phi: V::zero(),
                wd: V::zero(),
                phid: V::zero(),
            },
            None => Local::zero(),
        };
        if let Some(r) = &self.modal {
            (l.w, l.phi) = r.motion(b.q);
            (l.wd, l.phid) = r.motion(b.qd);
        }
        l
    }

    /// Current kinematic state of the marker.
    pub fn state<T: Scalar>(&self, b: &BodyState<T>) -> Marker<T> {
        self.state_of(&self.local(b))
    }

    /// The displacement of the point at q (first order: u + alpha x s + W q), what the
    /// validity monitor and the recovery read.
    pub fn displacement(&self, q: &[f64]) -> [f64; 3] {
        let mut d = match self.frame {
            Some(c) => {
                let (u, a, s) = (&q[c..c + 3], &q[c + 3..c + 6], self.s);
                [
                    u[0] + a[1] * s[2] - a[2] * s[1],
                    u[1] + a[2] * s[0] - a[0] * s[2],
                    u[2] + a[0] * s[1] - a[1] * s[0],
                ]
            }
            None => [0.0; 3],
        };
        if let Some(r) = &self.modal {
            d = f::add(d, r.motion(q).0.0);
        }
        d
    }

    /// The kinematic state from the local coordinates.
    pub fn state_of<T: Scalar>(&self, l: &Local<T>) -> Marker<T> {
        let mut m = match self.frame {
            Some(_) => {
                let s = V::<T>::c(self.s);
                Marker {
                    pos: V::c(self.point) + l.u + l.alpha.cross(s),
                    vel: l.ud + l.alphad.cross(s),
                    rot: l.alpha,
                    angvel: l.alphad,
                }
            }
            None => Marker {
                pos: V::c(self.point),
                vel: V::zero(),
                rot: V::zero(),
                angvel: V::zero(),
            },
        };
        // An elastic body adds W q to the position and Phi q to the rotation.
        if self.modal.is_some() {
            m.pos = m.pos + l.w;
            m.vel = m.vel + l.wd;
            m.rot = m.rot + l.phi;
            m.angvel = m.angvel + l.phid;
        }
        m
    }
}

/// A marker's local coordinates: its body's rigid motion (the tub's u and alpha; none on the
/// cabinet) and the modal motion at the point (W q, Phi q), with their rates. They are constant
/// linear maps of q and q' (the marker Jacobian), and a force element sees the state only
/// through them: an element's Jacobian over these, chained through the maps, is its Jacobian
/// over q (equations/jacobian.rs).
#[derive(Clone, Copy, Debug)]
pub struct Local<T> {
    pub u: V<T>,
    pub alpha: V<T>,
    pub w: V<T>,
    pub phi: V<T>,
    pub ud: V<T>,
    pub alphad: V<T>,
    pub wd: V<T>,
    pub phid: V<T>,
}

impl<T: Scalar> Local<T> {
    pub fn zero() -> Self {
        let z = V::zero();
        Local {
            u: z,
            alpha: z,
            w: z,
            phi: z,
            ud: z,
            alphad: z,
            wd: z,
            phid: z,
        }
    }
}

/// A load at a marker at its output ports: the tub's rigid rows (force, moment about p0) and
/// what the modes at the marker take (W^T modal_force + Phi^T modal_moment).
#[derive(Clone, Copy, Debug)]
pub struct Load<T> {
    pub force: V<T>,
    pub moment: V<T>,
    pub modal_force: V<T>,
    pub modal_moment: V<T>,
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
    pub fn moment(moment: V<T>) -> Self {
        Wrench {
            force: V::zero(),
            moment,
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
