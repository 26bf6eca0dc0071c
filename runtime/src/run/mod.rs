//! The run driver: static start, the integrator loop with restarts at the speed profile's
//! breakpoints, uniform sampling of the sensors by dense output, and a summary. A failure returns
//! a typed error with the time reached; the samples written up to then stay written.

mod monitor;
mod options;
mod summary;
#[cfg(test)]
mod tests;
mod work;

pub use monitor::spectral_radius;
pub use options::*;
pub use summary::*;
pub use work::*;

use crate::output::SampleSink;
use crate::statics::static_equilibrium;
use crate::system::{FirstOrder, Mechanical};
use monitor::{Monitor, Worst};
use std::time::Instant;
use washdyn_ode::Solver;

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
                RunError::Interrupted { .. } => RunStatus::Interrupted,
                _ => RunStatus::Failed,
            };
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
    let mut y = start_state(sys, opts, guard, progress)?;
    let mut qdd = vec![0.0; n];
    let mut zd = vec![0.0; lay.nz];
    let mut vals = vec![0.0; names.len()];
    let io = |t: f64| move |source| RunError::Io { t, source };
    sink.header(&names).map_err(io(t0))?;

    // Restart points: the profile's breakpoints inside (t0, t_end), then t_end.
    let stops = sys.sys.speed().stops(t0, t_end);
    let swept_end_rad = swept(sys.sys.speed(), t0, t_end);

    let dt = 1.0 / opts.sample_rate;
    let n_samples = ((t_end - t0) * opts.sample_rate + 1e-9).floor() as u64 + 1;
    let mut k = 0u64;
    let mut emit = |sys: &mut FirstOrder<S>,
                    sink: &mut dyn SampleSink,
                    t: f64,
                    y: &[f64],
                    summary: &mut Summary| {
        sys.rates(t, y, &mut qdd, &mut zd);
        let (q, qd) = (&y[..n], &y[n..2 * n]);
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
    fixed_step_stable(sys, guard, t0, &y)?;
    solver.init(sys, t0, &y)?;
    emit(sys, sink, t0, &y, summary)?;
    k += 1;
    let mut balance = energy_balance(sys, sink, t0, &y)?;
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
                summary.energy_throughput = Some(b.throughput);
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
                    steps: solver.stats().steps,
                    swept_rad: swept(sys.sys.speed(), t0, t),
                    swept_end_rad,
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
        summary.energy_throughput = Some(b.throughput);
    }
    progress(Progress {
        t: t_end,
        t_end,
        rpm: sys.sys.speed().rpm(t_end),
        start: None,
        steps: solver.stats().steps,
        swept_rad: swept_end_rad,
        swept_end_rad,
    });
    Ok(())
}

/// The run's first state [q; q'; z] from `opts.start` (the element states at their assembly
/// value, z = 0), after checking the run's times and sample rate.
fn start_state<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    opts: &RunOptions,
    guard: &Guard,
    progress: &mut dyn FnMut(Progress),
) -> Result<Vec<f64>, RunError> {
    let lay = sys.layout();
    let n = lay.n();
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
    // [q; q'; z]: the element states start at their assembly value, z = 0.
    let mut y = vec![0.0; lay.dim()];
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
            let swept_end_rad = swept(sys.sys.speed(), t0, t_end);
            let mut report = |k: usize, r: f64| {
                progress(Progress {
                    t: t0,
                    t_end,
                    rpm,
                    start: Some((k, r)),
                    steps: 0,
                    swept_rad: 0.0,
                    swept_end_rad,
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
    Ok(y)
}

/// A fixed step must lie inside RK4's stability region for the system's spectral radius at
/// the start.
fn fixed_step_stable<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    guard: &Guard,
    t0: f64,
    y: &[f64],
) -> Result<(), RunError> {
    if let Some(h) = guard.fixed_step {
        let radius = spectral_radius(sys, t0, y);
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
    Ok(())
}

/// The energy balance along the run when the sink records it (its header written), else None.
fn energy_balance<S: Mechanical>(
    sys: &mut FirstOrder<S>,
    sink: &mut dyn SampleSink,
    t0: f64,
    y: &[f64],
) -> Result<Option<crate::energy::Balance>, RunError> {
    let setup = |reason| RunError::Setup { t: t0, reason };
    let io = |t: f64| move |source| RunError::Io { t, source };
    Ok(if sink.wants_energy() {
        let b = crate::energy::Balance::new(&mut sys.sys, t0, y).ok_or_else(|| {
            setup("the energy balance needs the back end's resolved model".into())
        })?;
        sink.energy_header(&b.categories).map_err(io(t0))?;
        Some(b)
    } else {
        None
    })
}
