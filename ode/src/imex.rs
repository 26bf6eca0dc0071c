//! Implicit-explicit additive Runge-Kutta, ARK4(3)6L[2]SA (Kennedy & Carpenter 2003; the
//! tableaux in `tableau.rs`), for mechanical systems whose stiffness sits in their own linear
//! terms: the modal bodies' omega^2 q and 2 zeta omega q' with the mass block M1 go implicit
//! (L-stable ESDIRK), the forces of the elements between bodies explicit.
//!
//! Why: the Ritz basis' correction and Krylov coordinates have Rayleigh frequencies of kHz.
//! An explicit method steps on their stability limit (dopri5: 144 us on the elastic machine),
//! an implicit one iterates on a Jacobian that turns with the drum. Here the stiff part is
//! linear and known: the implicit stage equation of y = [q; v; z],
//!   Y = R + h gamma f_I(Y),  f_I = [v; -M1^-1 (K q + D v); 0],
//! is one linear solve with S = M1 + h gamma D + (h gamma)^2 K (K, D diagonal): dense on the
//! n1 coordinates of subsystem 1, a scalar division on the unit-mass rest. No Newton
//! iteration, no Jacobian. Above the band the L-stable part puts the kHz coordinates on their
//! static give (residual flexibility) instead of resolving their vibration.
//!
//! * S is refactored when h changes (a growth by less than 20 % is not taken, Hairer's
//!   trick); M1 is the system's at `init` and is taken anew at a refactorisation 10 ms after
//!   the last. The split f_E = f - f_I is exact for any M1 the method holds: a stale M1 costs
//!   stability margin, not accuracy.
//! * f_I at the step's start needs M1^-1: its LU is kept beside S's.
//! * Error: the embedded difference of both halves filtered through (I - h gamma J_I)^-1 (on
//!   the quasi-static kHz coordinates the raw difference is h omega times too large); PI
//!   control as dopri5's with the embedded order's exponent.
//! * Dense output: cubic Hermite from (y0, f0, y1, f1), f1 = f(t1, y1) (the next step's first
//!   stage): six right-hand sides a step, as dopri5.

use super::common::{
    PiControl, StartBuffers, Tolerance, Trials, after_landing, all_finite, error_norm,
    hermite_stepper, propose_step, start,
};
use super::lu::{lu_factor, lu_solve};
use super::tableau::{ARK436_E, ARK436_GAMMA, ARK436_I};
use super::{OdeError, OdeSystem, Options, Solver, Stats};

const STAGES: usize = 6;
/// Largest growth of the step after an accepted one.
const FAC_MAX: f64 = 5.0;
/// A proposed growth below this keeps the factored step size.
const KEEP_GROWTH: f64 = 1.2;
/// M1 is taken anew, when S is refactored, after this long (s): it turns with the drum, and a
/// stale one costs stability margin only.
const M1_AGE: f64 = 0.01;

/// The implicit part's data and factorisations; `nq` coordinates, the first `n1` with M1.
struct Linear {
    nq: usize,
    n1: usize,
    m1: Vec<f64>,
    k: Vec<f64>,
    c: Vec<f64>,
    /// LU of M1 (for f_I at a given state) and of S at `h`.
    m_lu: Vec<f64>,
    m_piv: Vec<usize>,
    s_lu: Vec<f64>,
    s_piv: Vec<usize>,
    /// The step size S belongs to (0 = none), and the time M1 was taken at.
    h: f64,
    t_m1: f64,
    w: Vec<f64>,
}

impl Linear {
    fn new(nq: usize) -> Self {
        let v = |n: usize| vec![0.0; n];
        Linear {
            nq,
            n1: 0,
            m1: v(nq * nq),
            k: v(nq),
            c: v(nq),
            m_lu: v(nq * nq),
            m_piv: vec![0; nq],
            s_lu: v(nq * nq),
            s_piv: vec![0; nq],
            h: 0.0,
            t_m1: 0.0,
            w: v(nq),
        }
    }

