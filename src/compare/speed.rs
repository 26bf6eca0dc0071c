//! Order tracks compared at equal drum speed instead of equal time (issue 51 point 3): a
//! measured and a simulated run-up never share a speed profile exactly, so each track is put on
//! one common speed grid and the two are compared there, per speed range, with the resonance
//! speeds of order 1 paired and a constant calibration factor (Wagner & Pfeiffer's correction
//! of the measured magnitudes) computed and reported.
//!
//! This file is the arithmetic only (grid, ranges, resonances, factor); `over_speed.rs` reads,
//! analyses, plots and reports.
//!
//! **Which blocks.** A track's blocks are taken *in speed order*, from the run's start up to the
//! first block at its top speed: a program's profile is not monotone (a distribution plateau,
//! steps, a measured tacho's jitter), and sorting by speed uses every block of it; blocks at one
//! speed (a plateau) merge into one point (the RMS of their amplitudes). The run-down after the
//! top speed is left out: it passes the resonances the other way, where the friction dampers
//! give other amplitudes, and would mix two curves into one.

use crate::analysis::RunUp;
use serde::{Deserialize, Serialize};

/// Spacing of the common speed grid, rpm.
pub const SPEED_STEP_RPM: f64 = 10.0;
/// A grid point is compared where both tracks are within this many dB of their own peak on the
/// grid: below it an order is noise or leakage, and its dB differences say nothing.
pub const LEVEL_FLOOR_DB: f64 = -20.0;
/// A local maximum of order 1 is a resonance where it stands this many dB above the higher of
/// the lowest points on either side before a higher maximum (its topographic prominence).
pub const RESONANCE_PROMINENCE_DB: f64 = 3.0;
/// Resonances of the two runs further apart than this are not paired, rpm.
pub const RESONANCE_PAIR_RPM: f64 = 150.0;
/// Default edges of the speed ranges, rpm: 0-400 (the suspension's resonances), 400-800,
/// 800-1400 (the spin) and above.
pub const DEFAULT_RANGE_EDGES: [f64; 3] = [400.0, 800.0, 1400.0];
/// Blocks whose mean speeds differ by less than this merge into one point, rpm (a plateau's
/// blocks, a measured tacho's jitter on it).
const MERGE_RPM: f64 = 1.0;

/// A track's points in speed order: (mean rpm of the block or merged blocks, amplitude;
/// `None` where not resolved).
pub type SpeedPoints = Vec<(f64, Option<f64>)>;

/// Order track `track` of `run` in speed order (see the module docs): the blocks at or above
/// the analysis' minimum speed up to the first at the top speed, sorted by speed, blocks within
/// [`MERGE_RPM`] merged (RMS of the resolved amplitudes).
pub fn track_points(run: &RunUp, track: usize) -> SpeedPoints {
    let amps = &run.tracks[track].amplitude;
    let top = run
        .blocks
        .iter()
        .fold(f64::NEG_INFINITY, |m, b| m.max(b.rpm));
    let end = run
        .blocks
        .iter()
        .position(|b| b.rpm >= top)
        .map_or(0, |k| k + 1);
    let mut pts: Vec<(f64, Option<f64>)> = run.blocks[..end]
        .iter()
        .zip(amps)
        .filter(|(b, _)| b.rpm >= run.min_rpm && b.rpm.is_finite())
        .map(|(b, a)| (b.rpm, *a))
        .collect();
    pts.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut out: SpeedPoints = Vec::with_capacity(pts.len());
    let mut k = 0;
    while k < pts.len() {
        let j = k + pts[k..]
            .iter()
            .take_while(|p| p.0 - pts[k].0 < MERGE_RPM)
            .count();
        let group = &pts[k..j];
        let rpm = group.iter().map(|p| p.0).sum::<f64>() / group.len() as f64;
        let vals: Vec<f64> = group.iter().filter_map(|p| p.1).collect();
        let amp = (!vals.is_empty())
            .then(|| (vals.iter().map(|v| v * v).sum::<f64>() / vals.len() as f64).sqrt());
        out.push((rpm, amp));
        k = j;
    }
    out
}

