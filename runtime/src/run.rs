//! The run driver: static start, the integrator loop with restarts at the speed profile's
//! breakpoints, uniform sampling of the sensors by dense output, and a summary. A failure returns
//! a typed error with the time reached; the samples written up to then stay written.

use crate::clearance::Watch;
use crate::equations::MarkerDef;
use crate::ode::{OdeError, OdeSystem, Solver, Stats};
use crate::output::SampleSink;
use crate::statics::static_equilibrium;
use crate::system::{FirstOrder, Mechanical};
use serde::Serialize;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use thiserror::Error;

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

/// The largest tub motion of a run, with when it happened.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Extremes {
    /// max |u| over the run, m, and its time, s.
    pub max_translation_m: f64,
    pub max_translation_t: f64,
    /// max |alpha| over the run, rad, and its time, s.
    pub max_rotation_rad: f64,
    pub max_rotation_t: f64,
    /// max over the force elements' tub ends of |u + alpha x s|, m, its time, s, and element.
    pub max_element_deflection_m: f64,
    pub max_element_deflection_t: f64,
    pub max_element: String,
    /// The bounds the run was checked against.
    pub translation_bound_m: f64,
    pub rotation_bound_rad: f64,
    /// max over the door ring's points of their displacement (rigid motion, plus the elastic
    /// tub's modes where its data has the point), m, its time, s, and the point.
    pub max_door_ring_m: f64,
    pub max_door_ring_t: f64,
    pub max_door_ring_point: String,
    /// Largest closure of the drum-tub gap (a drum front-edge point's radial motion towards the
    /// tub's ring, both bodies' elastic motion), m, its time, s, its edge point, and the radial
    /// clearance at rest (0: not watched).
    pub max_gap_closure_m: f64,
    pub max_gap_closure_t: f64,
    pub max_gap_closure_point: String,
    pub gap_clearance_m: f64,
    /// What the monitor watched beside the tub's rigid motion, and how.
    pub watched: Vec<String>,
}

/// What a run did; written as `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub model: String,
    pub scene: String,
    pub backend: String,
    pub integrator: String,
    pub rtol: f64,
    pub atol: f64,
    pub t_start: f64,
    pub t_end: f64,
    /// Time reached (t_end when the run succeeded).
    pub t_reached: f64,
    pub steps: u64,
    pub rejected_steps: u64,
    /// Right-hand-side evaluations by the integrator.
    pub rhs_evals: u64,
    /// Extra evaluations to get sensor accelerations at the samples.
    pub sample_evals: u64,
    pub jacobian_evals: u64,
    pub lu_decompositions: u64,
    pub newton_iterations: u64,
    /// Steps an explicit method took on its stability boundary (Hairer's test; dopri5), and
    /// the time from which it called the problem stiff, if it did.
    pub stiff_steps: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stiff_at: Option<f64>,
    /// Hand-overs between dopri5 and rodas4 (the composite method `auto`).
    pub method_switches: u64,
    /// |T - T0 - sum of the categories' work| over the energy throughput at the end, when the
    /// sink kept the energy balance (`run --energy`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_closure: Option<f64>,
    /// Generalized-alpha's spectral radius at infinity, when it ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    pub samples: u64,
    pub wall_time_s: f64,
    /// "ok", "failed" or "interrupted".
    pub status: String,
    /// Largest tub motion against the linearisation's bounds.
    pub validity: Extremes,
    /// Times the motion left the linearisation's range (one message per quantity).
    pub warnings: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The error class the study in docs/accuracy.md measured for this model, scene, method
    /// and tolerance (set by the CLI, which carries the study).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_class: Option<String>,
    /// When the model was a file: it and the data files it names, by absolute path with a
    /// content hash each (`ir::files::model_files`; set by the CLI), so `washdyn fields`
    /// recovers with that model and refuses it if it changed. Empty for a built-in model.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub model_files: Vec<crate::ir::files::FileHash>,
}

