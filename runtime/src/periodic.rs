//! The periodic steady state at constant speed by shooting, as a start: constant-speed studies
//! then need no settling time. Set-up code: it may allocate.
//!
//! The excitation repeats after [`statics::MEAN_REVOLUTIONS`] drum revolutions (4 drum = 45
//! motor revolutions at the belt ratio 11.25), so the steady state is a fixed point of the
//! flow map P over T = 4 revolutions: P(y) = y. Newton on r(y) = P(y) - y with the Jacobian
//! dP/dy - I by forward differences (2n + 1 integrations of one period each), from the
//! mean-load rest. P is integrated with dopri5 at rtol 1e-10, far below the difference step.

use crate::ode::lu::{lu_factor, lu_solve};
use crate::ode::{Dopri5, Options, Solver, Stepper};
use crate::speed::Speed;
use crate::statics::{MEAN_REVOLUTIONS, mean_load_equilibrium};
use crate::system::{FirstOrder, Mechanical};

/// Newton iterations at most.
const MAX_ITER: usize = 12;

/// The flow map over [t0, t0 + period] from y into `out`.
fn flow<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    t0: f64,
    period: f64,
    y: &[f64],
    out: &mut [f64],
) -> Result<(), String> {
    let mut s = Dopri5::new(
        y.len(),
        Options {
            rtol: 1e-10,
            atol: 1e-13,
            ..Options::default()
        },
    );
    let t1 = t0 + period;
    s.init(sys, t0, y).map_err(|e| e.to_string())?;
    while s.t() < t1 {
        s.step(sys, t1).map_err(|e| e.to_string())?;
    }
    out.copy_from_slice(s.y());
    Ok(())
}

/// The period of the steady state from t0 (4 drum revolutions), or why there is none: the
/// drum stands still, or its speed is not constant over that period (a run-up). The CLI asks
/// this before it writes anything.
pub fn period(speed: &Speed, t0: f64) -> Result<f64, String> {
    let d0 = speed.drive(t0);
    let omega = d0.omega.abs();
    if omega < 1e-9 {
        return Err(
            "periodic start: the drum stands still at the start; use --start static".into(),
        );
    }
    let period = MEAN_REVOLUTIONS * 2.0 * std::f64::consts::PI / omega;
    let d1 = speed.drive(t0 + period);
    let inside = speed.stops(t0, t0 + period).len() > 1;
    if (d1.omega - d0.omega).abs() > 1e-9 * omega
        || d0.omega_dot.abs() > 1e-12
        || d1.omega_dot.abs() > 1e-12
        || inside
    {
        return Err(format!(
            "periodic start: the drum speed is not constant over the {period:.4} s after t = {t0} s \
             (a periodic steady state needs constant speed)"
        ));
    }
    Ok(period)
}

/// The state [q; q'] at t0 on the periodic steady state. Refuses a speed that is not constant
/// over the period from t0 (a run-up has no periodic solution).
pub fn periodic_state<S: Mechanical>(sys: &mut FirstOrder<S>, t0: f64) -> Result<Vec<f64>, String> {
    let period = period(sys.sys.speed(), t0)?;
    let n = sys.layout().n();
    let m = 2 * n;
    let q0 = mean_load_equilibrium(&mut sys.sys, t0)?;
    let mut y = vec![0.0; m];
    y[..n].copy_from_slice(&q0);
    let mut py = vec![0.0; m];
    let mut yp = vec![0.0; m];
    let mut pp = vec![0.0; m];
    let mut jac = vec![0.0; m * m];
    let mut piv = vec![0; m];
    for _ in 0..MAX_ITER {
        flow(sys, t0, period, &y, &mut py)?;
        let r: Vec<f64> = py.iter().zip(&y).map(|(a, b)| a - b).collect();
        // Converged when the period map moves the state by less than 1e-9 of its scale
        // (positions in m and rad, velocities in m/s and rad/s).
        let scale = y.iter().fold(1e-3f64, |a, v| a.max(v.abs()));
        let res = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if res <= 1e-9 * scale {
            return Ok(y);
        }
        for j in 0..m {
            yp.copy_from_slice(&y);
            let d = 1e-7 * y[j].abs().max(1e-4);
            yp[j] += d;
            flow(sys, t0, period, &yp, &mut pp)?;
            for i in 0..m {
                jac[i * m + j] = (pp[i] - py[i]) / d - if i == j { 1.0 } else { 0.0 };
            }
        }
        lu_factor(&mut jac, m, &mut piv).map_err(|_| {
            "periodic start: singular shooting matrix (an undamped motion with the period?)"
                .to_string()
        })?;
        let mut dy: Vec<f64> = r.iter().map(|v| -v).collect();
        lu_solve(&jac, m, &piv, &mut dy);
        for i in 0..m {
            y[i] += dy[i];
        }
    }
    Err(format!(
        "periodic start: shooting did not converge in {MAX_ITER} Newton iterations"
    ))
}
