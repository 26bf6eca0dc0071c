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
pub mod body;
mod drum;
mod elastic;
mod energy;
mod jacobian;
pub mod kinematics;
mod part;
mod ports;
mod scales;
mod sensors;
mod states;

use crate::elements::{
    BoltedJoint, Contact, DamperJoint, Element, FrictionDamper, Gasket, LinearDamper, Spring,
};
use crate::geom::{V, f};
use crate::ir::{BodyRef, Effect, EffectSet, Model};
use crate::scalar::Scalar;
pub use bodies::{RotorDef, TubDef, UnbalanceDef, rotate};
pub use body::{Bodies, Body, Frame, Modes};
pub use drum::ElasticDrum;
pub use elastic::{CurveTerms, ModalBody, modal_damping};
pub use energy::{Category, EnergyWork, Kind};
pub use jacobian::{ForceJacobians, JacobianWork};
pub use kinematics::{
    Load, Local, Marker, MarkerDef, ModalRows, Wrench, add_rigid_mass, frame_point_jacobian,
};
pub use part::RigidPart;
pub use sensors::{SensorDef, Spin};

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
    /// First-order element states after q and q' (a presliding friction law's deflection).
    pub nz: usize,
}

impl Layout {
    /// The mechanical coordinates q (n1 + n2).
    pub fn n(&self) -> usize {
        self.n1 + self.n2
    }
    /// The first-order state's length: [q; q'; z].
    pub fn dim(&self) -> usize {
        2 * self.n() + self.nz
    }
}

/// The model, resolved for one scene into the data the derivation needs. Only the effects the
/// scene names are present: a left-out effect costs nothing in either back end.
#[derive(Clone, Debug)]
pub struct Equations {
    pub scene: EffectSet,
    pub layout: Layout,
    pub gravity: [f64; 3],
    /// The tub's weight (rigid, or the FE tub's with its modes).
    pub tub: TubDef,
    /// The constant part of M1 (row-major n1 x n1): the tub (rigid, or FE with the parts it
    /// carries: drum and rotors at their mounts) and the modal blocks.
    pub m1_const: Vec<f64>,
    /// The bodies: kinds, coordinates, modes, own terms and markers.
    pub bodies: Bodies,
    /// Rigid parts riding on the elastic tub (drum, rotors): their weight at their CoG.
    pub carried: Vec<(MarkerDef, f64)>,
    /// Unbalances as masses, or as prescribed forces (effect `unbalance_inertia`).
    pub unbalance_inertia: bool,
    pub rotors: Vec<RotorDef>,
    pub unbalances: Vec<UnbalanceDef>,
    /// Exact element kinematics, or linearised about rest (effect `element_geometry`).
    pub exact_geometry: bool,
    pub springs: Vec<Placed<Spring>>,
    pub dampers: Vec<Placed<LinearDamper>>,
    pub friction_dampers: Vec<Placed<FrictionDamper>>,
    /// The bearings of the friction dampers the scene gives their moving part (two each).
    pub damper_joints: Vec<Placed<DamperJoint>>,
    pub gaskets: Vec<Placed<Gasket>>,
    /// The tub-cabinet contacts (effect `contact`; none without it).
    pub contacts: Vec<Placed<Contact>>,
    /// The counterweights' bolts, three elements each (effect `counterweights`; none without).
    pub bolted_joints: Vec<Placed<BoltedJoint>>,
    pub sensors: Vec<SensorDef>,
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
        let rest = Drive {
            phi: 0.0,
            omega: 0.0,
            omega_dot: 0.0,
        };
        let (wa, _) = e.wrenches(&ma.state(&zero), &mb.state(&zero), exact, &rest, &[]);
        Placed {
            e,
            rest_force_a: wa.force.0,
            rest_moment_a: wa.moment.0,
        }
    }
}