impl Summary {
    /// A run that has not taken a step yet: status "ok", counters zero.
    pub fn new(labels: &Labels, integrator: &str, tol: (f64, f64), span: (f64, f64)) -> Summary {
        Summary {
            model: labels.model.clone(),
            scene: labels.scene.clone(),
            backend: labels.backend.clone(),
            integrator: integrator.to_string(),
            rtol: tol.0,
            atol: tol.1,
            t_start: span.0,
            t_end: span.1,
            t_reached: span.0,
            steps: 0,
            rejected_steps: 0,
            rhs_evals: 0,
            sample_evals: 0,
            jacobian_evals: 0,
            lu_decompositions: 0,
            newton_iterations: 0,
            stiff_steps: 0,
            stiff_at: None,
            method_switches: 0,
            rho_inf: None,
            energy_closure: None,
            samples: 0,
            wall_time_s: 0.0,
            status: "ok".into(),
            validity: Extremes::default(),
            warnings: Vec::new(),
            error: None,
            error_class: None,
            model_files: Vec::new(),
        }
    }

    fn take_stats(&mut self, s: Stats) {
        self.steps = s.steps;
        self.rejected_steps = s.rejected_steps;
        self.rhs_evals = s.rhs_evals;
        self.jacobian_evals = s.jacobian_evals;
        self.lu_decompositions = s.lu_decompositions;
        self.newton_iterations = s.newton_iterations;
        self.stiff_steps = s.stiff_steps;
        self.method_switches = s.method_switches;
        if let Some(t) = s.stiff_at
            && self.stiff_at.is_none()
        {
            self.stiff_at = Some(t);
            // A method that switched where the test fired (the composite `auto`) answered the
            // stiffness itself: no advice to give.
            if s.method_switches == 0 {
                self.warnings.push(format!(
                    "{} ran on its stability limit from t = {t:.4} s ({} of {} steps; Hairer's \
                     stiffness test): its step is set by stability there, not by the tolerance; \
                     an implicit method (galpha, sdirk4, rodas4, auto; docs/accuracy.md) would \
                     take larger steps",
                    self.integrator, s.stiff_steps, s.steps
                ));
            }
        }
    }
}

#[derive(Debug, Error)]
pub enum RunError {
    #[error("integration failed: {0}")]
    Ode(#[from] OdeError),
    #[error("writing samples failed at t = {t} s: {source}")]
    Io { t: f64, source: std::io::Error },
    /// The run could not start (e.g. no static equilibrium); `t` is the start time.
    #[error("{reason} (at t = {t} s)")]
    Setup { t: f64, reason: String },
    #[error(
        "{what} {value:.4e} {unit} at t = {t} s is more than {factor} x the {bound} {unit} bound \
         of the small-motion linearisation: the result would be meaningless (see --no-validity-stop)"
    )]
    Validity {
        t: f64,
        what: &'static str,
        value: f64,
        bound: f64,
        factor: f64,
        unit: &'static str,
    },
    #[error(
        "the fixed step {h:e} s exceeds the stability limit {limit:.3e} s of rk4 for this model \
         (spectral radius of the Jacobian {radius:.3e} 1/s at t = {t} s): use a step below it or \
         an adaptive integrator"
    )]
    Unstable {
        t: f64,
        h: f64,
        limit: f64,
        radius: f64,
    },
    #[error("interrupted at t = {t} s")]
    Interrupted { t: f64 },
    #[error(
        "no progress: at t = {t} s the last {window_s:.0} s of wall time gained {gained:.3e} s \
         of simulated time; the remaining {remaining:.3e} s would take about {projected_s:.2e} s"
    )]
    Stalled {
        t: f64,
        window_s: f64,
        gained: f64,
        remaining: f64,
        projected_s: f64,
    },
}

impl RunError {
    /// Time at which the run stopped (the start time for a run that could not start).
    pub fn time(&self) -> f64 {
        match self {
            RunError::Ode(e) => e.time(),
            RunError::Io { t, .. }
            | RunError::Setup { t, .. }
            | RunError::Validity { t, .. }
            | RunError::Interrupted { t }
            | RunError::Unstable { t, .. }
            | RunError::Stalled { t, .. } => *t,
        }
    }
}

