//! Pieces shared by the methods: the error norm, the automatic initial step, cubic Hermite
//! dense output and the rule for landing on `t_stop`.

use super::{OdeError, OdeSystem, Options, Stats};

/// The tolerances per component: atol_i = atol * s_i with the system's scales
/// ([`OdeSystem::atol_scales`]), so coordinates of different units and sizes are held to
/// comparable accuracy. Allocated in `new`, filled at `init`.
#[derive(Clone, Debug)]
pub struct Tolerance {
    pub rtol: f64,
    atol: f64,
    abs: Vec<f64>,
}

impl Tolerance {
    pub fn new(opts: &Options, dim: usize) -> Self {
        Tolerance {
            rtol: opts.rtol,
            atol: opts.atol,
            abs: vec![opts.atol; dim],
        }
    }

    /// Asks the system for its scales (no allocation).
    pub fn fill<S: OdeSystem + ?Sized>(&mut self, sys: &S) {
        self.abs.fill(1.0);
        sys.atol_scales(&mut self.abs);
        for a in self.abs.iter_mut() {
            *a *= self.atol;
        }
    }

    /// atol_i + rtol |y|.
    #[inline]
    pub fn scale(&self, i: usize, y: f64) -> f64 {
        self.abs[i] + self.rtol * y.abs()
    }
}

/// Hairer's weighted RMS norm of `err` with scale atol_i + rtol * max(|y0_i|, |y1_i|)
/// (Solving ODEs I, eq. II.4.11). A value <= 1 means the step meets the tolerance.
pub fn error_norm(err: &[f64], y0: &[f64], y1: &[f64], tol: &Tolerance) -> f64 {
    let n = err.len();
    if n == 0 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..n {
        let sc = tol.scale(i, y0[i].abs().max(y1[i].abs()));
        let q = err[i] / sc;
        sum += q * q;
    }
    (sum / n as f64).sqrt()
}

/// Whether every entry is finite.
pub fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Hairer's starting step size (Solving ODEs I, Section II.4, "automatic selection of the
/// initial step size") for a method of order `order`. `f0` = f(t0, y0) is given; `y1` and
/// `f1` are scratch buffers. Costs one right-hand side evaluation (counted in `stats`).
#[allow(clippy::too_many_arguments)]
pub fn initial_step<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t0: f64,
    y0: &[f64],
    f0: &[f64],
    order: u32,
    (opts, tol): (&Options, &Tolerance),
    y1: &mut [f64],
    f1: &mut [f64],
    stats: &mut Stats,
) -> f64 {
    let n = y0.len();
    if n == 0 {
        return opts.h_max.min(1.0);
    }
    let sc = |i: usize| tol.scale(i, y0[i]);
    let rms = |v: &dyn Fn(usize) -> f64| -> f64 {
        ((0..n).map(|i| v(i).powi(2)).sum::<f64>() / n as f64).sqrt()
    };
    let d0 = rms(&|i| y0[i] / sc(i));
    let d1 = rms(&|i| f0[i] / sc(i));
    let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    h0 = h0.min(opts.h_max);
    // One explicit Euler step estimates the second derivative.
    for i in 0..n {
        y1[i] = y0[i] + h0 * f0[i];
    }
    sys.rhs(t0 + h0, y1, f1);
    stats.rhs_evals += 1;
    let d2 = rms(&|i| (f1[i] - f0[i]) / sc(i)) / h0;
    let dmax = d1.max(d2);
    let h1 = if !dmax.is_finite() {
        h0 * 1e-3
    } else if dmax <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        (0.01 / dmax).powf(1.0 / (order as f64 + 1.0))
    };
    (100.0 * h0).min(h1).min(opts.h_max).max(opts.h_min)
}

/// The step to try from `t` towards `t_stop` with the proposed size `h`: returns the step and
/// whether it lands on `t_stop`. A step that would end within 1% of a step short of `t_stop`
/// is stretched to land on it, so no sliver step is left over.
pub fn clip_step(t: f64, h: f64, t_stop: f64) -> (f64, bool) {
    let remaining = t_stop - t;
    if h * 1.01 >= remaining {
        (remaining, true)
    } else {
        (h, false)
    }
}

