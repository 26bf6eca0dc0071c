//! Dormand-Prince 5(4) with FSAL, Hairer's error norm, a PI step size controller and Hairer's
//! fourth-order continuous extension for dense output. The workhorse for non-stiff models.
//!
//! Step control (Solving ODEs I, Section IV.2 of vol. II for the PI form):
//! h_new = h * clamp(0.9 * err^-(0.2 - 0.75*beta) * err_prev^beta, 0.2, 10), beta = 0.04; after a
//! rejection the step may not grow. A trial step whose stages are not finite is rejected with
//! h / 10; ten such trials in a row end the integration with `NonFinite` at the last good time.
//!
//! Stiffness detection (Hairer & Wanner I, Section IV.2; Hairer's dopri5.f): stages 6 and 7 sit
//! at the same time, so h rho ~ h |k7 - k6| / |y7 - y6| estimates h times the dominant
//! eigenvalue for free. Above 3.25 (the stability boundary along the negative axis) the step is
//! counted as stiff; 15 such steps with fewer than 6 non-stiff ones between them mark the
//! problem stiff (`Stats::stiff_at`): the run then chatters on the stability limit and an
//! implicit method would take larger steps.

use super::common::{
    PiControl, Tolerance, Trials, after_landing, all_finite, error_norm, initial_step, propose_step,
};
use super::tableau::{DOPRI5, DOPRI5_DENSE_D};
use super::{OdeError, OdeSystem, Options, Solver, Stats, Stepper};

/// Largest growth of the step after an accepted one.
const FAC_MAX: f64 = 10.0;
/// Hairer's stiffness test: h rho above this is on the stability boundary ...
const STIFF_H_RHO: f64 = 3.25;
/// ... this many times ...
const STIFF_COUNT: u32 = 15;
/// ... unless this many non-stiff steps came in between.
const NONSTIFF_RESET: u32 = 6;

pub struct Dopri5 {
    opts: Options,
    tol: Tolerance,
    n: usize,
    t: f64,
    t_prev: f64,
    /// Step size proposed for the next step (0 = choose at the first step).
    h: f64,
    /// Size of the last accepted step.
    h_last: f64,
    control: PiControl,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    y_new: Vec<f64>,
    /// Stage derivatives k1..k7; k[0] holds f(t, y) between steps (FSAL).
    k: [Vec<f64>; 7],
    err: Vec<f64>,
    /// Dense output coefficients of the last accepted step (Hairer's r1..r5).
    dense: [Vec<f64>; 5],
    stats: Stats,
    /// Hairer's stiffness counters: stiff steps so far, non-stiff steps since the last one.
    stiff_count: u32,
    nonstiff_count: u32,
}

impl Dopri5 {
    pub fn new(dim: usize, options: Options) -> Self {
        let v = || vec![0.0; dim];
        Dopri5 {
            tol: Tolerance::new(&options, dim),
            opts: options,
            n: dim,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            h_last: 0.0,
            control: PiControl::new(DOPRI5.order_hat, FAC_MAX),
            y: v(),
            y_prev: v(),
            y_new: v(),
            k: [v(), v(), v(), v(), v(), v(), v()],
            err: v(),
            dense: [v(), v(), v(), v(), v()],
            stats: Stats::default(),
            stiff_count: 0,
            nonstiff_count: 0,
        }
    }

    /// The step size the controller proposes next.
    pub fn step_size(&self) -> f64 {
        self.h
    }

    /// Restart the work counters (they accumulate across `init` calls).
    pub fn reset_stats(&mut self) {
        self.stats = Stats::default();
    }

    /// Whether Hairer's test calls the problem stiff now (15 stiff steps with fewer than 6
    /// non-stiff ones between them, since the last `reset_stiffness`).
    pub fn is_stiff(&self) -> bool {
        self.stiff_count >= STIFF_COUNT
    }

    /// Forget the stiffness counters (a composite method hands the problem back).
    pub fn reset_stiffness(&mut self) {
        self.stiff_count = 0;
        self.nonstiff_count = 0;
    }

    /// Options the composite method adjusts between hand-overs: the first step of the next
    /// `init` and the step budget.
    pub fn set_start(&mut self, h0: f64, max_steps: u64) {
        self.opts.h0 = h0;
        self.opts.max_steps = max_steps;
    }

    /// Hairer's test on the accepted step (before the FSAL swap): k7 - k6 against
    /// y7 - y6 = h sum_j (a7j - a6j) k_j, both at t + h.
    fn detect_stiffness(&mut self, h: f64, t_new: f64) {
        let a = &DOPRI5.a;
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..self.n {
            let dk = self.k[6][i] - self.k[5][i];
            let mut dy = 0.0;
            for j in 0..6 {
                dy += (a[6][j] - a[5][j]) * self.k[j][i];
            }
            num += dk * dk;
            den += (h * dy) * (h * dy);
        }
        if den > 0.0 && h * (num / den).sqrt() > STIFF_H_RHO {
            self.stats.stiff_steps += 1;
            self.nonstiff_count = 0;
            self.stiff_count += 1;
            if self.stiff_count >= STIFF_COUNT && self.stats.stiff_at.is_none() {
                self.stats.stiff_at = Some(t_new);
            }
        } else {
            self.nonstiff_count += 1;
            if self.nonstiff_count >= NONSTIFF_RESET {
                self.stiff_count = 0;
            }
        }
    }

