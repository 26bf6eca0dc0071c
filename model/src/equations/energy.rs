//! The energy balance by category: q'^T h split into the power of each source, so that the
//! work-energy theorem for M(t) q'' = h,
//!   T(t1) - T(t0) = integral of (q'^T h + q'^T M1' q' / 2) dt,   T = q'^T M q' / 2,
//! can say where the energy goes. The split is exact (the categories' h add up to h term by
//! term), so the balance closes whatever the kinematics; what each category means:
//! - drive: the prescribed rotation's terms (rotor spin, unbalances' inertia, the spinning
//!   drum's frame, Coriolis and stiffening terms) plus q'^T M1' q' / 2, added by the caller:
//!   the work the drive does on the vibration (the spin's own energy J Omega^2 / 2 is fixed by
//!   Omega(t) and is not in T);
//! - gravity: the weights' share of h (the body terms at g minus at g = 0, and a fixed frame's
//!   modal weight);
//! - `<body> modal strain`, `<body> modal damping`, `<body> feet`: -omega^2 q q' (and the
//!   characteristic curves' -f_nl(q_c) . q_c', minus the change of their strain energy) and
//!   -2 zeta omega q'^2 of the body's modes, the latter split by the modal strain energy method
//!   into the support springs' share 2 omega zeta_s s (the cabinet's feet, where the entry has
//!   `support_damping`) and the structure's;
//! - `<element> elastic`, `<element> dissipated`: the element's loads at the markers' current
//!   positions with their velocities set to zero, and the rest (friction, dampers, the
//!   bearings' and the gasket's damping, a contact's Hunt-Crossley damping and its clamp:
//!   `elements::contact` shows that part never positive). An element with a state of its own (a
//!   presliding friction law's bushing deflection z) stores k z^2 / 2 there: the state force's
//!   power is elastic but for the slider's -k z (v - z'), which the law makes never positive
//!   and which is dissipated; the rest is split as for any element, at z = 0.
//!
//! Strain and elastic categories store energy (their work is minus a potential change);
//! dissipated ones only take it (their work is never positive).

use super::kinematics::Local;
use super::{BodyState, Drive, Equations, Frame, Placed, Terms};
use crate::elements::Element;
use crate::geom::V;
use serde::Serialize;

/// What a category's work is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Work done by the prescribed rotation on the vibration.
    Drive,
    /// Work of the weights (minus the change of potential energy in gravity).
    Gravity,
    /// Work of a conservative part (minus the change of its stored energy).
    Stored,
    /// Work of a dissipative part (minus the energy it took out).
    Dissipated,
}

/// One category of the balance.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Category {
    pub name: String,
    pub kind: Kind,
}

/// Buffers for `Equations::powers` and [`powers`], allocated once: a run with `--energy`
/// calls them at every step without allocating.
pub struct EnergyWork {
    h: Vec<f64>,
    h0: Vec<f64>,
    /// M1 at t + dt and t - dt (the drive's q'^T M1' q' / 2), and an h for those evaluations:
    /// work arrays of the runtime's balance, which evaluates a back end.
    pub m1p: Vec<f64>,
    pub m1m: Vec<f64>,
    pub hs: Vec<f64>,
    /// The element states' rates (a slider's dissipation reads them).
    pub zd: Vec<f64>,
}

