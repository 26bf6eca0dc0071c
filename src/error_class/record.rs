//! The record `washdyn accuracy` writes (`accuracy.json`) and the error class reads: what was
//! measured, window by window. Below the runners, so a run's class needs no report.

use serde::{Deserialize, Serialize};

/// A scene and the time window studied.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Window {
    pub scene: String,
    pub t0: f64,
    pub t1: f64,
}

/// One run of the study and its errors against the reference.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Trial {
    pub method: String,
    /// Relative tolerance, or rk4's step in s.
    pub tol: f64,
    pub backend: String,
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub jacobians: u64,
    pub lu: u64,
    pub wall_s: f64,
    /// Largest relative RMS error over the acceleration channels; `None` when the run failed.
    pub accel_err: Option<f64>,
    /// Largest |dB| error of orders 1-3 over the acceleration channels and blocks.
    pub order_db: Option<f64>,
    pub status: String,
}

/// The study of one window.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WindowStudy {
    pub window: Window,
    /// The content hash of the model as this window's scene ran it (`error_class::content_hash`);
    /// `None`: measured on a model nobody recorded, which gives no run an error class.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_hash: Option<String>,
    pub reference: Trial,
    /// The second method's run at a tight tolerance, compared with the reference.
    pub confirmation: Trial,
    pub trials: Vec<Trial>,
    /// Generated against interpreted at one setting: (generated, interpreted).
    pub backends: Option<(Trial, Trial)>,
    /// Modes kept (cut-off Hz, coordinates) against the finest cut-off.
    pub truncation: Vec<(f64, usize, Trial)>,
    /// Other scenes over this window against this one.
    pub scenes: Vec<(String, Trial)>,
    /// Generalized-alpha at one tolerance for each spectral radius at infinity.
    #[serde(default)]
    pub rho_inf: Vec<(f64, Trial)>,
}

/// Everything the command measured; `accuracy.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Study {
    pub model: String,
    pub command: String,
    pub windows: Vec<WindowStudy>,
}
