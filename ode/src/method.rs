//! Picking an integrator by name at run time (CLI, model files) without generics at the call
//! site: [`Method`] parses the name, [`AnySolver`] dispatches to the concrete solver.
//!
//! Conventions shared by all solvers:
//! * Forward integration only; `step` with `t_stop <= t` does nothing.
//! * `Stats` accumulate from construction across `init` calls (`reset_stats` on the concrete
//!   solvers restarts them); `rejected_steps` includes Newton failures.
//! * `max_steps` bounds attempted steps (accepted + rejected) since construction.
//! * `NonFinite`: from `init` when y0 or f(t0, y0) is not finite; from `step` when the accepted
//!   state is not finite, or (adaptive methods) after ten consecutive trial steps with
//!   non-finite values, each tried with h / 10, at the last good time.
//! * `StepSizeUnderflow` when the controller wants a step below `h_min`; a final step shortened
//!   to land on `t_stop` may be smaller than `h_min`.
//! * State, dense output and counters live in the system-independent supertrait `Stepper`, so
//!   callers need not name the system type to read them.

use std::fmt;
use std::str::FromStr;

use super::{
    Auto, Dopri5, GeneralizedAlpha, Imex, OdeError, OdeSystem, Options, Rk4, Rodas4, Sdirk4,
    Solver, Stats, Stepper,
};

/// The available integrators, named `rk4`, `dopri5`, `sdirk4`, `rodas4`, `galpha`, `imex`,
/// `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    Rk4,
    Dopri5,
    Sdirk4,
    Rodas4,
    /// Generalized-alpha on the second-order equations.
    GeneralizedAlpha,
    /// ARK4(3)6L[2]SA: the modal bodies' own linear terms implicit, the elements explicit.
    Imex,
    /// dopri5 while not stiff, rodas4 while stiff (`ode/auto.rs`).
    Auto,
}

impl Method {
    pub const ALL: [Method; 7] = [
        Method::Rk4,
        Method::Dopri5,
        Method::Sdirk4,
        Method::Rodas4,
        Method::GeneralizedAlpha,
        Method::Imex,
        Method::Auto,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::Rk4 => "rk4",
            Method::Dopri5 => "dopri5",
            Method::Sdirk4 => "sdirk4",
            Method::Rodas4 => "rodas4",
            Method::GeneralizedAlpha => "galpha",
            Method::Imex => "imex",
            Method::Auto => "auto",
        }
    }

    /// Whether the method is implicit (stable on stiff systems, uses a Jacobian); `auto` is
    /// when the problem is stiff.
    pub fn implicit(self) -> bool {
        matches!(
            self,
            Method::Sdirk4
                | Method::Rodas4
                | Method::GeneralizedAlpha
                | Method::Imex
                | Method::Auto
        )
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown method name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown integrator `{0}` (expected rk4, dopri5, sdirk4, rodas4, galpha, imex or auto)")]
pub struct UnknownMethod(pub String);

impl FromStr for Method {
    type Err = UnknownMethod;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownMethod(s.to_string()))
    }
}

macro_rules! dispatch {
    ($self:expr, $s:ident => $e:expr) => {
        match $self {
            AnySolver::Rk4($s) => $e,
            AnySolver::Dopri5($s) => $e,
            AnySolver::Sdirk4($s) => $e,
            AnySolver::Rodas4($s) => $e,
            AnySolver::GeneralizedAlpha($s) => $e,
            AnySolver::Imex($s) => $e,
            AnySolver::Auto($s) => $e,
        }
    };
}

/// One of the integrators, chosen at run time.
pub enum AnySolver {
    Rk4(Rk4),
    Dopri5(Dopri5),
    Sdirk4(Sdirk4),
    Rodas4(Rodas4),
    GeneralizedAlpha(GeneralizedAlpha),
    Imex(Imex),
    Auto(Auto),
}

impl AnySolver {
    /// Allocates the chosen solver's work arrays for a system of dimension `dim`.
    pub fn new(method: Method, dim: usize, options: Options) -> Self {
        match method {
            Method::Rk4 => AnySolver::Rk4(Rk4::new(dim, options)),
            Method::Dopri5 => AnySolver::Dopri5(Dopri5::new(dim, options)),
            Method::Sdirk4 => AnySolver::Sdirk4(Sdirk4::new(dim, options)),
            Method::Rodas4 => AnySolver::Rodas4(Rodas4::new(dim, options)),
            Method::GeneralizedAlpha => {
                AnySolver::GeneralizedAlpha(GeneralizedAlpha::new(dim, options))
            }
            Method::Imex => AnySolver::Imex(Imex::new(dim, options)),
            Method::Auto => AnySolver::Auto(Auto::new(dim, options)),
        }
    }

    pub fn method(&self) -> Method {
        match self {
            AnySolver::Rk4(_) => Method::Rk4,
            AnySolver::Dopri5(_) => Method::Dopri5,
            AnySolver::Sdirk4(_) => Method::Sdirk4,
            AnySolver::Rodas4(_) => Method::Rodas4,
            AnySolver::GeneralizedAlpha(_) => Method::GeneralizedAlpha,
            AnySolver::Imex(_) => Method::Imex,
            AnySolver::Auto(_) => Method::Auto,
        }
    }
}

impl Stepper for AnySolver {
    fn name(&self) -> &'static str {
        self.method().name()
    }
    fn t(&self) -> f64 {
        dispatch!(self, s => s.t())
    }
    fn y(&self) -> &[f64] {
        dispatch!(self, s => s.y())
    }
    fn t_prev(&self) -> f64 {
        dispatch!(self, s => s.t_prev())
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        dispatch!(self, s => s.interpolate(t, out))
    }
    fn stats(&self) -> Stats {
        dispatch!(self, s => s.stats())
    }
}

impl<S: OdeSystem + ?Sized> Solver<S> for AnySolver {
    fn init(&mut self, sys: &mut S, t0: f64, y0: &[f64]) -> Result<(), OdeError> {
        dispatch!(self, s => Solver::<S>::init(s, sys, t0, y0))
    }
    fn step(&mut self, sys: &mut S, t_stop: f64) -> Result<(), OdeError> {
        dispatch!(self, s => Solver::<S>::step(s, sys, t_stop))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Method::ALL {
            assert_eq!(m.to_string().parse::<Method>(), Ok(m));
        }
        assert_eq!("DOPRI5".parse::<Method>(), Ok(Method::Dopri5));
        assert!("euler".parse::<Method>().is_err());
    }

    /// A CLI holds the model as `dyn OdeSystem` and the method as a name: both must work.
    #[test]
    fn runs_a_dyn_system_picked_by_name() {
        use crate::problems::Harmonic;
        for name in ["rk4", "dopri5", "sdirk4", "rodas4", "galpha", "auto"] {
            let m: Method = name.parse().unwrap();
            let opts = Options {
                h0: if m == Method::Rk4 { 1e-3 } else { 0.0 },
                ..Options::default()
            };
            let mut solver = AnySolver::new(m, 2, opts);
            let mut model = Harmonic { omega: 1.0 };
            let sys: &mut dyn OdeSystem = &mut model;
            solver.init(sys, 0.0, &[1.0, 0.0]).unwrap();
            while solver.t() < 1.0 {
                solver.step(sys, 1.0).unwrap();
            }
            assert_eq!(Stepper::name(&solver), name);
            let bound = if m == Method::GeneralizedAlpha {
                1e-3
            } else {
                1e-5
            };
            assert!((solver.y()[0] - 1f64.cos()).abs() < bound, "{name}");
        }
    }
}