/// The common grid: every `step` rpm (multiples of it) from `lo` to `hi`; empty where they do
/// not overlap.
pub fn speed_grid(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && step > 0.0 && hi >= lo) {
        return Vec::new();
    }
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// Speed span of a track's resolved points, rpm.
pub fn resolved_span(points: &[(f64, Option<f64>)]) -> Option<(f64, f64)> {
    let mut it = points.iter().filter(|p| p.1.is_some()).map(|p| p.0);
    let first = it.next()?;
    Some((first, it.next_back().unwrap_or(first)))
}

/// `points` at each speed of `grid`: linear in rpm between the two points around it, `None`
/// outside the points or where either of the two is not resolved.
pub fn on_grid(points: &[(f64, Option<f64>)], grid: &[f64]) -> Vec<Option<f64>> {
    grid.iter()
        .map(|&g| {
            let i = points.partition_point(|p| p.0 < g);
            let at = points.get(i)?;
            if at.0 == g {
                return at.1;
            }
            let before = points.get(i.checked_sub(1)?)?;
            let (a, b) = (before.1?, at.1?);
            let w = (g - before.0) / (at.0 - before.0);
            Some(a + w * (b - a))
        })
        .collect()
}

/// Largest value of a track on the grid.
fn peak(track: &[Option<f64>]) -> Option<f64> {
    track.iter().flatten().copied().fold(None, |m, v| match m {
        Some(m) if m >= v => Some(m),
        _ => Some(v),
    })
}

/// 20 log10(b / a) at each grid point where both are at least [`LEVEL_FLOOR_DB`] below their
/// own peak (and positive).
pub fn db_over_speed(a: &[Option<f64>], b: &[Option<f64>]) -> Vec<Option<f64>> {
    let floor = 10f64.powf(LEVEL_FLOOR_DB / 20.0);
    let (fa, fb) = (
        peak(a).unwrap_or(f64::INFINITY) * floor,
        peak(b).unwrap_or(f64::INFINITY) * floor,
    );
    a.iter()
        .zip(b)
        .map(|(a, b)| match (a, b) {
            (Some(a), Some(b)) if *a >= fa && *b >= fb && *a > 0.0 && *b > 0.0 => {
                Some(20.0 * (b / a).log10())
            }
            _ => None,
        })
        .collect()
}

/// The level difference of one order over one speed range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedRange {
    /// Lower edge, rpm.
    pub from_rpm: f64,
    /// Upper edge, rpm; `None`: no upper edge.
    pub to_rpm: Option<f64>,
    /// Grid points compared in the range (both above the floor).
    pub points: usize,
    /// RMS of 20 log10(B / A) over those points, dB.
    pub rms_db: Option<f64>,
    /// The difference of largest magnitude there (signed), dB, and its speed, rpm.
    pub max_db: Option<f64>,
    pub max_rpm: Option<f64>,
}

/// The ranges `[0, e0), [e0, e1), ..., [e_last, inf)` that hold a grid speed, with the
/// differences `db` (on `grid`) in each.
pub fn ranges(grid: &[f64], db: &[Option<f64>], edges: &[f64]) -> Vec<SpeedRange> {
    let mut bounds = vec![0.0];
    bounds.extend_from_slice(edges);
    (0..bounds.len())
        .filter_map(|r| {
            let (lo, hi) = (bounds[r], bounds.get(r + 1).copied());
            let inside = |g: f64| g >= lo && hi.is_none_or(|h| g < h);
            if !grid.iter().any(|g| inside(*g)) {
                return None;
            }
            let vals: Vec<(f64, f64)> = grid
                .iter()
                .zip(db)
                .filter(|(g, _)| inside(**g))
                .filter_map(|(g, d)| d.map(|d| (*g, d)))
                .collect();
            let n = vals.len();
            let worst = vals
                .iter()
                .copied()
                .reduce(|w, v| if v.1.abs() > w.1.abs() { v } else { w });
            Some(SpeedRange {
                from_rpm: lo,
                to_rpm: hi,
                points: n,
                rms_db: (n > 0)
                    .then(|| (vals.iter().map(|v| v.1 * v.1).sum::<f64>() / n as f64).sqrt()),
                max_db: worst.map(|w| w.1),
                max_rpm: worst.map(|w| w.0),
            })
        })
        .collect()
}

