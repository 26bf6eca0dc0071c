//! The one derivation of the equations of motion, M(q, t) qdd = h(q, qd, t), written once over
//! any `Scalar` (seed paper: d'Alembert's principle, linearised about the prescribed large drum
//! rotation; small tub motions).
//!
//! State: q = [q1; q2]. q1 = tub rigid motion about its rest CoG p0: translation u (global) and
//! small rotation alpha (3 + 3), later followed by tub and drum modes; q2 = cabinet modes (none
//! while the cabinet is fixed). M is block-diagonal: M1 depends on the drum angle through the
//! unbalances (and later the rotating drum modes), M2 is constant.
//!
//! Linearisation (consistent to first order in the small quantities, keeping products of small
//! quantities with large zeroth-order ones): positions of tub points are p0 + s + u + alpha x s;
//! the translational equation is written in global components, the rotational one in tub
//! components, so an applied force F at lever s enters as s x (F - alpha x F). That term carries
//! the load stiffness of the spring preloads and of gravity, which a fixed-direction linearisation
//! would drop (design-notes: preloaded springs); it makes the stiffness symmetric at equilibrium.

mod bodies;
mod elastic;
pub mod kinematics;

use crate::elements::{Element, FrictionDamper, Gasket, LinearDamper, Spring};
use crate::geom::{V, f};
use crate::ir::{BodyRef, Effect, EffectSet, Model, SensorKind};
use crate::scalar::Scalar;
pub use bodies::{RotorDef, TubDef, UnbalanceDef};
pub use elastic::ModalBody;
pub use kinematics::{Marker, MarkerDef, ModalRows, Wrench};

/// The prescribed drum motion at time t: angle, speed, acceleration (rad, rad/s, rad/s^2).
#[derive(Clone, Copy, Debug)]
pub struct Drive<T> {
    pub phi: T,
    pub omega: T,
    pub omega_dot: T,
}

/// Sizes of the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Subsystem 1: tub rigid (6) + tub modes + drum modes.
    pub n1: usize,
    /// Subsystem 2: cabinet modes.
    pub n2: usize,
}

impl Layout {
    pub fn n(&self) -> usize {
        self.n1 + self.n2
    }
}

/// A sensor resolved against the model.
#[derive(Clone, Debug)]
pub struct SensorDef {
    pub name: String,
    pub kind: SensorKind,
    pub at: MarkerDef,
    pub channels: [String; 3],
}

/// The model, resolved for one scene into the data the derivation needs. Only the effects the
/// scene names are present: a left-out effect costs nothing in either back end.
#[derive(Clone, Debug)]
pub struct Equations {
    pub scene: EffectSet,
    pub layout: Layout,
    pub gravity: [f64; 3],
    pub tub: TubDef,
    /// Unbalances as masses, or as prescribed forces (effect `unbalance_inertia`).
    pub unbalance_inertia: bool,
    pub rotors: Vec<RotorDef>,
    pub unbalances: Vec<UnbalanceDef>,
    /// Exact element kinematics, or linearised about rest (effect `element_geometry`).
    pub exact_geometry: bool,
    pub springs: Vec<Placed<Spring>>,
    pub dampers: Vec<Placed<LinearDamper>>,
    pub friction_dampers: Vec<Placed<FrictionDamper>>,
    pub gaskets: Vec<Placed<Gasket>>,
    pub sensors: Vec<SensorDef>,
    /// The cabinet's modes (subsystem 2), when the scene makes it elastic.
    pub cabinet: Option<ModalBody>,
}

/// A force element with its force on body a at rest: the load whose tilting with the tub the
/// linearised equations keep (alpha x F_rest) when exact geometry is off.
#[derive(Clone, Debug)]
pub struct Placed<E> {
    pub e: E,
    pub rest_force_a: [f64; 3],
    pub rest_moment_a: [f64; 3],
}

impl<E: Element> Placed<E> {
    fn new(e: E, exact: bool, n: usize) -> Self {
        let z = vec![0.0; n];
        let zero = BodyState::new(&z, &z);
        let (ma, mb) = e.markers();
        let (wa, _) = e.wrenches(&ma.state(&zero), &mb.state(&zero), exact);
        Placed {
            e,
            rest_force_a: wa.force.0,
            rest_moment_a: wa.moment.0,
        }
    }
}

