//! L-stable 5-stage SDIRK of order 4 (embedded order 3, gamma = 1/4; Hairer & Wanner, Solving
//! ODEs II, Table IV.6.5) for stiff models: stiff suspension springs, contact penalties.
//!
//! Each stage solves z_i = s_i + h*gamma*f(t + c_i h, y0 + z_i), s_i = sum_{j<i} a_ij h k_j, by
//! simplified Newton with the one matrix M = I - h*gamma*J for all stages. The stage derivative
//! is recovered as h k_i = (z_i - s_i) / gamma instead of a new f evaluation (better behaved
//! on stiff components). The method is stiffly accurate, so y1 = y0 + z_5.
//!
//! * Jacobian: `sys.jacobian` when it returns true, else forward differences. It is kept
//!   across steps while Newton contracts quickly (rate <= 0.1) and recomputed after slow
//!   convergence, a Newton failure or a rejected step.
//! * LU of M is redone only when h changes; a proposed growth by less than 20 % is not taken,
//!   so that the factorisation can be reused (Hairer's trick).
//! * Newton start: the previous step's Hermite interpolant extrapolated to t + c_i h (an
//!   O(h^4) guess) when h <= 3 h_prev; else (and on the first step) k_i = k_(i-1).
//! * Newton stop, Jacobian reuse and the step control after a trial: `newton.rs` (shared with
//!   generalized-alpha); at most 7 iterations a stage.
//! * Error estimate: the embedded difference sum (b_i - b^_i) h k_i filtered through M^-1, as
//!   Hairer does, so the estimate does not blow up on stiff components.
//! * Dense output: cubic Hermite from (y0, f0, y1, f1) with f1 = k_5, the derivative at the
//!   (stiffly accurate) last stage; third order, no extra right-hand side evaluation.

use super::common::{
    StartBuffers, Tolerance, Trials, all_finite, error_norm, hermite, hermite_stepper,
    propose_step, start,
};
use super::iteration::IterationMatrix;
use super::newton::{self, Attempt, Jacobian, Rate, Verdict};
use super::tableau::{SDIRK4, SDIRK4_GAMMA};
use super::{OdeError, OdeSystem, Options, Solver, Stats};

const STAGES: usize = 5;
const MAX_NEWTON: u32 = 7;

pub struct Sdirk4 {
    opts: Options,
    tol: Tolerance,
    n: usize,
    t: f64,
    t_prev: f64,
    h: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    y_new: Vec<f64>,
    /// f at (t, y) and (t_prev, y_prev), for dense output and the first Newton guess.
    f: Vec<f64>,
    f_prev: Vec<f64>,
    jac: Vec<f64>,
    lu: IterationMatrix,
    /// Whether the stored Jacobian may be used, and whether it is from the current point.
    jac_age: Jacobian,
    /// Step size the LU of M belongs to (0 = none).
    lu_h: f64,
    /// h k_i for the stages.
    hk: [Vec<f64>; STAGES],
    z: Vec<f64>,
    s: Vec<f64>,
    ytmp: Vec<f64>,
    ftmp: Vec<f64>,
    delta: Vec<f64>,
    scale: Vec<f64>,
    /// Newton rate estimate carried between stages and steps.
    eta: f64,
    /// Largest Newton contraction in the last attempt.
    theta_max: f64,
    stats: Stats,
}