/// Progress as the run goes: simulated time and drum speed.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub t: f64,
    pub t_end: f64,
    pub rpm: f64,
    /// While the periodic start iterates (before t moves): one-period integrations so far and
    /// the fixed point's residual relative to its tolerance (done at 1).
    pub start: Option<(usize, f64)>,
}

/// Labels for the summary.
#[derive(Clone, Debug, Default)]
pub struct Labels {
    pub model: String,
    pub scene: String,
    pub backend: String,
}

/// [`run_guarded`] with the default [`Guard`].
#[allow(clippy::result_large_err)]
pub fn run<S, V>(
    sys: &mut FirstOrder<S>,
    solver: &mut V,
    opts: &RunOptions,
    labels: &Labels,
    tol: (f64, f64),
    sink: &mut dyn SampleSink,
    progress: &mut dyn FnMut(Progress),
) -> Result<Summary, (RunError, Summary)>
where
    S: Mechanical,
    V: Solver<FirstOrder<S>>,
{
    run_guarded(
        sys,
        solver,
        opts,
        labels,
        tol,
        sink,
        progress,
        &Guard::default(),
    )
}

/// Integrate `sys` with `solver`, streaming samples into `sink`, watching the tub motion, the
/// progress and the interrupt flag of `guard`. Returns the summary either way; on failure
/// together with the error (the sink has been flushed).
#[allow(clippy::result_large_err, clippy::too_many_arguments)]
pub fn run_guarded<S, V>(
    sys: &mut FirstOrder<S>,
    solver: &mut V,
    opts: &RunOptions,
    labels: &Labels,
    tol: (f64, f64),
    sink: &mut dyn SampleSink,
    progress: &mut dyn FnMut(Progress),
    guard: &Guard,
) -> Result<Summary, (RunError, Summary)>
where
    S: Mechanical,
    V: Solver<FirstOrder<S>>,
{
    let wall = Instant::now();
    let mut summary = Summary::new(labels, solver.name(), tol, (opts.t_start, opts.t_end));
    summary.validity = Extremes {
        translation_bound_m: guard.translation_m,
        rotation_bound_rad: guard.rotation_rad,
        gap_clearance_m: guard.watch.drum_gap.as_ref().map_or(0.0, |g| g.clearance),
        watched: guard.watch.notes.clone(),
        ..Extremes::default()
    };
    let mut worst = Worst::default();
    let result = drive(
        sys,
        solver,
        opts,
        sink,
        progress,
        &mut summary,
        guard,
        &mut worst,
    );
    let ex = &mut summary.validity;
    if let Some(i) = worst.element {
        ex.max_element = guard.elements[i].0.clone();
    }
    if let (Some(i), Some(r)) = (worst.ring, &guard.watch.door_ring) {
        ex.max_door_ring_point = r.points[i].name.clone();
    }
    if let (Some(i), Some(g)) = (worst.gap, &guard.watch.drum_gap) {
        ex.max_gap_closure_point = g.edge[i].name.clone();
    }
    let _ = sink.flush();
    summary.take_stats(solver.stats());
    summary.wall_time_s = wall.elapsed().as_secs_f64();
    match result {
        Ok(()) => Ok(summary),
        Err(e) => {
            summary.status = match e {
                RunError::Interrupted { .. } => "interrupted",
                _ => "failed",
            }
            .into();
            summary.error = Some(e.to_string());
            summary.t_reached = e.time();
            Err((e, summary))
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn drive<S, V>(
    sys: &mut FirstOrder<S>,
    solver: &mut V,
    opts: &RunOptions,
    sink: &mut dyn SampleSink,
    progress: &mut dyn FnMut(Progress),
    summary: &mut Summary,
    guard: &Guard,
    worst: &mut Worst,
) -> Result<(), RunError>
where
    S: Mechanical,
    V: Solver<FirstOrder<S>>,
{
    let lay = sys.layout();
    let n = lay.n();
    let names = sys.sys.channel_names();
    let (t0, t_end) = (opts.t_start, opts.t_end);
    // Written to reject NaN too.
    let ordered = |a: f64, b: f64| a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater);
    if !ordered(t_end, t0) || !ordered(opts.sample_rate, 0.0) {
        return Err(RunError::Setup {
            t: t0,
            reason: format!(
                "need t_end > t_start and a positive sample rate (t_start {t0}, t_end {t_end}, rate {})",
                opts.sample_rate
            ),
        });
    }
    let setup = |reason| RunError::Setup { t: t0, reason };
    let mut y = vec![0.0; 2 * n];
    match opts.start {
        Start::Static => {
            y[..n].copy_from_slice(&static_equilibrium(&mut sys.sys, t0).map_err(setup)?)
        }
        Start::MeanLoad => y[..n].copy_from_slice(
            &crate::statics::mean_load_equilibrium(&mut sys.sys, t0).map_err(setup)?,
        ),
        Start::Periodic => {
            use crate::periodic::{StartStop, Watch, periodic_state_watched};
            let rpm = sys.sys.speed().rpm(t0);
            let mut report = |k: usize, r: f64| {
                progress(Progress {
                    t: t0,
                    t_end,
                    rpm,
                    start: Some((k, r)),
                })
            };
            let watch = Watch {
                interrupt: guard.interrupt.as_deref(),
                progress: Some(&mut report),
            };
            y = match periodic_state_watched(sys, t0, watch) {
                Ok((y, _)) => y,
                Err(StartStop::Interrupted) => return Err(RunError::Interrupted { t: t0 }),
                Err(StartStop::Failed(e)) => return Err(setup(e)),
            };
        }
        Start::Reference => {}
    }
    let mut qdd = vec![0.0; n];
    let mut vals = vec![0.0; names.len()];
    let io = |t: f64| move |source| RunError::Io { t, source };
    sink.header(&names).map_err(io(t0))?;

    // Restart points: the profile's breakpoints inside (t0, t_end), then t_end.
    let stops = sys.sys.speed().stops(t0, t_end);

    let dt = 1.0 / opts.sample_rate;
    let n_samples = ((t_end - t0) * opts.sample_rate + 1e-9).floor() as u64 + 1;
    let mut k = 0u64;
    let mut emit = |sys: &mut FirstOrder<S>,
                    sink: &mut dyn SampleSink,
                    t: f64,
                    y: &[f64],
                    summary: &mut Summary| {
        let (q, qd) = y.split_at(n);
        sys.accelerations(t, q, qd, &mut qdd);
        summary.sample_evals += 1;
        sys.sys.sensors(t, q, qd, &qdd, &mut vals);
        let rpm = sys.sys.speed().rpm(t);
        summary.samples += 1;
        sink.state(t, sys.sys.speed().drive(t).phi, q)
            .map_err(io(t))?;
        sink.sample(t, rpm, &vals).map_err(io(t))
    };

    let mut monitor = Monitor::new(guard, t0, Instant::now());
    monitor.check(t0, &y[..n], summary)?;
    monitor.elements(t0, &y[..n], summary, worst);
    monitor.clearances(t0, sys.sys.speed().drive(t0).phi, &y[..n], summary, worst);
    if let Some(h) = guard.fixed_step {
        let radius = spectral_radius(sys, t0, &y);
        let limit = RK4_STABILITY / radius;
        if h > limit {
            return Err(RunError::Unstable {
                t: t0,
                h,
                limit,
                radius,
            });
        }
    }
    solver.init(sys, t0, &y)?;
    emit(sys, sink, t0, &y, summary)?;
    k += 1;
    let mut balance = if sink.wants_energy() {
        let b = crate::energy::Balance::new(&mut sys.sys, t0, &y).ok_or_else(|| {
            setup("the energy balance needs the back end's resolved model".into())
        })?;
        sink.energy_header(&b.categories).map_err(io(t0))?;
        Some(b)
    } else {
        None
    };
    let mut last_report = Instant::now();
    for &stop in &stops {
        while solver.t() < stop {
            solver.step(sys, stop)?;
            let t = solver.t();
            summary.t_reached = t;
            if let Some(b) = balance.as_mut() {
                b.step(&mut sys.sys, solver, |ti, rpm, kin, work| {
                    sink.energy(ti, rpm, kin, work).map_err(io(ti))
                })?;
                // At the last row (a failed run keeps it); the end's below.
                summary.energy_closure = Some(b.row_closure);
            }
            monitor.check(t, &solver.y()[..n], summary)?;
            monitor.elements(t, &solver.y()[..n], summary, worst);
            let phi = sys.sys.speed().drive(t).phi;
            monitor.clearances(t, phi, &solver.y()[..n], summary, worst);
            monitor.progress(t, t_end)?;
            while k < n_samples {
                let ts = t0 + k as f64 * dt;
                if ts > t {
                    break;
                }
                solver.interpolate(ts, &mut y);
                emit(sys, sink, ts, &y, summary)?;
                k += 1;
            }
            if last_report.elapsed().as_millis() >= 100 {
                last_report = Instant::now();
                progress(Progress {
                    t,
                    t_end,
                    rpm: sys.sys.speed().rpm(t),
                    start: None,
                });
            }
        }
        if stop < t_end {
            // The drum acceleration jumps here: restart without history.
            y.copy_from_slice(solver.y());
            solver.init(sys, stop, &y)?;
        }
    }
    if let Some(b) = balance.as_mut() {
        summary.energy_closure = Some(b.closure(&mut sys.sys, solver.t(), solver.y()));
    }
    progress(Progress {
        t: t_end,
        t_end,
        rpm: sys.sys.speed().rpm(t_end),
        start: None,
    });
    Ok(())
}

/// Where the worst values of the run happened (indices into the guard's lists), named in the
/// summary at the end so the step loop does not allocate.
#[derive(Default)]
struct Worst {
    element: Option<usize>,
    ring: Option<usize>,
    gap: Option<usize>,
}

/// Watches a run between steps: the tub motion against the linearisation's bounds, the
/// interrupt flag, and the simulated time gained per wall-clock window.
struct Monitor<'a> {
    guard: &'a Guard,
    warned_translation: bool,
    warned_rotation: bool,
    warned_element: bool,
    warned_ring: bool,
    warned_gap: bool,
    window_start: Instant,
    window_t: f64,
    calls: u32,
}

impl<'a> Monitor<'a> {
    fn new(guard: &'a Guard, t0: f64, now: Instant) -> Self {
        Monitor {
            guard,
            warned_translation: false,
            warned_rotation: false,
            warned_element: false,
            warned_ring: false,
            warned_gap: false,
            window_start: now,
            window_t: t0,
            calls: 0,
        }
    }

    /// The floating frame's translation u and rotation alpha (from `Watch::frame`).
    fn check(&mut self, t: f64, q: &[f64], summary: &mut Summary) -> Result<(), RunError> {
        let c = self.guard.watch.frame;
        if q.len() < c + 6 {
            return Ok(());
        }
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let (u, a) = (norm(&q[c..c + 3]), norm(&q[c + 3..c + 6]));
        let ex = &mut summary.validity;
        if u > ex.max_translation_m {
            ex.max_translation_m = u;
            ex.max_translation_t = t;
        }
        if a > ex.max_rotation_rad {
            ex.max_rotation_rad = a;
            ex.max_rotation_t = t;
        }
        let g = self.guard;
        for (value, bound, what, unit, warned) in [
            (
                u,
                g.translation_m,
                "tub translation",
                "m",
                &mut self.warned_translation,
            ),
            (
                a,
                g.rotation_rad,
                "tub rotation",
                "rad",
                &mut self.warned_rotation,
            ),
        ] {
            if value > bound && !*warned {
                *warned = true;
                summary.warnings.push(format!(
                    "{what} {value:.4e} {unit} at t = {t} s exceeds the {bound} {unit} bound of \
                     the small-motion linearisation"
                ));
            }
            if let Some(factor) = g.stop_factor
                && value > factor * bound
            {
                return Err(RunError::Validity {
                    t,
                    what,
                    value,
                    bound,
                    factor,
                    unit,
                });
            }
        }
        Ok(())
    }

    /// The largest deflection of an element's tub end, and a warning past the translation bound.
    fn elements(&mut self, t: f64, q: &[f64], summary: &mut Summary, worst: &mut Worst) {
        let ex = &mut summary.validity;
        for (i, (_, m)) in self.guard.elements.iter().enumerate() {
            let d = m.displacement(q);
            let v = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if v > ex.max_element_deflection_m {
                ex.max_element_deflection_m = v;
                ex.max_element_deflection_t = t;
                worst.element = Some(i);
            }
        }
        let bound = self.guard.translation_m;
        if !self.warned_element && ex.max_element_deflection_m > bound {
            self.warned_element = true;
            let (v, name) = (
                ex.max_element_deflection_m,
                worst
                    .element
                    .map_or("", |i| self.guard.elements[i].0.as_str()),
            );
            summary.warnings.push(format!(
                "element `{name}` deflected {v:.4e} m at t = {t} s, beyond the {bound} m \
                 tub-cabinet clearance"
            ));
        }
    }

    /// The door ring's largest displacement (warned about at the translation bound, the
    /// tub-cabinet clearance) and the drum-tub gap's largest closure (warned about at its
    /// clearance); `phi` is the drive angle at t.
    fn clearances(
        &mut self,
        t: f64,
        phi: f64,
        q: &[f64],
        summary: &mut Summary,
        worst: &mut Worst,
    ) {
        if q.len() < 6 {
            return;
        }
        let ex = &mut summary.validity;
        let w = &self.guard.watch;
        if let Some(ring) = &w.door_ring {
            let (v, i) = ring.excursion(q);
            if v > ex.max_door_ring_m {
                ex.max_door_ring_m = v;
                ex.max_door_ring_t = t;
                worst.ring = Some(i);
            }
            let bound = self.guard.translation_m;
            if v > bound && !self.warned_ring {
                self.warned_ring = true;
                summary.warnings.push(format!(
                    "door ring point `{}` moved {v:.4e} m at t = {t} s, beyond the {bound} m \
                     tub-cabinet clearance",
                    ring.points[i].name
                ));
            }
        }
        let ex = &mut summary.validity;
        if let Some(gap) = &w.drum_gap {
            let (v, i) = gap.closure(phi, q);
            if v > ex.max_gap_closure_m {
                ex.max_gap_closure_m = v;
                ex.max_gap_closure_t = t;
                worst.gap = Some(i);
            }
            if v > gap.clearance && !self.warned_gap {
                self.warned_gap = true;
                summary.warnings.push(format!(
                    "drum edge point `{}` closed the drum-tub gap by {v:.4e} m at t = {t} s, \
                     beyond its {:.4} m clearance",
                    gap.edge[i].name, gap.clearance
                ));
            }
        }
    }

    /// The interrupt flag, every step; the wall clock, every 64th step.
    fn progress(&mut self, t: f64, t_end: f64) -> Result<(), RunError> {
        if let Some(flag) = &self.guard.interrupt
            && flag.load(Ordering::Relaxed)
        {
            return Err(RunError::Interrupted { t });
        }
        self.calls = self.calls.wrapping_add(1);
        if !self.calls.is_multiple_of(64) {
            return Ok(());
        }
        let window_s = self.window_start.elapsed().as_secs_f64();
        if window_s < self.guard.stall_window_s {
            return Ok(());
        }
        let gained = t - self.window_t;
        let remaining = t_end - t;
        let projected_s = remaining / gained * window_s;
        // Written to catch gained = 0 (projected inf) and NaN alike.
        if projected_s.is_nan() || projected_s > self.guard.max_projected_s {
            return Err(RunError::Stalled {
                t,
                window_s,
                gained,
                remaining,
                projected_s,
            });
        }
        self.window_start = Instant::now();
        self.window_t = t;
        Ok(())
    }
}

/// Largest |eigenvalue| of df/dy at (t, y), by power iteration on finite-difference products
/// J v: the mean growth of |J^k v| over the iterations after a transient of 20. A dominant
/// complex pair makes v rotate, not converge; the growth rate still tends to |lambda|. Set-up
/// code: it allocates.
pub fn spectral_radius<S: OdeSystem>(sys: &mut S, t: f64, y: &[f64]) -> f64 {
    let m = y.len();
    let mut f0 = vec![0.0; m];
    let mut f1 = vec![0.0; m];
    let mut yp = vec![0.0; m];
    sys.rhs(t, y, &mut f0);
    let ynorm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
    // A fixed pseudo-random start, so every mode has a share.
    let mut v: Vec<f64> = (0..m)
        .map(|i| ((i as f64 + 1.0) * 0.618_034).fract() - 0.5)
        .collect();
    let (mut log_sum, mut count) = (0.0, 0);
    for k in 0..120 {
        let vn = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(vn > 0.0 && vn.is_finite()) {
            break;
        }
        let eps = 1e-7 * (1.0 + ynorm) / vn;
        for i in 0..m {
            yp[i] = y[i] + eps * v[i];
        }
        sys.rhs(t, &yp, &mut f1);
        for i in 0..m {
            v[i] = (f1[i] - f0[i]) / eps;
        }
        let jn = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(jn > 0.0 && jn.is_finite()) {
            break;
        }
        if k >= 20 {
            log_sum += (jn / vn).ln();
            count += 1;
        }
        v.iter_mut().for_each(|x| *x /= jn);
    }
    if count == 0 {
        0.0
    } else {
        (log_sum / count as f64).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The summary advises an implicit method when the test fired and the method stayed on
    /// its stability limit, and not when it switched there (the composite method).
    #[test]
    fn stiffness_advice_only_for_a_method_that_did_not_switch() {
        let labels = Labels {
            model: "m".into(),
            scene: "s".into(),
            backend: "generated".into(),
        };
        let stiff = Stats {
            steps: 100,
            stiff_steps: 40,
            stiff_at: Some(0.5),
            ..Stats::default()
        };
        let mut dopri5 = Summary::new(&labels, "dopri5", (1e-6, 1e-9), (0.0, 1.0));
        dopri5.take_stats(stiff);
        assert_eq!(dopri5.warnings.len(), 1, "{:?}", dopri5.warnings);
        assert!(dopri5.warnings[0].contains("stability limit"));
        let mut auto = Summary::new(&labels, "auto", (1e-6, 1e-9), (0.0, 1.0));
        auto.take_stats(Stats {
            method_switches: 3,
            ..stiff
        });
        assert!(auto.warnings.is_empty(), "{:?}", auto.warnings);
        assert_eq!(auto.stiff_at, Some(0.5));
    }

    /// y' = A y, A block-diagonal with the eigenvalues -1, -4000 and the pair -10 +- 3000 i.
    struct Linear;
    impl OdeSystem for Linear {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = -y[0];
            dy[1] = -4000.0 * y[1];
            dy[2] = -10.0 * y[2] - 3000.0 * y[3];
            dy[3] = 3000.0 * y[2] - 10.0 * y[3];
        }
    }

    #[test]
    fn spectral_radius_of_a_known_spectrum() {
        // The largest |lambda| is 4000 by construction; the pair's modulus is 3000.02.
        let r = spectral_radius(&mut Linear, 0.0, &[0.1, 0.2, 0.3, 0.4]);
        assert!((r / 4000.0 - 1.0).abs() < 1e-3, "{r}");
    }
}
