//! The periodic steady state at constant speed by shooting, as a start: constant-speed studies
//! then need no settling time. Set-up code: it may allocate.
//!
//! The excitation repeats after [`statics::MEAN_REVOLUTIONS`] drum revolutions (4 drum = 45
//! motor revolutions at the belt ratio 11.25), so the steady state is a fixed point of the
//! flow map P over T = 4 revolutions: P(y) = y, found from the mean-load rest by Anderson
//! acceleration of the fixed-point iteration y <- P(y) (Walker & Ni 2011, type II, memory
//! [`MEMORY`]): each iteration is one integration of one period, and on an affine map the
//! method is GMRES on (dP/dy - I) without forming it. The damped fast modes contract in one
//! period by themselves; the few slow ones (the suspension, lightly damped modes) are what the
//! memory solves for. Before: Newton with dP/dy by differences, 2n + 1 integrations per
//! iteration. P is integrated with dopri5 at rtol 1e-10. (Integrating the early iterations
//! at a tolerance 1e-2 of the residual was tried: the changing map spoils the memory, and the
//! rigid machine at 600 rpm took 157 integrations instead of 17.)

use crate::statics::{MEAN_REVOLUTIONS, mean_load_equilibrium};
use crate::system::{FirstOrder, Mechanical};
use nalgebra::{DMatrix, DVector};
use std::sync::atomic::{AtomicBool, Ordering};
use washdyn_model::speed::Speed;
use washdyn_ode::{Dopri5, OdeSystem, Options, Solver, Stepper};

/// Anderson's memory (previous iterates kept).
const MEMORY: usize = 16;
/// The fixed point's residual, relative to the state's scale: Anderson converges linearly
/// (Newton's last step overshot 1e-9 by orders), so it is asked for two orders more.
const TOL: f64 = 1e-11;
/// Integrations of one period at most.
const MAX_FLOWS: usize = 300;

/// Why the periodic start stopped without a state.
#[derive(Debug, Clone, PartialEq)]
pub enum StartStop {
    /// The interrupt flag was set (Ctrl-C): polled at every step of every period.
    Interrupted,
    /// No periodic state: the reason.
    Failed(String),
}

impl From<String> for StartStop {
    fn from(s: String) -> Self {
        StartStop::Failed(s)
    }
}

/// What the periodic start reports and obeys while it iterates: one period of the elastic
/// machine at rtol 1e-10 takes seconds, and the whole start minutes.
#[derive(Default)]
pub struct Watch<'a> {
    /// Polled at every integrator step: when set, the start stops with
    /// [`StartStop::Interrupted`].
    pub interrupt: Option<&'a AtomicBool>,
    /// Called after every period: (periods integrated so far, residual / tolerance).
    pub progress: Option<&'a mut dyn FnMut(usize, f64)>,
}

/// The flow map over [t0, t0 + period] from y into `out`, integrated at `rtol`.
fn flow<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    t0: f64,
    period: f64,
    y: &[f64],
    out: &mut [f64],
    rtol: f64,
    interrupt: Option<&AtomicBool>,
) -> Result<(), StartStop> {
    let mut s = Dopri5::new(
        y.len(),
        Options {
            rtol,
            atol: rtol * 1e-3,
            ..Options::default()
        },
    );
    let t1 = t0 + period;
    s.init(sys, t0, y).map_err(|e| e.to_string())?;
    while s.t() < t1 {
        if interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) {
            return Err(StartStop::Interrupted);
        }
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
    Ok(periodic_state_counted(sys, t0)?.0)
}

/// [`periodic_state`] and the number of one-period integrations it took.
pub fn periodic_state_counted<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    t0: f64,
) -> Result<(Vec<f64>, usize), String> {
    periodic_state_watched(sys, t0, Watch::default()).map_err(|e| match e {
        StartStop::Interrupted => "periodic start: interrupted".to_string(),
        StartStop::Failed(s) => s,
    })
}

/// [`periodic_state_counted`], reporting each period to `watch.progress` and stopping when
/// `watch.interrupt` is set.
pub fn periodic_state_watched<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    t0: f64,
    mut watch: Watch,
) -> Result<(Vec<f64>, usize), StartStop> {
    let period = period(sys.sys.speed(), t0)?;
    let n = sys.layout().n();
    // The whole state: [q; q'; z] (the element states are periodic too).
    let m = sys.layout().dim();
    let q0 = mean_load_equilibrium(&mut sys.sys, t0)?;
    let mut y = vec![0.0; m];
    y[..n].copy_from_slice(&q0);
    // The least squares weigh each component as the integrators' tolerance does (metres at
    // the markers), so no unit dominates.
    let mut w = vec![1.0; m];
    sys.atol_scales(&mut w);
    let mut g = vec![0.0; m];
    // History of (f_k, g_k), newest last.
    let mut hist: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    let mut best = f64::INFINITY;
    let rtol = 1e-10;
    for k in 0..MAX_FLOWS {
        flow(sys, t0, period, &y, &mut g, rtol, watch.interrupt)?;
        let f: Vec<f64> = g.iter().zip(&y).map(|(a, b)| a - b).collect();
        // Converged when the period map moves the state by less than TOL of its scale
        // (positions in m and rad, velocities in m/s and rad/s).
        let scale = y.iter().fold(1e-3f64, |a, v| a.max(v.abs()));
        let res = f.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if let Some(p) = watch.progress.as_mut() {
            p(k + 1, res / (TOL * scale));
        }
        if res <= TOL * scale {
            return Ok((y, k + 1));
        }
        if !res.is_finite() {
            return Err(StartStop::Failed(format!(
                "periodic start: the state became non-finite after {} periods",
                k + 1
            )));
        }
        // A step that made things much worse starts the memory afresh (the map is not
        // affine there: friction changing between sticking and sliding).
        if res > 1e3 * best {
            hist.clear();
        }
        best = best.min(res);
        hist.push((f.clone(), g.clone()));
        if hist.len() > MEMORY + 1 {
            hist.remove(0);
        }
        let mk = hist.len() - 1;
        if mk == 0 {
            y.copy_from_slice(&g);
            continue;
        }
        // min || W (f_k - dF gamma) ||, dF's columns f_{i+1} - f_i; then y = g_k - dG gamma.
        let df = DMatrix::from_fn(m, mk, |i, j| w[i] * (hist[j + 1].0[i] - hist[j].0[i]));
        let rhs = DVector::from_fn(m, |i, _| w[i] * f[i]);
        let svd = df.svd(true, true);
        // Directions below 1e-12 of the largest carry no information (relative cut-off).
        let eps = 1e-12 * svd.singular_values.max();
        let gamma = svd
            .solve(&rhs, eps)
            .map_err(|e| StartStop::Failed(format!("periodic start: {e}")))?;
        for i in 0..m {
            let mut v = g[i];
            for j in 0..mk {
                v -= gamma[j] * (hist[j + 1].1[i] - hist[j].1[i]);
            }
            y[i] = v;
        }
    }
    Err(StartStop::Failed(format!(
        "periodic start: no periodic state after {MAX_FLOWS} integrations of one period"
    )))
}
