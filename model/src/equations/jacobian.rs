//! The Jacobians of the generalised forces, dh/dq and dh/dq' (M depends on t only), by the
//! structure of the one derivation, exact to round-off with no step size to choose:
//! - the force elements (the nonlinear terms): each element's loads at its markers' ports are a
//!   function of the two markers' local coordinates only (`Local`: u, alpha, W q, Phi q and
//!   rates). Their local Jacobian comes from one evaluation over `Dual<N>` (N <= 24 lanes) per
//!   level (positions, rates), independent of the number of modes, and is chained through the
//!   constant marker maps: dh += P^T (d load / d z) G, with G the marker's input ports (identity
//!   columns of u, alpha; mode-shape rows W, Phi) and P its output ports (the tub's rigid rows;
//!   W^T, Phi^T on the modes);
//! - the body terms (weight, rotors, unbalances, the spinning drum, modal stiffness and
//!   damping; affine in q and q'): the same derivation over `Dual<LANES>` without the
//!   elements and without M1, seeded along the columns of subsystem 1 only, since they do not
//!   depend on the cabinet's coordinates (whose own terms are diagonal, `ModalBody`).
//!
//! `force_jacobians_dual` seeds the whole derivation instead: the reference the tests hold the
//! structured route to.

use super::kinematics::MarkerDef;
use super::ports::{Field, Port, add_port_row, inputs, outputs, ported, scatter_rows, seeded};
use super::{BodyState, Drive, Equations, Modes, Placed, Terms};
use crate::dual::{Dual, LANES};
use crate::elements::Element;
use crate::scalar::Scalar;

type D = Dual<LANES>;

/// Lanes of an element's local Jacobian: at most two markers x four ports (u, alpha, W q,
/// Phi q) x 3; an element with fewer input ports takes the smallest of these that fits.
pub(super) const LOCAL: [usize; 3] = [6, 12, 24];

/// Work arrays of `force_jacobians`, allocated once per system.
#[derive(Clone, Debug)]
pub struct JacobianWork {
    q: Vec<D>,
    qd: Vec<D>,
    m1: Vec<D>,
    h: Vec<D>,
    /// Two ports' load Jacobians chained through the input ports, 6 x n.
    x: Vec<f64>,
    /// The element states as constants of the widest local lanes (`states.rs`).
    z: Vec<Dual<{ LOCAL[2] }>>,
}

impl JacobianWork {
    pub fn new(eq: &Equations) -> Self {
        let (n, n1) = (eq.layout.n(), eq.layout.n1);
        JacobianWork {
            q: vec![D::c(0.0); n],
            qd: vec![D::c(0.0); n],
            m1: vec![D::c(0.0); n1 * n1],
            h: vec![D::c(0.0); n],
            x: vec![0.0; 6 * (n + eq.layout.nz)],
            z: vec![Dual::c(0.0); eq.layout.nz],
        }
    }
}

impl Equations {
    /// dh/dq into `hq` and dh/dq' into `hqd` (row-major n x n each) at (d, q, q'), by the
    /// structure of the derivation (module doc), with the element states at their assembly
    /// value (the static start's Newton; a system with states iterates on its whole Jacobian).
    /// Never allocates.
    pub fn force_jacobians(
        &self,
        d: &Drive<f64>,
        q: &[f64],
        qd: &[f64],
        w: &mut JacobianWork,
        hq: &mut [f64],
        hqd: &mut [f64],
    ) {
        let (n, n1) = (self.layout.n(), self.layout.n1);
        hq.fill(0.0);
        hqd.fill(0.0);
        // Body terms: the columns of q1 and q1' (seed s: column s % n1, of hqd when s >= n1).
        let rows = (n, n);
        self.seeded_passes(d, q, qd, w, hq, hqd, rows, 2 * n1, Terms::Bodies, |s| {
            (s >= n1, s % n1)
        });
        // Subsystem 2's own terms are diagonal (modes on a fixed frame), but for the curves'.
        for b in self.bodies.list.iter().filter(|b| b.in_subsystem2()) {
            if let Some(m) = b.modal() {
                m.add_elastic_jacobian(hq, hqd, n);
                m.add_curves_jacobian(q, hq, n);
            }
        }
        // Force elements by their local Jacobians.
        let st = BodyState::new(q, qd);
        self.all_element_jacobians(&st, d, (&mut w.x, &mut []), hq, hqd, n, None);
    }

