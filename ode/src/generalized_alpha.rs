//! The generalized-alpha method (Chung & Hulbert 1993) on the second-order equations
//! q'' = A(t, q, q'), in Arnold & Bruels' form (Multibody System Dynamics 18, 2007), which
//! multibody codes use by default: second order, unconditionally stable for linear systems,
//! with numerical damping of the highest frequencies set by one number, the spectral radius
//! rho_inf at h omega -> infinity (1: none, 0: asymptotic annihilation).
//!
//! With the pseudo-accelerations a_n:
//!   q1 = q0 + h v0 + h^2 (1/2 - beta) a0 + h^2 beta a1,   v1 = v0 + h (1 - gamma) a0 + h gamma a1,
//!   (1 - alpha_m) a1 + alpha_m a0 = (1 - alpha_f) q''1 + alpha_f q''0,   q''1 = A(t1, q1, v1).
//! The unknown is q''1; Newton's matrix is I - beta' (h^2 beta dA/dq + h gamma dA/dv) with
//! beta' = (1 - alpha_f) / (1 - alpha_m): n x n, half the size of a first-order method's.
//!
//! * The system says it is second order through `OdeSystem::second_order` (y = [q; q'; z],
//!   f = [q'; q''; z']); any other system is refused with `OdeError::NotSecondOrder`. Trailing
//!   first-order states z (a presliding friction law's) take the same scheme's velocity
//!   update with pseudo-rates b: z1 = z0 + h ((1 - gamma) b0 + gamma b1),
//!   (1 - alpha_m) b1 + alpha_m b0 = (1 - alpha_f) z'1 + alpha_f z'0 (second order for
//!   gamma = 1/2 + alpha_f - alpha_m, as for v); z'1 joins the Newton unknowns.
//! * Jacobian: the system's ported pieces (`ported.rs`: the cabinet's modes eliminated
//!   through its ports) or mass form when it gives them, else the lower half of
//!   `sys.jacobian` when analytic, else forward differences in q and q' (2n evaluations). Newton's stop rule, the Jacobian's reuse and the step control
//!   after a trial are `sdirk4`'s (`newton.rs`).
//! * Error estimate (Zienkiewicz & Xie's for Newmark-type methods): the local error of q is
//!   h^2 (beta - 1/6) (q''1 - q''0); only the positions enter the norm. Step factor
//!   0.9 err^(-1/3), in [0.2, 5].
//! * Dense output: cubic Hermite from (y0, f0, y1, f1).

use super::common::{
    StartBuffers, Tolerance, Trials, all_finite, error_norm, hermite_stepper, propose_step, start,
};
use super::lu::{lu_factor, lu_solve};
use super::newton::{self, Attempt, Jacobian, Rate, Verdict};
use super::ported::{self, PortedJacobian, PortedLu};
use super::{OdeError, OdeSystem, Options, Solver, Stats};

/// Multibody codes' usual numerical damping (e.g. the default of HHT-type integrators).
pub const DEFAULT_RHO_INF: f64 = 0.8;
const MAX_NEWTON: u32 = 8;

/// The method's four parameters from rho_inf (Chung & Hulbert's optimal choice).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaParams {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl AlphaParams {
    pub fn from_rho_inf(rho: f64) -> Self {
        let alpha_m = (2.0 * rho - 1.0) / (rho + 1.0);
        let alpha_f = rho / (rho + 1.0);
        let gamma = 0.5 + alpha_f - alpha_m;
        AlphaParams {
            alpha_m,
            alpha_f,
            gamma,
            beta: 0.25 * (gamma + 0.5) * (gamma + 0.5),
        }
    }
}

