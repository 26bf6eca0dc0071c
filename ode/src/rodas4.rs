//! RODAS4, a linearly implicit (Rosenbrock) method of order 4 with an embedded order 3,
//! L-stable and stiffly accurate (Hairer & Wanner, Solving ODEs II, Section VI.4; tableau
//! [`RODAS4`](super::tableau::RODAS4)). No Newton iteration: each step solves six linear systems
//! with the one matrix W = I / (h gamma) - J, so its cost is predictable and it cannot diverge,
//! but it needs a Jacobian at every step (analytic when the system has one).
//!
//! * Jacobian and df/dt at every accepted point; df/dt by a forward difference in t (one extra
//!   f evaluation), as Hairer's `rodas` does for non-autonomous systems. After a rejection
//!   the same J is refactorised with the new h.
//! * Error estimate: the last stage (e = (0,..,0,1)), in Hairer's RMS norm; h_new = h * 0.9 *
//!   err^(-1/4), limited to [h/5, 6h], no growth after a rejection.
//! * The right-hand side at the new point is the next step's first stage, so dense output is the
//!   cubic Hermite interpolant from (y0, f0, y1, f1) at no extra cost (third order).

use super::common::{
    StartBuffers, Tolerance, Trials, after_landing, all_finite, error_norm, hermite_stepper,
    propose_step, start,
};
use super::iteration::IterationMatrix;
use super::tableau::RODAS4;
use super::{OdeError, OdeSystem, Options, Solver, Stats};

const STAGES: usize = 6;
const SAFETY: f64 = 0.9;
const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 6.0;

pub struct Rodas4 {
    opts: Options,
    tol: Tolerance,
    n: usize,
    t: f64,
    t_prev: f64,
    h: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    y_new: Vec<f64>,
    /// f at (t, y) and (t_prev, y_prev).
    f: Vec<f64>,
    f_prev: Vec<f64>,
    /// df/dt at (t, y).
    ft: Vec<f64>,
    jac: Vec<f64>,
    /// The Jacobian belongs to the current (t, y).
    jac_valid: bool,
    lu: IterationMatrix,
    /// Step size the LU of W belongs to (0 = none).
    lu_h: f64,
    u: [Vec<f64>; STAGES],
    ytmp: Vec<f64>,
    ftmp: Vec<f64>,
    err: Vec<f64>,
    stats: Stats,
}

impl Rodas4 {
    pub fn new(dim: usize, options: Options) -> Self {
        let v = || vec![0.0; dim];
        Rodas4 {
            tol: Tolerance::new(&options, dim),
            opts: options,
            n: dim,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            y: v(),
            y_prev: v(),
            y_new: v(),
            f: v(),
            f_prev: v(),
            ft: v(),
            jac: vec![0.0; dim * dim],
            jac_valid: false,
            lu: IterationMatrix::new(dim),
            lu_h: 0.0,
            u: [v(), v(), v(), v(), v(), v()],
            ytmp: v(),
            ftmp: v(),
            err: v(),
            stats: Stats::default(),
        }
    }

    /// The step size the controller proposes next.
    pub fn step_size(&self) -> f64 {
        self.h
    }

    /// f(t, y) at the current state.
    pub fn rhs_now(&self) -> &[f64] {
        &self.f
    }

    /// Options the composite method adjusts between hand-overs: the first step of the next
    /// `init` and the step budget.
    pub fn set_start(&mut self, h0: f64, max_steps: u64) {
        self.opts.h0 = h0;
        self.opts.max_steps = max_steps;
    }

    /// Restart the work counters (they accumulate across `init` calls).
    pub fn reset_stats(&mut self) {
        self.stats = Stats::default();
    }