    /// Every force element's Jacobian into hq / hqd (dimension `dim`); with `ports`, each
    /// marker on subsystem 2 as six port columns of its own (`force_jacobians_ported`), and
    /// with element states (`z` not empty) their rows and columns from `dim - nz` (`states.rs`).
    #[allow(clippy::too_many_arguments)]
    fn all_element_jacobians(
        &self,
        st: &BodyState<f64>,
        d: &Drive<f64>,
        (x, z): (&mut [f64], &mut [Dual<{ LOCAL[2] }>]),
        hq: &mut [f64],
        hqd: &mut [f64],
        dim: usize,
        mut ports: Option<&mut usize>,
    ) {
        let w = &mut (x, z);
        let p = ports.as_deref_mut();
        self.element_jacobians(&self.springs, st, d, w, hq, hqd, dim, p);
        let p = ports.as_deref_mut();
        self.element_jacobians(&self.dampers, st, d, w, hq, hqd, dim, p);
        let p = ports.as_deref_mut();
        self.element_jacobians(&self.friction_dampers, st, d, w, hq, hqd, dim, p);
        let p = ports.as_deref_mut();
        self.element_jacobians(&self.damper_joints, st, d, w, hq, hqd, dim, p);
        let p = ports.as_deref_mut();
        self.element_jacobians(&self.gaskets, st, d, w, hq, hqd, dim, p);
        let p = ports.as_deref_mut();
        self.element_jacobians(&self.contacts, st, d, w, hq, hqd, dim, p);
        self.element_jacobians(&self.bolted_joints, st, d, w, hq, hqd, dim, ports);
    }

    /// Every force element's markers in the order `all_element_jacobians` visits them.
    fn element_markers(&self) -> impl Iterator<Item = &MarkerDef> {
        fn pairs<E: Element>(l: &[Placed<E>]) -> impl Iterator<Item = &MarkerDef> {
            l.iter().flat_map(|p| {
                let (a, b) = p.e.markers();
                [a, b]
            })
        }
        pairs(&self.springs)
            .chain(pairs(&self.dampers))
            .chain(pairs(&self.friction_dampers))
            .chain(pairs(&self.damper_joints))
            .chain(pairs(&self.gaskets))
            .chain(pairs(&self.contacts))
            .chain(pairs(&self.bolted_joints))
    }

    /// The element markers on subsystem 2's modes (the ported form's ports, six coordinates
    /// each: W q and Phi q there).
    fn port_markers(&self) -> impl Iterator<Item = &MarkerDef> {
        let n1 = self.layout.n1;
        self.element_markers()
            .filter(move |m| m.modal.as_ref().is_some_and(|r| r.start >= n1))
    }

    /// The number of port coordinates r of the ported form (`washdyn_ode::ported`): six per
    /// element marker on subsystem 2. `None` where the form does not apply: subsystem 2 is
    /// empty, or holds anything but modes on a fixed frame (a damper's moving part).
    pub fn ported_ports(&self) -> Option<usize> {
        let (n, n1) = (self.layout.n(), self.layout.n1);
        let mut modes = 0;
        for b in self.bodies.list.iter().filter(|b| b.in_subsystem2()) {
            match (&b.modes, b.modal()) {
                // Characteristic curves couple the chosen modes: no diagonal subsystem 2.
                (Modes::Frame(_), Some(m)) if m.curves.is_some() => return None,
                (Modes::Frame(_), Some(m)) => modes += m.n,
                (Modes::Rigid, None) => {}
                _ => return None,
            }
        }
        if n == n1 || modes != n - n1 {
            return None;
        }
        Some(6 * self.port_markers().count())
    }