/// Cubic Hermite interpolation on [t0, t0 + h] from the end values and slopes; third order,
/// used by RK4 and SDIRK4 as their dense output.
#[allow(clippy::too_many_arguments)]
pub fn hermite(
    t0: f64,
    h: f64,
    y0: &[f64],
    f0: &[f64],
    y1: &[f64],
    f1: &[f64],
    t: f64,
    out: &mut [f64],
) {
    if h == 0.0 {
        out.copy_from_slice(y1);
        return;
    }
    let s = (t - t0) / h;
    let s2 = s * s;
    let s3 = s2 * s;
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    for i in 0..out.len() {
        out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
    }
}

/// The smallest step allowed at time t: `h_min`, and never below the time resolution (a few
/// ulps of t), where t + h would not advance and the integration would stall.
pub fn min_step(t: f64, opts: &Options) -> f64 {
    opts.h_min.max(4.0 * f64::EPSILON * t.abs())
}

/// The budget check shared by the methods: every attempted step (accepted or rejected) counts.
/// Attempted steps (accepted + rejected): what the step budget counts.
pub fn attempts(stats: &Stats) -> u64 {
    stats.steps + stats.rejected_steps
}

pub fn check_budget(stats: &Stats, opts: &Options, t: f64) -> Result<(), OdeError> {
    let attempts = attempts(stats);
    if attempts >= opts.max_steps {
        Err(OdeError::StepBudget { t, steps: attempts })
    } else {
        Ok(())
    }
}

/// The next trial step of an adaptive method from `t` with the controller's size `h`: the step
/// budget, then `h_max`, then the underflow check, then the landing on `t_stop`. Returns the
/// step to try, whether it lands, and the size proposed before any cut.
pub fn propose_step(
    t: f64,
    h: f64,
    t_stop: f64,
    opts: &Options,
    stats: &Stats,
) -> Result<(f64, bool, f64), OdeError> {
    check_budget(stats, opts, t)?;
    let h_prop = h.min(opts.h_max);
    if h_prop < min_step(t, opts) {
        return Err(OdeError::StepSizeUnderflow { t, h: h_prop });
    }
    let (h, lands) = clip_step(t, h_prop, t_stop);
    Ok((h, lands, h_prop))
}

/// The size after an accepted step. A step cut short to reach `t_stop` says nothing against
/// the step proposed before the cut: keep that, so stepping on without `init` is not slowed.
pub fn after_landing(h_next: f64, h_prop: f64, lands: bool, rejected_last: bool) -> f64 {
    if lands && !rejected_last {
        h_next.max(h_prop)
    } else {
        h_next
    }
}

/// The buffers [`start`] fills.
pub struct StartBuffers<'a> {
    pub y: &'a mut [f64],
    pub y_prev: &'a mut [f64],
    pub f: &'a mut [f64],
    pub f_prev: &'a mut [f64],
    /// Scratch for the initial step guess.
    pub ytmp: &'a mut [f64],
    pub ftmp: &'a mut [f64],
}

/// The start shared by the methods with Hermite dense output (sdirk4, rodas4, galpha):
/// y = y_prev = y0, f = f_prev = f(t0, y0), both checked finite, and the first step size
/// (`h0`, or Hairer's guess for a method of order `order`).
pub fn start<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t0: f64,
    y0: &[f64],
    order: u32,
    (opts, tol): (&Options, &Tolerance),
    b: StartBuffers,
    stats: &mut Stats,
) -> Result<f64, OdeError> {
    b.y.copy_from_slice(y0);
    b.y_prev.copy_from_slice(y0);
    if !all_finite(y0) {
        return Err(OdeError::NonFinite { t: t0 });
    }
    sys.rhs(t0, b.y, b.f);
    stats.rhs_evals += 1;
    b.f_prev.copy_from_slice(b.f);
    if !all_finite(b.f) {
        return Err(OdeError::NonFinite { t: t0 });
    }
    Ok(if opts.h0 > 0.0 {
        opts.h0.min(opts.h_max)
    } else {
        initial_step(sys, t0, b.y, b.f, order, (opts, tol), b.ytmp, b.ftmp, stats)
    })
}

