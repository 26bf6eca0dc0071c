//! The composite method `auto`: dopri5 while the problem is not stiff, rodas4 while it is,
//! switching both ways (the idea of LSODA and of DifferentialEquations.jl's
//! `AutoTsit5(Rodas4())`).
//!
//! - dopri5 -> rodas4 when Hairer's stiffness test fires (`Dopri5::is_stiff`: 15 steps on the
//!   stability boundary with fewer than 6 others between them).
//! - rodas4 -> dopri5 when dopri5 would be stable at twice rodas4's step: every
//!   [`CHECK_EVERY`] accepted steps the spectral radius of df/dy is estimated by
//!   [`POWER_STEPS`] power iterations on differences of f (counted as right-hand sides), and
//!   rodas4 hands back when 3.25 / rho >= 2 h. The factor 2 is the hysteresis that keeps the
//!   two from handing the problem to and fro.
//!
//! Each hand-over starts the other method at the current state (`init`: one right-hand side
//! and no history), with the step the first method ended on. Dense output is the active
//! method's. Counters are the sum of both methods'.

use super::common::attempts;
use super::{Dopri5, OdeError, OdeSystem, Options, Rodas4, Solver, Stats, Stepper};

/// dopri5's stability boundary on the negative real axis (Hairer's test uses it too).
const STABLE_H_RHO: f64 = 3.25;
/// rodas4 hands back when dopri5 is stable at this multiple of its step.
const HYSTERESIS: f64 = 2.0;
/// Accepted rodas4 steps between estimates of the spectral radius.
const CHECK_EVERY: u32 = 25;
/// Power iterations per estimate.
const POWER_STEPS: usize = 6;

pub struct Auto {
    opts: Options,
    // Boxed: the two methods' state is large, `AnySolver` holds this by value.
    dopri: Box<Dopri5>,
    rodas: Box<Rodas4>,
    on_rodas: bool,
    since_check: u32,
    switches: u64,
    /// Power iteration: the direction, the perturbed state and its f.
    v: Vec<f64>,
    yp: Vec<f64>,
    fp: Vec<f64>,
    /// Right-hand sides of the estimates.
    probe_rhs: u64,
}

impl Auto {
    pub fn new(dim: usize, options: Options) -> Self {
        let v = || vec![0.0; dim];
        Auto {
            opts: options,
            dopri: Box::new(Dopri5::new(dim, options)),
            rodas: Box::new(Rodas4::new(dim, options)),
            on_rodas: false,
            since_check: 0,
            switches: 0,
            v: v(),
            yp: v(),
            fp: v(),
            probe_rhs: 0,
        }
    }

    /// The budget left to the active method (the other's attempts count against it).
    fn budget(&self, other: &Stats) -> u64 {
        self.opts.max_steps.saturating_sub(attempts(other))
    }

    /// Estimate of the spectral radius of df/dy at rodas4's current state: power iteration
    /// on J v ~ (f(y + eps v) - f(y)) / eps from the last step's increment.
    fn spectral_radius<S: OdeSystem + ?Sized>(&mut self, sys: &mut S) -> f64 {
        let t = self.rodas.t();
        self.rodas.interpolate(self.rodas.t_prev(), &mut self.yp);
        let y = self.rodas.y();
        let n = y.len();
        let y_norm = y.iter().map(|x| x * x).sum::<f64>().sqrt();
        // Start from the last step's increment (the motion the solver sees), else all ones.
        let mut prev = vec_norm_diff(&mut self.v, y, &self.yp);
        if prev == 0.0 {
            self.v.fill(1.0);
            prev = (n as f64).sqrt();
        }
        let f0 = self.rodas.rhs_now();
        let mut rho = 0.0f64;
        for _ in 0..POWER_STEPS {
            let eps = 1e-7 * (1.0 + y_norm);
            let scale = eps / prev;
            for i in 0..n {
                self.yp[i] = y[i] + scale * self.v[i];
            }
            sys.rhs(t, &self.yp, &mut self.fp);
            self.probe_rhs += 1;
            let mut norm = 0.0;
            for i in 0..n {
                self.v[i] = (self.fp[i] - f0[i]) / eps;
                norm += self.v[i] * self.v[i];
            }
            let norm = norm.sqrt();
            if !norm.is_finite() || norm == 0.0 {
                break;
            }
            // |J v| / |v| with |v| = 1 after the scaling.
            rho = rho.max(norm);
            prev = norm;
        }
        rho
    }
}