/// The counterweights' bolts the scene has (three elements each, two slider states), their
/// states numbered on from `layout.nz`.
fn bolted_joints(
    model: &Model,
    bodies: &Bodies,
    layout: &mut Layout,
    exact: bool,
) -> Vec<Placed<BoltedJoint>> {
    let n = layout.n();
    let mut out = Vec::new();
    for (ci, w) in model.counterweights.iter().enumerate() {
        let body = BodyRef::Counterweight(ci);
        if bodies.get(body).is_none() {
            continue;
        }
        for j in model
            .bolted_joints
            .iter()
            .filter(|j| j.counterweight == w.name)
        {
            let (a, b) = (
                bodies.marker(BodyRef::Tub, j.point),
                bodies.marker(body, j.point),
            );
            let elements = BoltedJoint::elements(j, a, b, layout.nz);
            layout.nz += 2;
            out.extend(elements.into_iter().map(|e| Placed::new(e, exact, n)));
        }
    }
    out
}

impl Equations {
    /// Resolve a checked model for a scene.
    pub fn new(model: &Model, scene: &EffectSet) -> Equations {
        let bodies = Bodies::new(model, scene);
        let mut layout = bodies.layout;
        let mk = |body: BodyRef, point: [f64; 3]| bodies.marker(body, point);
        let (tub, m1_const, carried) = bodies.constant_mass(model);
        let all_rotors: Vec<RotorDef> = model
            .rotors
            .iter()
            .map(|r| RotorDef::new(r, mk(BodyRef::Tub, r.mount_point())))
            .collect();
        let drum = bodies.spinning();
        let unbalances = model
            .unbalances
            .iter()
            .filter(|u| scene.has(&Effect::Unbalance(u.rotor.clone())))
            .map(|u| {
                let r = all_rotors
                    .iter()
                    .find(|r| r.name == u.rotor)
                    .expect("checked: rotor exists");
                let rows = drum
                    .filter(|_| BodyRef::Drum.rotor() == Some(u.rotor.as_str()))
                    .map(|d| d.modes.rows(u.position));
                UnbalanceDef::new(u, r, rows)
            })
            .collect();
        let rotors = if scene.has(&Effect::Gyroscopic) {
            all_rotors
        } else {
            Vec::new()
        };
        let gasket_damping = scene.has(&Effect::GasketDamping);
        let exact = scene.has(&Effect::ElementGeometry);
        let n = layout.n();
        let place = |e| Placed::new(e, exact, n);
        let springs = model
            .springs
            .iter()
            .map(|s| Spring::new(s, mk(s.a.body, s.a.point), mk(s.b.body, s.b.point)))
            .map(place)
            .collect();
        let dampers = model
            .dampers
            .iter()
            .map(|d| LinearDamper::new(d, mk(d.a.body, d.a.point), mk(d.b.body, d.b.point)))
            .map(|e| Placed::new(e, exact, n))
            .collect();
        // Each friction damper: the massless element, or two bearings on its moving part.
        let mut friction_dampers = Vec::new();
        let mut damper_joints = Vec::new();
        let with_dampers = scene.has(&Effect::FrictionDampers);
        for (i, d) in model
            .friction_dampers
            .iter()
            .enumerate()
            .filter(|_| with_dampers)
        {
            let (a, b) = (mk(d.a.body, d.a.point), mk(d.b.body, d.b.point));
            let part = BodyRef::DamperPart(i);
            if bodies.get(part).is_some() {
                let ends = ((a, mk(part, d.a.point)), (b, mk(part, d.b.point)));
                let [rod, housing] = DamperJoint::pair(d, ends.0, ends.1);
                damper_joints.push(Placed::new(rod, exact, n));
                damper_joints.push(Placed::new(housing, exact, n));
            } else {
                let law = scene.friction_law(d.law);
                let e = FrictionDamper::new(d, law, layout.nz, a, b);
                layout.nz += usize::from(e.state().is_some());
                friction_dampers.push(Placed::new(e, exact, n));
            }
        }
        let gaskets = model
            .gaskets
            .iter()
            .map(|g| Gasket::new(g, mk(g.a, g.point), mk(g.b, g.point), gasket_damping))
            .map(|e| Placed::new(e, exact, n))
            .collect();
        let contacts = model
            .contacts
            .iter()
            .filter(|_| scene.has(&Effect::Contact))
            .map(|c| Contact::new(c, mk(c.a, c.point), mk(c.b, c.b_point())))
            .map(|e| Placed::new(e, exact, n))
            .collect();
        let bolted_joints = bolted_joints(model, &bodies, &mut layout, exact);
        let sensors = model
            .sensors
            .iter()
            .map(|s| SensorDef {
                name: s.name.clone(),
                kind: s.kind,
                at: mk(s.body, s.point),
                spin: Spin::new(&bodies, s.body, s.point),
                channels: s.channels(),
            })
            .collect();
        Equations {
            exact_geometry: exact,
            unbalance_inertia: scene.has(&Effect::UnbalanceInertia),
            scene: scene.clone(),
            layout,
            gravity: model.gravity,
            tub,
            m1_const,
            carried,
            rotors,
            unbalances,
            springs,
            dampers,
            friction_dampers,
            damper_joints,
            gaskets,
            contacts,
            bolted_joints,
            sensors,
            bodies,
        }
    }

