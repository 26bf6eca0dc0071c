//! y' = y^2, y(0) = 1: y = 1 / (1 - t) blows up at t = 1. Exercises the failure paths.

use crate::OdeSystem;

#[derive(Clone, Copy, Debug, Default)]
pub struct Blowup;

impl OdeSystem for Blowup {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[0] * y[0];
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = 2.0 * y[0];
        true
    }
}
