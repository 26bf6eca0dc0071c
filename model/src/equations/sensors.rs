//! Sensors: what a point of a body reads, displacement or acceleration in global components
//! (first order in the small quantities, like the equations). A point on the drum turns with
//! it: the tub's motion at the drum's mount carried to the turning point, plus the elastic
//! drum's own modes there, the same motion the field recovery gives its node
//! (src/fields/recovery.rs).

use super::{Bodies, BodyRef, Drive, Equations, Frame, MarkerDef, ModalRows, rotate};
use crate::geom::{V, f};
use crate::ir::SensorKind;
use crate::scalar::Scalar;

/// A sensor resolved against the model.
#[derive(Clone, Debug)]
pub struct SensorDef {
    pub name: String,
    pub kind: SensorKind,
    pub at: MarkerDef,
    /// A drum point that turns with the drum (off its axis, or where the elastic drum has a
    /// modal point); `None`: the point stays where `at` is.
    pub spin: Option<Spin>,
    pub channels: [String; 3],
}

/// A point turning with the drum: at drive angle phi it is at B + R(ratio phi) lever.
#[derive(Clone, Debug)]
pub struct Spin {
    /// The drum's mount B on the tub, and its lever from the tub's reference p0.
    pub mount: [f64; 3],
    pub mount_s: [f64; 3],
    /// The point at rest (drum angle 0) from B.
    pub lever: [f64; 3],
    pub axis: [f64; 3],
    pub ratio: f64,
    /// The tub's mode rows at B (elastic tub).
    pub tub: Option<ModalRows>,
    /// The drum's own mode rows at the point, drum frame (elastic drum).
    pub drum: Option<ModalRows>,
}

impl Spin {
    /// For a sensor at `point` on body `body`; `None` for a body that does not spin, and for a
    /// point on the axis that the elastic drum has no modal point at (it reads the mount's
    /// frame, as the sensor's marker does).
    pub fn new(bodies: &Bodies, body: BodyRef, point: [f64; 3]) -> Option<Spin> {
        let b = bodies.get(body)?;
        let Frame::Spinning {
            mount, axis, ratio, ..
        } = &b.frame
        else {
            return None;
        };
        let lever = f::sub(point, mount.point);
        let rows = b
            .modal()
            .filter(|d| crate::ir::modal::point_at(d.data(), point).is_some())
            .map(|d| d.rows(point));
        if f::norm(f::cross(lever, *axis)) <= 1e-9 && rows.is_none() {
            return None;
        }
        Some(Spin {
            mount: mount.point,
            mount_s: mount.s,
            lever,
            axis: *axis,
            ratio: *ratio,
            tub: mount.modal.clone(),
            drum: rows,
        })
    }
}

/// The floating frame's motion (rigid coordinates from `c`) of a point at lever `r` from its
/// reference (x = q or q''), with the rotation's
/// second-order terms when the scene keeps exact geometry: the dynamics are linear in alpha,
/// but a sensor reads the material point, whose centripetal part alpha' x (alpha' x r) and
/// position term alpha x (alpha x r) / 2 carry the even orders (2x the rocking frequency).
#[allow(clippy::too_many_arguments)]
fn rigid<T: Scalar>(
    c: usize,
    exact: bool,
    kind: SensorKind,
    q: &[T],
    qd: &[T],
    x: &[T],
    r: V<T>,
) -> V<T> {
    let u = V::from_slice(&x[c..c + 3]);
    let a = V::from_slice(&x[c + 3..c + 6]);
    let al = V::from_slice(&q[c + 3..c + 6]);
    let second = match kind {
        _ if !exact => V::zero(),
        SensorKind::Displacement => al.cross(al.cross(r)).scale(T::c(0.5)),
        SensorKind::Acceleration => {
            let ald = V::from_slice(&qd[c + 3..c + 6]);
            ald.cross(ald.cross(r)) + (a.cross(al.cross(r)) + al.cross(a.cross(r))).scale(T::c(0.5))
        }
    };
    u + a.cross(r) + second
}