    /// The ported form of the force Jacobians (`washdyn_ode::ported`, r = `ported_ports`):
    /// dh/dq and dh/dq' over [q1; p; z] (na x na, na = n1 + r + nz) at element states `z`
    /// into `eq` and `ev` (the states' rows and columns: `states.rs`), the diagonals of
    /// subsystem 2's own terms into `dq` and `dv`, and the ports' map B2 (n2 x r) into `b2`.
    /// Without states, `T^T E T + diag(0, d)` is `force_jacobians`' result. Never allocates.
    #[allow(clippy::too_many_arguments)]
    pub fn force_jacobians_ported(
        &self,
        d: &Drive<f64>,
        (q, qd, z): (&[f64], &[f64], &[f64]),
        w: &mut JacobianWork,
        eq: &mut [f64],
        ev: &mut [f64],
        dq: &mut [f64],
        dv: &mut [f64],
        b2: &mut [f64],
    ) {
        let (n, n1) = (self.layout.n(), self.layout.n1);
        let r = b2.len() / (n - n1);
        let na = n1 + r + z.len();
        for (zw, v) in w.z.iter_mut().zip(z) {
            *zw = Dual::c(*v);
        }
        eq.fill(0.0);
        ev.fill(0.0);
        self.seeded_passes(d, q, qd, w, eq, ev, (n1, na), 2 * n1, Terms::Bodies, |s| {
            (s >= n1, s % n1)
        });
        dq.fill(0.0);
        dv.fill(0.0);
        for b in self.bodies.list.iter().filter(|b| b.in_subsystem2()) {
            if let Some(m) = b.modal() {
                m.add_elastic_diagonal(dq, dv, n1);
            }
        }
        let st = BodyState::new(q, qd);
        let mut next = 0;
        let work = (&mut w.x[..], &mut w.z[..z.len()]);
        self.all_element_jacobians(&st, d, work, eq, ev, na, Some(&mut next));
        debug_assert_eq!(next, r, "ports counted as visited");
        b2.fill(0.0);
        for (k, m) in self.port_markers().enumerate() {
            let rows = m.modal.as_ref().expect("a port marker has modes");
            for (j, (wr, pr)) in rows.w.iter().zip(&rows.phi).enumerate() {
                let row = &mut b2[(rows.start - n1 + j) * r + 6 * k..][..6];
                row[..3].copy_from_slice(wr);
                row[3..].copy_from_slice(pr);
            }
        }
    }

    /// The same Jacobians from the whole derivation over dual numbers, every column seeded
    /// (the q2 columns through the terms that depend on them): the structured route's
    /// reference.
    pub fn force_jacobians_dual(
        &self,
        d: &Drive<f64>,
        q: &[f64],
        qd: &[f64],
        w: &mut JacobianWork,
        hq: &mut [f64],
        hqd: &mut [f64],
    ) {
        let (n, n1) = (self.layout.n(), self.layout.n1);
        let n2 = n - n1;
        // Seeds: the columns of q1 and q1' first (every term), then those of q2 and q2'.
        let col = move |s: usize| -> (bool, usize) {
            if s < 2 * n1 {
                (s >= n1, s % n1)
            } else {
                let k = s - 2 * n1;
                (k >= n2, n1 + k % n2)
            }
        };
        self.seeded_passes(d, q, qd, w, hq, hqd, (n, n), 2 * n, Terms::All, col);
    }

