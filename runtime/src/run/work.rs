//! The work a run has ahead of it, for projecting its wall time from the speed profile rather
//! than from the rate so far: an adaptive integrator's step follows the fastest excitation it
//! must resolve (the drum orders, whose frequencies scale with the drum speed), so its wall
//! cost per simulated second grows about as `a + |Omega(t)|`; the floor `a` stands for the
//! slowest dynamics (the suspension, the contacts and the start's transients), which hold the
//! step when the drum barely turns. A run-up's first seconds at low speed thus cost far less
//! than its last ones, and a projection linear in simulated time understates the rest many
//! times over.

use washdyn_model::speed::Speed;

/// The cost floor `a` of the work model, rad/s (10 rad/s is the 93 rpm wash hold: the hold
/// costs as much again as its speed says). Chosen for the runs that take hours, the elastic
/// run-ups whose step the tolerance sets: docs/performance.md has `auto` reaching 44.7 s of
/// the run-up in 394 s (8.8 s of wall a simulated second) and the whole of it in 6751 s (so
/// about 48 after 44.7 s; two versions of the scene, a rough figure), a ratio of 5.4 against
/// (a + mean |Omega|) ratios of 5.2 for a = 0 and 3.7 for a = 10 rad/s. A run whose step
/// stability sets is not sped up by a slow drum: the rigid `run reference` (dopri5 on its
/// stability limit) takes 1 590 steps a simulated second at 93 rpm and 1 680 at 1 330 rpm
/// (its progress lines), a ~ 600 rad/s by wall time, so there the projection errs long (at
/// t = 7.5 s it said 97 s for the 23 s left), never short.
pub const WORK_FLOOR_RAD_S: f64 = 10.0;

/// The work from `t0` to `t` of a run on `speed`: the integral of `WORK_FLOOR_RAD_S +
/// |Omega|` over [t0, t], exact for the piecewise-linear profile (|Omega| split where the speed
/// changes sign). Zero for t <= t0.
pub fn work(speed: &Speed, t0: f64, t: f64) -> f64 {
    if t <= t0 {
        return 0.0;
    }
    let mut knots = vec![t0];
    knots.extend(speed.stops(t0, t));
    let omega = |t: f64| speed.drive(t).omega;
    let mut w = WORK_FLOOR_RAD_S * (t - t0);
    for pair in knots.windows(2) {
        let (a, b) = (omega(pair[0]), omega(pair[1]));
        let dt = pair[1] - pair[0];
        // Linear between knots: the mean of |Omega|, or the two triangles around its zero.
        w += if a * b >= 0.0 {
            0.5 * (a.abs() + b.abs()) * dt
        } else {
            0.5 * (a * a + b * b) / (a.abs() + b.abs()) * dt
        };
    }
    w
}

/// The wall time still to go, s: the wall time `elapsed_s` spent on the work from `w_from` to
/// `w_now` (the run's [`work`] at the times the clock started and now), scaled to the work left
/// up to `w_end`. `None` before any work was done (nothing to scale).
pub fn projected_remaining_s(elapsed_s: f64, w_from: f64, w_now: f64, w_end: f64) -> Option<f64> {
    let done = w_now - w_from;
    (done > 0.0 && elapsed_s.is_finite()).then(|| elapsed_s * (w_end - w_now).max(0.0) / done)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A linear ramp Omega = k t from rest: W(t) = a t + k t^2 / 2, so a run that took E s to
    /// t has E (W(T) - W(t)) / W(t) to go, e.g. half-way through a ramp with a = 0 three
    /// quarters of the work are left: 3 E.
    #[test]
    fn projection_of_a_linear_ramp_is_the_closed_form() {
        let (t_end, rpm_end) = (100.0, 1200.0);
        let speed = Speed::new(&[[0.0, 0.0], [t_end, rpm_end]]);
        let k = rpm_end * PI / 30.0 / t_end;
        let a = WORK_FLOOR_RAD_S;
        let closed = |t: f64| a * t + 0.5 * k * t * t;
        for t in [1.0, 25.0, 50.0, 99.0] {
            let w = work(&speed, 0.0, t);
            assert!((w - closed(t)).abs() <= 1e-12 * closed(t), "W({t})");
        }
        let (t, elapsed) = (25.0, 40.0);
        let (w, w_end) = (work(&speed, 0.0, t), work(&speed, 0.0, t_end));
        let exact = elapsed * (closed(t_end) - closed(t)) / closed(t);
        let p = projected_remaining_s(elapsed, 0.0, w, w_end).unwrap();
        assert!((p - exact).abs() <= 1e-12 * exact);
        // Linear in simulated time would say 3 x 40 s; the ramp's remaining work says more.
        assert!(p > 3.0 * elapsed);
        // The clock started later: only the work since then counts.
        let w10 = work(&speed, 0.0, 10.0);
        let p = projected_remaining_s(elapsed, w10, w, w_end).unwrap();
        let exact = elapsed * (closed(t_end) - closed(t)) / (closed(t) - closed(10.0));
        assert!((p - exact).abs() <= 1e-12 * exact);
        assert_eq!(projected_remaining_s(elapsed, w, w, w_end), None);
    }

    /// Beyond the profile the speed holds; through a reversal |Omega| is two triangles.
    #[test]
    fn work_holds_past_the_profile_and_folds_a_reversal() {
        let w = 10.0 * PI / 30.0;
        let speed = Speed::new(&[[0.0, -10.0], [2.0, 10.0]]);
        let a = WORK_FLOOR_RAD_S;
        let exact = a * 5.0 + w + 3.0 * w;
        assert!((work(&speed, 0.0, 5.0) - exact).abs() < 1e-12 * exact);
        assert_eq!(work(&speed, 3.0, 3.0), 0.0);
    }
}
