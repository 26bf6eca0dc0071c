//! Markers: points fixed on a body, the interface between bodies and force elements. A force
//! element sees only the two markers' states and returns a wrench on each; the body maps the
//! wrench to generalised forces. Elastic bodies later add W q to a marker without touching
//! any element.

use super::BodyState;
use crate::geom::{V, f};
use crate::ir::BodyRef;
use crate::scalar::Scalar;

/// A marker's definition: body and rest point (global), with its lever from the tub's reference,
/// and on an elastic body its mode-shape rows.
#[derive(Clone, Debug, PartialEq)]
pub struct MarkerDef {
    pub body: BodyRef,
    pub point: [f64; 3],
    /// point - p0 (used for tub markers).
    pub s: [f64; 3],
    /// The body's modes at this point, when the scene makes the body elastic.
    pub modal: Option<ModalRows>,
}

/// Translation W and rotation Phi per unit modal coordinate at a marker; the body's modal
/// coordinates start at `start` in q.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalRows {
    pub start: usize,
    pub w: Vec<[f64; 3]>,
    pub phi: Vec<[f64; 3]>,
}

impl ModalRows {
    /// sum_k W_k x_k and sum_k Phi_k x_k over the body's slice of `x`.
    pub fn motion<T: crate::scalar::Scalar>(&self, x: &[T]) -> (V<T>, V<T>) {
        let (mut w, mut p) = (V::<T>::zero(), V::<T>::zero());
        for (k, (wk, pk)) in self.w.iter().zip(&self.phi).enumerate() {
            let xk = x[self.start + k];
            w = w + V::<T>::c(*wk).scale(xk);
            p = p + V::<T>::c(*pk).scale(xk);
        }
        (w, p)
    }
}

impl MarkerDef {
    pub fn new(body: BodyRef, point: [f64; 3], p0: [f64; 3]) -> Self {
        MarkerDef {
            body,
            point,
            s: f::sub(point, p0),
            modal: None,
        }
    }

    /// Current kinematic state of the marker.
    pub fn state<T: Scalar>(&self, b: &BodyState<T>) -> Marker<T> {
        let st = &b.tub;
        let mut m = match self.body {
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
        };
        // An elastic body adds W q to the position and Phi q to the rotation.
        if let Some(r) = &self.modal {
            let (w, p) = r.motion(b.q);
            let (wd, pd) = r.motion(b.qd);
            m.pos = m.pos + w;
            m.vel = m.vel + wd;
            m.rot = m.rot + p;
            m.angvel = m.angvel + pd;
        }
        m
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