impl Sdirk4 {
    pub fn new(dim: usize, options: Options) -> Self {
        let v = || vec![0.0; dim];
        Sdirk4 {
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
            jac: vec![0.0; dim * dim],
            lu: IterationMatrix::new(dim),
            jac_age: Jacobian::default(),
            lu_h: 0.0,
            hk: [v(), v(), v(), v(), v()],
            z: v(),
            s: v(),
            ytmp: v(),
            ftmp: v(),
            delta: v(),
            scale: v(),
            eta: 1.0,
            theta_max: 0.0,
            stats: Stats::default(),
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

    /// df/dy at (t, y) into `jac`: analytic if the system has it, else forward differences
    /// with increments sqrt(eps * max(1e-5, |y_j|)) (Hairer's choice).
    fn compute_jacobian<S: OdeSystem + ?Sized>(&mut self, sys: &mut S) {
        self.stats.jacobian_evals += 1;
        if self.lu.jacobian(sys, self.t, &self.y, &mut self.jac) {
            return;
        }
        let n = self.n;
        // A fresh f(t, y): the stored one comes from the Newton solve and is not accurate
        // enough to difference against.
        sys.rhs(self.t, &self.y, &mut self.ftmp);
        self.ytmp.copy_from_slice(&self.y);
        for j in 0..n {
            let yj = self.y[j];
            let d = (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
            self.ytmp[j] = yj + d;
            let d = self.ytmp[j] - yj;
            sys.rhs(self.t, &self.ytmp, &mut self.delta);
            for i in 0..n {
                self.jac[i * n + j] = (self.delta[i] - self.ftmp[i]) / d;
            }
            self.ytmp[j] = yj;
        }
        self.stats.rhs_evals += n as u64 + 1;
    }

    /// Refreshes the Jacobian when it is stale and factors I - h gamma J when h changed; false
    /// when it is singular.
    fn iteration_matrix<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> bool {
        let g = SDIRK4_GAMMA;
        if !self.jac_age.valid {
            self.compute_jacobian(sys);
            self.jac_age = Jacobian {
                valid: true,
                fresh: true,
            };
            self.lu_h = 0.0;
        }
        if self.lu_h != h {
            self.stats.lu_decompositions += 1;
            if self.lu.factor(&self.jac, 1.0, h * g).is_err() {
                self.lu_h = 0.0;
                return false;
            }
            self.lu_h = h;
        }
        true
    }

    /// Stage `st`'s explicit part `s` (the earlier stages' sum) and the Newton start `z`: the
    /// last step's interpolant at `tc` when `predict`, else the previous stage derivative.
    fn stage_guess(&mut self, st: usize, h: f64, tc: f64, predict: bool) {
        let n = self.n;
        let g = SDIRK4_GAMMA;
        let tab = &SDIRK4;
        {
            let (done, _) = self.hk.split_at(st);
            for i in 0..n {
                let mut acc = 0.0;
                for (j, hkj) in done.iter().enumerate() {
                    acc += tab.a[st][j] * hkj[i];
                }
                self.s[i] = acc;
                if !predict {
                    // The stage derivative equals the previous one.
                    let prev = if st == 0 {
                        h * self.f[i]
                    } else {
                        done[st - 1][i]
                    };
                    self.z[i] = acc + g * prev;
                }
            }
        }
        if predict {
            hermite(
                self.t_prev,
                self.t - self.t_prev,
                &self.y_prev,
                &self.f_prev,
                &self.y,
                &self.f,
                tc,
                &mut self.ytmp,
            );
            for i in 0..n {
                self.z[i] = self.ytmp[i] - self.y[i];
            }
        }
    }

    /// Newton's iteration for a stage at `tc` from the guess in `z`, to convergence (then `eta`
    /// is the rate's), or the attempt's failure.
    fn solve_stage<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        tc: f64,
        h: f64,
        kappa: f64,
    ) -> Result<(), Attempt> {
        let n = self.n;
        let g = SDIRK4_GAMMA;
        let mut rate = Rate::new(self.eta, kappa, MAX_NEWTON);
        let mut converged = false;
        for it in 0..MAX_NEWTON {
            for i in 0..n {
                self.ytmp[i] = self.y[i] + self.z[i];
            }
            sys.rhs(tc, &self.ytmp, &mut self.ftmp);
            self.stats.rhs_evals += 1;
            self.stats.newton_iterations += 1;
            for i in 0..n {
                self.delta[i] = self.s[i] + h * g * self.ftmp[i] - self.z[i];
            }
            self.lu.solve(&self.jac, &mut self.delta);
            let mut sum = 0.0;
            for i in 0..n {
                let q = self.delta[i] / self.scale[i];
                sum += q * q;
            }
            let dnorm = if n > 0 { (sum / n as f64).sqrt() } else { 0.0 };
            if !dnorm.is_finite() {
                return Err(Attempt::NonFinite);
            }
            let verdict = rate.judge(it, dnorm, &mut self.theta_max);
            if verdict == Verdict::Failed {
                return Err(Attempt::NewtonFailed);
            }
            for i in 0..n {
                self.z[i] += self.delta[i];
            }
            if verdict == Verdict::Converged {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(Attempt::NewtonFailed);
        }
        self.eta = rate.eta();
        Ok(())
    }

    /// One trial step of size h from (t, y) into `y_new`.
    fn attempt<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> Attempt {
        let n = self.n;
        let g = SDIRK4_GAMMA;
        let tab = &SDIRK4;
        if !self.iteration_matrix(sys, h) {
            return Attempt::Singular;
        }
        for i in 0..n {
            self.scale[i] = self.tol.scale(i, self.y[i]);
        }
        let kappa = newton::tolerance(&self.opts);
        self.theta_max = 0.0;

        // After the first step, guesses come from extrapolating the last step's interpolant,
        // unless that would reach far beyond it (cubic extrapolation error grows like (h/h_prev)^4).
        let predict = self.t_prev < self.t && h <= 3.0 * (self.t - self.t_prev);
        for st in 0..STAGES {
            let tc = self.t + tab.c[st] * h;
            self.stage_guess(st, h, tc, predict);
            if let Err(failed) = self.solve_stage(sys, tc, h, kappa) {
                return failed;
            }
            for i in 0..n {
                self.hk[st][i] = (self.z[i] - self.s[i]) / g;
            }
        }
        for i in 0..n {
            self.y_new[i] = self.y[i] + self.z[i];
        }
        if !all_finite(&self.y_new) {
            return Attempt::NonFinite;
        }
        // Embedded difference, filtered through M^-1.
        for i in 0..n {
            let mut e = 0.0;
            for st in 0..STAGES {
                e += (tab.b[st] - tab.b_hat[st]) * self.hk[st][i];
            }
            self.delta[i] = e;
        }
        self.lu.solve(&self.jac, &mut self.delta);
        let err = error_norm(&self.delta, &self.y, &self.y_new, &self.tol);
        if err.is_finite() {
            Attempt::Done(err)
        } else {
            Attempt::NonFinite
        }
    }
}

hermite_stepper!(Sdirk4, "sdirk4");

impl<S: OdeSystem + ?Sized> Solver<S> for Sdirk4 {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        self.tol.fill(sys);
        assert_eq!(y0.len(), self.n, "state dimension");
        self.t = t0;
        self.t_prev = t0;
        self.jac_age = Jacobian::default();
        self.lu_h = 0.0;
        self.eta = 1.0;
        self.lu.set_second_order(sys.second_order());
        self.lu.set_ported(&*sys);
        self.h = start(
            sys,
            t0,
            y0,
            SDIRK4.order,
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
        // Nothing to do at or before the current time (forward integration only).
        if t_stop.is_nan() || t_stop <= self.t {
            return Ok(());
        }
        let mut trials = Trials::default();
        loop {
            let (h, lands, h_prop) = propose_step(self.t, self.h, t_stop, &self.opts, &self.stats)?;
            let outcome = self.attempt(sys, h);
            let accepted = newton::after_trial(
                outcome,
                0.25,
                (h, h_prop, lands),
                self.theta_max,
                self.t,
                &self.opts,
                &mut self.stats,
                &mut trials,
                &mut self.jac_age,
                &mut self.h,
            )?;
            if !accepted {
                continue;
            }

            let t_new = if lands { t_stop } else { self.t + h };
            std::mem::swap(&mut self.y_prev, &mut self.y);
            std::mem::swap(&mut self.y, &mut self.y_new);
            std::mem::swap(&mut self.f_prev, &mut self.f);
            for i in 0..self.n {
                self.f[i] = self.hk[STAGES - 1][i] / h;
            }
            self.stats.steps += 1;
            self.t_prev = self.t;
            self.t = t_new;
            if !all_finite(&self.y) {
                return Err(OdeError::NonFinite { t: t_new });
            }
            return Ok(());
        }
    }
}