pub struct GeneralizedAlpha {
    opts: Options,
    tol: Tolerance,
    p: AlphaParams,
    /// Positions (half the second-order state), and the first-order states after it.
    n: usize,
    nz: usize,
    t: f64,
    t_prev: f64,
    h: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    y_new: Vec<f64>,
    f: Vec<f64>,
    f_prev: Vec<f64>,
    ftmp: Vec<f64>,
    /// Pseudo-accelerations a_n, which approximate q''(t_n + (alpha_m - alpha_f) h_acc).
    acc: Vec<f64>,
    h_acc: f64,
    /// a_n moved to the trial step's h (see `shift_acc`).
    a0: Vec<f64>,
    /// The Newton unknown q''_(n+1) and its correction.
    x: Vec<f64>,
    dx: Vec<f64>,
    /// d[A; G]/dq and d[A; G]/dv ((n + nz) x n; G = z'), d[A; G]/dz ((n + nz) x nz), and the
    /// full first-order Jacobian buffer; or, when the system gives its mass form
    /// (`mass_form`, no z), dh/dq and dh/dq' with M in `mass`.
    aq: Vec<f64>,
    av: Vec<f64>,
    az: Vec<f64>,
    mass: Vec<f64>,
    mass_form: bool,
    /// The ported pieces and their factorisation (`ported.rs`), when the system is ported;
    /// `ported_form`: the last Jacobian is theirs.
    ported: Option<(PortedJacobian, PortedLu)>,
    ported_form: bool,
    jac: Vec<f64>,
    lu: Vec<f64>,
    piv: Vec<usize>,
    /// Whether the stored Jacobian may be used, and whether it is from the current point.
    jac_age: Jacobian,
    lu_h: f64,
    scale: Vec<f64>,
    err: Vec<f64>,
    /// A(t, y), the base of the difference quotients (then scratch for the Newton residual).
    base: Vec<f64>,
    eta: f64,
    theta_max: f64,
    stats: Stats,
}

impl GeneralizedAlpha {
    /// For a first-order state of dimension `dim` = 2n (a system with first-order states
    /// reshapes the buffers at its first `init`), with the options' `rho_inf`.
    pub fn new(dim: usize, options: Options) -> Self {
        Self::with_rho_inf(dim, options, options.rho_inf)
    }

    pub fn with_rho_inf(dim: usize, options: Options, rho_inf: f64) -> Self {
        let n = dim / 2;
        let v = |k: usize| vec![0.0; k];
        GeneralizedAlpha {
            tol: Tolerance::new(&options, dim),
            opts: options,
            p: AlphaParams::from_rho_inf(rho_inf),
            n,
            nz: 0,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            y: v(dim),
            y_prev: v(dim),
            y_new: v(dim),
            f: v(dim),
            f_prev: v(dim),
            ftmp: v(dim),
            acc: v(n),
            h_acc: 0.0,
            a0: v(n),
            x: v(n),
            dx: v(n),
            aq: v(n * n),
            av: v(n * n),
            az: Vec::new(),
            mass: v(n * n),
            mass_form: false,
            ported: None,
            ported_form: false,
            jac: v(dim * dim),
            lu: v(n * n),
            piv: vec![0; n],
            jac_age: Jacobian::default(),
            lu_h: 0.0,
            scale: v(dim),
            err: v(n),
            base: v(n),
            eta: 1.0,
            theta_max: 0.0,
            stats: Stats::default(),
        }
    }

    /// Sizes the buffers for n positions and nz first-order states (allocates only when the
    /// shape changes: once, at the first `init`).
    fn shape(&mut self, n: usize, nz: usize) {
        if (n, nz) == (self.n, self.nz) {
            return;
        }
        let (m, dim) = (n + nz, 2 * n + nz);
        (self.n, self.nz) = (n, nz);
        for (b, len) in [
            (&mut self.acc, m),
            (&mut self.a0, m),
            (&mut self.x, m),
            (&mut self.dx, m),
            (&mut self.aq, m * n),
            (&mut self.av, m * n),
            (&mut self.az, m * nz),
            (&mut self.mass, n * n),
            (&mut self.lu, m * m),
            (&mut self.err, n),
            (&mut self.base, m),
            (&mut self.jac, dim * dim),
        ] {
            b.clear();
            b.resize(len, 0.0);
        }
        self.piv.resize(m, 0);
    }

    pub fn params(&self) -> AlphaParams {
        self.p
    }

    pub fn reset_stats(&mut self) {
        self.stats = Stats::default();
    }

