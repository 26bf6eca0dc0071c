//! Drum angle and speed from a tacho pulse channel (a test rig's optical or magnetic sensor on
//! the drum or on the motor shaft, sampled like the accelerometers).
//!
//! Three steps, each in its own file:
//!
//! 1. `edges`: a Schmitt trigger (threshold ± hysteresis/2) finds the pulses; each edge's
//!    time is interpolated linearly between the two samples around the threshold crossing, so
//!    it is sub-sample accurate where the edge spans a sample or two (a sensor behind an
//!    anti-alias filter). A logic-level edge sharper than a sample is only known to ±half a
//!    sample (29 µs rms at 10 kHz): then the fit window must average more pulses.
//! 2. `pulses`: missing pulses (an interval much longer than its neighbours') are filled in
//!    and extra pulses (much shorter) dropped, judged against neighbours on both sides so that
//!    a run-up from standstill is not a defect.
//! 3. `fit`: the angle and speed between pulses. Edge-timing noise is what limits the
//!    speed: ±5 % of noise on a 0.2 ms edge moves each edge by ~5 µs (rms), which is 0.2 rpm
//!    at 1400 rpm from one 1-pulse-per-revolution interval (43 ms). So each pulse's angle,
//!    speed and acceleration come from a local polynomial least-squares fit over the pulses
//!    within `smoothing_s` (exact for a constant acceleration, noise averaged over the
//!    window). A monotone cubic Hermite curve (Hyman's limiter) through the fitted angles
//!    gives the angle, which never runs backwards; a cubic Hermite curve through the fitted
//!    speeds and accelerations gives the speed, continuous at every sample.

mod edges;
mod fit;
mod pulses;
#[cfg(test)]
mod tests;

use std::f64::consts::PI;

/// Which pulse edge marks the drum's position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Edge {
    /// Low to high.
    #[default]
    Rising,
    /// High to low.
    Falling,
}

/// How to read a tacho channel.
#[derive(Debug, Clone, PartialEq)]
pub struct TachoSettings {
    /// Pulses per revolution of the shaft the sensor sits on (>= 1).
    pub pulses_per_rev: u32,
    /// The edge that marks a pulse.
    pub edge: Edge,
    /// Switching level in the signal's unit; default midway between the robust low and high
    /// levels (1st and 99th percentiles, so pulses as narrow as ~2 % of a period still count).
    pub threshold: Option<f64>,
    /// Full width of the Schmitt trigger's band (signal unit, >= 0); default 10 % of the level
    /// span. It keeps noise on a slow edge from counting twice.
    pub hysteresis: Option<f64>,
    /// Revolutions of the sensor's shaft per drum revolution: 1 for a drum tacho, the belt
    /// ratio (11.25) for a motor-side tacho (drum angle = motor angle / ratio).
    pub ratio: f64,
    /// Time window (s, >= 0) of the local fit that averages edge-timing noise over neighbouring
    /// pulses; 0 uses the nearest three pulses only (no averaging). Longer windows average
    /// more noise but flatten faster speed changes: 0.5 s follows a 0.5 Hz ripple of 2 rpm
    /// to 0.07 rpm; a 1-pulse drum tacho with ±5 % noise needs ~0.8 s for 0.05 rpm at
    /// 1400 rpm. A constant acceleration comes out exact with any window.
    pub smoothing_s: f64,
}

impl Default for TachoSettings {
    /// One rising edge per drum revolution, automatic levels, 0.5 s smoothing.
    fn default() -> Self {
        TachoSettings {
            pulses_per_rev: 1,
            edge: Edge::Rising,
            threshold: None,
            hysteresis: None,
            ratio: 1.0,
            smoothing_s: DEFAULT_SMOOTHING_S,
        }
    }
}

/// Default fit window, s: a 0.5 Hz speed ripple kept to ~4 %, ~260 pulses of a motor-side
/// tacho (2 per motor turn) at 1400 drum rpm, ~12 of a 1-pulse drum tacho.
pub const DEFAULT_SMOOTHING_S: f64 = 0.5;