    /// Stages 2..7 and the new solution for step size h; returns the error norm.
    fn attempt<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> f64 {
        let n = self.n;
        let t0 = self.t;
        let tab = &DOPRI5;
        for s in 1..7 {
            {
                let (done, _) = self.k.split_at(s);
                for i in 0..n {
                    let mut acc = 0.0;
                    for (j, kj) in done.iter().enumerate() {
                        acc += tab.a[s][j] * kj[i];
                    }
                    self.y_new[i] = self.y[i] + h * acc;
                }
            }
            // Stage 7 is evaluated at the new solution (its row of A is b).
            sys.rhs(t0 + tab.c[s] * h, &self.y_new, &mut self.k[s]);
        }
        self.stats.rhs_evals += 6;
        for i in 0..n {
            let mut e = 0.0;
            for s in 0..7 {
                e += (tab.b[s] - tab.b_hat[s]) * self.k[s][i];
            }
            self.err[i] = h * e;
        }
        let norm = error_norm(&self.err, &self.y, &self.y_new, &self.tol);
        if norm.is_finite() && !all_finite(&self.y_new) {
            return f64::INFINITY;
        }
        norm
    }
}

impl Stepper for Dopri5 {
    fn name(&self) -> &'static str {
        "dopri5"
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn y(&self) -> &[f64] {
        &self.y
    }

    fn t_prev(&self) -> f64 {
        self.t_prev
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let theta = if self.h_last > 0.0 {
            (t - self.t_prev) / self.h_last
        } else {
            0.0
        };
        let th1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5] = &self.dense;
        for i in 0..out.len() {
            out[i] = r1[i] + theta * (r2[i] + th1 * (r3[i] + theta * (r4[i] + th1 * r5[i])));
        }
    }

    fn stats(&self) -> Stats {
        self.stats
    }
}

impl<S: OdeSystem + ?Sized> Solver<S> for Dopri5 {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        self.tol.fill(sys);
        assert_eq!(y0.len(), self.n, "state dimension");
        self.t = t0;
        self.t_prev = t0;
        self.h_last = 0.0;
        self.control.reset();
        self.y.copy_from_slice(y0);
        self.y_prev.copy_from_slice(y0);
        // Dense output before the first step is the constant y0.
        for d in self.dense.iter_mut() {
            d.fill(0.0);
        }
        self.dense[0].copy_from_slice(y0);
        if !all_finite(y0) {
            return Err(OdeError::NonFinite { t: t0 });
        }
        sys.rhs(t0, &self.y, &mut self.k[0]);
        self.stats.rhs_evals += 1;
        if !all_finite(&self.k[0]) {
            return Err(OdeError::NonFinite { t: t0 });
        }
        self.h = if self.opts.h0 > 0.0 {
            self.opts.h0.min(self.opts.h_max)
        } else {
            let (a, b) = self.k.split_at_mut(1);
            let (y1, rest) = b.split_at_mut(1);
            initial_step(
                sys,
                t0,
                &self.y,
                &a[0],
                DOPRI5.order,
                (&self.opts, &self.tol),
                &mut y1[0],
                &mut rest[0],
                &mut self.stats,
            )
        };
        Ok(())
    }

    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        // Nothing to do at or before the current time (forward integration only).
        if t_stop.is_nan() || t_stop <= self.t {
            return Ok(());
        }
        let mut trials = Trials::default();
        loop {
            let (h, lands, h_prop) = propose_step(self.t, self.h, t_stop, &self.opts, &self.stats)?;
            let err = self.attempt(sys, h);

            if !err.is_finite() {
                self.h = trials.non_finite(self.t, h, &mut self.stats)?;
                continue;
            }
            if err > 1.0 {
                trials.rejected(&mut self.stats);
                self.h = self.control.rejected(h, err);
                continue;
            }

            // Accepted: PI controller for the next step.
            let fac = self.control.accepted(err, &trials);
            self.h = after_landing(
                (h * fac).min(self.opts.h_max),
                h_prop,
                lands,
                trials.rejected_last,
            );

            let t_new = if lands { t_stop } else { self.t + h };
            // Dense output coefficients (Hairer's continuous extension).
            let d = &DOPRI5_DENSE_D;
            for i in 0..self.n {
                let y0 = self.y[i];
                let y1 = self.y_new[i];
                let dy = y1 - y0;
                let r3 = h * self.k[0][i] - dy;
                self.dense[0][i] = y0;
                self.dense[1][i] = dy;
                self.dense[2][i] = r3;
                self.dense[3][i] = dy - h * self.k[6][i] - r3;
                let mut acc = 0.0;
                for (ds, ks) in d.iter().zip(&self.k) {
                    acc += ds * ks[i];
                }
                self.dense[4][i] = h * acc;
            }
            self.detect_stiffness(h, t_new);
            std::mem::swap(&mut self.y_prev, &mut self.y);
            std::mem::swap(&mut self.y, &mut self.y_new);
            // FSAL: f(t_new, y_new) becomes the first stage of the next step.
            self.k.swap(0, 6);
            self.stats.steps += 1;
            self.t_prev = self.t;
            self.t = t_new;
            self.h_last = h;
            if !all_finite(&self.y) {
                return Err(OdeError::NonFinite { t: t_new });
            }
            return Ok(());
        }
    }
}