/// The constant factor on B that minimises the RMS of the dB differences `db` (order 1 over
/// the common grid): the geometric mean of A / B, i.e. 10^(-mean dB / 20). `None` where no
/// point is compared.
pub fn calibration_factor(db: &[Option<f64>]) -> Option<f64> {
    let vals: Vec<f64> = db.iter().flatten().copied().collect();
    (!vals.is_empty()).then(|| {
        let mean = vals.iter().sum::<f64>() / vals.len() as f64;
        10f64.powf(-mean / 20.0)
    })
}

/// Resonances of a track in speed order: the local maxima at or above [`LEVEL_FLOOR_DB`] of
/// the track's peak with a prominence of at least [`RESONANCE_PROMINENCE_DB`] (an unresolved
/// point ends the walk to either side). Each speed is the vertex of the parabola through the
/// log amplitudes of the maximum and its two neighbours (finer than the blocks' spacing, which
/// is 10-40 rpm at 20-80 rpm/s); (rpm, amplitude at the maximum).
pub fn resonances(points: &[(f64, Option<f64>)]) -> Vec<(f64, f64)> {
    let Some(top) = points.iter().filter_map(|p| p.1).reduce(f64::max) else {
        return Vec::new();
    };
    let floor = top * 10f64.powf(LEVEL_FLOOR_DB / 20.0);
    let ratio = 10f64.powf(RESONANCE_PROMINENCE_DB / 20.0);
    let v = |k: usize| points[k].1;
    let mut found = Vec::new();
    for k in 1..points.len().saturating_sub(1) {
        let (Some(x), Some(l), Some(r)) = (v(k), v(k - 1), v(k + 1)) else {
            continue;
        };
        if !(x > l && x >= r && x >= floor && x > 0.0) {
            continue;
        }
        // Lowest point on each side before a higher one or a gap.
        let base = |it: &mut dyn Iterator<Item = usize>| {
            let mut lo = x;
            for j in it {
                match v(j) {
                    Some(y) if y <= x => lo = lo.min(y),
                    _ => break,
                }
            }
            lo
        };
        let left = base(&mut (0..k).rev());
        let right = base(&mut (k + 1..points.len()));
        if x < ratio * left.max(right) {
            continue;
        }
        found.push((
            vertex(points[k - 1].0, points[k].0, points[k + 1].0, l, x, r),
            x,
        ));
    }
    found
}

/// The speed of the vertex of the parabola through (r0, ln a0), (r1, ln a1), (r2, ln a2),
/// kept between r0 and r2; r1 where the three are not a maximum.
fn vertex(r0: f64, r1: f64, r2: f64, a0: f64, a1: f64, a2: f64) -> f64 {
    if !(a0 > 0.0 && a2 > 0.0) {
        return r1;
    }
    let (y0, y1, y2) = (a0.ln(), a1.ln(), a2.ln());
    let (d0, d2) = ((y1 - y0) / (r1 - r0), (y2 - y1) / (r2 - r1));
    let curv = (d2 - d0) / (r2 - r0);
    if !(curv < 0.0 && curv.is_finite()) {
        return r1;
    }
    // The slope is d0 at the midpoint of r0, r1 and falls by 2 curv per rpm.
    let r = 0.5 * (r0 + r1) - d0 / (2.0 * curv);
    r.clamp(r0, r2)
}

/// A resonance of order 1 in either run, paired with the other's nearest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Resonance {
    /// Speed in A and in B, rpm (`None`: no resonance within [`RESONANCE_PAIR_RPM`]).
    pub rpm_a: Option<f64>,
    pub rpm_b: Option<f64>,
    /// rpm B - rpm A.
    pub diff_rpm: Option<f64>,
    /// Order-1 amplitude at the maximum in A and B (SI units; B calibrated where asked).
    pub level_a: Option<f64>,
    pub level_b: Option<f64>,
}

