//! Undamped harmonic oscillator x'' = -omega^2 x as y = (x, v): the simplest vibration model,
//! with the exact solution x = x0 cos(omega t) + v0/omega sin(omega t).

use crate::OdeSystem;

#[derive(Clone, Copy, Debug)]
pub struct Harmonic {
    pub omega: f64,
}

impl Harmonic {
    /// Exact state at t from y0 at t = 0.
    pub fn exact(&self, y0: [f64; 2], t: f64) -> [f64; 2] {
        let (w, x0, v0) = (self.omega, y0[0], y0[1]);
        let (s, c) = (w * t).sin_cos();
        [x0 * c + v0 / w * s, -x0 * w * s + v0 * c]
    }
}

impl OdeSystem for Harmonic {
    fn dim(&self) -> usize {
        2
    }
    fn second_order(&self) -> Option<usize> {
        Some(1)
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -self.omega * self.omega * y[0];
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], jac: &mut [f64]) -> bool {
        jac.copy_from_slice(&[0.0, 1.0, -self.omega * self.omega, 0.0]);
        true
    }
    /// All of it: unit mass, omega^2 (an IMEX method then integrates it implicitly).
    fn linear_part(
        &mut self,
        _t: f64,
        _y: &[f64],
        _m1: &mut [f64],
        k: &mut [f64],
        c: &mut [f64],
    ) -> Option<usize> {
        k[0] = self.omega * self.omega;
        c[0] = 0.0;
        Some(0)
    }
}
