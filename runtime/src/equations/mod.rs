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
pub mod kinematics;

use crate::elements::{FrictionDamper, Gasket, LinearDamper, Spring};
use crate::geom::{V, f};
use crate::ir::{BodyRef, Effect, EffectSet, Model, SensorKind};
use crate::scalar::Scalar;
pub use bodies::{RotorDef, TubDef, UnbalanceDef};
pub use kinematics::{Marker, MarkerDef, Wrench};

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
    pub rotors: Vec<RotorDef>,
    pub unbalances: Vec<UnbalanceDef>,
    pub springs: Vec<Spring>,
    pub dampers: Vec<LinearDamper>,
    pub friction_dampers: Vec<FrictionDamper>,
    pub gaskets: Vec<Gasket>,
    pub sensors: Vec<SensorDef>,
}

impl Equations {
    /// Resolve a checked model for a scene.
    pub fn new(model: &Model, scene: &EffectSet) -> Equations {
        let tub = TubDef::new(&model.tub);
        let p0 = tub.p0;
        let mk = |body: BodyRef, point: [f64; 3]| MarkerDef::new(body, point, p0);
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
        Equations {
            scene: scene.clone(),
            layout: Layout { n1: 6, n2: 0 },
            gravity: model.gravity,
            tub,
            rotors,
            unbalances,
            springs: model
                .springs
                .iter()
                .map(|s| Spring::new(s, mk(s.a.body, s.a.point), mk(s.b.body, s.b.point)))
                .collect(),
            dampers: model
                .dampers
                .iter()
                .map(|d| LinearDamper::new(d, mk(d.a.body, d.a.point), mk(d.b.body, d.b.point)))
                .collect(),
            friction_dampers: if scene.has(&Effect::FrictionDampers) {
                model
                    .friction_dampers
                    .iter()
                    .map(|d| {
                        FrictionDamper::new(d, mk(d.a.body, d.a.point), mk(d.b.body, d.b.point))
                    })
                    .collect()
            } else {
                Vec::new()
            },
            gaskets: model
                .gaskets
                .iter()
                .map(|g| Gasket::new(g, mk(g.a, g.point), mk(g.b, g.point), gasket_damping))
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
        }
    }

    /// Evaluate M1 (row-major n1 x n1, overwritten) and h (length n, overwritten).
    pub fn eval<T: Scalar>(&self, d: &Drive<T>, q: &[T], qd: &[T], m1: &mut [T], h: &mut [T]) {
        let n1 = self.layout.n1;
        debug_assert_eq!(m1.len(), n1 * n1);
        debug_assert_eq!(h.len(), self.layout.n());
        m1.fill(T::zero());
        h.fill(T::zero());
        let st = TubState::new(q, qd);
        let g = V::<T>::c(self.gravity);

        self.tub.add(&st, g, m1, n1, h);
        for r in &self.rotors {
            r.add(&st, d, h);
        }
        for u in &self.unbalances {
            u.add(&st, d, g, m1, n1, h);
        }

        for e in &self.springs {
            let (a, b) = (e.a.state(&st), e.b.state(&st));
            let (wa, wb) = e.wrenches(&a, &b);
            self.apply(&e.a, &st, &wa, h);
            self.apply(&e.b, &st, &wb, h);
        }
        for e in &self.dampers {
            let (a, b) = (e.a.state(&st), e.b.state(&st));
            let (wa, wb) = e.wrenches(&a, &b);
            self.apply(&e.a, &st, &wa, h);
            self.apply(&e.b, &st, &wb, h);
        }
        for e in &self.friction_dampers {
            let (a, b) = (e.a.state(&st), e.b.state(&st));
            let (wa, wb) = e.wrenches(&a, &b);
            self.apply(&e.a, &st, &wa, h);
            self.apply(&e.b, &st, &wb, h);
        }
        for e in &self.gaskets {
            let (a, b) = (e.a.state(&st), e.b.state(&st));
            let (wa, wb) = e.wrenches(&a, &b);
            self.apply(&e.a, &st, &wa, h);
            self.apply(&e.b, &st, &wb, h);
        }
    }

    /// Generalised forces of a wrench acting on a body at a marker.
    fn apply<T: Scalar>(&self, at: &MarkerDef, st: &TubState<T>, w: &Wrench<T>, h: &mut [T]) {
        match at.body {
            BodyRef::Tub => {
                // Translation: global components. Rotation: tub components (see module doc).
                w.force.add_to(h, 0);
                let s = V::<T>::c(at.s);
                let f_tub = w.force - st.alpha.cross(w.force);
                let m_tub = w.moment - st.alpha.cross(w.moment);
                (s.cross(f_tub) + m_tub).add_to(h, 3);
            }
            // Fixed until its modes arrive: it takes the reactions.
            BodyRef::Cabinet => {}
        }
    }

    /// Sensor reading from the state and its second derivative: acceleration or displacement in
    /// global components (first order in the small quantities, like the equations).
    pub fn sensor<T: Scalar>(&self, i: usize, q: &[T], qd: &[T], qdd: &[T]) -> [T; 3] {
        let s = &self.sensors[i];
        let _ = qd;
        match (s.at.body, s.kind) {
            (BodyRef::Cabinet, _) => [T::zero(); 3],
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