    /// dA/dq, dA/dv at (t, y): the system's mass form (M, dh/dq, dh/dq'), or the lower half
    /// of the analytic Jacobian, or forward differences.
    fn compute_jacobian<S: OdeSystem + ?Sized>(&mut self, sys: &mut S) {
        let (n, nz) = (self.n, self.nz);
        let (m, rows) = (2 * n + nz, n + nz);
        self.stats.jacobian_evals += 1;
        self.ported_form = match &mut self.ported {
            Some((j, _)) => sys.ported_jacobians(self.t, &self.y, j),
            None => false,
        };
        if self.ported_form {
            return;
        }
        self.mass_form = nz == 0
            && sys.second_order() == Some(n)
            && sys.mass_jacobians(self.t, &self.y, &mut self.mass, &mut self.aq, &mut self.av);
        if self.mass_form {
            return;
        }
        if sys.jacobian(self.t, &self.y, &mut self.jac) {
            for i in 0..rows {
                let row = &self.jac[(n + i) * m..(n + i + 1) * m];
                self.aq[i * n..(i + 1) * n].copy_from_slice(&row[..n]);
                self.av[i * n..(i + 1) * n].copy_from_slice(&row[n..2 * n]);
                self.az[i * nz..(i + 1) * nz].copy_from_slice(&row[2 * n..]);
            }
            return;
        }
        // A(t, y) afresh: the stored one is the Newton unknown, not an exact evaluation.
        sys.rhs(self.t, &self.y, &mut self.ftmp);
        self.base.copy_from_slice(&self.ftmp[n..]);
        self.y_new.copy_from_slice(&self.y);
        for j in 0..m {
            let yj = self.y[j];
            self.y_new[j] = yj + (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
            let d = self.y_new[j] - yj;
            sys.rhs(self.t, &self.y_new, &mut self.ftmp);
            let (target, cols, col) = match j {
                j if j < n => (&mut self.aq, n, j),
                j if j < 2 * n => (&mut self.av, n, j - n),
                j => (&mut self.az, nz, j - 2 * n),
            };
            for i in 0..rows {
                target[i * cols + col] = (self.ftmp[n + i] - self.base[i]) / d;
            }
            self.y_new[j] = yj;
        }
        self.stats.rhs_evals += m as u64 + 1;
    }

    /// Refreshes the Jacobian when it is stale and factors the iteration matrix when h changed
    /// (I - cq A - cv B, or M times it); false when it is singular.
    fn iteration_matrix<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> bool {
        let (n, nz) = (self.n, self.nz);
        let rows = n + nz;
        let AlphaParams {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.p;
        let bp = (1.0 - alpha_f) / (1.0 - alpha_m);
        if !self.jac_age.valid {
            self.compute_jacobian(sys);
            self.jac_age = Jacobian {
                valid: true,
                fresh: true,
            };
            self.lu_h = 0.0;
        }
        if self.lu_h != h {
            // I - cq A - cv B, or M times it: M - cq dh/dq - cv dh/dq' (dense or ported).
            let (cq, cv) = (bp * h * h * beta, bp * h * gamma);
            self.stats.lu_decompositions += 1;
            let factored = if let (true, Some((j, lu))) = (self.ported_form, &mut self.ported) {
                lu.factor_mass(j, 1.0, cv, cq).is_ok()
            } else {
                // [I 0; 0 I] - [cq A_q + cv A_v, cz A_z; cq G_q + cv G_v, cz G_z], cz = cv.
                for i in 0..rows {
                    for j in 0..n {
                        self.lu[i * rows + j] = -cq * self.aq[i * n + j] - cv * self.av[i * n + j];
                    }
                    for j in 0..nz {
                        self.lu[i * rows + n + j] = -cv * self.az[i * nz + j];
                    }
                }
                if self.mass_form {
                    for (l, m) in self.lu.iter_mut().zip(&self.mass) {
                        *l += m;
                    }
                } else {
                    for i in 0..rows {
                        self.lu[i * rows + i] += 1.0;
                    }
                }
                lu_factor(&mut self.lu, rows, &mut self.piv).is_ok()
            };
            if !factored {
                self.lu_h = 0.0;
                return false;
            }
            self.lu_h = h;
        }
        true
    }

    /// The Newton correction: `dx` (the residual A(y) - x) becomes the iteration matrix's
    /// solve of it, in forces when the matrix is M times it.
    fn solve_correction(&mut self) {
        let (n, rows) = (self.n, self.n + self.nz);
        if let (true, Some((j, lu))) = (self.ported_form, &mut self.ported) {
            // The residual in forces, M (A(y) - x), through the ported factorisation.
            self.base.copy_from_slice(&self.dx);
            ported::mass_times(j, &self.base, &mut self.dx);
            lu.solve_mass(j, &mut self.dx);
        } else {
            if self.mass_form {
                // The residual in forces: M (A(y) - x).
                self.base.copy_from_slice(&self.dx);
                for (i, d) in self.dx.iter_mut().enumerate() {
                    let row = &self.mass[i * n..(i + 1) * n];
                    *d = row.iter().zip(&self.base).map(|(m, r)| m * r).sum();
                }
            }
            lu_solve(&self.lu, rows, &self.piv, &mut self.dx);
        }
    }

    /// The Newton correction's weighted RMS size in the state.
    fn correction_norm(&self, h: f64) -> f64 {
        let (n, nz) = (self.n, self.nz);
        let AlphaParams {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.p;
        let bp = (1.0 - alpha_f) / (1.0 - alpha_m);
        // The correction's size in the state: dq = h^2 beta beta' dx, dv = h gamma beta' dx.
        // dz = h gamma beta' dx_z.
        let mut sum = 0.0;
        for i in 0..n {
            let dq = h * h * beta * bp * self.dx[i] / self.scale[i];
            let dv = h * gamma * bp * self.dx[i] / self.scale[n + i];
            sum += dq * dq + dv * dv;
        }
        for j in 0..nz {
            let dz = h * gamma * bp * self.dx[n + j] / self.scale[2 * n + j];
            sum += dz * dz;
        }
        if n + nz > 0 {
            (sum / (2 * n + nz) as f64).sqrt()
        } else {
            0.0
        }
    }

    fn attempt<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, h: f64) -> Attempt {
        let (n, nz) = (self.n, self.nz);
        let rows = n + nz;
        let beta = self.p.beta;
        if !self.iteration_matrix(sys, h) {
            return Attempt::Singular;
        }
        for i in 0..2 * n + nz {
            self.scale[i] = self.tol.scale(i, self.y[i]);
        }
        self.shift_acc(h);
        let t1 = self.t + h;
        // Start from q''_n.
        self.x.copy_from_slice(&self.f[n..]);
        let mut rate = Rate::new(self.eta, newton::tolerance(&self.opts), MAX_NEWTON);
        self.theta_max = 0.0;
        for it in 0..MAX_NEWTON {
            self.update_state(h);
            sys.rhs(t1, &self.y_new, &mut self.ftmp);
            self.stats.rhs_evals += 1;
            self.stats.newton_iterations += 1;
            for i in 0..rows {
                self.dx[i] = self.ftmp[n + i] - self.x[i];
            }
            self.solve_correction();
            let dnorm = self.correction_norm(h);
            if !dnorm.is_finite() {
                return Attempt::NonFinite;
            }
            let verdict = rate.judge(it, dnorm, &mut self.theta_max);
            if verdict == Verdict::Failed {
                return Attempt::NewtonFailed;
            }
            for i in 0..rows {
                self.x[i] += self.dx[i];
            }
            if verdict == Verdict::Converged {
                self.eta = rate.eta();
                self.update_state(h);
                if !all_finite(&self.y_new) {
                    return Attempt::NonFinite;
                }
                let c = h * h * (beta - 1.0 / 6.0);
                for i in 0..n {
                    self.err[i] = c * (self.x[i] - self.f[n + i]);
                }
                let err = error_norm(&self.err, &self.y[..n], &self.y_new[..n], &self.tol);
                return if err.is_finite() {
                    Attempt::Done(err)
                } else {
                    Attempt::NonFinite
                };
            }
        }
        Attempt::NewtonFailed
    }

    /// a_n belongs to the step size it was formed with: it approximates q'' at
    /// t_n + (alpha_m - alpha_f) h_acc. A step of another size needs it at
    /// t_n + (alpha_m - alpha_f) h, else every change of h costs an O(h) error in a and the
    /// method drops to first order on variable steps. The shift takes the third derivative
    /// from the last step's accelerations.
    fn shift_acc(&mut self, h: f64) {
        let (n, rows) = (self.n, self.n + self.nz);
        let dt = self.t - self.t_prev;
        let k = if dt > 0.0 {
            (self.p.alpha_m - self.p.alpha_f) * (h - self.h_acc) / dt
        } else {
            0.0
        };
        for i in 0..rows {
            self.a0[i] = self.acc[i] + k * (self.f[n + i] - self.f_prev[n + i]);
        }
    }

    /// y_new = (q1, v1, z1) from the current unknown x = (q''_(n+1), z'_(n+1)); a1 is
    /// recomputed on acceptance.
    fn update_state(&mut self, h: f64) {
        let (n, nz) = (self.n, self.nz);
        let AlphaParams {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.p;
        for i in 0..n {
            let a0 = self.a0[i];
            let a1 = (alpha_f * self.f[n + i] - alpha_m * a0 + (1.0 - alpha_f) * self.x[i])
                / (1.0 - alpha_m);
            self.y_new[i] = self.y[i] + h * self.y[n + i] + h * h * ((0.5 - beta) * a0 + beta * a1);
            self.y_new[n + i] = self.y[n + i] + h * ((1.0 - gamma) * a0 + gamma * a1);
        }
        for j in 0..nz {
            let (i, b0) = (2 * n + j, self.a0[n + j]);
            let b1 = (alpha_f * self.f[i] - alpha_m * b0 + (1.0 - alpha_f) * self.x[n + j])
                / (1.0 - alpha_m);
            self.y_new[i] = self.y[i] + h * ((1.0 - gamma) * b0 + gamma * b1);
        }
    }
}

hermite_stepper!(GeneralizedAlpha, "galpha");

impl<S: OdeSystem + ?Sized> Solver<S> for GeneralizedAlpha {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        self.tol.fill(sys);
        match sys.second_order() {
            Some(n) if 2 * n <= y0.len() && y0.len() == self.y.len() => {
                self.shape(n, y0.len() - 2 * n)
            }
            _ => return Err(OdeError::NotSecondOrder { t: t0 }),
        }
        self.t = t0;
        self.t_prev = t0;
        self.jac_age = Jacobian::default();
        self.lu_h = 0.0;
        self.eta = 1.0;
        // The ported form, with the trailing states after the ports.
        ported::prepare(&mut self.ported, &*sys, Some(self.n), self.nz);
        self.h = start(
            sys,
            t0,
            y0,
            2,
            (&self.opts, &self.tol),
            StartBuffers {
                y: &mut self.y,
                y_prev: &mut self.y_prev,
                f: &mut self.f,
                f_prev: &mut self.f_prev,
                ytmp: &mut self.y_new,
                ftmp: &mut self.ftmp,
            },
            &mut self.stats,
        )?;
        let n = self.n;
        self.acc.copy_from_slice(&self.f[n..]);
        self.h_acc = 0.0;
        Ok(())
    }

    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        if t_stop.is_nan() || t_stop <= self.t {
            return Ok(());
        }
        let mut trials = Trials::default();
        loop {
            let (h, lands, h_prop) = propose_step(self.t, self.h, t_stop, &self.opts, &self.stats)?;
            let outcome = self.attempt(sys, h);
            let accepted = newton::after_trial(
                outcome,
                1.0 / 3.0,
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

            let (n, rows) = (self.n, self.n + self.nz);
            let AlphaParams {
                alpha_m, alpha_f, ..
            } = self.p;
            for i in 0..rows {
                self.acc[i] = (alpha_f * self.f[n + i] - alpha_m * self.a0[i]
                    + (1.0 - alpha_f) * self.x[i])
                    / (1.0 - alpha_m);
            }
            self.h_acc = h;
            let t_new = if lands { t_stop } else { self.t + h };
            std::mem::swap(&mut self.y_prev, &mut self.y);
            std::mem::swap(&mut self.y, &mut self.y_new);
            std::mem::swap(&mut self.f_prev, &mut self.f);
            self.f[..n].copy_from_slice(&self.y[n..2 * n]);
            self.f[n..].copy_from_slice(&self.x);
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
