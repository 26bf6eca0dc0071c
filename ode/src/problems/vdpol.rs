//! Van der Pol oscillator in Hairer & Wanner's scaling: y1' = y2,
//! y2' = ((1 - y1^2) y2 - y1) / eps. eps = 1e-6 on [0, 2] from y(0) = (2, 0) is problem VDPOL
//! of the Test Set for IVP Solvers (Mazzia & Magherini), with a published reference at t = 2.
//! eps = 1/mu^2 relates it to the classic form x'' = mu (1 - x^2) x' - x by t = mu * tau,
//! y2 = x' / mu.

use crate::OdeSystem;

#[derive(Clone, Copy, Debug)]
pub struct VanDerPol {
    pub eps: f64,
}

impl VanDerPol {
    /// Test Set VDPOL: eps, initial value, end time and reference (`vdpol.f`, `solut`,
    /// computed with RADAU at rtol = atol = 1.1e-18).
    pub const TESTSET_EPS: f64 = 1e-6;
    pub const TESTSET_Y0: [f64; 2] = [2.0, 0.0];
    pub const TESTSET_T_END: f64 = 2.0;
    pub const TESTSET_REFERENCE: [f64; 2] = [0.1706167732170483e1, -0.8928097010247975];
}

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn second_order(&self) -> Option<usize> {
        Some(1)
    }
    fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) {
        f[0] = y[1];
        f[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / self.eps;
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = 0.0;
        jac[1] = 1.0;
        jac[2] = (-2.0 * y[0] * y[1] - 1.0) / self.eps;
        jac[3] = (1.0 - y[0] * y[0]) / self.eps;
        true
    }
}

/// The classic form x'' = mu (1 - x^2) x' - x as y = (x, x'), for mildly stiff mu = 1..10.
/// For mu = 1 the periodic orbit passes through (2.00861986087484313650940188, 0) with period
/// 6.6632868593231301896996820305 (values attributed to Hairer, Norsett & Wanner in widely used
/// course material on their Van der Pol example; the period is published independently by
/// P. Amore, arXiv:2111.12198, T = 6.663286859323130).
#[derive(Clone, Copy, Debug)]
pub struct VanDerPolClassic {
    pub mu: f64,
}

impl VanDerPolClassic {
    pub const MU1_AMPLITUDE: f64 = 2.008_619_860_874_843;
    pub const MU1_PERIOD: f64 = 6.663_286_859_323_13;
}

impl OdeSystem for VanDerPolClassic {
    fn dim(&self) -> usize {
        2
    }
    fn second_order(&self) -> Option<usize> {
        Some(1)
    }
    fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) {
        f[0] = y[1];
        f[1] = self.mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = 0.0;
        jac[1] = 1.0;
        jac[2] = -2.0 * self.mu * y[0] * y[1] - 1.0;
        jac[3] = self.mu * (1.0 - y[0] * y[0]);
        true
    }
}