    /// J and df/dt at (t, y); `self.f` holds f(t, y). Forward differences for J when the
    /// system has no analytic Jacobian (increments as in `sdirk4`).
    fn jacobian<S: OdeSystem + ?Sized>(&mut self, sys: &mut S) {
        let n = self.n;
        self.stats.jacobian_evals += 1;
        if !self.lu.jacobian(sys, self.t, &self.y, &mut self.jac) {
            self.ytmp.copy_from_slice(&self.y);
            for j in 0..n {
                let yj = self.y[j];
                self.ytmp[j] = yj + (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
                let d = self.ytmp[j] - yj;
                sys.rhs(self.t, &self.ytmp, &mut self.ftmp);
                for i in 0..n {
                    self.jac[i * n + j] = (self.ftmp[i] - self.f[i]) / d;
                }
                self.ytmp[j] = yj;
            }
            self.stats.rhs_evals += n as u64;
        }
        let dt = (f64::EPSILON * self.t.abs().max(1e-5)).sqrt();
        let dt = (self.t + dt) - self.t;
        sys.rhs(self.t + dt, &self.y, &mut self.ft);
        self.stats.rhs_evals += 1;
        for i in 0..n {
            self.ft[i] = (self.ft[i] - self.f[i]) / dt;
        }
        self.jac_valid = true;
        self.lu_h = 0.0;
    }

    /// One trial step of size h into `y_new`; the error norm, or `None` for non-finite
    /// values, or `Err` for a singular W.
    fn attempt<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> Result<Option<f64>, ()> {
        let n = self.n;
        let m = &RODAS4;
        if self.lu_h != h {
            self.stats.lu_decompositions += 1;
            if self.lu.factor(&self.jac, 1.0 / (h * m.gamma), 1.0).is_err() {
                self.lu_h = 0.0;
                return Err(());
            }
            self.lu_h = h;
        }
        for st in 0..STAGES {
            let (done, rest) = self.u.split_at_mut(st);
            let ui = &mut rest[0];
            if st == 0 {
                ui.copy_from_slice(&self.f);
            } else {
                for i in 0..n {
                    let mut acc = self.y[i];
                    for (j, uj) in done.iter().enumerate() {
                        acc += m.a[st][j] * uj[i];
                    }
                    self.ytmp[i] = acc;
                }
                sys.rhs(self.t + m.c[st] * h, &self.ytmp, ui);
                self.stats.rhs_evals += 1;
            }
            for i in 0..n {
                let mut acc = ui[i] + h * m.d[st] * self.ft[i];
                for (j, uj) in done.iter().enumerate() {
                    acc += m.cm[st][j] / h * uj[i];
                }
                ui[i] = acc;
            }
            self.lu.solve(&self.jac, ui);
        }
        for i in 0..n {
            let mut y = self.y[i];
            let mut e = 0.0;
            for st in 0..STAGES {
                y += m.b[st] * self.u[st][i];
                e += m.e[st] * self.u[st][i];
            }
            self.y_new[i] = y;
            self.err[i] = e;
        }
        if !all_finite(&self.y_new) {
            return Ok(None);
        }
        let err = error_norm(&self.err, &self.y, &self.y_new, &self.tol);
        Ok(err.is_finite().then_some(err))
    }
}

hermite_stepper!(Rodas4, "rodas4");

impl<S: OdeSystem + ?Sized> Solver<S> for Rodas4 {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        self.tol.fill(sys);
        assert_eq!(y0.len(), self.n, "state dimension");
        self.t = t0;
        self.t_prev = t0;
        self.jac_valid = false;
        self.lu_h = 0.0;
        self.lu.set_second_order(sys.second_order());
        self.lu.set_ported(&*sys);
        self.h = start(
            sys,
            t0,
            y0,
            RODAS4.order,
            (&self.opts, &self.tol),
            StartBuffers {
                y: &mut self.y,
                y_prev: &mut self.y_prev,
                f: &mut self.f,
                f_prev: &mut self.f_prev,
                ytmp: &mut self.ytmp,
                ftmp: &mut self.ftmp,
            },
            &mut self.stats,
        )?;
        Ok(())
    }

    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        if t_stop.is_nan() || t_stop <= self.t {
            return Ok(());
        }
        let mut trials = Trials::default();
        loop {
            let (h, lands, h_prop) = propose_step(self.t, self.h, t_stop, &self.opts, &self.stats)?;
            if !self.jac_valid {
                self.jacobian(sys);
            }
            let err = match self.attempt(sys, h) {
                Err(()) => return Err(OdeError::Singular { t: self.t }),
                Ok(None) => {
                    self.h = trials.non_finite(self.t, h, &mut self.stats)?;
                    continue;
                }
                Ok(Some(err)) => err,
            };
            let fac = SAFETY * err.max(1e-10).powf(-0.25);
            if err > 1.0 {
                trials.rejected(&mut self.stats);
                self.h = h * fac.clamp(FAC_MIN, 1.0);
                continue;
            }
            let fac = trials.accept_factor(fac, FAC_MIN, FAC_MAX);
            self.h = after_landing(
                (h * fac).min(self.opts.h_max),
                h_prop,
                lands,
                trials.rejected_last,
            );
            let t_new = if lands { t_stop } else { self.t + h };
            std::mem::swap(&mut self.y_prev, &mut self.y);
            std::mem::swap(&mut self.y, &mut self.y_new);
            std::mem::swap(&mut self.f_prev, &mut self.f);
            sys.rhs(t_new, &self.y, &mut self.f);
            self.stats.rhs_evals += 1;
            self.stats.steps += 1;
            self.t_prev = self.t;
            self.t = t_new;
            self.jac_valid = false;
            if !all_finite(&self.y) || !all_finite(&self.f) {
                return Err(OdeError::NonFinite { t: t_new });
            }
            return Ok(());
        }
    }
}
