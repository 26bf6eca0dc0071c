//! The work a run has ahead of it, for projecting its wall time from the speed profile rather
//! than from the rate so far. An adaptive integrator's step follows the fastest excitation it
//! must resolve (the drum orders, whose frequencies scale with the drum speed) where its
//! tolerance sets the step, so its wall cost per simulated second grows with |Omega(t)|; where
//! its stability sets the step (the rigid `run reference`: dopri5 on its stability limit takes
//! 1 590 steps a simulated second at 93 rpm and 1 680 at 1 330 rpm) the cost barely depends on
//! the speed. So the wall time is modelled as `c0 (t - t_c) + c1 S(t)`, with `S` the angle the
//! drum sweeps, the integral of |Omega| (exact for the profile: [`swept`]), and `c0`, `c1` >= 0
//! fitted to the run's own wall time as it goes ([`CostFit`]): a run-up's slow start then does
//! not understate its fast end, and a run whose cost is flat is not projected long.

use washdyn_model::speed::Speed;

/// The prior ratio `c0 / c1` of the cost model, rad/s, used while the run's own history cannot
/// tell the two terms apart (the speed has not changed since the clock started): 10 rad/s is
/// about the 93 rpm wash hold. From the elastic run-ups of docs/performance.md (`auto`: 44.7 s
/// in 394 s of wall, the whole run-up in 6 751 s, a cost per simulated second 5.4 times higher
/// after 44.7 s than before), which fit a ratio between 0 and 10 rad/s.
pub const WORK_FLOOR_RAD_S: f64 = 10.0;

/// The angle the drum sweeps from `t0` to `t` on `speed`, rad: the integral of |Omega| over
/// [t0, t], exact for the piecewise-linear profile (|Omega| split where the speed changes
/// sign). Zero for t <= t0.
pub fn swept(speed: &Speed, t0: f64, t: f64) -> f64 {
    if t <= t0 {
        return 0.0;
    }
    let omega = |t: f64| speed.drive(t).omega;
    // Linear between knots: the mean of |Omega|, or the two triangles around its zero. No
    // allocation: the run loop reports its progress with it (tests/no_alloc.rs).
    let segment = |from: f64, to: f64| {
        let (a, b) = (omega(from), omega(to));
        let dt = to - from;
        if a * b >= 0.0 {
            0.5 * (a.abs() + b.abs()) * dt
        } else {
            0.5 * (a * a + b * b) / (a.abs() + b.abs()) * dt
        }
    };
    let mut from = t0;
    let mut w = 0.0;
    for &k in speed.knots().iter().filter(|&&k| k > t0 && k < t) {
        w += segment(from, k);
        from = k;
    }
    w + segment(from, t)
}

/// The run's cost model `wall = c0 dt + c1 dS` fitted by least squares to its history (wall
/// time, simulated time and swept angle since the clock started), both coefficients kept >= 0.
#[derive(Clone, Debug, Default)]
pub struct CostFit {
    /// Sums of the normal equations over the history: x = dt, y = dS, w = wall.
    sxx: f64,
    sxy: f64,
    syy: f64,
    sxw: f64,
    syw: f64,
}

impl CostFit {
    /// One point of the history: `wall_s` of wall time spent on `dt` s simulated and `ds` rad
    /// swept since the clock started.
    pub fn add(&mut self, wall_s: f64, dt: f64, ds: f64) {
        if !(wall_s.is_finite() && dt.is_finite() && ds.is_finite()) {
            return;
        }
        self.sxx += dt * dt;
        self.sxy += dt * ds;
        self.syy += ds * ds;
        self.sxw += dt * wall_s;
        self.syw += ds * wall_s;
    }