    /// The modes of body `id`, when the scene makes it elastic.
    pub fn modes(&self, id: BodyRef) -> Option<&ModalBody> {
        self.bodies.modes(id)
    }

    /// The spinning elastic drum's terms, when the scene makes the drum elastic.
    pub fn elastic_drum(&self) -> Option<&ElasticDrum> {
        self.bodies.spinning()
    }

    /// Evaluate M1 (row-major n1 x n1, overwritten) and h (length n, overwritten), with the
    /// element states at their assembly value (z = 0: the static start's).
    pub fn eval<T: Scalar>(&self, d: &Drive<T>, q: &[T], qd: &[T], m1: &mut [T], h: &mut [T]) {
        self.eval_terms(d, q, qd, &[], Some(m1), h, Terms::All);
    }

    /// As `eval`, at element states `z` (length `layout.nz`).
    #[allow(clippy::too_many_arguments)]
    pub fn eval_states<T: Scalar>(
        &self,
        d: &Drive<T>,
        q: &[T],
        qd: &[T],
        z: &[T],
        m1: &mut [T],
        h: &mut [T],
    ) {
        self.eval_terms(d, q, qd, z, Some(m1), h, Terms::All);
    }

    /// h alone (length n, overwritten) at element states `z`: what a solve of M1 through its
    /// structure needs (M1 is never formed).
    pub fn forces<T: Scalar>(&self, d: &Drive<T>, q: &[T], qd: &[T], z: &[T], h: &mut [T]) {
        self.eval_terms(d, q, qd, z, None, h, Terms::All);
    }

    /// The element states' rates z' (length `layout.nz`, overwritten; an empty `zd` asks for
    /// none).
    pub fn state_rates<T: Scalar>(&self, q: &[T], qd: &[T], z: &[T], zd: &mut [T]) {
        if zd.is_empty() {
            return;
        }
        let b = BodyState::new(q, qd);
        for p in &self.friction_dampers {
            if let Some(i) = p.e.state() {
                let (ma, mb) = p.e.markers();
                zd[i] =
                    p.e.state_rate(&ma.state(&b), &mb.state(&b), self.exact_geometry, z);
            }
        }
    }