/// Fewest pulses that define a speed and its change.
pub const MIN_PULSES: usize = 3;

impl TachoSettings {
    /// A motor-side tacho: `pulses_per_rev` per motor revolution, `ratio` motor turns per drum
    /// turn.
    pub fn motor(pulses_per_rev: u32, ratio: f64) -> TachoSettings {
        TachoSettings {
            pulses_per_rev,
            ratio,
            ..TachoSettings::default()
        }
    }

    /// Every field in range; the error names the first field that is not.
    pub fn validate(&self) -> Result<(), TachoError> {
        let bad = |field: &'static str, value: f64, expected: &'static str| {
            Err(TachoError::InvalidSetting {
                field,
                value,
                expected,
            })
        };
        if self.pulses_per_rev == 0 {
            return bad("pulses_per_rev", 0.0, "an integer >= 1");
        }
        if !(self.ratio.is_finite() && self.ratio > 0.0) {
            return bad("ratio", self.ratio, "a finite number > 0");
        }
        if let Some(t) = self.threshold.filter(|t| !t.is_finite()) {
            return bad("threshold", t, "a finite number");
        }
        if let Some(h) = self.hysteresis.filter(|h| !(h.is_finite() && *h >= 0.0)) {
            return bad("hysteresis", h, "a finite number >= 0");
        }
        if !(self.smoothing_s.is_finite() && self.smoothing_s >= 0.0) {
            return bad("smoothing_s", self.smoothing_s, "a finite number >= 0 (s)");
        }
        Ok(())
    }

    /// Drum angle between two pulses, rad.
    pub fn pulse_angle(&self) -> f64 {
        2.0 * PI / (self.pulses_per_rev as f64 * self.ratio)
    }
}

