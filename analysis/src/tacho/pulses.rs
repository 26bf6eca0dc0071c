//! Missing and extra pulses: found against the neighbouring intervals, repaired.
//!
//! A pulse interval is judged against the median of up to two intervals on each side (not
//! itself): during a run-up the intervals shrink steadily, and neighbours on both sides
//! bracket the interval, so the median follows the acceleration. At the ends of the record
//! the neighbours are all on one side; there a line fitted to their pulse rates is also
//! extrapolated, so the long first intervals of a start from standstill are expected.

/// An interval longer than this times the expected one has missed pulses.
const MISSING_RATIO: f64 = 1.5;
/// An interval shorter than this times the expected one ends in a spurious pulse.
const EXTRA_RATIO: f64 = 0.5;
/// Fewest intervals to judge one against the others.
const MIN_INTERVALS: usize = 4;

/// Pulse times after repair, and what was changed.
pub(super) struct Repaired {
    /// Pulse times, one pulse angle apart.
    pub times: Vec<f64>,
    /// Inserted pulses.
    pub missing: Vec<f64>,
    /// Dropped pulses.
    pub extra: Vec<f64>,
}

/// Drop spurious pulses, then fill in missed ones.
pub(super) fn repair(raw: &[f64]) -> Repaired {
    let mut times = raw.to_vec();
    let mut extra = Vec::new();
    let mut missing = Vec::new();
    if times.len() <= MIN_INTERVALS {
        return Repaired {
            times,
            missing,
            extra,
        };
    }
    drop_extra(&mut times, &mut extra);
    let times = fill_missing(&times, &mut missing);
    Repaired {
        times,
        missing,
        extra,
    }
}

/// Interval `k` (from pulse `k` to `k + 1`).
fn interval(t: &[f64], k: usize) -> f64 {
    t[k + 1] - t[k]
}

/// Median of the intervals within two of `k`, without `k` itself.
fn neighbour_median(t: &[f64], k: usize) -> f64 {
    let m = t.len() - 1;
    crate::metrics::median(
        (k.saturating_sub(2)..(k + 3).min(m))
            .filter(|&j| j != k)
            .map(|j| interval(t, j))
            .collect(),
    )
}

/// Interval `k` as expected from a constant acceleration fitted to the pulse rates of its
/// neighbours (within two, by least squares), started at pulse `k`'s time. Infinite when
/// that trend stops before the next pulse.
fn trend_interval(t: &[f64], k: usize) -> f64 {
    let m = t.len() - 1;
    let pts: Vec<(f64, f64)> = (k.saturating_sub(2)..(k + 3).min(m))
        .filter(|&j| j != k)
        .map(|j| (0.5 * (t[j] + t[j + 1]) - t[k], 1.0 / interval(t, j)))
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let rate0 = my - slope * mx;
    // One pulse: rate0 * I + slope * I^2 / 2 = 1, the larger root in a cancellation-free form.
    let disc = rate0 * rate0 + 2.0 * slope;
    if disc < 0.0 {
        return f64::INFINITY;
    }
    let denom = rate0 + disc.sqrt();
    if denom > 0.0 {
        2.0 / denom
    } else {
        f64::INFINITY
    }
}

/// Interval `k` expected from its neighbours, allowing for a start from (or stop to)
/// standstill at the record's ends.
fn expected_long(t: &[f64], k: usize) -> f64 {
    let m = t.len() - 1;
    let median = neighbour_median(t, k);
    if k < 2 || k + 2 >= m {
        median.max(trend_interval(t, k))
    } else {
        median
    }
}

/// Drop the pulse that ends (or starts) each too-short interval, whichever leaves the merged
/// interval closer to the expected one.
fn drop_extra(times: &mut Vec<f64>, extra: &mut Vec<f64>) {
    let mut k = 0;
    while k + 1 < times.len() && times.len() > MIN_INTERVALS + 1 {
        let expected = neighbour_median(times, k);
        if interval(times, k) >= EXTRA_RATIO * expected {
            k += 1;
            continue;
        }
        let m = times.len() - 1;
        let misfit = |merged: f64| (merged / expected).ln().abs();
        let merge_next = (k + 1 < m).then(|| misfit(interval(times, k) + interval(times, k + 1)));
        let merge_prev = (k > 0).then(|| misfit(interval(times, k - 1) + interval(times, k)));
        let drop = match (merge_prev, merge_next) {
            (Some(p), Some(n)) if p < n => k,
            (Some(_), None) => k,
            _ => k + 1,
        };
        extra.push(times.remove(drop));
        k = k.saturating_sub(2);
    }
}

/// Split each too-long interval into the whole number of intervals it spans.
fn fill_missing(times: &[f64], missing: &mut Vec<f64>) -> Vec<f64> {
    let m = times.len() - 1;
    let mut out = Vec::with_capacity(times.len());
    for k in 0..m {
        out.push(times[k]);
        let len = interval(times, k);
        let expected = expected_long(times, k);
        if len <= MISSING_RATIO * expected {
            continue;
        }
        let parts = (len / expected).round().max(2.0);
        // A gap of more than ~10^6 pulses is a stop or a dead sensor, not missed pulses.
        if parts > 1e6 {
            continue;
        }
        let parts = parts as usize;
        for p in 1..parts {
            let t = times[k] + len * p as f64 / parts as f64;
            out.push(t);
            missing.push(t);
        }
    }
    out.push(times[m]);
    out
}

/// Largest deviation (rad/s) of an interval's mean speed from the mean of its two
/// neighbours': a steady acceleration cancels, a misplaced pulse does not.
pub(super) fn max_speed_jump(times: &[f64], dphi: f64) -> f64 {
    let speeds: Vec<f64> = times.windows(2).map(|w| dphi / (w[1] - w[0])).collect();
    speeds
        .windows(3)
        .map(|s| (s[1] - 0.5 * (s[0] + s[2])).abs())
        .fold(0.0, f64::max)
}