    /// `(c0, c1)`: s of wall per simulated s, and per rad swept. `None` before any history.
    pub fn coefficients(&self) -> Option<(f64, f64)> {
        let (sxx, sxy, syy) = (self.sxx, self.sxy, self.syy);
        if sxx <= 0.0 {
            return None;
        }
        let det = sxx * syy - sxy * sxy;
        // Collinear history (one speed since the clock started): the prior ratio c0 = a c1.
        if det <= 1e-6 * sxx * syy || syy <= 0.0 {
            let a = WORK_FLOOR_RAD_S;
            let zz = a * a * sxx + 2.0 * a * sxy + syy;
            let c1 = (a * self.sxw + self.syw) / zz;
            return Some((a * c1.max(0.0), c1.max(0.0)));
        }
        let c0 = (syy * self.sxw - sxy * self.syw) / det;
        let c1 = (sxx * self.syw - sxy * self.sxw) / det;
        Some(if c0 < 0.0 {
            (0.0, (self.syw / syy).max(0.0))
        } else if c1 < 0.0 {
            ((self.sxw / sxx).max(0.0), 0.0)
        } else {
            (c0, c1)
        })
    }

    /// The wall time still to go, s, for `dt_left` s simulated and `ds_left` rad swept.
    pub fn remaining_s(&self, dt_left: f64, ds_left: f64) -> Option<f64> {
        let (c0, c1) = self.coefficients()?;
        Some(c0 * dt_left.max(0.0) + c1 * ds_left.max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A linear ramp Omega = k t from rest sweeps S(t) = k t^2 / 2.
    #[test]
    fn swept_angle_of_a_ramp_is_the_closed_form() {
        let (t_end, rpm_end) = (100.0, 1200.0);
        let speed = Speed::new(&[[0.0, 0.0], [t_end, rpm_end]]);
        let k = rpm_end * PI / 30.0 / t_end;
        for t in [1.0, 25.0, 50.0, 99.0] {
            let s = swept(&speed, 0.0, t);
            let exact = 0.5 * k * t * t;
            assert!((s - exact).abs() <= 1e-12 * exact, "S({t})");
        }
    }

    /// Beyond the profile the speed holds; through a reversal |Omega| is two triangles.
    #[test]
    fn swept_holds_past_the_profile_and_folds_a_reversal() {
        let w = 10.0 * PI / 30.0;
        let speed = Speed::new(&[[0.0, -10.0], [2.0, 10.0]]);
        let exact = w + 3.0 * w;
        assert!((swept(&speed, 0.0, 5.0) - exact).abs() < 1e-12 * exact);
        assert_eq!(swept(&speed, 3.0, 3.0), 0.0);
    }

    /// A run whose wall time is exactly c0 t + c1 S(t) on a ramp: the fit recovers both, so the
    /// projection is exact; a cost flat in the speed (c1 = 0, the rigid run's) projects linearly
    /// in simulated time; a history at one speed takes the prior ratio.
    #[test]
    fn the_fit_recovers_the_cost_model_and_projects_exactly() {
        let speed = Speed::new(&[[0.0, 0.0], [100.0, 1200.0]]);
        for (c0, c1) in [(0.5, 0.02), (2.0, 0.0), (0.0, 0.1)] {
            let mut fit = CostFit::default();
            for i in 1..=40 {
                let t = 0.5 * f64::from(i);
                let s = swept(&speed, 0.0, t);
                fit.add(c0 * t + c1 * s, t, s);
            }
            let (a, b) = fit.coefficients().unwrap();
            assert!((a - c0).abs() < 1e-9 && (b - c1).abs() < 1e-9, "{a} {b}");
            let (dt, ds) = (80.0, swept(&speed, 20.0, 100.0));
            let exact = c0 * dt + c1 * ds;
            assert!((fit.remaining_s(dt, ds).unwrap() - exact).abs() < 1e-6 * exact);
        }
        // One speed so far (a hold): wall = 3 s per simulated s, with S = w t.
        let w = 93.0 * PI / 30.0;
        let mut fit = CostFit::default();
        for i in 1..=10 {
            let t = f64::from(i);
            fit.add(3.0 * t, t, w * t);
        }
        let (a, b) = fit.coefficients().unwrap();
        assert!((a / b - WORK_FLOOR_RAD_S).abs() < 1e-9);
        assert!((a + b * w - 3.0).abs() < 1e-9, "the rate so far is kept");
        assert_eq!(CostFit::default().remaining_s(1.0, 1.0), None);
    }
}
