//! Pulse edges: robust levels, a Schmitt trigger, sub-sample edge times.

use super::{Edge, TachoError, TachoSettings};

/// Percentiles taken as the low and high levels: robust to spikes, yet inside pulses as
/// narrow as ~2 % of a period.
const LEVEL_PERCENTILES: (f64, f64) = (0.01, 0.99);
/// Half-width of the middle band (fraction of the level span, around the mid level) that a
/// pulse train crosses only on its edges.
const MIDDLE_BAND: f64 = 0.2;
/// Largest fraction of samples in the middle band for a signal with two levels. A square
/// wave with edges of a few samples has ~0 %, a sine (a magnetic pick-up) 26 %, uniform
/// noise 40 %, Gaussian noise 65 %.
const MAX_MIDDLE_FRACTION: f64 = 0.35;
/// Default hysteresis as a fraction of the level span.
const DEFAULT_HYSTERESIS: f64 = 0.1;

/// Robust low and high levels of the signal.
fn levels(signal: &[f64]) -> (f64, f64) {
    let mut v = signal.to_vec();
    let n = v.len();
    let at = |p: f64| ((n - 1) as f64 * p).round() as usize;
    let (lo_i, hi_i) = (at(LEVEL_PERCENTILES.0), at(LEVEL_PERCENTILES.1));
    let lo = *v.select_nth_unstable_by(lo_i, f64::total_cmp).1;
    let hi = *v.select_nth_unstable_by(hi_i, f64::total_cmp).1;
    (lo, hi)
}

/// Threshold and hysteresis to use: the settings', or from the levels. Refuses a signal
/// without two levels, which would otherwise trigger on noise.
fn trigger_levels(signal: &[f64], settings: &TachoSettings) -> Result<(f64, f64), TachoError> {
    let (lo, hi) = levels(signal);
    let span = hi - lo;
    if span <= 1e-12 * lo.abs().max(hi.abs()) {
        return Err(TachoError::NoPulses {
            reason: format!("the signal is flat (1st and 99th percentiles {lo} and {hi})"),
        });
    }
    let threshold = match settings.threshold {
        Some(t) => t,
        None => {
            let mid = 0.5 * (lo + hi);
            let band = MIDDLE_BAND * span;
            let inside = signal.iter().filter(|v| (*v - mid).abs() < band).count();
            let fraction = inside as f64 / signal.len() as f64;
            if fraction > MAX_MIDDLE_FRACTION {
                return Err(TachoError::NoPulses {
                    reason: format!(
                        "{:.0} % of the samples lie between the low and high levels \
                         ({lo} and {hi}), so there are no two levels to switch between \
                         (noise?); set `threshold` to force one",
                        100.0 * fraction
                    ),
                });
            }
            mid
        }
    };
    let hysteresis = settings.hysteresis.unwrap_or(DEFAULT_HYSTERESIS * span);
    Ok((threshold, hysteresis))
}

/// Times of the chosen edges, each interpolated linearly between the two samples that
/// straddle the threshold. Only full transitions count: the trigger starts in neither state,
/// so a record that begins inside a pulse does not yield a false edge.
pub(super) fn detect(
    time: &[f64],
    signal: &[f64],
    settings: &TachoSettings,
) -> Result<Vec<f64>, TachoError> {
    let (thr, hyst) = trigger_levels(signal, settings)?;
    let (upper, lower) = (thr + 0.5 * hyst, thr - 0.5 * hyst);
    let mut high: Option<bool> = None;
    let mut last_switch = 0;
    let mut edges = Vec::new();
    for (i, &y) in signal.iter().enumerate() {
        let rise = high != Some(true) && y >= upper;
        let fall = high != Some(false) && y < lower;
        if !(rise || fall) {
            continue;
        }
        let wanted = match settings.edge {
            Edge::Rising => rise && high == Some(false),
            Edge::Falling => fall && high == Some(true),
        };
        if wanted && let Some(t) = crossing(time, signal, thr, last_switch, i, rise) {
            edges.push(t);
        }
        high = Some(rise);
        last_switch = i;
    }
    Ok(edges)
}

/// The threshold crossing between samples `from` and `to` (where the trigger switched), the
/// last one before `to`: `y_j` on the old side of `thr`, `y_{j+1}` on the new.
fn crossing(time: &[f64], y: &[f64], thr: f64, from: usize, to: usize, rise: bool) -> Option<f64> {
    let above = |v: f64| v >= thr;
    let j = (from..to).rev().find(|&j| above(y[j]) != rise)?;
    let f = (thr - y[j]) / (y[j + 1] - y[j]);
    Some(time[j] + f * (time[j + 1] - time[j]))
}
