//! A mechanical system with a first-order state after [q; q'] (as a presliding friction
//! law's deflection follows the state): the oscillator x'' = -omega^2 x + c z with
//! z' = lambda (sin t - z), z(0) = 0. The tail is solved first, then the driven oscillator:
//! z = lambda / (1 + lambda^2) (lambda sin t - cos t + exp(-lambda t)), and x is the response
//! of x'' + omega^2 x = c z to each of z's three terms (closed forms in `exact`).

use crate::OdeSystem;

#[derive(Clone, Copy, Debug)]
pub struct Tailed {
    pub omega: f64,
    pub lambda: f64,
    pub c: f64,
}

impl Tailed {
    /// Exact (x, x', z) at t from x(0) = 1, x'(0) = 0, z(0) = 0 (omega != 1).
    pub fn exact(&self, t: f64) -> [f64; 3] {
        let (w, l, c) = (self.omega, self.lambda, self.c);
        let k = c * l / (1.0 + l * l);
        // Particular solutions of x'' + w^2 x = k (l sin t - cos t + exp(-l t)).
        let a = k * l / (w * w - 1.0);
        let b = -k / (w * w - 1.0);
        let e = k / (l * l + w * w);
        let xp = a * t.sin() + b * t.cos() + e * (-l * t).exp();
        let vp = a * t.cos() - b * t.sin() - l * e * (-l * t).exp();
        // The homogeneous part meets x(0) = 1, x'(0) = 0.
        let (c0, s0) = (1.0 - (b + e), -(a - l * e) / w);
        let (s, co) = (w * t).sin_cos();
        let z = k / c * (l * t.sin() - t.cos() + (-l * t).exp());
        [
            c0 * co + s0 * s + xp,
            -c0 * w * s + s0 * w * co + vp,
            if c == 0.0 { 0.0 } else { z },
        ]
    }
}

impl OdeSystem for Tailed {
    fn dim(&self) -> usize {
        3
    }
    fn second_order(&self) -> Option<usize> {
        Some(1)
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -self.omega * self.omega * y[0] + self.c * y[2];
        dy[2] = self.lambda * (t.sin() - y[2]);
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], jac: &mut [f64]) -> bool {
        let w2 = self.omega * self.omega;
        jac.copy_from_slice(&[0.0, 1.0, 0.0, -w2, 0.0, self.c, 0.0, 0.0, -self.lambda]);
        true
    }
}
