//! Classic fixed-step RK4. Useful as a cross-check and for smooth non-stiff models where a
//! fixed sampling grid is wanted.
//!
//! Step size: `Options::h0` when > 0. With h0 = 0 the first `step` after `init` picks
//! h = (t_stop - t) / 1000 and keeps it until the next `init`. The last step before `t_stop` is
//! shortened to land on it exactly. Times are computed as t_init + n*h, so they do not drift.
//! Dense output is cubic Hermite from (y0, f0, y1, f1); f1 is the first stage of the next step,
//! so a step costs 4 right-hand side evaluations.

use super::common::{all_finite, check_budget, clip_step, hermite_stepper, min_step};
use super::tableau::RK4;
use super::{OdeError, OdeSystem, Options, Solver, Stats};

pub struct Rk4 {
    opts: Options,
    n: usize,
    /// Fixed step in use; 0 until chosen.
    h: f64,
    t_init: f64,
    /// Steps of size `h` taken since `init` (the time base for t_init + n*h).
    n_steps: u64,
    t: f64,
    t_prev: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    /// f at (t_prev, y_prev) and at (t, y).
    f_prev: Vec<f64>,
    f: Vec<f64>,
    k: [Vec<f64>; 3],
    tmp: Vec<f64>,
    stats: Stats,
}

impl Rk4 {
    pub fn new(dim: usize, options: Options) -> Self {
        Rk4 {
            opts: options,
            n: dim,
            h: 0.0,
            t_init: 0.0,
            n_steps: 0,
            t: 0.0,
            t_prev: 0.0,
            y: vec![0.0; dim],
            y_prev: vec![0.0; dim],
            f_prev: vec![0.0; dim],
            f: vec![0.0; dim],
            k: [vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]],
            tmp: vec![0.0; dim],
            stats: Stats::default(),
        }
    }

    /// The fixed step in use (0 before the first step when `h0` = 0).
    pub fn step_size(&self) -> f64 {
        self.h
    }

    /// Restart the work counters (they accumulate across `init` calls).
    pub fn reset_stats(&mut self) {
        self.stats = Stats::default();
    }
}

hermite_stepper!(Rk4, "rk4");

impl<S: OdeSystem + ?Sized> Solver<S> for Rk4 {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        assert_eq!(y0.len(), self.n, "state dimension");
        self.t = t0;
        self.t_prev = t0;
        self.t_init = t0;
        self.n_steps = 0;
        self.h = self.opts.h0;
        self.y.copy_from_slice(y0);
        self.y_prev.copy_from_slice(y0);
        if !all_finite(y0) {
            return Err(OdeError::NonFinite { t: t0 });
        }
        sys.rhs(t0, &self.y, &mut self.f);
        self.stats.rhs_evals += 1;
        self.f_prev.copy_from_slice(&self.f);
        if !all_finite(&self.f) {
            return Err(OdeError::NonFinite { t: t0 });
        }
        Ok(())
    }

    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        // Nothing to do at or before the current time (forward integration only).
        if t_stop.is_nan() || t_stop <= self.t {
            return Ok(());
        }
        check_budget(&self.stats, &self.opts, self.t)?;
        if self.h <= 0.0 {
            // Automatic choice; never below h_min, so a short interval is a single step.
            self.h = ((t_stop - self.t) / 1000.0).max(self.opts.h_min);
        }
        if self.h < min_step(self.t, &self.opts) {
            return Err(OdeError::StepSizeUnderflow {
                t: self.t,
                h: self.h,
            });
        }
        let (h, lands) = clip_step(self.t, self.h, t_stop);
        let n = self.n;
        let t0 = self.t;
        let tab = &RK4;

        // Stage 1 is f(t0, y0), already in `self.f`.
        std::mem::swap(&mut self.y_prev, &mut self.y);
        std::mem::swap(&mut self.f_prev, &mut self.f);
        let (y0, k1) = (&self.y_prev, &self.f_prev);
        for s in 1..4 {
            for i in 0..n {
                let mut acc = tab.a[s][0] * k1[i];
                for j in 1..s {
                    acc += tab.a[s][j] * self.k[j - 1][i];
                }
                self.tmp[i] = y0[i] + h * acc;
            }
            sys.rhs(t0 + tab.c[s] * h, &self.tmp, &mut self.k[s - 1]);
        }
        for i in 0..n {
            let mut acc = tab.b[0] * k1[i];
            for s in 1..4 {
                acc += tab.b[s] * self.k[s - 1][i];
            }
            self.y[i] = y0[i] + h * acc;
        }
        let t1 = if lands {
            t_stop
        } else {
            self.n_steps += 1;
            self.t_init + self.n_steps as f64 * self.h
        };
        if lands {
            // The grid restarts at t_stop if the caller keeps stepping without `init`.
            self.t_init = t_stop;
            self.n_steps = 0;
        }
        sys.rhs(t1, &self.y, &mut self.f);
        self.stats.rhs_evals += 4;
        self.stats.steps += 1;
        self.t_prev = t0;
        self.t = t1;
        if !all_finite(&self.y) || !all_finite(&self.f) {
            return Err(OdeError::NonFinite { t: t1 });
        }
        Ok(())
    }
}