impl Equations {
    /// Resolve a checked model for a scene.
    pub fn new(model: &Model, scene: &EffectSet) -> Equations {
        let tub = TubDef::new(&model.tub);
        let p0 = tub.p0;
        let n1 = 6;
        let cabinet = model
            .elastic
            .iter()
            .find(|e| e.name == "cabinet" && scene.has(&Effect::Elastic(e.name.clone())))
            .map(|e| ModalBody::new(e, n1, model.gravity));
        let layout = Layout {
            n1,
            n2: cabinet.as_ref().map_or(0, |c| c.n),
        };
        let mk = |body: BodyRef, point: [f64; 3]| {
            let mut m = MarkerDef::new(body, point, p0);
            if body == BodyRef::Cabinet
                && let Some(c) = &cabinet
            {
                m.modal = Some(c.rows(point));
            }
            m
        };
        let rotors: Vec<RotorDef> = model.rotors.iter().map(|r| RotorDef::new(r, p0)).collect();
        let unbalances = model
            .unbalances
            .iter()
            .filter(|u| scene.has(&Effect::Unbalance(u.rotor.clone())))
            .map(|u| {
                let r = rotors
                    .iter()
                    .find(|r| r.name == u.rotor)
                    .expect("checked: rotor exists");
                UnbalanceDef::new(u, r, p0)
            })
            .collect();
        let rotors = if scene.has(&Effect::Gyroscopic) {
            rotors
        } else {
            Vec::new()
        };
        let gasket_damping = scene.has(&Effect::GasketDamping);
        let exact = scene.has(&Effect::ElementGeometry);
        let n = layout.n();
        let place = |e| Placed::new(e, exact, n);
        Equations {
            exact_geometry: exact,
            unbalance_inertia: scene.has(&Effect::UnbalanceInertia),
            scene: scene.clone(),
            layout,
            gravity: model.gravity,
            tub,
            rotors,
            unbalances,
            springs: model
                .springs
                .iter()
                .map(|s| Spring::new(s, mk(s.a.body, s.a.point), mk(s.b.body, s.b.point)))
                .map(place)
                .collect(),
            dampers: model
                .dampers
                .iter()
                .map(|d| LinearDamper::new(d, mk(d.a.body, d.a.point), mk(d.b.body, d.b.point)))
                .map(|e| Placed::new(e, exact, n))
                .collect(),
            friction_dampers: if scene.has(&Effect::FrictionDampers) {
                model
                    .friction_dampers
                    .iter()
                    .map(|d| {
                        FrictionDamper::new(d, mk(d.a.body, d.a.point), mk(d.b.body, d.b.point))
                    })
                    .map(|e| Placed::new(e, exact, n))
                    .collect()
            } else {
                Vec::new()
            },
            gaskets: model
                .gaskets
                .iter()
                .map(|g| Gasket::new(g, mk(g.a, g.point), mk(g.b, g.point), gasket_damping))
                .map(|e| Placed::new(e, exact, n))
                .collect(),
            sensors: model
                .sensors
                .iter()
                .map(|s| SensorDef {
                    name: s.name.clone(),
                    kind: s.kind,
                    at: mk(s.body, s.point),
                    channels: s.channels(),
                })
                .collect(),
            cabinet,
        }
    }

    /// Evaluate M1 (row-major n1 x n1, overwritten) and h (length n, overwritten).
    pub fn eval<T: Scalar>(&self, d: &Drive<T>, q: &[T], qd: &[T], m1: &mut [T], h: &mut [T]) {
        let n1 = self.layout.n1;
        debug_assert_eq!(m1.len(), n1 * n1);
        debug_assert_eq!(h.len(), self.layout.n());
        m1.fill(T::zero());
        h.fill(T::zero());
        let b = BodyState::new(q, qd);
        let st = &b.tub;
        let g = V::<T>::c(self.gravity);

        self.tub.add(st, g, m1, n1, h);
        for r in &self.rotors {
            r.add(st, d, h);
        }
        for u in &self.unbalances {
            u.add(st, d, g, self.unbalance_inertia, m1, n1, h);
        }
        if let Some(c) = &self.cabinet {
            c.add(q, qd, h);
        }
        let st = &b;

        self.elements(&self.springs, st, h);
        self.elements(&self.dampers, st, h);
        self.elements(&self.friction_dampers, st, h);
        self.elements(&self.gaskets, st, h);
    }

    fn elements<T: Scalar, E: Element>(&self, list: &[Placed<E>], st: &BodyState<T>, h: &mut [T]) {
        for p in list {
            let (ma, mb) = p.e.markers();
            let (wa, wb) =
                p.e.wrenches(&ma.state(st), &mb.state(st), self.exact_geometry);
            self.apply(ma, st, &wa, p, true, h);
            self.apply(mb, st, &wb, p, false, h);
        }
    }

