//! Integrators for y' = f(t, y): one method a file, tableaux as data, standard test problems in
//! `problems/`. All work arrays are allocated in `new`; `init`, `step` and `interpolate` never
//! allocate (a counting allocator test checks it).

// Index loops over vectors read like the formulas they implement.
#![allow(clippy::needless_range_loop)]

use thiserror::Error;

pub mod auto;
mod common;
pub mod dopri5;
pub mod generalized_alpha;
pub mod imex;
mod iteration;
pub mod lu;
pub mod method;
mod newton;
pub mod ported;
pub mod problems;
pub mod rk4;
pub mod rodas4;
mod rounded;
pub mod sdirk4;
pub mod tableau;
#[cfg(test)]
mod tests;

pub use auto::Auto;
pub use dopri5::Dopri5;
pub use generalized_alpha::GeneralizedAlpha;
pub use imex::Imex;
pub use method::{AnySolver, Method, UnknownMethod};
pub use ported::PortedJacobian;
pub use rk4::Rk4;
pub use rodas4::Rodas4;
pub use rounded::Rounded;
pub use sdirk4::Sdirk4;

/// A first-order ODE system y' = f(t, y).
pub trait OdeSystem {
    fn dim(&self) -> usize;
    /// f(t, y) into `dy`.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]);
    /// df/dy at (t, y), row-major `dim x dim` into `jac`. Return `false` when the system has no
    /// analytic Jacobian: the implicit integrators then use finite differences.
    fn jacobian(&mut self, _t: f64, _y: &[f64], _jac: &mut [f64]) -> bool {
        false
    }
    /// Scales of the absolute tolerance: component i is held to atol * s[i] (entries are 1 on
    /// entry). A system whose components differ in units or size (metres, radians, modal
    /// coordinates, velocities) says here what an error of atol means for each.
    fn atol_scales(&self, _s: &mut [f64]) {}
    /// `Some(n)` when the state is y = [q; q'] with n positions and f = [q'; q''] (a
    /// mechanical system in first-order form): methods for second-order equations
    /// (generalized-alpha) need it.
    fn second_order(&self) -> Option<usize> {
        None
    }
    /// For a second-order system (`second_order` is `Some(n)`) written M(t) q'' = h(t, q, q'):
    /// M, dh/dq and dh/dq' at (t, y), row-major n x n each. The implicit methods then
    /// factorise d^2 M - c d dh/dq' - c^2 dh/dq and never form M^-1 dh. `false`: not
    /// available (they use `jacobian`).
    fn mass_jacobians(
        &mut self,
        _t: f64,
        _y: &[f64],
        _m: &mut [f64],
        _hq: &mut [f64],
        _hqd: &mut [f64],
    ) -> bool {
        false
    }
    /// For a second-order system whose coordinates split into q1 (the first n1, full mass
    /// matrix) and q2 (unit mass, own terms diagonal: modes on a fixed frame) that meet only
    /// through r port coordinates p = B2^T q2: `Some((n1, r))`. The implicit methods then
    /// factorise an (n1 + r) matrix in place of the n x n mass form (`ported.rs`; plus the
    /// trailing states for generalized-alpha).
    fn ported_shape(&self) -> Option<(usize, usize)> {
        None
    }
    /// The linear terms an IMEX method takes implicitly, for a second-order system y = [q; q';
    /// z] (`second_order` is `Some(n)`): the mass block M1 (n1 x n1, row-major, into the
    /// first n1^2 entries of `m1`; the coordinates after n1 have unit mass) at (t, y), and
    /// each coordinate's own stiffness `k` and damping `c` (length n), so that the implicit
    /// part is q' = q'', M1 q'' = -k q - c q' (e.g. the modal bodies' omega^2 and
    /// 2 zeta omega). Returns n1; `None`: no such split (the IMEX method then refuses).
    fn linear_part(
        &mut self,
        _t: f64,
        _y: &[f64],
        _m1: &mut [f64],
        _k: &mut [f64],
        _c: &mut [f64],
    ) -> Option<usize> {
        None
    }
    /// The ported pieces at (t, y) into `j` (shaped by `ported_shape`). `false`: not
    /// available now (the methods fall back to `mass_jacobians`).
    fn ported_jacobians(&mut self, _t: f64, _y: &[f64], _j: &mut PortedJacobian) -> bool {
        false
    }
}