/// Why a tacho channel could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TachoError {
    /// A setting outside its range.
    #[error("tacho setting `{field}` = {value}: expected {expected}")]
    InvalidSetting {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// Time and signal differ in length.
    #[error("tacho: time has {time} samples, the signal {signal}")]
    LengthMismatch { time: usize, signal: usize },
    /// A time or signal sample is NaN or infinite.
    #[error("tacho: {what} sample {index} is not finite")]
    NotFinite { what: &'static str, index: usize },
    /// Time does not increase strictly.
    #[error("tacho: time sample {index} ({time} s) does not increase")]
    TimeNotIncreasing { index: usize, time: f64 },
    /// No level change to find pulses in (constant signal, or noise without two levels).
    #[error("tacho: no pulses in the signal: {reason}")]
    NoPulses { reason: String },
    /// Too few pulses (after repair) to define a speed.
    #[error("tacho: {found} pulses found, need at least {needed}")]
    TooFewPulses { found: usize, needed: usize },
}

/// How trustworthy the pulse train was, and what was repaired.
#[derive(Debug, Clone, PartialEq)]
pub struct TachoQuality {
    /// Edges the trigger found (before repair).
    pub pulses: usize,
    /// Times (s) of the pulses inserted into too-long intervals (missed by the sensor).
    pub missing: Vec<f64>,
    /// Times (s) of the pulses dropped from too-short intervals (spurious).
    pub extra: Vec<f64>,
    /// Largest deviation (rpm) of a pulse interval's mean drum speed from the mean of its two
    /// neighbours', after repair: a steady acceleration cancels; a defect left over, or the
    /// edge-timing noise, shows here.
    pub max_speed_jump_rpm: f64,
    /// Time span (s) with a valid angle and speed.
    pub span: (f64, f64),
}

/// Drum angle and speed at the input's samples inside the valid span.
#[derive(Debug, Clone, PartialEq)]
pub struct TachoSpeed {
    /// Index of the first input sample inside the valid span.
    pub first: usize,
    /// Sample times (s) inside the valid span: `input_time[first..first + time.len()]`.
    pub time: Vec<f64>,
    /// Drum angle (rad), increasing, 0 at the first pulse used (up to the fit's correction of
    /// that pulse's edge noise, ~1e-4 rad).
    pub angle: Vec<f64>,
    /// Drum speed (rad/s).
    pub speed: Vec<f64>,
    /// Drum speed (rpm), for the user.
    pub rpm: Vec<f64>,
    /// Pulse times (s) after repair, each `settings.pulse_angle()` after the previous.
    pub pulses: Vec<f64>,
    /// What was found and repaired.
    pub quality: TachoQuality,
}

/// rad/s per rpm.
const RPM: f64 = 2.0 * PI / 60.0;

/// Drum angle and speed from a tacho channel sampled at `time` (s, strictly increasing).
///
/// Valid from one pulse period before the first pulse to one after the last (shorter where
/// the record ends, or where the speed would fall to zero): no farther, since the speed
/// there is an extrapolation.
pub fn speed_from_tacho(
    time: &[f64],
    signal: &[f64],
    settings: &TachoSettings,
) -> Result<TachoSpeed, TachoError> {
    settings.validate()?;
    check_input(time, signal)?;
    let raw = edges::detect(time, signal, settings)?;
    if raw.len() < MIN_PULSES {
        return Err(TachoError::TooFewPulses {
            found: raw.len(),
            needed: MIN_PULSES,
        });
    }
    let repaired = pulses::repair(&raw);
    if repaired.times.len() < MIN_PULSES {
        return Err(TachoError::TooFewPulses {
            found: repaired.times.len(),
            needed: MIN_PULSES,
        });
    }
    let dphi = settings.pulse_angle();
    let curve = fit::AngleCurve::new(&repaired.times, dphi, settings.smoothing_s);
    let span = curve.span(time[0], time[time.len() - 1]);
    let first = time.partition_point(|&t| t < span.0);
    let end = time.partition_point(|&t| t <= span.1);
    let times = time[first..end.max(first)].to_vec();
    let (angle, speed) = curve.evaluate(&times);
    let quality = TachoQuality {
        pulses: raw.len(),
        max_speed_jump_rpm: pulses::max_speed_jump(&repaired.times, dphi) / RPM,
        missing: repaired.missing,
        extra: repaired.extra,
        span,
    };
    Ok(TachoSpeed {
        first,
        rpm: speed.iter().map(|w| w / RPM).collect(),
        time: times,
        angle,
        speed,
        pulses: repaired.times,
        quality,
    })
}

/// `(time_s, drum_rpm)` columns at the input's samples inside the valid span: what
/// [`crate::Signals`] takes (cut the other channels to `first..first + len`).
pub fn drum_rpm_columns(
    time: &[f64],
    signal: &[f64],
    settings: &TachoSettings,
) -> Result<(Vec<f64>, Vec<f64>), TachoError> {
    let s = speed_from_tacho(time, signal, settings)?;
    Ok((s.time, s.rpm))
}

/// Same lengths, finite samples, strictly increasing time.
fn check_input(time: &[f64], signal: &[f64]) -> Result<(), TachoError> {
    if time.len() != signal.len() {
        return Err(TachoError::LengthMismatch {
            time: time.len(),
            signal: signal.len(),
        });
    }
    if signal.is_empty() {
        return Err(TachoError::NoPulses {
            reason: "the signal is empty".into(),
        });
    }
    if let Some(index) = time.iter().position(|t| !t.is_finite()) {
        return Err(TachoError::NotFinite {
            what: "time",
            index,
        });
    }
    if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
        return Err(TachoError::NotFinite {
            what: "signal",
            index,
        });
    }
    if let Some(i) = time.windows(2).position(|w| w[1] <= w[0]) {
        return Err(TachoError::TimeNotIncreasing {
            index: i + 1,
            time: time[i + 1],
        });
    }
    Ok(())
}
