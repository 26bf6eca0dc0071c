//! Simplified Newton iterations as sdirk4 and generalized-alpha use them (Hairer & Wanner,
//! Solving ODEs II, Section IV.8): the convergence test on the corrections, and what a step
//! does after a trial (Jacobian refresh, step size, keeping the LU). One place, so the two
//! methods cannot drift apart.
//!
//! * Newton stop: eta * |dz| <= kappa with eta = theta / (1 - theta), theta the observed
//!   contraction; divergence (theta >= 0.99) or a predicted miss within the iterations left
//!   fail the trial.
//! * A failed trial is retried first with a Jacobian at the current point, then with h / 2; at
//!   `h_min` the step fails with `NewtonDivergence`. Non-finite values: h / 10.
//! * After an accepted step, a growth by less than [`FREEZE`] is not taken while Newton
//!   converged quickly, so the LU of the iteration matrix is reused; slow convergence
//!   (contraction above [`THETA_REFRESH`]) refreshes the Jacobian for the next step.

use super::common::{Trials, after_landing};
use super::{OdeError, Options, Stats};

const SAFETY: f64 = 0.9;
const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 5.0;
/// Newton contraction above which the Jacobian is refreshed for the next step.
const THETA_REFRESH: f64 = 0.1;
/// Proposed growth factors in [1, FREEZE] keep the old h (and its LU).
const FREEZE: f64 = 1.2;
/// Newton tolerance, relative to the error tolerance (Hairer & Wanner recommend 0.01..0.1).
const KAPPA: f64 = 0.03;

/// The Newton tolerance in the error norm for relative tolerance `rtol`.
pub fn tolerance(opts: &Options) -> f64 {
    (10.0 * f64::EPSILON / opts.rtol).max(KAPPA)
}

/// The outcome of one trial step.
pub enum Attempt {
    /// Newton converged; the error norm of the step.
    Done(f64),
    NewtonFailed,
    NonFinite,
    Singular,
}

/// The age of the stored Jacobian.
#[derive(Clone, Copy, Debug, Default)]
pub struct Jacobian {
    /// A Jacobian is stored and may be used.
    pub valid: bool,
    /// It was computed at the current (t, y).
    pub fresh: bool,
}

/// What an iteration's correction says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Converged,
    Continue,
    Failed,
}

/// Convergence bookkeeping of one nonlinear solve.
pub struct Rate {
    eta: f64,
    dnorm_old: f64,
    kappa: f64,
    max_iter: u32,
}

impl Rate {
    /// For a solve of at most `max_iter` iterations, starting from the rate `eta_prev` the last
    /// converged solve ended with (Hairer's start: eta_prev^0.8).
    pub fn new(eta_prev: f64, kappa: f64, max_iter: u32) -> Rate {
        Rate {
            eta: eta_prev.max(f64::EPSILON).powf(0.8),
            dnorm_old: 0.0,
            kappa,
            max_iter,
        }
    }

    /// Iteration `it` gave a correction of norm `dnorm` (finite); `theta_max` keeps the
    /// largest contraction seen. The correction is to be applied unless `Failed`.
    pub fn judge(&mut self, it: u32, dnorm: f64, theta_max: &mut f64) -> Verdict {
        if it > 0 {
            let theta = dnorm / self.dnorm_old;
            *theta_max = theta_max.max(theta);
            if theta >= 0.99 {
                return Verdict::Failed;
            }
            self.eta = theta / (1.0 - theta);
            // Predicted error after the remaining iterations still too large.
            let left = (self.max_iter - 1 - it) as i32;
            if self.eta * theta.powi(left) * dnorm > self.kappa {
                return Verdict::Failed;
            }
        }
        if self.eta * dnorm <= self.kappa || dnorm == 0.0 {
            return Verdict::Converged;
        }
        self.dnorm_old = dnorm;
        Verdict::Continue
    }

    /// The rate to start the next solve from.
    pub fn eta(&self) -> f64 {
        self.eta
    }
}

/// What the step loop does after a trial of size `h` (proposed `h_prop`, landing on t_stop
/// when `lands`) from time `t`. `Ok(true)`: accepted, `h_next` holds the next step's size;
/// `Ok(false)`: rejected, try again with `h_next`; `Err`: the step fails. `exponent` is
/// 1 / (order of the error estimate + 1); `theta_max` the largest Newton contraction of the
/// trial.
#[allow(clippy::too_many_arguments)]
pub fn after_trial(
    outcome: Attempt,
    exponent: f64,
    (h, h_prop, lands): (f64, f64, bool),
    theta_max: f64,
    t: f64,
    opts: &Options,
    stats: &mut Stats,
    trials: &mut Trials,
    jac: &mut Jacobian,
    h_next: &mut f64,
) -> Result<bool, OdeError> {
    let err = match outcome {
        Attempt::Done(err) => err,
        Attempt::Singular => return Err(OdeError::Singular { t }),
        Attempt::NewtonFailed => {
            trials.rejected(stats);
            if !jac.fresh {
                // Retry the same h with a Jacobian at the current point.
                jac.valid = false;
                return Ok(false);
            }
            if h <= opts.h_min {
                return Err(OdeError::NewtonDivergence { t, h });
            }
            *h_next = (0.5 * h).max(opts.h_min);
            return Ok(false);
        }
        Attempt::NonFinite => {
            let h_new = trials.non_finite(t, h, stats)?;
            if !jac.fresh {
                jac.valid = false;
            }
            *h_next = h_new;
            return Ok(false);
        }
    };
    let fac = SAFETY * err.max(1e-10).powf(-exponent);
    if err > 1.0 {
        trials.rejected(stats);
        *h_next = h * fac.clamp(FAC_MIN, 1.0);
        if !jac.fresh {
            jac.valid = false;
        }
        return Ok(false);
    }
    let mut fac = trials.accept_factor(fac, FAC_MIN, FAC_MAX);
    let slow = theta_max > THETA_REFRESH;
    if (1.0..=FREEZE).contains(&fac) && !slow {
        fac = 1.0;
    }
    *h_next = after_landing(
        (h * fac).min(opts.h_max),
        h_prop,
        lands,
        trials.rejected_last,
    );
    if slow {
        jac.valid = false;
    }
    jac.fresh = false;
    Ok(true)
}
