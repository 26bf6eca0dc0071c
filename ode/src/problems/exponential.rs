//! y' = lambda * y, the Dahlquist test equation: y(t) = y0 * exp(lambda * (t - t0)).

use crate::OdeSystem;

#[derive(Clone, Copy, Debug)]
pub struct Exponential {
    pub lambda: f64,
}

impl Exponential {
    pub fn exact(&self, t0: f64, y0: f64, t: f64) -> f64 {
        y0 * (self.lambda * (t - t0)).exp()
    }
}

impl OdeSystem for Exponential {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = self.lambda * y[0];
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = self.lambda;
        true
    }
}
