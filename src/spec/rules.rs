//! The rules of a run specification, in one place for every command that runs: each rule is
//! one function on a shared context that collects every violation, so one message lists them
//! all, and nothing is written before they pass. A rule names the fields it mentions through
//! the reader's [`Spelling`].

use super::RunSpec;
use super::field::{Field, Refusal, Spelling};
use washdyn_ode::{Method, Rounded};

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

/// What the rules need beyond the specification: the method and tolerance it resolves to on
/// its model, and what the model and the caller give.
#[derive(Clone, Debug)]
pub struct Context {
    pub method: Method,
    pub tol: f64,
    /// End of the model's speed profile, s.
    pub profile_end: f64,
    /// Sensor channels written per sample; `None`: the size is not checked.
    pub channels: Option<usize>,
    /// Highest frequency the analysis after the run resolves, Hz; `None`: no analysis.
    pub analysis_band_hz: Option<f64>,
}

impl Context {
    /// A context for the rules that need no model (`channels` unchecked, no analysis).
    pub fn bare(method: Method, tol: f64, profile_end: f64) -> Context {
        Context {
            method,
            tol,
            profile_end,
            channels: None,
            analysis_band_hz: None,
        }
    }
}

/// Collects the violations.
struct Ctxt<'a> {
    spec: &'a RunSpec,
    cx: &'a Context,
    errors: Vec<Refusal>,
}

impl Ctxt<'_> {
    fn error(&mut self, field: Field, text: impl Fn(Spelling) -> String) {
        self.errors.push(Refusal::new(field, text));
    }

    /// `value` finite and within [lo, hi].
    fn range(&mut self, field: Field, value: f64, (lo, hi): (f64, f64), unit: &str, why: &str) {
        if !(value.is_finite() && value >= lo && value <= hi) {
            let sep = if unit.is_empty() { "" } else { " " };
            self.error(field, |s| {
                format!(
                    "{} must be in [{lo:e}, {hi:e}]{sep}{unit}{why}, got {value}",
                    field.name(s)
                )
            });
        }
    }
}

impl RunSpec {
    /// Every rule on this specification in `cx`; `Err` lists every violation with its field
    /// (the caller's `Error::Settings`).
    pub fn validate(&self, cx: &Context) -> Result<(), Vec<Refusal>> {
        let mut c = Ctxt {
            spec: self,
            cx,
            errors: Vec::new(),
        };
        check_step(&mut c);
        check_rho_inf(&mut c);
        c.range(Field::Tol, cx.tol, TOL, "", "");
        check_window(&mut c);
        check_sample_rate(&mut c);
        check_max_steps(&mut c);
        check_max_projected_wall(&mut c);
        if c.errors.is_empty() {
            check_output_size(&mut c);
        }
        if c.errors.is_empty() {
            Ok(())
        } else {
            Err(c.errors)
        }
    }

    /// The simulated end time in `cx`.
    pub fn end(&self, cx: &Context) -> f64 {
        self.t_end.unwrap_or(cx.profile_end)
    }
}

fn check_step(c: &mut Ctxt) {
    match (c.cx.method, c.spec.step) {
        (Method::Rk4, Some(h)) => c.range(Field::Step, h, RK4_STEP, "s", " for rk4"),
        (Method::Rk4, None) => {}
        (m, Some(h)) => c.error(Field::Step, |s| {
            let (step, tol) = (Field::Step.name(s), Field::Tol.name(s));
            format!(
                "{step} applies to rk4 only: {} chooses its own steps from {tol}, got {step} {h}",
                format!("{m:?}").to_lowercase()
            )
        }),
        (_, None) => {}
    }
}

/// Generalized-alpha's spectral radius at infinity: Chung & Hulbert's family is defined on
/// [0, 1] (1: no numerical damping; 0: the unresolved modes annihilated in one step).
fn check_rho_inf(c: &mut Ctxt) {
    match (c.cx.method, c.spec.rho_inf) {
        (Method::GeneralizedAlpha, Some(r)) => c.range(Field::RhoInf, r, (0.0, 1.0), "", ""),
        (m, Some(r)) => c.error(Field::RhoInf, |s| {
            let rho = Field::RhoInf.name(s);
            format!(
                "{rho} applies to galpha only: {m} has no spectral radius to set, got {rho} {r}"
            )
        }),
        (_, None) => {}
    }
}

/// The window: an end in (0, T_END_MAX], a start at 0 or later and before the end.
fn check_window(c: &mut Ctxt) {
    if let Some(t) = c.spec.t_end
        && !(t > 0.0 && t <= T_END_MAX)
    {
        c.error(Field::TEnd, |s| {
            format!(
                "{} must be > 0 and at most {T_END_MAX} s, got {t}",
                Field::TEnd.name(s)
            )
        });
        return;
    }
    let (t0, end) = (c.spec.t_start, c.spec.end(c.cx));
    if !(t0.is_finite() && t0 >= 0.0 && t0 < end) {
        c.error(Field::TStart, |s| {
            format!(
                "{} must be at least 0 and before the end of the run ({} s), got {t0}",
                Field::TStart.name(s),
                Rounded(end)
            )
        });
    }
}

fn check_sample_rate(c: &mut Ctxt) {
    let rate = c.spec.sample_rate;
    c.range(Field::SampleRate, rate, SAMPLE_RATE, "Hz", "");
    if let Some(band) = c.cx.analysis_band_hz
        && rate.is_finite()
        && rate < 2.0 * band
    {
        c.error(Field::SampleRate, |s| {
            format!(
                "{} must be at least {} Hz for the analysis (twice its {band} Hz band), \
                 got {rate} (or pass --no-plots)",
                Field::SampleRate.name(s),
                2.0 * band,
            )
        });
    }
}

fn check_max_steps(c: &mut Ctxt) {
    if c.spec.max_steps == Some(0) {
        c.error(Field::MaxSteps, |s| {
            format!("{} must be at least 1, got 0", Field::MaxSteps.name(s))
        });
    }
}

/// The progress guard's budget: a duration, so > 0; `inf` never stops, NaN never compares.
fn check_max_projected_wall(c: &mut Ctxt) {
    let v = c.spec.max_projected_wall;
    if v.is_nan() || v <= 0.0 {
        c.error(Field::MaxProjectedWall, |s| {
            format!(
                "{} must be > 0 s (inf: never stop), got {v}",
                Field::MaxProjectedWall.name(s)
            )
        });
    }
}

fn check_output_size(c: &mut Ctxt) {
    let Some(ch) = c.cx.channels else { return };
    let samples = (c.spec.end(c.cx) * c.spec.sample_rate).floor() + 1.0;
    // Columns: time, drum speed, the channels.
    let bytes = samples * (ch as f64 + 2.0) * 8.0;
    if bytes > MAX_OUTPUT_BYTES && !c.spec.allow_large_output {
        c.error(Field::AllowLargeOutput, |s| {
            format!(
                "the sensor output would hold {samples:.3e} samples x {} columns = {:.1} GB (8 \
                 bytes a value), more than the {:.0} GB limit: lower {} or {}, or pass {}",
                ch + 2,
                bytes / 1e9,
                MAX_OUTPUT_BYTES / 1e9,
                Field::TEnd.name(s),
                Field::SampleRate.name(s),
                Field::AllowLargeOutput.name(s),
            )
        });
    }
}
