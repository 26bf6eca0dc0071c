//! The run driver: static start, the integrator loop with restarts at the speed profile's
//! breakpoints, uniform sampling of the sensors by dense output, and a summary. A failure returns
//! a typed error with the time reached; the samples written up to then stay written.

use crate::ode::{OdeError, Solver, Stats};
use crate::output::SampleSink;
use crate::statics::static_equilibrium;
use crate::system::{FirstOrder, Mechanical};
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// How the run starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// Static equilibrium at t0 (the default: no drop transient).
    Static,
    /// q = 0, q' = 0: the model's reference position.
    Reference,
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
    pub samples: u64,
    pub wall_time_s: f64,
    /// "ok" or "failed".
    pub status: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

impl Summary {
    fn take_stats(&mut self, s: Stats) {
        self.steps = s.steps;
        self.rejected_steps = s.rejected_steps;
        self.rhs_evals = s.rhs_evals;
        self.jacobian_evals = s.jacobian_evals;
        self.lu_decompositions = s.lu_decompositions;
        self.newton_iterations = s.newton_iterations;
    }
}

#[derive(Debug, Error)]
pub enum RunError {
    #[error("integration failed: {0}")]
    Ode(#[from] OdeError),
    #[error("writing samples failed at t = {t} s: {source}")]
    Io { t: f64, source: std::io::Error },
    #[error("{0}")]
    Setup(String),
}

impl RunError {
    /// Time at which the run stopped, where known.
    pub fn time(&self) -> Option<f64> {
        match self {
            RunError::Ode(e) => Some(e.time()),
            RunError::Io { t, .. } => Some(*t),
            RunError::Setup(_) => None,
        }
    }
}

/// Progress as the run goes: simulated time and drum speed.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    pub t: f64,
    pub t_end: f64,
    pub rpm: f64,
}

/// Labels for the summary.
#[derive(Clone, Debug, Default)]
pub struct Labels {
    pub model: String,
    pub scene: String,
    pub backend: String,
}

/// Integrate `sys` with `solver`, streaming samples into `sink`. Returns the summary either way;
/// on failure together with the error (the sink has been flushed).
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
    let wall = Instant::now();
    let mut summary = Summary {
        model: labels.model.clone(),
        scene: labels.scene.clone(),
        backend: labels.backend.clone(),
        integrator: solver.name().to_string(),
        rtol: tol.0,
        atol: tol.1,
        t_start: opts.t_start,
        t_end: opts.t_end,
        t_reached: opts.t_start,
        steps: 0,
        rejected_steps: 0,
        rhs_evals: 0,
        sample_evals: 0,
        jacobian_evals: 0,
        lu_decompositions: 0,
        newton_iterations: 0,
        samples: 0,
        wall_time_s: 0.0,
        status: "ok".into(),
        error: None,
    };
    let result = drive(sys, solver, opts, sink, progress, &mut summary);
    let _ = sink.flush();
    summary.take_stats(solver.stats());
    summary.wall_time_s = wall.elapsed().as_secs_f64();
    match result {
        Ok(()) => Ok(summary),
        Err(e) => {
            summary.status = "failed".into();
            summary.error = Some(e.to_string());
            if let Some(t) = e.time() {
                summary.t_reached = t;
            }
            Err((e, summary))
        }
    }
}

fn drive<S, V>(
    sys: &mut FirstOrder<S>,
    solver: &mut V,
    opts: &RunOptions,
    sink: &mut dyn SampleSink,
    progress: &mut dyn FnMut(Progress),
    summary: &mut Summary,
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
        return Err(RunError::Setup(format!(
            "need t_end > t_start and a positive sample rate (t_start {t0}, t_end {t_end}, rate {})",
            opts.sample_rate
        )));
    }
    let q0 = match opts.start {
        Start::Static => static_equilibrium(&mut sys.sys, t0).map_err(RunError::Setup)?,
        Start::Reference => vec![0.0; n],
    };
    let mut y = vec![0.0; 2 * n];
    y[..n].copy_from_slice(&q0);
    let mut qdd = vec![0.0; n];
    let mut vals = vec![0.0; names.len()];
    let io = |t: f64| move |source| RunError::Io { t, source };
    sink.header(&names).map_err(io(t0))?;

    // Restart points: the profile's breakpoints inside (t0, t_end), then t_end.
    let mut stops: Vec<f64> = sys
        .sys
        .speed()
        .breakpoints()
        .iter()
        .copied()
        .filter(|&b| b > t0 && b < t_end)
        .collect();
    stops.push(t_end);

    let dt = 1.0 / opts.sample_rate;
    let n_samples = ((t_end - t0) * opts.sample_rate + 1e-9).floor() as u64 + 1;
    let mut k = 0u64;
    let mut emit = |sys: &mut FirstOrder<S>, t: f64, y: &[f64], summary: &mut Summary| {
        let (q, qd) = y.split_at(n);
        sys.accelerations(t, q, qd, &mut qdd);
        summary.sample_evals += 1;
        sys.sys.sensors(t, q, qd, &qdd, &mut vals);
        let rpm = sys.sys.speed().rpm(t);
        summary.samples += 1;
        sink.sample(t, rpm, &vals).map_err(io(t))
    };

    solver.init(sys, t0, &y)?;
    emit(sys, t0, &y, summary)?;
    k += 1;
    let mut last_report = Instant::now();
    for &stop in &stops {
        while solver.t() < stop {
            solver.step(sys, stop)?;
            let t = solver.t();
            summary.t_reached = t;
            while k < n_samples {
                let ts = t0 + k as f64 * dt;
                if ts > t {
                    break;
                }
                solver.interpolate(ts, &mut y);
                emit(sys, ts, &y, summary)?;
                k += 1;
            }
            if last_report.elapsed().as_millis() >= 100 {
                last_report = Instant::now();
                progress(Progress {
                    t,
                    t_end,
                    rpm: sys.sys.speed().rpm(t),
                });
            }
        }
        if stop < t_end {
            // The drum acceleration jumps here: restart without history.
            y.copy_from_slice(solver.y());
            solver.init(sys, stop, &y)?;
        }
    }
    progress(Progress {
        t: t_end,
        t_end,
        rpm: sys.sys.speed().rpm(t_end),
    });
    Ok(())
}