impl EnergyWork {
    pub fn new(eq: &Equations) -> Self {
        let n = eq.layout.n();
        let n1 = eq.layout.n1;
        EnergyWork {
            h: vec![0.0; n],
            h0: vec![0.0; n],
            m1p: vec![0.0; n1 * n1],
            m1m: vec![0.0; n1 * n1],
            hs: vec![0.0; n],
            zd: vec![0.0; eq.layout.nz],
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A marker's local coordinates with every velocity set to zero.
fn still(l: &Local<f64>) -> Local<f64> {
    Local {
        ud: V::zero(),
        alphad: V::zero(),
        wd: V::zero(),
        phid: V::zero(),
        ..*l
    }
}

impl Equations {
    /// The categories of [`Equations::powers`], in its order.
    pub fn energy_categories(&self) -> Vec<Category> {
        let c = |name: String, kind| Category { name, kind };
        let mut v = vec![
            c("drive".into(), Kind::Drive),
            c("gravity".into(), Kind::Gravity),
        ];
        for b in &self.bodies.list {
            let Some(m) = b.modal() else { continue };
            let name = b.id.name();
            v.push(c(format!("{name} modal strain"), Kind::Stored));
            v.push(c(format!("{name} modal damping"), Kind::Dissipated));
            if m.support_damping.is_some() {
                v.push(c(format!("{name} feet"), Kind::Dissipated));
            }
        }
        fn of<E: Element>(list: &[Placed<E>], v: &mut Vec<Category>) {
            for p in list {
                if E::ELASTIC {
                    v.push(Category {
                        name: format!("{} elastic", p.e.name()),
                        kind: Kind::Stored,
                    });
                }
                if E::DISSIPATIVE {
                    v.push(Category {
                        name: format!("{} dissipated", p.e.name()),
                        kind: Kind::Dissipated,
                    });
                }
            }
        }
        of(&self.springs, &mut v);
        of(&self.dampers, &mut v);
        of(&self.friction_dampers, &mut v);
        of(&self.damper_joints, &mut v);
        of(&self.gaskets, &mut v);
        of(&self.contacts, &mut v);
        of(&self.bolted_joints, &mut v);
        v
    }

    /// The power of each category at (d, q, q'), in the order of `energy_categories`; they add
    /// up to q'^T h. The drive's share lacks q'^T M1' q' / 2, which needs M1 at neighbouring
    /// times ([`powers`] adds it).
    /// `z`: the element states (empty without states; their rates are taken here).
    #[allow(clippy::too_many_arguments)]
    pub fn powers(
        &self,
        d: &Drive<f64>,
        q: &[f64],
        qd: &[f64],
        z: &[f64],
        w: &mut EnergyWork,
        out: &mut Vec<f64>,
    ) {
        out.clear();
        self.eval_terms(d, q, qd, &[], None, &mut w.h, Terms::Bodies);
        self.eval_terms(d, q, qd, &[], None, &mut w.h0, Terms::BodiesWithoutGravity);
        let (with_g, without_g) = (dot(qd, &w.h), dot(qd, &w.h0));
        // A fixed frame's modal weight does not scale with the g of the body terms.
        let mut fixed_weight = 0.0;
        let mut own = 0.0;
        out.extend([0.0, 0.0]);
        for b in &self.bodies.list {
            let Some(m) = b.modal() else { continue };
            let r = m.start..m.start + m.n;
            let (qm, vm) = (&q[r.clone()], &qd[r]);
            if b.frame == Frame::Fixed {
                fixed_weight += dot(&m.weight, vm);
            }
            let curves = m.curves.as_ref().map_or(0.0, |c| c.power(qm, vm));
            let strain: f64 = (0..m.n).map(|k| -m.omega2[k] * qm[k] * vm[k]).sum::<f64>() + curves;
            let damping: f64 = (0..m.n).map(|k| -m.damping[k] * vm[k] * vm[k]).sum();
            own += strain + damping;
            match &m.support_damping {
                Some(f) => {
                    let feet: f64 = (0..m.n).map(|k| -f[k] * vm[k] * vm[k]).sum();
                    out.extend([strain, damping - feet, feet]);
                }
                None => out.extend([strain, damping]),
            }
        }
        out[0] = without_g - fixed_weight - own;
        out[1] = with_g - without_g + fixed_weight;
        let st = BodyState::new(q, qd);
        // Out of the work arrays and back without allocating (an empty Vec in between).
        let mut zd = std::mem::take(&mut w.zd);
        self.state_rates(q, qd, z, &mut zd);
        let s = States { z, zd: &zd };
        self.element_powers(&self.springs, &st, d, qd, s, w, out);
        self.element_powers(&self.dampers, &st, d, qd, s, w, out);
        self.element_powers(&self.friction_dampers, &st, d, qd, s, w, out);
        self.element_powers(&self.damper_joints, &st, d, qd, s, w, out);
        self.element_powers(&self.gaskets, &st, d, qd, s, w, out);
        self.element_powers(&self.contacts, &st, d, qd, s, w, out);
        self.element_powers(&self.bolted_joints, &st, d, qd, s, w, out);
        w.zd = zd;
    }

    #[allow(clippy::too_many_arguments)]
    fn element_powers<E: Element>(
        &self,
        list: &[Placed<E>],
        st: &BodyState<f64>,
        d: &Drive<f64>,
        qd: &[f64],
        s: States,
        w: &mut EnergyWork,
        out: &mut Vec<f64>,
    ) {
        for p in list {
            let (ma, mb) = p.e.markers();
            let (la, lb) = (ma.local(st), mb.local(st));
            let power = |la: &Local<f64>, lb: &Local<f64>, z: &[f64], h: &mut Vec<f64>| {
                h.fill(0.0);
                let (a, b) = self.element_loads(p, la, lb, d, z);
                ma.scatter(&a, h);
                mb.scatter(&b, h);
                dot(qd, h)
            };
            if p.e.state().is_some() {
                // The state's force (its whole power, tilt terms too) stores but what its
                // slider dissipates by the law; the rest is split as below at z = 0.
                let total = power(&la, &lb, s.z, &mut w.h);
                let without = power(&la, &lb, &[], &mut w.h);
                let at_rest = power(&still(&la), &still(&lb), &[], &mut w.h0);
                let (a, b) = (ma.state_of(&la), mb.state_of(&lb));
                let slider =
                    p.e.state_dissipation(&a, &b, self.exact_geometry, s.z, s.zd);
                out.push(at_rest + (total - without - slider));
                out.push(without - at_rest + slider);
                continue;
            }
            // An element without an elastic part has none at rest velocity (zero loads), and
            // one that does not dissipate is its elastic part: one evaluation each.
            let elastic = E::ELASTIC.then(|| power(&still(&la), &still(&lb), s.z, &mut w.h0));
            if let Some(e) = elastic {
                out.push(e);
            }
            if E::DISSIPATIVE {
                out.push(power(&la, &lb, s.z, &mut w.h) - elastic.unwrap_or(0.0));
            }
        }
    }
}

/// The element states and their rates, for `element_powers`.
#[derive(Clone, Copy)]
struct States<'a> {
    z: &'a [f64],
    zd: &'a [f64],
}
