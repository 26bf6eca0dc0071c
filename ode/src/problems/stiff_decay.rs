//! y' = -k (y - cos t): a fast relaxation (rate k) onto a slowly moving target, the shape of a
//! stiff spring dragged along by a slow motion. Closed form for y(0) = y0:
//! y = p(t) + (y0 - p(0)) exp(-k t), p(t) = (k^2 cos t + k sin t) / (k^2 + 1).

use crate::OdeSystem;

#[derive(Clone, Copy, Debug)]
pub struct StiffDecay {
    pub k: f64,
}

impl StiffDecay {
    pub fn exact(&self, y0: f64, t: f64) -> f64 {
        let k = self.k;
        let p = |t: f64| (k * k * t.cos() + k * t.sin()) / (k * k + 1.0);
        p(t) + (y0 - p(0.0)) * (-k * t).exp()
    }
}

impl OdeSystem for StiffDecay {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -self.k * (y[0] - t.cos());
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = -self.k;
        true
    }
}