    /// Columns of hq / hqd from passes over `Dual<LANES>`: seed s (of `seeds`) is column
    /// `col(s)`; passes that seed q2 columns only (s >= 2 n1) take `Terms::Subsystem2`.
    #[allow(clippy::too_many_arguments)]
    fn seeded_passes(
        &self,
        d: &Drive<f64>,
        q: &[f64],
        qd: &[f64],
        w: &mut JacobianWork,
        hq: &mut [f64],
        hqd: &mut [f64],
        (rows, stride): (usize, usize),
        seeds: usize,
        terms: Terms,
        col: impl Fn(usize) -> (bool, usize),
    ) {
        let (n, n1) = (self.layout.n(), self.layout.n1);
        let dd = Drive {
            phi: D::c(d.phi),
            omega: D::c(d.omega),
            omega_dot: D::c(d.omega_dot),
        };
        for start in (0..seeds).step_by(LANES) {
            let end = (start + LANES).min(seeds);
            for i in 0..n {
                w.q[i] = D::c(q[i]);
                w.qd[i] = D::c(qd[i]);
            }
            for s in start..end {
                let (vel, c) = col(s);
                let x = if vel { &mut w.qd[c] } else { &mut w.q[c] };
                x.d[s - start] = 1.0;
            }
            // A pass that seeds only q2 columns skips the terms of q1 alone; a pass that
            // straddles the two needs all. Only the whole derivation needs M1 (the tracer's
            // shape); the Jacobians never read it.
            let t = match terms {
                Terms::All if start >= 2 * n1 => Terms::Subsystem2,
                t => t,
            };
            let m1 = (t != Terms::Bodies).then_some(&mut w.m1[..]);
            self.eval_terms(&dd, &w.q, &w.qd, &[], m1, &mut w.h, t);
            for s in start..end {
                let (vel, c) = col(s);
                let target = if vel { &mut *hqd } else { &mut *hq };
                for r in 0..rows {
                    target[r * stride + c] = w.h[r].d[s - start];
                }
                // Rows past `rows` are left out only where they are zero (the body terms'
                // rows of subsystem 2).
                debug_assert!(w.h[rows..].iter().all(|v| v.d[s - start] == 0.0));
            }
        }
    }

    /// h's Jacobians (dimension `dim`) += each element's (`element_jacobian`, over the fewest
    /// lanes that hold its input ports). With `ports` (the next free port slot), a marker on
    /// subsystem 2 reads and loads six port columns of its own instead of its modes.
    #[allow(clippy::too_many_arguments)]
    fn element_jacobians<E: Element>(
        &self,
        list: &[Placed<E>],
        st: &BodyState<f64>,
        d: &Drive<f64>,
        (x, z): &mut (&mut [f64], &mut [Dual<{ LOCAL[2] }>]),
        hq: &mut [f64],
        hqd: &mut [f64],
        dim: usize,
        mut ports: Option<&mut usize>,
    ) {
        let n1 = self.layout.n1;
        for p in list {
            let (ma, mb) = p.e.markers();
            // Each marker's port slot (ported form, subsystem 2's markers).
            let mut slot = |m: &MarkerDef| -> Option<usize> {
                let next = ports.as_deref_mut()?;
                m.modal.as_ref().filter(|r| r.start >= n1)?;
                *next += 6;
                Some(n1 + *next - 6)
            };
            let slots = [slot(ma), slot(mb)];
            // The element's input ports, marker a's then b's: lane k seeds the k-th present.
            let mut ins = [None; 8];
            let (ia, ib) = (inputs(ma), inputs(mb));
            ins[..4].copy_from_slice(&ported(ia, slots[0]));
            ins[4..].copy_from_slice(&ported(ib, slots[1]));
            let lanes = 3 * ins.iter().flatten().count();
            let a = (p, &ins, slots, st, d);
            // An element with a state (when the states are asked for) on the widest lanes,
            // those of the states' constants.
            if p.e.state().is_some() && !z.is_empty() {
                self.element_jacobian::<E, { LOCAL[2] }>(a, x, z, hq, hqd, dim);
            } else if lanes <= LOCAL[0] {
                self.element_jacobian::<E, { LOCAL[0] }>(a, x, &mut [], hq, hqd, dim);
            } else if lanes <= LOCAL[1] {
                self.element_jacobian::<E, { LOCAL[1] }>(a, x, &mut [], hq, hqd, dim);
            } else {
                self.element_jacobian::<E, { LOCAL[2] }>(a, x, &mut [], hq, hqd, dim);
            }
        }
    }