/// Pair A's and B's resonances, nearest first, none further apart than
/// [`RESONANCE_PAIR_RPM`]; the unpaired stay alone. In speed order.
pub fn pair_resonances(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<Resonance> {
    let mut cand: Vec<(f64, usize, usize)> = a
        .iter()
        .enumerate()
        .flat_map(|(i, x)| {
            b.iter()
                .enumerate()
                .map(move |(j, y)| ((x.0 - y.0).abs(), i, j))
        })
        .filter(|c| c.0 <= RESONANCE_PAIR_RPM)
        .collect();
    cand.sort_by(|p, q| p.0.total_cmp(&q.0));
    let (mut used_a, mut used_b) = (vec![false; a.len()], vec![false; b.len()]);
    let mut out = Vec::new();
    for (_, i, j) in cand {
        if !used_a[i] && !used_b[j] {
            used_a[i] = true;
            used_b[j] = true;
            out.push(Resonance {
                rpm_a: Some(a[i].0),
                rpm_b: Some(b[j].0),
                diff_rpm: Some(b[j].0 - a[i].0),
                level_a: Some(a[i].1),
                level_b: Some(b[j].1),
            });
        }
    }
    let alone = |x: &(f64, f64), first: bool| Resonance {
        rpm_a: first.then_some(x.0),
        rpm_b: (!first).then_some(x.0),
        diff_rpm: None,
        level_a: first.then_some(x.1),
        level_b: (!first).then_some(x.1),
    };
    out.extend(
        a.iter()
            .zip(&used_a)
            .filter(|u| !u.1)
            .map(|(x, _)| alone(x, true)),
    );
    out.extend(
        b.iter()
            .zip(&used_b)
            .filter(|u| !u.1)
            .map(|(x, _)| alone(x, false)),
    );
    out.sort_by(|p, q| {
        let k = |r: &Resonance| r.rpm_a.or(r.rpm_b).unwrap_or(0.0);
        k(p).total_cmp(&k(q))
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_interpolation_is_linear_in_rpm_and_gaps_stay_gaps() {
        let pts = vec![(100.0, Some(1.0)), (120.0, Some(3.0)), (140.0, None)];
        let g = speed_grid(95.0, 140.0, 10.0);
        assert_eq!(g, [100.0, 110.0, 120.0, 130.0, 140.0]);
        assert_eq!(
            on_grid(&pts, &g),
            [Some(1.0), Some(2.0), Some(3.0), None, None]
        );
        assert!(speed_grid(200.0, 100.0, 10.0).is_empty());
        assert!(speed_grid(f64::NAN, 100.0, 10.0).is_empty());
    }

    #[test]
    fn ranges_floor_and_factor() {
        let g = [300.0, 390.0, 400.0, 500.0];
        let db = [Some(1.0), Some(-3.0), None, Some(2.0)];
        let r = ranges(&g, &db, &[400.0, 800.0]);
        assert_eq!(r.len(), 2);
        assert_eq!(
            (r[0].points, r[0].max_db, r[0].max_rpm),
            (2, Some(-3.0), Some(390.0))
        );
        assert!((r[0].rms_db.unwrap() - 5f64.sqrt()).abs() < 1e-12);
        assert_eq!(
            (r[1].from_rpm, r[1].to_rpm, r[1].points),
            (400.0, Some(800.0), 1)
        );
        // 20 log10(2) everywhere: the factor halves B.
        let f = calibration_factor(&[Some(20.0 * 2f64.log10()); 3]).unwrap();
        assert!((f - 0.5).abs() < 1e-12);
        assert_eq!(calibration_factor(&[None]), None);
        // Below -20 dB of its own peak a point is not compared.
        let d = db_over_speed(&[Some(1.0), Some(0.05)], &[Some(1.0), Some(0.05)]);
        assert_eq!(d, [Some(0.0), None]);
    }

    #[test]
    fn a_parabola_peak_is_found_between_the_points() {
        // ln a = -(r - 503)^2 / 2000 sampled every 20 rpm: a prominent maximum at 503 rpm.
        let pts: SpeedPoints = (0..40)
            .map(|k| {
                let r = 100.0 + 20.0 * k as f64;
                (r, Some((-(r - 503.0).powi(2) / 2000.0).exp()))
            })
            .collect();
        let found = resonances(&pts);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!((found[0].0 - 503.0).abs() < 1e-6, "{found:?}");
        let p = pair_resonances(&found, &[(520.0, 1.0), (900.0, 0.5)]);
        assert_eq!(p.len(), 2);
        assert!((p[0].diff_rpm.unwrap() - 17.0).abs() < 1e-6);
        assert_eq!((p[1].rpm_a, p[1].rpm_b), (None, Some(900.0)));
    }
}