    /// Asks the system for M1, K, D at (t, y) and factors M1.
    fn refresh<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        stats: &mut Stats,
    ) -> Result<(), OdeError> {
        let n1 = sys
            .linear_part(t, y, &mut self.m1, &mut self.k, &mut self.c)
            .ok_or(OdeError::NoLinearPart { t })?;
        self.n1 = n1;
        self.t_m1 = t;
        self.h = 0.0;
        let nn = n1 * n1;
        self.m_lu[..nn].copy_from_slice(&self.m1[..nn]);
        stats.lu_decompositions += 1;
        lu_factor(&mut self.m_lu[..nn], n1, &mut self.m_piv[..n1])
            .map_err(|_| OdeError::Singular { t })
    }

    /// Factors S = M1 + h gamma D + (h gamma)^2 K for step size h.
    fn factor(&mut self, t: f64, h: f64, stats: &mut Stats) -> Result<(), OdeError> {
        let n1 = self.n1;
        let g = h * ARK436_GAMMA;
        let nn = n1 * n1;
        self.s_lu[..nn].copy_from_slice(&self.m1[..nn]);
        for i in 0..n1 {
            self.s_lu[i * n1 + i] += g * self.c[i] + g * g * self.k[i];
        }
        stats.lu_decompositions += 1;
        if lu_factor(&mut self.s_lu[..nn], n1, &mut self.s_piv[..n1]).is_err() {
            self.h = 0.0;
            return Err(OdeError::Singular { t });
        }
        self.h = h;
        Ok(())
    }

    /// f_I(y) into `fi`.
    fn eval(&mut self, y: &[f64], fi: &mut [f64]) {
        let (nq, n1) = (self.nq, self.n1);
        fi.fill(0.0);
        for i in 0..nq {
            let (q, v) = (y[i], y[nq + i]);
            fi[i] = v;
            self.w[i] = -(self.k[i] * q + self.c[i] * v);
        }
        lu_solve(
            &self.m_lu[..n1 * n1],
            n1,
            &self.m_piv[..n1],
            &mut self.w[..n1],
        );
        fi[nq..2 * nq].copy_from_slice(&self.w);
    }

    /// Solves Y = r + h gamma f_I(Y) at the factored h: Y into `y`, f_I(Y) into `fi`.
    fn solve(&mut self, r: &[f64], y: &mut [f64], fi: &mut [f64]) {
        let (nq, n1) = (self.nq, self.n1);
        let g = self.h * ARK436_GAMMA;
        let (rq, rv) = (&r[..nq], &r[nq..2 * nq]);
        // (M1 + g D + g^2 K) V = M1 R_v - g K R_q on subsystem 1, per coordinate after it.
        for i in 0..n1 {
            let row = &self.m1[i * n1..(i + 1) * n1];
            let mv: f64 = row.iter().zip(&rv[..n1]).map(|(m, v)| m * v).sum();
            self.w[i] = mv - g * self.k[i] * rq[i];
        }
        lu_solve(
            &self.s_lu[..n1 * n1],
            n1,
            &self.s_piv[..n1],
            &mut self.w[..n1],
        );
        for i in n1..nq {
            let (k, c) = (self.k[i], self.c[i]);
            self.w[i] = (rv[i] - g * k * rq[i]) / (1.0 + g * c + g * g * k);
        }
        y.copy_from_slice(r);
        fi.fill(0.0);
        for i in 0..nq {
            let v = self.w[i];
            y[nq + i] = v;
            y[i] = rq[i] + g * v;
            fi[i] = v;
            fi[nq + i] = (v - rv[i]) / g;
        }
    }
}

pub struct Imex {
    opts: Options,
    tol: Tolerance,
    n: usize,
    t: f64,
    t_prev: f64,
    h: f64,
    control: PiControl,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    y_new: Vec<f64>,
    /// f at (t, y) and (t_prev, y_prev): the first stage and the dense output.
    f: Vec<f64>,
    f_prev: Vec<f64>,
    /// The stages' explicit and implicit derivatives.
    fe: [Vec<f64>; STAGES],
    fi: [Vec<f64>; STAGES],
    r: Vec<f64>,
    ys: Vec<f64>,
    err: Vec<f64>,
    /// Sized for the largest second-order system of this dimension (dim / 2 coordinates).
    lin: Linear,
    stats: Stats,
}