/// Why an integration stopped early. Every variant carries the time reached.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum OdeError {
    #[error("step size underflow at t = {} s (h = {h:e} s)", Rounded(*t))]
    StepSizeUnderflow { t: f64, h: f64 },
    #[error("Newton iteration diverged at t = {} s (h = {h:e} s)", Rounded(*t))]
    NewtonDivergence { t: f64, h: f64 },
    #[error("non-finite state at t = {} s", Rounded(*t))]
    NonFinite { t: f64 },
    #[error("step budget of {steps} steps exhausted at t = {} s", Rounded(*t))]
    StepBudget { t: f64, steps: u64 },
    #[error("singular iteration matrix at t = {} s", Rounded(*t))]
    Singular { t: f64 },
    #[error("the method needs a second-order system y = [q; q'] (at t = {} s)", Rounded(*t))]
    NotSecondOrder { t: f64 },
    #[error("the IMEX method needs the system's linear part (at t = {} s)", Rounded(*t))]
    NoLinearPart { t: f64 },
}

impl OdeError {
    /// The time the integration reached.
    pub fn time(&self) -> f64 {
        match *self {
            OdeError::StepSizeUnderflow { t, .. }
            | OdeError::NewtonDivergence { t, .. }
            | OdeError::NonFinite { t }
            | OdeError::StepBudget { t, .. }
            | OdeError::Singular { t }
            | OdeError::NotSecondOrder { t }
            | OdeError::NoLinearPart { t } => t,
        }
    }
}

/// Work counters, reported in `summary.json` and the work-precision study.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Stats {
    pub steps: u64,
    pub rejected_steps: u64,
    pub rhs_evals: u64,
    pub jacobian_evals: u64,
    pub lu_decompositions: u64,
    pub newton_iterations: u64,
    /// Explicit methods with stiffness detection (dopri5): accepted steps on which h times
    /// the estimated spectral radius exceeded the stability boundary (Hairer's test).
    pub stiff_steps: u64,
    /// The first time Hairer's test called the problem stiff (15 such steps with fewer than 6
    /// non-stiff ones between them): the method runs on its stability limit from there.
    pub stiff_at: Option<f64>,
    /// The composite method (`auto`): hand-overs between dopri5 and rodas4.
    pub method_switches: u64,
}

/// Step control and budgets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub rtol: f64,
    pub atol: f64,
    /// Initial step (adaptive) or the fixed step (RK4); 0 = choose automatically.
    pub h0: f64,
    pub h_max: f64,
    pub h_min: f64,
    pub max_steps: u64,
    /// Generalized-alpha's spectral radius at h omega -> infinity, in [0, 1]: 1 keeps every
    /// mode (no numerical damping), 0 annihilates the unresolved ones in one step. Other
    /// methods ignore it.
    pub rho_inf: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            rtol: 1e-6,
            atol: 1e-9,
            h0: 0.0,
            h_max: f64::INFINITY,
            h_min: 1e-14,
            max_steps: 50_000_000,
            rho_inf: generalized_alpha::DEFAULT_RHO_INF,
        }
    }
}

/// What a stepping integrator holds independent of the system it integrates: the state after
/// the last accepted step, dense output inside that step, and its counters. A supertrait of
/// `Solver<S>`, so `solver.t()` resolves without naming the system type.
pub trait Stepper {
    fn name(&self) -> &'static str;
    /// Current time and state (end of the last accepted step).
    fn t(&self) -> f64;
    fn y(&self) -> &[f64];
    /// Start of the last accepted step.
    fn t_prev(&self) -> f64;
    /// Dense output: the state at `t` in [t_prev, t] into `out`.
    fn interpolate(&self, t: f64, out: &mut [f64]);
    /// Work counters so far (they accumulate across `init` calls).
    fn stats(&self) -> Stats;
}

/// A stepping integrator. The caller owns the loop, so it can sample dense output and evaluate
/// sensors between steps, and stop at discontinuities of the right-hand side.
pub trait Solver<S: OdeSystem + ?Sized>: Stepper {
    /// Start at (t0, y0); discards any history (call again after a discontinuity).
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError>;
    /// Take one accepted step, never past `t_stop`, landing exactly on it when it is within
    /// reach. The right-hand side may be discontinuous at `t_stop`: the caller calls `init`
    /// again there.
    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError>;
}