    /// One element's loads over `Dual<N>` seeded along its markers' input ports `ins`, one
    /// level at a time, chained through the ports' maps into hq / hqd; with the element
    /// states `z` (constants, not empty), its state's row and column too (`states.rs`).
    #[allow(clippy::type_complexity)]
    fn element_jacobian<E: Element, const N: usize>(
        &self,
        (p, ins, slots, st, d): (
            &Placed<E>,
            &[Option<(Port<'_>, Field)>; 8],
            [Option<usize>; 2],
            &BodyState<f64>,
            &Drive<f64>,
        ),
        x: &mut [f64],
        z: &mut [Dual<N>],
        hq: &mut [f64],
        hqd: &mut [f64],
        n: usize,
    ) {
        let dl = Drive {
            phi: Dual::<N>::c(d.phi),
            omega: Dual::<N>::c(d.omega),
            omega_dot: Dual::<N>::c(d.omega_dot),
        };
        let (ma, mb) = p.e.markers();
        let (la, lb) = (ma.local(st), mb.local(st));
        // The element's state's row and column, after the coordinates (and ports).
        let state = p.e.state().filter(|_| !z.is_empty());
        let zrow = state.map(|s| n - z.len() + s);
        // Columns the element's inputs reach.
        let (mut c0, mut c1) = (n, 0);
        for &(port, _) in ins.iter().flatten() {
            let (a, b) = port.cols();
            (c0, c1) = (c0.min(a), c1.max(b));
        }
        for rate in [false, true] {
            let (sa, next) = seeded::<N>(ma, &la, rate, 0);
            let (sb, _) = seeded::<N>(mb, &lb, rate, next);
            let (ya, yb) = self.element_loads(p, &sa, &sb, &dl, z);
            let h = if rate { &mut *hqd } else { &mut *hq };
            if let Some(r) = zrow {
                let (a, b) = (ma.state_of(&sa), mb.state_of(&sb));
                let zd = p.e.state_rate(&a, &b, self.exact_geometry, z);
                add_port_row(ins, &zd, &mut h[r * n..(r + 1) * n]);
            }
            for ((m, y), slot) in [(ma, &ya), (mb, &yb)].into_iter().zip(slots) {
                // The marker's ports in pairs sharing rows: (force, moment) on the tub's
                // rigid rows, (W, Phi) on its modes (or its port rows).
                let outs = ported(outputs(m, y), slot);
                for pair in outs.chunks(2) {
                    let (Some((po, vf)), Some((pm, vm))) = (pair[0], pair[1]) else {
                        continue;
                    };
                    // x = d(load at the two ports)/dq over columns c0..c1, six rows
                    // (force or W port 0..3, moment or Phi port 3..6) of length n:
                    // the local 3 x 3 blocks times each input port's map.
                    for a in 0..6 {
                        let v = if a < 3 { vf.0[a] } else { vm.0[a - 3] };
                        let row = &mut x[a * n..(a + 1) * n];
                        row[c0..c1].fill(0.0);
                        add_port_row(ins, &v, row);
                    }
                    scatter_rows(po, pm, x, c0, c1, n, h);
                }
            }
        }
        if let (Some(s), Some(r)) = (state, zrow) {
            let l = (&la, &lb);
            self.state_column(p, l, slots, (s, r), &dl, z, x, hqd, n);
        }
    }
}

/// The force Jacobians of a scene for the generated back end (every scene: the static start
/// and, above the traced size, the implicit methods): the interpreter's derivation with its
/// own work arrays, so both back ends get the same bits.
#[derive(Clone, Debug)]
pub struct ForceJacobians {
    pub eq: Equations,
    work: JacobianWork,
}

impl ForceJacobians {
    pub fn new(eq: Equations) -> Self {
        let work = JacobianWork::new(&eq);
        ForceJacobians { eq, work }
    }

    /// For a checked model's scene by name (generated code: its own `model()` and `SCENE`).
    pub fn for_scene(model: &crate::ir::Model, scene: &str) -> Self {
        let s = model
            .scene(Some(scene))
            .expect("the generated scene exists in its model");
        Self::new(Equations::new(model, &s))
    }

    pub fn eval(&mut self, d: &Drive<f64>, q: &[f64], qd: &[f64], hq: &mut [f64], hqd: &mut [f64]) {
        self.eq.force_jacobians(d, q, qd, &mut self.work, hq, hqd);
    }
}