/// v = a - b, returning |v|.
fn vec_norm_diff(v: &mut [f64], a: &[f64], b: &[f64]) -> f64 {
    let mut s = 0.0;
    for i in 0..v.len() {
        v[i] = a[i] - b[i];
        s += v[i] * v[i];
    }
    s.sqrt()
}

impl Stepper for Auto {
    fn name(&self) -> &'static str {
        "auto"
    }
    fn t(&self) -> f64 {
        if self.on_rodas {
            self.rodas.t()
        } else {
            self.dopri.t()
        }
    }
    fn y(&self) -> &[f64] {
        if self.on_rodas {
            self.rodas.y()
        } else {
            self.dopri.y()
        }
    }
    fn t_prev(&self) -> f64 {
        if self.on_rodas {
            self.rodas.t_prev()
        } else {
            self.dopri.t_prev()
        }
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        if self.on_rodas {
            self.rodas.interpolate(t, out)
        } else {
            self.dopri.interpolate(t, out)
        }
    }
    fn stats(&self) -> Stats {
        let (a, b) = (self.dopri.stats(), self.rodas.stats());
        Stats {
            steps: a.steps + b.steps,
            rejected_steps: a.rejected_steps + b.rejected_steps,
            rhs_evals: a.rhs_evals + b.rhs_evals + self.probe_rhs,
            jacobian_evals: a.jacobian_evals + b.jacobian_evals,
            lu_decompositions: a.lu_decompositions + b.lu_decompositions,
            newton_iterations: a.newton_iterations + b.newton_iterations,
            stiff_steps: a.stiff_steps,
            stiff_at: a.stiff_at,
            method_switches: self.switches,
        }
    }
}

impl<S: OdeSystem + ?Sized> Solver<S> for Auto {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        self.since_check = 0;
        if self.on_rodas {
            let b = self.budget(&self.dopri.stats());
            self.rodas.set_start(self.opts.h0, b);
            Solver::<S>::init(&mut *self.rodas, sys, t0, y0)
        } else {
            let b = self.budget(&self.rodas.stats());
            self.dopri.set_start(self.opts.h0, b);
            Solver::<S>::init(&mut *self.dopri, sys, t0, y0)
        }
    }

    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        if t_stop.is_nan() || t_stop <= self.t() {
            return Ok(());
        }
        if !self.on_rodas && self.dopri.is_stiff() {
            // Hand over to rodas4 at the current state, with dopri5's last step.
            let (t, h) = (self.dopri.t(), self.dopri.step_size());
            let b = self.budget(&self.dopri.stats());
            self.rodas.set_start(h, b);
            self.yp.copy_from_slice(self.dopri.y());
            Solver::<S>::init(&mut *self.rodas, sys, t, &self.yp)?;
            self.on_rodas = true;
            self.since_check = 0;
            self.switches += 1;
        } else if self.on_rodas && self.since_check >= CHECK_EVERY {
            self.since_check = 0;
            let rho = self.spectral_radius(sys);
            let h = self.rodas.step_size();
            if rho.is_finite() && rho * HYSTERESIS * h <= STABLE_H_RHO {
                let t = self.rodas.t();
                let b = self.budget(&self.rodas.stats());
                self.dopri.set_start(h, b);
                self.yp.copy_from_slice(self.rodas.y());
                Solver::<S>::init(&mut *self.dopri, sys, t, &self.yp)?;
                self.dopri.reset_stiffness();
                self.on_rodas = false;
                self.switches += 1;
            }
        }
        let r = if self.on_rodas {
            self.since_check += 1;
            Solver::<S>::step(&mut *self.rodas, sys, t_stop)
        } else {
            Solver::<S>::step(&mut *self.dopri, sys, t_stop)
        };
        // The budget is the two methods' together.
        r.map_err(|e| match e {
            OdeError::StepBudget { t, .. } => OdeError::StepBudget {
                t,
                steps: attempts(&Stepper::stats(self)),
            },
            e => e,
        })
    }
}