    /// M1 (when asked for: the Jacobians need h only) and h, or only some of h's terms (the
    /// others are left out, so the derivatives of the rest stay exact along the seeded
    /// columns: see `Terms`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn eval_terms<T: Scalar>(
        &self,
        d: &Drive<T>,
        q: &[T],
        qd: &[T],
        z: &[T],
        mut m1: Option<&mut [T]>,
        h: &mut [T],
        terms: Terms,
    ) {
        let n1 = self.layout.n1;
        debug_assert_eq!(h.len(), self.layout.n());
        if let Some(m1) = m1.as_deref_mut() {
            debug_assert_eq!(m1.len(), n1 * n1);
            for (m, c) in m1.iter_mut().zip(&self.m1_const) {
                *m = T::c(*c);
            }
        }
        h.fill(T::zero());
        let b = BodyState::new(q, qd);
        let g = if terms == Terms::BodiesWithoutGravity {
            V::zero()
        } else {
            V::<T>::c(self.gravity)
        };

        // The bodies' own terms, and the parts they carry (weights, rotors, unbalances), in
        // the layout's order: the floating body, what rides on it, the spinning body, then
        // subsystem 2.
        let [floating, rest @ ..] = &self.bodies.list[..] else {
            unreachable!("the tub is the first body")
        };
        if terms != Terms::Subsystem2 {
            self.tub.add(&b, g, h);
            floating.add(&b, d, g, None, n1, h);
            for (at, mass) in &self.carried {
                let w = g * *mass;
                at.apply(&b, &Wrench::force(w), w, h);
            }
            for r in &self.rotors {
                r.add(&b, d, h);
            }
            for u in &self.unbalances {
                u.add(&b, d, g, self.unbalance_inertia, m1.as_deref_mut(), n1, h);
            }
        }
        for body in rest {
            if terms != Terms::Subsystem2 || body.in_subsystem2() {
                body.add(&b, d, g, m1.as_deref_mut(), n1, h);
            }
        }

        if matches!(terms, Terms::Bodies | Terms::BodiesWithoutGravity) {
            return;
        }
        self.elements(&self.springs, &b, d, z, h);
        self.elements(&self.dampers, &b, d, z, h);
        self.elements(&self.friction_dampers, &b, d, z, h);
        self.elements(&self.damper_joints, &b, d, z, h);
        self.elements(&self.gaskets, &b, d, z, h);
        self.elements(&self.contacts, &b, d, z, h);
        self.elements(&self.bolted_joints, &b, d, z, h);
    }

    fn elements<T: Scalar, E: Element>(
        &self,
        list: &[Placed<E>],
        st: &BodyState<T>,
        d: &Drive<T>,
        z: &[T],
        h: &mut [T],
    ) {
        for p in list {
            let (ma, mb) = p.e.markers();
            let (la, lb) = (ma.local(st), mb.local(st));
            let (a, b) = self.element_loads(p, &la, &lb, d, z);
            ma.scatter(&a, h);
            mb.scatter(&b, h);
        }
    }

    /// An element's loads at its two markers' ports from their local coordinates: the whole
    /// dependence of h on the state through the element (its Jacobian is taken over these).
    pub(crate) fn element_loads<T: Scalar, E: Element>(
        &self,
        p: &Placed<E>,
        la: &Local<T>,
        lb: &Local<T>,
        d: &Drive<T>,
        z: &[T],
    ) -> (Load<T>, Load<T>) {
        let (ma, mb) = p.e.markers();
        let (wa, wb) = p.e.wrenches(
            &ma.state_of(la),
            &mb.state_of(lb),
            self.exact_geometry,
            d,
            z,
        );
        (
            self.load(ma, la, &wa, p, true),
            self.load(mb, lb, &wb, p, false),
        )
    }

    /// The load of a wrench acting on a body at a marker (`on_a`: the element's end a, whose
    /// rest load is stored; end b's is its negative). The moment is seen from the tilted frame:
    /// the current wrench tilts with it (exact geometry), or the rest wrench (linearised), so
    /// the term stays linear in the state.
    fn load<T: Scalar, E>(
        &self,
        at: &MarkerDef,
        l: &Local<T>,
        w: &Wrench<T>,
        rest: &Placed<E>,
        on_a: bool,
    ) -> Load<T> {
        let (f_tilt, m_tilt) = if self.exact_geometry {
            (w.force, w.moment)
        } else {
            let sign = if on_a { 1.0 } else { -1.0 };
            (
                V::c(rest.rest_force_a) * sign,
                V::c(rest.rest_moment_a) * sign,
            )
        };
        let in_frame = Wrench {
            force: w.force,
            moment: if at.frame.is_some() {
                w.moment - l.alpha.cross(m_tilt)
            } else {
                w.moment
            },
        };
        let wq = at.modal.as_ref().map(|_| l.w);
        at.load(l.alpha, wq, &in_frame, f_tilt)
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

/// Which terms of h an evaluation includes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Terms {
    All,
    /// Only the terms that depend on q2 (the cabinet's modes): its modal terms and the force
    /// elements (the tub's, rotors', unbalances' and drum's terms depend on q1 alone).
    Subsystem2,
    /// Every term but the force elements (the Jacobians take those by their local structure).
    Bodies,
    /// `Bodies` with g = 0 (the energy balance's gravity share is the difference; a fixed
    /// frame's modal weight is a constant and stays).
    BodiesWithoutGravity,
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
