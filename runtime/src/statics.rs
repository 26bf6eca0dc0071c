//! Static equilibrium h(q, 0, t0) = 0 (or its mean over drum revolutions) by Newton's method
//! with the exact force Jacobian (`Mechanical::force_jacobians`, which every back end has):
//! the start of a run, so the tub does not drop under the unbalance's extra weight. Set-up
//! code: it may allocate.

use crate::system::Mechanical;
use washdyn_ode::lu::{lu_factor, lu_solve};

/// Solve for the rest position at time t0 (velocities zero). Returns q.
pub fn static_equilibrium<S: Mechanical>(sys: &mut S, t0: f64) -> Result<Vec<f64>, String> {
    equilibrium_avg(sys, t0, 1, 0.0)
}

/// Drum revolutions the mean-load start averages over: 4 revolutions hold exactly 45 motor
/// revolutions at the belt ratio 11.25, so both unbalances' forces average out.
pub const MEAN_REVOLUTIONS: f64 = 4.0;
/// Samples a revolution of that average (up to order 31 averages exactly).
const MEAN_SAMPLES_PER_REV: usize = 64;

/// The rest position under gravity and the mean loads at the speed of t0: h(q, 0, t) averaged
/// over [`MEAN_REVOLUTIONS`] drum revolutions at that speed. A rotating unbalance's
/// centrifugal force has mean zero there and is left to the dynamics, instead of being applied
/// as a static load (at 1180 rpm the static start would lift the tub 0.6 m). Loads that turn
/// with nothing (gravity, preloads, the drum's own centrifugal load in its frame) stay.
/// Without speed at t0 this is the static start.
pub fn mean_load_equilibrium<S: Mechanical>(sys: &mut S, t0: f64) -> Result<Vec<f64>, String> {
    let omega = sys.speed().drive(t0).omega.abs();
    if omega < 1e-9 {
        return equilibrium_avg(sys, t0, 1, 0.0);
    }
    let n_avg = (MEAN_REVOLUTIONS as usize) * MEAN_SAMPLES_PER_REV;
    let span = MEAN_REVOLUTIONS * 2.0 * std::f64::consts::PI / omega;
    equilibrium_avg(sys, t0, n_avg, span)
}

/// Newton on the residual h(q, 0, t) averaged over `samples` times spread evenly over
/// [t0, t0 + span), with the averaged stiffness.
fn equilibrium_avg<S: Mechanical>(
    sys: &mut S,
    t0: f64,
    samples: usize,
    span: f64,
) -> Result<Vec<f64>, String> {
    let lay = sys.layout();
    let (n, n1) = (lay.n(), lay.n1);
    let mut m1 = vec![0.0; n1 * n1];
    let zero = vec![0.0; n];
    let mut q = vec![0.0; n];
    let mut h = vec![0.0; n];
    // h(q, 0, t) at one sample time.
    let mut hk = vec![0.0; n];
    let (mut hq, mut hqd) = (vec![0.0; n * n], vec![0.0; n * n]);
    let time = |k: usize| t0 + span * k as f64 / samples as f64;
    let mut last_res = f64::INFINITY;
    for _ in 0..50 {
        h.fill(0.0);
        // The largest load sampled: the average cancels it to round-off, not to zero.
        let mut scale = 0.0f64;
        for k in 0..samples {
            sys.eval(time(k), &q, &zero, &mut m1, &mut hk);
            for i in 0..n {
                h[i] += hk[i] / samples as f64;
                scale = scale.max(hk[i].abs());
            }
        }
        let res = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if res < 1e-10 + 1e-13 * scale {
            return Ok(q);
        }
        let stalled = res > 0.5 * last_res;
        last_res = res;
        // Row-major dh/dq, averaged like the residual (a rotating load tilted with the tub has
        // a large stiffness at each instant and none on average): the back end's exact force
        // Jacobians.
        let mut k = vec![0.0; n * n];
        for s in 0..samples {
            sys.force_jacobians(time(s), &q, &zero, &mut hq, &mut hqd);
            for (kk, v) in k.iter_mut().zip(&hq) {
                *kk += v / samples as f64;
            }
        }
        let mut piv = vec![0; n];
        lu_factor(&mut k, n, &mut piv)
            .map_err(|_| "static equilibrium: singular stiffness (a free rigid-body motion?)")?;
        let mut dq: Vec<f64> = h.iter().map(|v| -v).collect();
        lu_solve(&k, n, &piv, &mut dq);
        for i in 0..n {
            q[i] += dq[i];
        }
        // A step this small ends it too (Newton's next error is its square): a stiff
        // bearing (a damper's moving part on 5e7 N/m) turns the positions' round-off into a
        // residual on the tub above the absolute floor (1e-9 N), which no step can lower.
        let step = dq.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let size = q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if step <= 1e-10 * size {
            return Ok(q);
        }
        // So does a residual that stopped falling under steps of round-off's size: stiff
        // joints (a counterweight's bolts, 1e9 N/m) turn the positions' round-off into a
        // residual noise that no Newton step lowers, and Newton would contract it by far more
        // than half.
        if stalled && step <= 1e-8 * size {
            return Ok(q);
        }
    }
    Err("static equilibrium: Newton did not converge in 50 iterations".into())
}
