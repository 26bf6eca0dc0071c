//! What a run reports: the summary (extremes, validity, integrator counters, advice), the typed
//! error with the time reached, progress and labels. The loop fills them; the CLI writes them.

use serde::Serialize;
use thiserror::Error;
use washdyn_ode::{OdeError, Rounded, Stats};

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
    /// The energy throughput the closure is relative to, J: the integral of |dT/dt| (the sum
    /// of the categories' powers) over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_throughput: Option<f64>,
    /// Generalized-alpha's spectral radius at infinity, when it ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    pub samples: u64,
    pub wall_time_s: f64,
    pub status: RunStatus,
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
    pub model_files: Vec<washdyn_model::ir::files::FileHash>,
    /// What the analysis after the run did, when one was asked for (set by the CLI).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub analysis: Option<AnalysisStatus>,
    /// The run's id (`washdyn run`: its UTC start and a suffix), which every file it wrote
    /// carries (`washdyn::run_dir`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run_id: Option<String>,
    /// How the run started (`static`, `mean`, `periodic`, `reference`; set by the set-up).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<String>,
    /// The sensor file's samples per second, Hz (set by the set-up).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample_rate_hz: Option<f64>,
    /// The files the run wrote, relative to its folder, in writing order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
    /// Per channel and tracked drum order, the largest amplitude over the run and the drum
    /// speed there (the analysis' order tracks; empty without the analysis).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub order_peaks: Vec<OrderPeak>,
}

/// The analysis after a run (`washdyn run` without `--no-plots`), in summary.json as
/// `{"status": "done" | "skipped" | "failed", ...}`: a short run is analysed in shorter blocks
/// or not at all, and says so, and a failed analysis fails the run's status with it.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum AnalysisStatus {
    /// Written, in blocks of `block_length_s`; `note`: what was fitted to the run.
    Done {
        block_length_s: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        note: Option<String>,
    },
    /// Not made, and why.
    Skipped { note: String },
    /// Failed with this error.
    Failed { error: String },
}

/// The largest amplitude of one drum order in one channel over the run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrderPeak {
    pub channel: String,
    /// Drum order.
    pub order: f64,
    /// Amplitude, in `unit`.
    pub level: f64,
    pub unit: String,
    /// Drum speed at the peak, rpm.
    pub rpm: f64,
}

/// How a run ended: `ok`, `failed` (the error and its time in the summary) or `interrupted`
/// (Ctrl-C, SIGTERM, SIGHUP). Written lowercase in summary.json and a study's summaries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    Ok,
    Failed,
    Interrupted,
}

impl RunStatus {
    /// As the files write it.
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Ok => "ok",
            RunStatus::Failed => "failed",
            RunStatus::Interrupted => "interrupted",
        }
    }

    /// From a file's text; `None` for anything else.
    pub fn parse(s: &str) -> Option<RunStatus> {
        [RunStatus::Ok, RunStatus::Failed, RunStatus::Interrupted]
            .into_iter()
            .find(|r| r.name() == s)
    }
}

impl std::fmt::Display for RunStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
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
            energy_throughput: None,
            samples: 0,
            wall_time_s: 0.0,
            status: RunStatus::Ok,
            validity: Extremes::default(),
            warnings: Vec::new(),
            error: None,
            error_class: None,
            model_files: Vec::new(),
            analysis: None,
            run_id: None,
            start: None,
            sample_rate_hz: None,
            files: Vec::new(),
            order_peaks: Vec::new(),
        }
    }

    pub(super) fn take_stats(&mut self, s: Stats) {
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
    #[error("writing samples failed at t = {} s: {source}", Rounded(*t))]
    Io { t: f64, source: std::io::Error },
    /// The run could not start (e.g. no static equilibrium); `t` is the start time.
    #[error("{reason} (at t = {} s)", Rounded(*t))]
    Setup { t: f64, reason: String },
    #[error(
        "{what} {value:.4e} {unit} at t = {} s is more than {factor} x the {bound} {unit} bound \
         of the small-motion linearisation: the result would be meaningless (see --no-validity-stop)",
        Rounded(*t)
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
         (spectral radius of the Jacobian {radius:.3e} 1/s at t = {} s): use a step below it or \
         an adaptive integrator",
        Rounded(*t)
    )]
    Unstable {
        t: f64,
        h: f64,
        limit: f64,
        radius: f64,
    },
    #[error("interrupted at t = {} s", Rounded(*t))]
    Interrupted { t: f64 },
    /// The progress guard: the rest of the run projected beyond its wall-time budget.
    #[error(
        "no progress: at t = {} s the last {window_s:.0} s of wall time gained {gained:.3e} s \
         of simulated time; the remaining {remaining:.3e} s would take about {projected_s:.2e} s, \
         beyond the {} s budget: a faster method may finish it (the scene's default: leave out \
         --integrator; on a stiff scene `--integrator galpha`), or give it the time with \
         `--max-projected-wall <s>` (`inf`: never stop)",
        Rounded(*t),
        Rounded(*budget_s)
    )]
    Stalled {
        t: f64,
        window_s: f64,
        gained: f64,
        remaining: f64,
        projected_s: f64,
        /// The guard's budget, s of wall time.
        budget_s: f64,
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
    /// Accepted steps so far.
    pub steps: u64,
    /// The angle the drum swept ([`swept`]) from the run's start to `t` and to `t_end`, rad:
    /// with the simulated time, what projects its wall time ([`CostFit`]).
    pub swept_rad: f64,
    pub swept_end_rad: f64,
}

/// Labels for the summary.
#[derive(Clone, Debug, Default)]
pub struct Labels {
    pub model: String,
    pub scene: String,
    pub backend: String,
}

#[cfg(test)]
mod tests {
    use super::RunStatus;

    /// The files' words (summary.json, a study's `status` column) and back: the three
    /// statuses, lowercase in JSON, and nothing else parses.
    #[test]
    fn run_status_reads_back_what_the_files_write() {
        for s in [RunStatus::Ok, RunStatus::Failed, RunStatus::Interrupted] {
            assert_eq!(RunStatus::parse(s.name()), Some(s));
            let json = serde_json::to_string(&s).unwrap();
            assert_eq!(json, format!("\"{}\"", s.name()));
            assert_eq!(serde_json::from_str::<RunStatus>(&json).unwrap(), s);
        }
        assert_eq!(RunStatus::parse("OK"), None);
        assert_eq!(RunStatus::parse(""), None);
    }
}