/// `Stepper` for a method whose dense output is the cubic Hermite interpolant of its fields
/// `t_prev`, `t`, `y_prev`, `y`, `f_prev`, `f` and whose counters are `stats`.
macro_rules! hermite_stepper {
    ($ty:ty, $name:expr) => {
        impl $crate::Stepper for $ty {
            fn name(&self) -> &'static str {
                $name
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
                $crate::common::hermite(
                    self.t_prev,
                    self.t - self.t_prev,
                    &self.y_prev,
                    &self.f_prev,
                    &self.y,
                    &self.f,
                    t,
                    out,
                );
            }
            fn stats(&self) -> $crate::Stats {
                self.stats
            }
        }
    };
}
pub(crate) use hermite_stepper;

/// Trials with non-finite values a step may take in a row (each with h / 10) before it fails.
pub const MAX_NONFINITE_TRIALS: u32 = 10;

/// The rejected trials within one `step` call of an adaptive method.
#[derive(Debug, Default)]
pub struct Trials {
    /// The last trial was rejected: the next accepted step may not grow.
    pub rejected_last: bool,
    nonfinite: u32,
}

impl Trials {
    /// A trial that gave non-finite values: rejected, retried with h / 10; after
    /// [`MAX_NONFINITE_TRIALS`] of them the step fails at the last good time `t`.
    pub fn non_finite(&mut self, t: f64, h: f64, stats: &mut Stats) -> Result<f64, OdeError> {
        stats.rejected_steps += 1;
        self.rejected_last = true;
        self.nonfinite += 1;
        if self.nonfinite >= MAX_NONFINITE_TRIALS {
            return Err(OdeError::NonFinite { t });
        }
        Ok(h * 0.1)
    }

    /// Any other rejected trial (error estimate above 1, Newton failure).
    pub fn rejected(&mut self, stats: &mut Stats) {
        stats.rejected_steps += 1;
        self.rejected_last = true;
    }

    /// The growth factor after an accepted step: within [fac_min, fac_max], and at most 1
    /// right after a rejection.
    pub fn accept_factor(&self, fac: f64, fac_min: f64, fac_max: f64) -> f64 {
        let fac = fac.clamp(fac_min, fac_max);
        if self.rejected_last {
            fac.min(1.0)
        } else {
            fac
        }
    }
}

/// Hairer's PI step size controller for the explicit and IMEX Runge-Kutta pairs (Solving ODEs
/// II, Section IV.2; Gustafsson): a rejected step shrinks by clamp(0.9 err^-alpha, 0.2, 1), an
/// accepted one grows by clamp(0.9 err^-alpha err_prev^beta, 0.2, fac_max) (at most 1 right
/// after a rejection). alpha = 1 / (embedded order + 1) - 0.75 beta.
#[derive(Clone, Copy, Debug)]
pub struct PiControl {
    alpha: f64,
    beta: f64,
    fac_max: f64,
    /// The previous accepted error norm (the "I" part).
    err_prev: f64,
}

impl PiControl {
    const SAFETY: f64 = 0.9;
    const FAC_MIN: f64 = 0.2;
    const ERR_START: f64 = 1e-4;

    /// For an embedded method of order `order_hat`, beta = 0.04.
    pub fn new(order_hat: u32, fac_max: f64) -> Self {
        let beta = 0.04;
        PiControl {
            alpha: 1.0 / (order_hat as f64 + 1.0) - 0.75 * beta,
            beta,
            fac_max,
            err_prev: Self::ERR_START,
        }
    }

    /// Forget the history (a restart at `init`).
    pub fn reset(&mut self) {
        self.err_prev = Self::ERR_START;
    }

    /// The step to retry with after step `h` was rejected with error norm `err` (> 1).
    pub fn rejected(&self, h: f64, err: f64) -> f64 {
        h * (Self::SAFETY * err.powf(-self.alpha)).clamp(Self::FAC_MIN, 1.0)
    }

    /// The growth factor after a step accepted with error norm `err`; remembers `err`.
    pub fn accepted(&mut self, err: f64, trials: &Trials) -> f64 {
        let fac = trials.accept_factor(
            Self::SAFETY * err.max(1e-10).powf(-self.alpha) * self.err_prev.powf(self.beta),
            Self::FAC_MIN,
            self.fac_max,
        );
        self.err_prev = err.max(Self::ERR_START);
        fac
    }
}
