//! The rules for a run's settings, in one place for `run` and `sweep`: each rule is one function
//! on a shared context that collects every violation, so one message lists them all, and nothing
//! is written before they pass.

use crate::error::{Error, Refusal};
use washdyn_ode::Method;

/// Fixed step of rk4, s: below 1e-7 s a 20 s run-up needs 2e8 steps (hours); above 1e-2 s the
/// step exceeds the stability limit of the stiffest element of the reference machine (the
/// reference run uses 1e-4 s).
pub const RK4_STEP: (f64, f64) = (1e-7, 1e-2);
/// Relative tolerance: below 1e-12 it asks for more than f64 holds; above 1e-1 the adaptive
/// methods' error control stops meaning anything.
pub const TOL: (f64, f64) = (1e-12, 1e-1);
/// Longest simulated time, s: an hour, far beyond any washing programme's spin phase.
pub const T_END_MAX: f64 = 3600.0;
/// Sample rate, Hz: at least 1 sample per second, at most 100 kHz (the integrators' steps are
/// 1e-4 s and longer, so a faster rate only interpolates).
pub const SAMPLE_RATE: (f64, f64) = (1.0, 1e5);
/// Largest output without `--allow-large-output`, bytes (estimate: samples x columns x 8).
pub const MAX_OUTPUT_BYTES: f64 = 2e9;

/// What a run is asked to do, as far as the rules need it.
#[derive(Clone, Debug)]
pub struct Settings {
    pub method: Method,
    /// `--t-end`; `None`: the end of the speed profile.
    pub t_end: Option<f64>,
    /// End of the model's speed profile, s.
    pub profile_end: f64,
    pub tol: f64,
    pub step: Option<f64>,
    /// `--rho-inf` (generalized-alpha only).
    pub rho_inf: Option<f64>,
    pub sample_rate: f64,
    pub max_steps: Option<u64>,
    /// Sensor channels written per sample; `None`: the size is not checked.
    pub channels: Option<usize>,
    /// Highest frequency the analysis after the run resolves, Hz; `None`: no analysis.
    pub analysis_band_hz: Option<f64>,
    pub allow_large_output: bool,
    /// `--max-projected-wall`: the progress guard's budget, s (`inf`: never stops).
    pub max_projected_s: f64,
}

/// Collects the violations.
#[derive(Default)]
struct Ctxt {
    errors: Vec<Refusal>,
}

impl Ctxt {
    fn error(&mut self, option: &'static str, message: String) {
        self.errors.push(Refusal { option, message });
    }

    /// `value` finite and within [lo, hi].
    fn range(
        &mut self,
        option: &'static str,
        value: f64,
        (lo, hi): (f64, f64),
        unit: &str,
        why: &str,
    ) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            self.error(
                option,
                format!(
                    "{option} must be in [{lo:e}, {hi:e}]{}{unit}{why}, got {value}",
                    if unit.is_empty() { "" } else { " " }
                ),
            );
        }
    }
}

/// Every rule on `s`; `Err` ([`Error::Settings`]) lists every violation with its option.
pub fn check(s: &Settings) -> Result<(), Error> {
    let mut cx = Ctxt::default();
    check_step(&mut cx, s);
    check_rho_inf(&mut cx, s);
    check_tol(&mut cx, s);
    check_t_end(&mut cx, s);
    check_sample_rate(&mut cx, s);
    check_max_steps(&mut cx, s);
    check_max_projected_wall(&mut cx, s);
    if cx.errors.is_empty() {
        check_output_size(&mut cx, s);
    }
    if cx.errors.is_empty() {
        Ok(())
    } else {
        Err(Error::Settings(cx.errors))
    }
}

/// The simulated end time the settings give.
pub fn t_end(s: &Settings) -> f64 {
    s.t_end.unwrap_or(s.profile_end)
}

fn check_step(cx: &mut Ctxt, s: &Settings) {
    match (s.method, s.step) {
        (Method::Rk4, Some(h)) => cx.range("--step", h, RK4_STEP, "s", " for rk4"),
        (Method::Rk4, None) => {}
        (m, Some(h)) => cx.error(
            "--step",
            format!(
                "--step applies to rk4 only: {} chooses its own steps from --tol, got --step {h}",
                format!("{m:?}").to_lowercase()
            ),
        ),
        (_, None) => {}
    }
}

/// Generalized-alpha's spectral radius at infinity: Chung & Hulbert's family is defined on
/// [0, 1] (1: no numerical damping; 0: the unresolved modes annihilated in one step).
fn check_rho_inf(cx: &mut Ctxt, s: &Settings) {
    match (s.method, s.rho_inf) {
        (Method::GeneralizedAlpha, Some(r)) => cx.range("--rho-inf", r, (0.0, 1.0), "", ""),
        (m, Some(r)) => cx.error(
            "--rho-inf",
            format!(
                "--rho-inf applies to galpha only: {m} has no spectral radius to set, got \
             --rho-inf {r}"
            ),
        ),
        (_, None) => {}
    }
}

fn check_tol(cx: &mut Ctxt, s: &Settings) {
    cx.range("--tol", s.tol, TOL, "", "");
}

fn check_t_end(cx: &mut Ctxt, s: &Settings) {
    if let Some(t) = s.t_end
        && !(t > 0.0 && t <= T_END_MAX)
    {
        cx.error(
            "--t-end",
            format!("--t-end must be > 0 and at most {T_END_MAX} s, got {t}"),
        );
    }
}

fn check_sample_rate(cx: &mut Ctxt, s: &Settings) {
    cx.range("--sample-rate", s.sample_rate, SAMPLE_RATE, "Hz", "");
    if let Some(band) = s.analysis_band_hz
        && s.sample_rate.is_finite()
        && s.sample_rate < 2.0 * band
    {
        cx.error(
            "--sample-rate",
            format!(
                "--sample-rate must be at least {} Hz for the analysis (twice its {band} Hz band), \
             got {} (or pass --no-plots)",
                2.0 * band,
                s.sample_rate
            ),
        );
    }
}

fn check_max_steps(cx: &mut Ctxt, s: &Settings) {
    if s.max_steps == Some(0) {
        cx.error(
            "--max-steps",
            "--max-steps must be at least 1, got 0".into(),
        );
    }
}

/// The progress guard's budget: a duration, so > 0; `inf` never stops, NaN never compares.
fn check_max_projected_wall(cx: &mut Ctxt, s: &Settings) {
    let v = s.max_projected_s;
    if v.is_nan() || v <= 0.0 {
        cx.error(
            "--max-projected-wall",
            format!("--max-projected-wall must be > 0 s (inf: never stop), got {v}"),
        );
    }
}

fn check_output_size(cx: &mut Ctxt, s: &Settings) {
    let Some(ch) = s.channels else { return };
    let samples = (t_end(s) * s.sample_rate).floor() + 1.0;
    // Columns: time, drum speed, the channels.
    let bytes = samples * (ch as f64 + 2.0) * 8.0;
    if bytes > MAX_OUTPUT_BYTES && !s.allow_large_output {
        cx.error("--allow-large-output", format!(
            "the sensor output would hold {samples:.3e} samples x {} columns = {:.1} GB (8 bytes \
             a value), more than the {:.0} GB limit: lower --t-end or --sample-rate, or pass \
             --allow-large-output",
            ch + 2,
            bytes / 1e9,
            MAX_OUTPUT_BYTES / 1e9
        ));
    }
}
