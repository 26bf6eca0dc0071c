//! What a run is asked to do and what it guards: the start, the output window and sampling,
//! the limits of the linearisation and the interrupt flag. Set-up data, apart from the loop.

use crate::clearance::Watch;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use washdyn_model::equations::MarkerDef;

/// The method a model file's integrator name stands for (a scene's `solver`).
pub fn method_of(i: washdyn_model::ir::Integrator) -> washdyn_ode::Method {
    use washdyn_model::ir::Integrator as I;
    use washdyn_ode::Method as M;
    match i {
        I::Rk4 => M::Rk4,
        I::Dopri5 => M::Dopri5,
        I::Sdirk4 => M::Sdirk4,
        I::Rodas4 => M::Rodas4,
        I::Galpha => M::GeneralizedAlpha,
        I::Imex => M::Imex,
        I::Auto => M::Auto,
    }
}

/// How the run starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// Static equilibrium at t0 (the default: no drop transient).
    Static,
    /// q = 0, q' = 0: the model's reference position.
    Reference,
    /// Rest under gravity and the mean loads at the start speed: rotating unbalances are
    /// left to the dynamics (`statics::mean_load_equilibrium`).
    MeanLoad,
    /// On the periodic steady state at constant speed (`periodic::periodic_state`, shooting).
    Periodic,
}

impl Start {
    /// The start as `--start` and a study file spell it.
    pub fn name(self) -> &'static str {
        match self {
            Start::Static => "static",
            Start::MeanLoad => "mean",
            Start::Reference => "reference",
            Start::Periodic => "periodic",
        }
    }
}

impl std::str::FromStr for Start {
    type Err = String;
    fn from_str(s: &str) -> Result<Start, String> {
        match s {
            "static" => Ok(Start::Static),
            "mean" => Ok(Start::MeanLoad),
            "reference" => Ok(Start::Reference),
            "periodic" => Ok(Start::Periodic),
            _ => Err(format!(
                "unknown start `{s}` (static, mean, periodic, reference)"
            )),
        }
    }
}

#[derive(Clone, Debug)]
pub struct RunOptions {
    pub t_start: f64,
    pub t_end: f64,
    /// Sampling rate of the sensor output, Hz.
    pub sample_rate: f64,
    pub start: Start,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            t_start: 0.0,
            t_end: 1.0,
            sample_rate: 2000.0,
            start: Start::Static,
        }
    }
}

/// Bounds of the small-motion linearisation the equations rest on (equations/mod.rs: tub
/// positions p0 + s + u + alpha x s). Rotation: at 0.05 rad, sin a and tan a differ from a by
/// 4e-4 and 8e-4 relative and cos a from 1 by 1.2e-3, so dropped second-order terms stay near
/// 1e-3. Translation: the tub-cabinet clearance of the reference machine, 0.30 m cabinet
/// half-width - 0.27 m tub radius = 30 mm; beyond it the tub would hit the cabinet, which the
/// model does not contain.
#[derive(Clone, Debug)]
pub struct Guard {
    /// Largest tub rotation |alpha| without a warning, rad.
    pub rotation_rad: f64,
    /// Largest tub translation |u| (from the reference position) without a warning, m.
    pub translation_m: f64,
    /// The run stops with [`RunError::Validity`] at this multiple of a bound; `None`: never.
    pub stop_factor: Option<f64>,
    /// Polled between steps: when set, the run stops with [`RunError::Interrupted`].
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Wall-clock window over which progress is measured, s.
    pub stall_window_s: f64,
    /// A run whose simulated-time rate over a window projects the remaining time to more than
    /// this (wall-clock seconds) stops with [`RunError::Stalled`].
    pub max_projected_s: f64,
    /// Force elements' tub ends (name, the body layer's marker on the tub's frame): their
    /// rigid displacement u + alpha x s is the element's deflection (the cabinet is fixed),
    /// reported and warned about at the translation bound (the tub wall's clearance), never a
    /// stop (`clearance::element_tub_ends`).
    pub elements: Vec<(String, MarkerDef)>,
    /// The fixed step of an explicit fixed-step method (rk4), s: checked at the start against
    /// the stability limit [`RK4_STABILITY`] / spectral radius of the Jacobian.
    pub fixed_step: Option<f64>,
    /// The door ring (warned about at the translation bound, the tub-cabinet clearance) and the
    /// drum-tub gap (warned about at its clearance); reported, never a stop.
    pub watch: Watch,
}

/// RK4's stability interval on the negative real axis, |h lambda| <= 2.785 (Hairer & Wanner,
/// Solving ODEs II, Fig. IV.2.1; on the imaginary axis 2.828). 2.78 covers both directions
/// up to the last digit that matters here.
pub const RK4_STABILITY: f64 = 2.78;

impl Default for Guard {
    fn default() -> Self {
        Guard {
            rotation_rad: 0.05,
            translation_m: 0.03,
            stop_factor: Some(5.0),
            interrupt: None,
            stall_window_s: 10.0,
            max_projected_s: 3600.0,
            fixed_step: None,
            elements: Vec::new(),
            watch: Watch::default(),
        }
    }
}