impl Imex {
    pub fn new(dim: usize, options: Options) -> Self {
        let v = || vec![0.0; dim];
        Imex {
            tol: Tolerance::new(&options, dim),
            opts: options,
            n: dim,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            control: PiControl::new(ARK436_E.order_hat, FAC_MAX),
            y: v(),
            y_prev: v(),
            y_new: v(),
            f: v(),
            f_prev: v(),
            fe: std::array::from_fn(|_| v()),
            fi: std::array::from_fn(|_| v()),
            r: v(),
            ys: v(),
            err: v(),
            lin: Linear::new(dim / 2),
            stats: Stats::default(),
        }
    }

    /// Stages 2..6 and the new solution for step size h (S factored for it); the error norm.
    fn attempt<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> f64 {
        let n = self.n;
        let (ae, ai) = (&ARK436_E.a, &ARK436_I.a);
        self.lin.eval(&self.y, &mut self.fi[0]);
        for i in 0..n {
            self.fe[0][i] = self.f[i] - self.fi[0][i];
        }
        for s in 1..STAGES {
            for i in 0..n {
                let mut acc = 0.0;
                for j in 0..s {
                    acc += ae[s][j] * self.fe[j][i] + ai[s][j] * self.fi[j][i];
                }
                self.r[i] = self.y[i] + h * acc;
            }
            let (fe, fi) = (&mut self.fe[s], &mut self.fi[s]);
            self.lin.solve(&self.r, &mut self.ys, fi);
            sys.rhs(self.t + ARK436_E.c[s] * h, &self.ys, fe);
            for i in 0..n {
                fe[i] -= fi[i];
            }
        }
        self.stats.rhs_evals += (STAGES - 1) as u64;
        let (b, bh) = (&ARK436_E.b, &ARK436_E.b_hat);
        for i in 0..n {
            let (mut acc, mut e) = (0.0, 0.0);
            for s in 0..STAGES {
                let k = self.fe[s][i] + self.fi[s][i];
                acc += b[s] * k;
                e += (b[s] - bh[s]) * k;
            }
            self.y_new[i] = self.y[i] + h * acc;
            self.err[i] = h * e;
        }
        // Filtered through (I - h gamma J_I)^-1, as Hairer does for SDIRK: unfiltered, the
        // stiff coordinates' stage differences times h omega swamp the estimate.
        self.lin.solve(&self.err, &mut self.ys, &mut self.r);
        let norm = error_norm(&self.ys, &self.y, &self.y_new, &self.tol);
        if norm.is_finite() && !all_finite(&self.y_new) {
            return f64::INFINITY;
        }
        norm
    }
}

hermite_stepper!(Imex, "imex");

impl<S: OdeSystem + ?Sized> Solver<S> for Imex {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        self.tol.fill(sys);
        assert_eq!(y0.len(), self.n, "state dimension");
        if sys.second_order().is_none_or(|nq| 2 * nq > self.n) {
            return Err(OdeError::NotSecondOrder { t: t0 });
        }
        self.t = t0;
        self.t_prev = t0;
        self.control.reset();
        self.h = start(
            sys,
            t0,
            y0,
            ARK436_E.order,
            (&self.opts, &self.tol),
            StartBuffers {
                y: &mut self.y,
                y_prev: &mut self.y_prev,
                f: &mut self.f,
                f_prev: &mut self.f_prev,
                ytmp: &mut self.ys,
                ftmp: &mut self.r,
            },
            &mut self.stats,
        )?;
        // The linear part's shape is checked here, before the first step.
        self.lin.refresh(sys, t0, y0, &mut self.stats)?;
        self.lin.factor(t0, self.h, &mut self.stats)
    }

    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        if t_stop.is_nan() || t_stop <= self.t {
            return Ok(());
        }
        let mut trials = Trials::default();
        loop {
            let (mut h, lands, h_prop) =
                propose_step(self.t, self.h, t_stop, &self.opts, &self.stats)?;
            // A small growth keeps the factorisation (not on a landing step).
            if !lands && h > self.lin.h && h < KEEP_GROWTH * self.lin.h {
                h = self.lin.h;
            }
            if h != self.lin.h {
                if self.t - self.lin.t_m1 > M1_AGE {
                    self.lin.refresh(sys, self.t, &self.y, &mut self.stats)?;
                }
                self.lin.factor(self.t, h, &mut self.stats)?;
            }
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
            let fac = self.control.accepted(err, &trials);
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
            if !all_finite(&self.y) || !all_finite(&self.f) {
                return Err(OdeError::NonFinite { t: t_new });
            }
            return Ok(());
        }
    }
}
