//! The measured drum speed as a run's speed table: the points of a piecewise-linear rpm(t),
//! few enough for a model file, written as the CSV `sweep --profiles`, a study's
//! `speed.profile` and `washdyn run --speed` read (`time_s,drum_rpm`).

use super::{Measured, MeasuredError};
use std::io::Write;
use std::path::Path;

/// Spacing of the candidate points, s: a run-up's speed changes over seconds, a 1-pulse
/// tacho's speed is known per revolution (43 ms at 1400 rpm).
pub const TABLE_STEP_S: f64 = 0.05;
/// Largest deviation, rpm, of the table's line from the measured speed at the candidate points
/// (the tacho's speed is good to ~0.05 rpm; finer keeps noise as points).
pub const TABLE_TOL_RPM: f64 = 0.05;

/// `(time s, drum rpm)` points of the measured speed: candidates every [`TABLE_STEP_S`], of
/// which a point is kept where a line over the candidates skipped would leave the speed by more
/// than [`TABLE_TOL_RPM`] (doubled until at most `max_points`, >= 2, remain). The first and
/// last samples are always kept.
pub fn speed_table(m: &Measured, max_points: usize) -> Vec<[f64; 2]> {
    let (t, rpm) = (&m.signals.time, &m.signals.drum_rpm);
    if t.is_empty() {
        return Vec::new();
    }
    let stride = ((TABLE_STEP_S * m.signals.sample_rate).round() as usize).max(1);
    let mut idx: Vec<usize> = (0..t.len()).step_by(stride).collect();
    if idx.last() != Some(&(t.len() - 1)) {
        idx.push(t.len() - 1);
    }
    let cand: Vec<[f64; 2]> = idx.iter().map(|&i| [t[i], rpm[i]]).collect();
    let max_points = max_points.max(2);
    let mut tol = TABLE_TOL_RPM;
    loop {
        let kept = simplify(&cand, tol);
        if kept.len() <= max_points {
            return kept;
        }
        tol *= 2.0;
    }
}

/// Greedy: from each kept point, the farthest candidate whose line stays within `tol` of
/// every candidate between.
fn simplify(c: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let mut out = vec![c[0]];
    let mut a = 0;
    while a + 1 < c.len() {
        let mut b = a + 1;
        while b + 1 < c.len() && fits(c, a, b + 1, tol) {
            b += 1;
        }
        out.push(c[b]);
        a = b;
    }
    out
}

/// Whether the line from `c[a]` to `c[b]` passes within `tol` of the candidates between.
fn fits(c: &[[f64; 2]], a: usize, b: usize, tol: f64) -> bool {
    let ([ta, ra], [tb, rb]) = (c[a], c[b]);
    c[a + 1..b].iter().all(|&[t, r]| {
        let line = ra + (rb - ra) * (t - ta) / (tb - ta);
        (line - r).abs() <= tol
    })
}

/// Write a speed table as CSV `time_s,drum_rpm` (every digit: the numbers read back exact).
pub fn write_speed_csv(path: impl AsRef<Path>, table: &[[f64; 2]]) -> Result<(), MeasuredError> {
    let path = path.as_ref();
    let mut text = String::from("time_s,drum_rpm\n");
    for [t, r] in table {
        text.push_str(&format!("{t},{r}\n"));
    }
    std::fs::File::create(path)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .map_err(|source| MeasuredError::Write {
            path: path.to_path_buf(),
            source,
        })
}