    /// Generalised forces of a wrench acting on a body at a marker (`on_a`: the element's end a,
    /// whose rest load is stored; end b's is its negative).
    fn apply<T: Scalar, E>(
        &self,
        at: &MarkerDef,
        st: &BodyState<T>,
        w: &Wrench<T>,
        rest: &Placed<E>,
        on_a: bool,
        h: &mut [T],
    ) {
        match at.body {
            BodyRef::Tub => {
                // Translation: global components. Rotation: tub components (see module doc).
                w.force.add_to(h, 0);
                let s = V::<T>::c(at.s);
                // The load seen from the tilted tub: the current load, or (linearised) the rest
                // load, so the term stays linear in the state.
                let (f_tilt, m_tilt) = if self.exact_geometry {
                    (w.force, w.moment)
                } else {
                    let sign = if on_a { 1.0 } else { -1.0 };
                    (
                        V::c(rest.rest_force_a) * sign,
                        V::c(rest.rest_moment_a) * sign,
                    )
                };
                let f_tub = w.force - st.tub.alpha.cross(f_tilt);
                let m_tub = w.moment - st.tub.alpha.cross(m_tilt);
                (s.cross(f_tub) + m_tub).add_to(h, 3);
            }
            // Rigid: fixed, it takes the reactions. Elastic: W^T F + Phi^T M (the cabinet has no
            // rigid DOF, so its modal frame is the global one).
            BodyRef::Cabinet => {
                if let Some(r) = &at.modal {
                    for (k, (wk, pk)) in r.w.iter().zip(&r.phi).enumerate() {
                        let gk = w.force.dot(V::c(*wk)) + w.moment.dot(V::c(*pk));
                        h[r.start + k] += gk;
                    }
                }
            }
        }
    }

    /// Sensor reading from the state and its second derivative: acceleration or displacement in
    /// global components (first order in the small quantities, like the equations).
    pub fn sensor<T: Scalar>(&self, i: usize, q: &[T], qd: &[T], qdd: &[T]) -> [T; 3] {
        let s = &self.sensors[i];
        match (s.at.body, s.kind) {
            (BodyRef::Cabinet, kind) => match &s.at.modal {
                None => [T::zero(); 3],
                Some(r) => {
                    let x = if kind == SensorKind::Displacement {
                        q
                    } else {
                        qdd
                    };
                    r.motion(x).0.0
                }
            },
            (BodyRef::Tub, SensorKind::Displacement) => {
                let st = TubState::new(q, qd);
                (st.u + st.alpha.cross(V::c(s.at.s))).0
            }
            (BodyRef::Tub, SensorKind::Acceleration) => {
                let a = V::from_slice(&qdd[0..3]);
                let b = V::from_slice(&qdd[3..6]);
                (a + b.cross(V::c(s.at.s))).0
            }
        }
    }

    /// Total number of sensor channels (3 per sensor).
    pub fn n_channels(&self) -> usize {
        3 * self.sensors.len()
    }

    /// The tub's rest CoG, the reference point of its DOF.
    pub fn p0(&self) -> [f64; 3] {
        self.tub.p0
    }
}

/// The whole state as the markers see it: the tub's rigid coordinates unpacked, and q, q' for
/// the modal coordinates.
#[derive(Clone, Copy, Debug)]
pub struct BodyState<'a, T> {
    pub tub: TubState<T>,
    pub q: &'a [T],
    pub qd: &'a [T],
}

impl<'a, T: Scalar> BodyState<'a, T> {
    pub fn new(q: &'a [T], qd: &'a [T]) -> Self {
        BodyState {
            tub: TubState::new(q, qd),
            q,
            qd,
        }
    }
}

/// The tub's rigid coordinates, unpacked.
#[derive(Clone, Copy, Debug)]
pub struct TubState<T> {
    pub u: V<T>,
    pub alpha: V<T>,
    pub ud: V<T>,
    pub alphad: V<T>,
}

impl<T: Scalar> TubState<T> {
    pub fn new(q: &[T], qd: &[T]) -> Self {
        TubState {
            u: V::from_slice(&q[0..3]),
            alpha: V::from_slice(&q[3..6]),
            ud: V::from_slice(&qd[0..3]),
            alphad: V::from_slice(&qd[3..6]),
        }
    }
}

/// Rest direction unit vector between two points (set-up helper for elements).
pub fn rest_axis(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    f::unit(f::sub(b, a))
}
