//! Two coordinates with a full mass matrix, a stiff own spring and damper on the second and a
//! cubic spring and a harmonic force on the first: the shape of a modal body carried by a rigid
//! one (subsystem 1), small enough to check an IMEX split against a tight reference.
//! M q'' = h with M = [[2, 1/2], [1/2, 1]] and
//! h = [-k (q0 - q1) - q0^3 + sin 3t, k (q0 - q1) - omega^2 q1 - 2 zeta omega q1'], k = 10.

use crate::OdeSystem;

#[derive(Clone, Copy, Debug)]
pub struct Coupled {
    /// The second coordinate's own circular frequency (rad/s) and damping ratio.
    pub omega: f64,
    pub zeta: f64,
}

const M: [f64; 4] = [2.0, 0.5, 0.5, 1.0];
const K: f64 = 10.0;

impl OdeSystem for Coupled {
    fn dim(&self) -> usize {
        4
    }
    fn second_order(&self) -> Option<usize> {
        Some(2)
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        let (q0, q1, v1) = (y[0], y[1], y[3]);
        let w = self.omega;
        let h0 = -K * (q0 - q1) - q0 * q0 * q0 + (3.0 * t).sin();
        let h1 = K * (q0 - q1) - w * w * q1 - 2.0 * self.zeta * w * v1;
        // M^-1 h by Cramer's rule.
        let det = M[0] * M[3] - M[1] * M[2];
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = (M[3] * h0 - M[1] * h1) / det;
        dy[3] = (M[0] * h1 - M[2] * h0) / det;
    }
    fn linear_part(
        &mut self,
        _t: f64,
        _y: &[f64],
        m1: &mut [f64],
        k: &mut [f64],
        c: &mut [f64],
    ) -> Option<usize> {
        m1[..4].copy_from_slice(&M);
        k.copy_from_slice(&[0.0, self.omega * self.omega]);
        c.copy_from_slice(&[0.0, 2.0 * self.zeta * self.omega]);
        Some(2)
    }
}