impl Equations {
    /// Sensor `i`'s reading at drive `d` from the state and its second derivative.
    pub fn sensor<T: Scalar>(
        &self,
        i: usize,
        d: &Drive<T>,
        q: &[T],
        qd: &[T],
        qdd: &[T],
    ) -> [T; 3] {
        let s = &self.sensors[i];
        let x = if s.kind == SensorKind::Displacement {
            q
        } else {
            qdd
        };
        if let Some(sp) = &s.spin {
            return self.spinning(sp, s.kind, d, q, qd, qdd);
        }
        let elastic = s.at.modal.as_ref().map_or(V::zero(), |r| r.motion(x).0);
        match s.at.frame {
            None => elastic.0,
            // A scene that linearises its elements (no `element_geometry`) reads its sensors
            // to first order too, so its only nonlinearity stays the friction law.
            Some(c) => (rigid(c, self.exact_geometry, s.kind, q, qd, x, V::c(s.at.s)) + elastic).0,
        }
    }

    /// A point turning with the drum at lever r(t) = R(theta) lever from B, theta = ratio phi:
    /// u + alpha x (s_B + r) + (W_B + Phi_B x r) q_tub + R(theta) W_drum q_drum, and its second
    /// time derivative (r' = Omega e x r, r'' = Omega' e x r + Omega^2 e x (e x r), Omega =
    /// ratio omega). The rotation's second-order terms are those of a point fixed at r (the
    /// terms with the lever's own rate are of second order in the small motion times Omega).
    fn spinning<T: Scalar>(
        &self,
        sp: &Spin,
        kind: SensorKind,
        d: &Drive<T>,
        q: &[T],
        qd: &[T],
        qdd: &[T],
    ) -> [T; 3] {
        let (c0, _) = self.bodies.floating();
        let e = V::<T>::c(sp.axis);
        let th = d.phi * sp.ratio;
        let (c, sn) = (th.cos(), th.sin());
        let r = rotate(e, c, sn, V::c(sp.lever));
        let lever = V::<T>::c(sp.mount_s) + r;
        let drum_w = |x: &[T]| {
            sp.drum
                .as_ref()
                .map_or(V::zero(), |rows| rotate(e, c, sn, rows.motion(x).0))
        };
        let tub_rows = |x: &[T], r: V<T>| {
            sp.tub.as_ref().map_or(V::zero(), |rows| {
                let (w, p) = rows.motion(x);
                w + p.cross(r)
            })
        };
        match kind {
            SensorKind::Displacement => {
                (rigid(c0, self.exact_geometry, kind, q, qd, q, lever) + tub_rows(q, r) + drum_w(q))
                    .0
            }
            SensorKind::Acceleration => {
                let om = d.omega * sp.ratio;
                let omd = d.omega_dot * sp.ratio;
                let rd = e.cross(r).scale(om);
                let rdd = e.cross(r).scale(omd) + e.cross(e.cross(r)).scale(om * om);
                let ad = V::from_slice(&qd[c0 + 3..c0 + 6]);
                let al = V::from_slice(&q[c0 + 3..c0 + 6]);
                let mut acc = rigid(c0, self.exact_geometry, kind, q, qd, qdd, lever)
                    + ad.cross(rd).scale(T::c(2.0))
                    + al.cross(rdd);
                if let Some(rows) = &sp.tub {
                    let (_, pd) = rows.motion(qd);
                    let (_, pq) = rows.motion(q);
                    acc = acc + tub_rows(qdd, r) + pd.cross(rd).scale(T::c(2.0)) + pq.cross(rdd);
                }
                let (v, vd, va) = (drum_w(q), drum_w(qd), drum_w(qdd));
                acc = acc
                    + va
                    + e.cross(vd).scale(om * T::c(2.0))
                    + e.cross(v).scale(omd)
                    + e.cross(e.cross(v)).scale(om * om);
                acc.0
            }
        }
    }
}
