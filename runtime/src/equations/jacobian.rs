//! The Jacobians of the generalised forces, dh/dq and dh/dq' (M depends on t only), from the
//! one derivation evaluated over dual numbers: `LANES` columns per pass, exact to round-off,
//! with no step size to choose. The implicit integrators, statics and the frequency-domain
//! linearisation use them instead of differences of q''.

use super::{Drive, Equations, Terms};
use crate::dual::{Dual, LANES};
use crate::scalar::Scalar;

type D = Dual<LANES>;

/// Work arrays of `force_jacobians`, allocated once per system.
#[derive(Clone, Debug)]
pub struct JacobianWork {
    q: Vec<D>,
    qd: Vec<D>,
    m1: Vec<D>,
    h: Vec<D>,
}

impl JacobianWork {
    pub fn new(eq: &Equations) -> Self {
        let (n, n1) = (eq.layout.n(), eq.layout.n1);
        JacobianWork {
            q: vec![D::c(0.0); n],
            qd: vec![D::c(0.0); n],
            m1: vec![D::c(0.0); n1 * n1],
            h: vec![D::c(0.0); n],
        }
    }
}

impl Equations {
    /// dh/dq into `hq` and dh/dq' into `hqd` (row-major n x n each) at (d, q, q'). Never
    /// allocates.
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
        let dd = Drive {
            phi: D::c(d.phi),
            omega: D::c(d.omega),
            omega_dot: D::c(d.omega_dot),
        };
        // Seeds: the columns of q1 and q1' first (every term), then those of q2 and q2'
        // (only the terms that depend on them); one pass seeds LANES of them. Seed s is
        // column c of hq, or of hqd when `vel`.
        let n2 = n - n1;
        let col = |s: usize| -> (bool, usize) {
            if s < 2 * n1 {
                (s >= n1, s % n1)
            } else {
                let k = s - 2 * n1;
                (k >= n2, n1 + k % n2)
            }
        };
        for start in (0..2 * n).step_by(LANES) {
            let end = (start + LANES).min(2 * n);
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
            // straddles the two needs all.
            let terms = if start >= 2 * n1 {
                Terms::Subsystem2
            } else {
                Terms::All
            };
            self.eval_terms(&dd, &w.q, &w.qd, &mut w.m1, &mut w.h, terms);
            for s in start..end {
                let (vel, c) = col(s);
                let target = if vel { &mut *hqd } else { &mut *hq };
                for r in 0..n {
                    target[r * n + c] = w.h[r].d[s - start];
                }
            }
        }
    }
}

/// The Jacobians of a scene for a back end that does not trace them (the generated code above
/// 12 coordinates): the interpreter's derivation with its own work arrays.
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
