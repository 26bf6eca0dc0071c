//! `washdyn compare RUN MEASUREMENT` and `washdyn compare --over-speed RUN_A RUN_B`: a
//! simulated run against a measurement (or two runs of different speed profiles) at equal
//! drum speed, as Wagner & Pfeiffer set measured and simulated order plots side by side
//! (Figures 10 and 13). The arithmetic is in `speed.rs`; this file reads, analyses (each side
//! on its own angle grid, the same options for both, as [`super::compare`] does), plots and
//! writes the report (`speed_report.rs`).
//!
//! A (the run) is the reference: dB = 20 log10(B / A), B the measurement. The calibration
//! factor multiplies B (the paper corrected the measured magnitudes by a constant factor); it
//! is always computed and reported, and applied only with `calibrate`.

use crate::analysis::angle::{AngleGrid, Kernel};
use crate::analysis::{AnalysisError, AnalysisOptions, RunUp, Signals, plot, unique_stems};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use super::runs::{Cost, load, load_measured};
use super::speed::{
    LEVEL_FLOOR_DB, RESONANCE_PROMINENCE_DB, Resonance, SPEED_STEP_RPM, SpeedRange,
    calibration_factor, db_over_speed, on_grid, pair_resonances, ranges, resolved_span, resonances,
    speed_grid, track_points,
};
use super::{CompareError, options};

/// What the comparison over speed is asked to do.
#[derive(Debug, Clone)]
pub struct SpeedArgs {
    /// A: a run's directory (the simulation; the reference of the differences).
    pub run: PathBuf,
    /// B: a measured signal file (CSV or Parquet), or another run's directory.
    pub other: PathBuf,
    /// Names of A and B in tables and plots.
    pub labels: [String; 2],
    pub out: PathBuf,
    /// Motor speed / drum speed (the motor order tracked).
    pub motor_ratio: f64,
    /// Also write the plots as SVG.
    pub svg: bool,
    /// Multiply B by its calibration factor before comparing (the factor is reported either
    /// way).
    pub calibrate: bool,
    /// Edges of the speed ranges, rpm (positive, increasing).
    pub range_edges: Vec<f64>,
}

/// One tracked order of one channel over the common speed grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrderOverSpeed {
    pub order: f64,
    pub label: String,
    /// Largest value on the grid in A and B (SI units; B calibrated where asked).
    pub peak_a: Option<f64>,
    pub peak_b: Option<f64>,
    /// 20 log10(B / A) per speed range.
    pub ranges: Vec<SpeedRange>,
}

/// The constant factor on B that brings its order 1 to A's (see
/// [`calibration_factor`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// The factor, and 20 log10 of it in dB; `None`: order 1 compared nowhere.
    pub factor: Option<f64>,
    pub factor_db: Option<f64>,
    /// Grid points of order 1 it was computed over.
    pub points: usize,
    /// Whether B was multiplied by it (`--calibrate`).
    pub applied: bool,
}

/// One channel of both sides over speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelOverSpeed {
    pub channel: String,
    pub unit: String,
    /// The common grid: from the larger of the two sides' lowest resolved order-1 speeds to
    /// the smaller of their highest, every [`SPEED_STEP_RPM`], rpm.
    pub from_rpm: f64,
    pub to_rpm: f64,
    pub calibration: Calibration,
    pub orders: Vec<OrderOverSpeed>,
    /// Order 1's resonances, paired.
    pub resonances: Vec<Resonance>,
}

/// Both sides analysed and compared over speed; `runs` holds each compared channel's two
/// analyses (B calibrated where asked), for the plots.
#[derive(Debug, Clone)]
pub struct OverSpeed {
    pub channels: Vec<ChannelOverSpeed>,
    pub runs: Vec<[RunUp; 2]>,
    /// Channels of one side only (not compared).
    pub only_a: Vec<String>,
    pub only_b: Vec<String>,
    /// Channels zero throughout on both sides (not compared).
    pub zero_in_both: Vec<String>,
}

/// One side of the comparison (compare.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedSource {
    pub label: String,
    pub path: String,
    /// `run` or `measurement`.
    pub kind: String,
    pub samples: usize,
    pub sample_rate_hz: f64,
    pub t_start_s: f64,
    pub t_end_s: f64,
    /// Drum speed range over the signal, rpm.
    pub rpm_min: f64,
    pub rpm_max: f64,
    /// A run's cost (its summary.json).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost: Option<Cost>,
}

/// The whole comparison over speed (compare.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedComparison {
    /// A (the reference) and B.
    pub sources: [SpeedSource; 2],
    pub grid_step_rpm: f64,
    /// Grid points are compared where both are within this of their own peak, dB.
    pub floor_db: f64,
    /// Prominence of a resonance, dB.
    pub prominence_db: f64,
    pub order_block_revs: usize,
    pub samples_per_rev: usize,
    pub range_edges_rpm: Vec<f64>,
    pub calibrate: bool,
    pub channels: Vec<ChannelOverSpeed>,
    pub only_a: Vec<String>,
    pub only_b: Vec<String>,
    pub zero_in_both: Vec<String>,
}

/// Refuse edges that are not positive, finite and increasing.
pub fn check_edges(edges: &[f64]) -> Result<(), CompareError> {
    let ok = edges.iter().all(|e| e.is_finite() && *e > 0.0) && edges.is_sorted_by(|a, b| a < b);
    ok.then_some(()).ok_or_else(|| CompareError::SpeedRanges {
        edges: edges.to_vec(),
    })
}

/// Multiply a channel's analysis by `f` (spectra and tracks are linear in the signal).
fn scaled(run: &RunUp, f: f64) -> RunUp {
    let mut r = run.clone();
    for t in &mut r.tracks {
        t.amplitude.iter_mut().flatten().for_each(|v| *v *= f);
    }
    for s in r.order_spectra.iter_mut().flatten() {
        s.iter_mut().for_each(|v| *v *= f);
    }
    for b in &mut r.blocks {
        b.spectrum.amplitude.iter_mut().for_each(|v| *v *= f);
        b.spectrum.energy.iter_mut().for_each(|v| *v *= f);
    }
    r
}

/// Compare one channel's two analyses over speed; `names` name the sides in errors. Returns
/// the comparison and B's analysis calibrated where asked.
fn channel_over_speed(
    ra: &RunUp,
    rb: &RunUp,
    calibrate: bool,
    edges: &[f64],
    names: [&Path; 2],
) -> Result<(ChannelOverSpeed, RunUp), CompareError> {
    let one = ra.tracks.iter().position(|t| t.order == 1.0).unwrap_or(0);
    let (pa, pb) = (track_points(ra, one), track_points(rb, one));
    let none = [f64::NAN; 2];
    let (sa, sb) = (resolved_span(&pa), resolved_span(&pb));
    let grid = match (sa, sb) {
        (Some(a), Some(b)) => speed_grid(a.0.max(b.0), a.1.min(b.1), SPEED_STEP_RPM),
        _ => Vec::new(),
    };
    if grid.is_empty() {
        return Err(CompareError::NoCommonSpeed {
            a: names[0].to_path_buf(),
            b: names[1].to_path_buf(),
            span_a: sa.map_or(none, |s| [s.0, s.1]),
            span_b: sb.map_or(none, |s| [s.0, s.1]),
        });
    }
    let db1 = db_over_speed(&on_grid(&pa, &grid), &on_grid(&pb, &grid));
    let factor = calibration_factor(&db1);
    let f = if calibrate {
        factor.unwrap_or(1.0)
    } else {
        1.0
    };
    let rb = if f == 1.0 { rb.clone() } else { scaled(rb, f) };
    let orders = (0..ra.tracks.len().min(rb.tracks.len()))
        .map(|t| {
            let ga = on_grid(&track_points(ra, t), &grid);
            let gb = on_grid(&track_points(&rb, t), &grid);
            let top = |g: &[Option<f64>]| g.iter().flatten().copied().reduce(f64::max);
            OrderOverSpeed {
                order: ra.tracks[t].order,
                label: ra.tracks[t].label.clone(),
                peak_a: top(&ga),
                peak_b: top(&gb),
                ranges: ranges(&grid, &db_over_speed(&ga, &gb), edges),
            }
        })
        .collect();
    let res = pair_resonances(&resonances(&pa), &resonances(&track_points(&rb, one)));
    let c = ChannelOverSpeed {
        channel: ra.channel.clone(),
        unit: ra.quantity.si_unit().to_string(),
        from_rpm: grid[0],
        to_rpm: grid[grid.len() - 1],
        calibration: Calibration {
            factor,
            factor_db: factor.map(|f| 20.0 * f.log10()),
            points: db1.iter().flatten().count(),
            applied: calibrate && factor.is_some(),
        },
        orders,
        resonances: res,
    };
    Ok((c, rb))
}

/// Compare two signal sets over speed: the channels both record (by name), each side on its own
/// angle grid with the same `opts`, tracks put on a common speed grid. `names` name the sides
/// in errors.
pub fn compare_signals_over_speed(
    a: &Signals,
    b: &Signals,
    opts: &AnalysisOptions,
    calibrate: bool,
    edges: &[f64],
    names: [&Path; 2],
) -> Result<OverSpeed, CompareError> {
    check_edges(edges)?;
    let (mut pairs, mut zero_in_both, mut only_a) = (Vec::new(), Vec::new(), Vec::new());
    for c in &a.channels {
        match b.channel(&c.name) {
            None => only_a.push(c.name.clone()),
            Some(o) if c.data.iter().chain(&o.data).all(|v| *v == 0.0) => {
                zero_in_both.push(c.name.clone())
            }
            Some(o) => pairs.push((c, o)),
        }
    }
    let only_b: Vec<String> = b
        .channels
        .iter()
        .filter(|c| a.channel(&c.name).is_none())
        .map(|c| c.name.clone())
        .collect();
    if pairs.is_empty() && zero_in_both.is_empty() {
        return Err(CompareError::Channels {
            a: names[0].to_path_buf(),
            b: names[1].to_path_buf(),
            only_a,
            only_b,
        });
    }
    let kernel = Kernel::new();
    let resample = |s: &Signals, side: usize| {
        let g = AngleGrid::new(&s.drum_rpm, s.sample_rate, opts.samples_per_rev);
        let data: Vec<&[f64]> = pairs
            .iter()
            .map(|p| if side == 0 { p.0 } else { p.1 }.data.as_slice())
            .collect();
        let x = g.resample_all(&kernel, &data);
        (g, x)
    };
    let ((ga, xa), (gb, xb)) = (resample(a, 0), resample(b, 1));
    use rayon::prelude::*;
    let done = pairs
        .par_iter()
        .zip(xa.par_iter().zip(&xb))
        .map(|((ca, cb), (ya, yb))| {
            let ra = RunUp::analyse_resampled(a, ca, opts, &ga, ya)?;
            let rb = RunUp::analyse_resampled(b, cb, opts, &gb, yb)?;
            let (c, rb) = channel_over_speed(&ra, &rb, calibrate, edges, names)?;
            Ok((c, [ra, rb]))
        })
        .collect::<Result<Vec<_>, CompareError>>()?;
    let (channels, runs) = done.into_iter().unzip();
    Ok(OverSpeed {
        channels,
        runs,
        only_a,
        only_b,
        zero_in_both,
    })
}

/// A side's description for the report.
fn source(s: &Signals, label: &str, path: &Path, cost: Option<Cost>) -> SpeedSource {
    let (lo, hi) = s
        .drum_rpm
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |m, r| {
            (m.0.min(*r), m.1.max(*r))
        });
    SpeedSource {
        label: label.to_string(),
        path: path.display().to_string(),
        kind: if cost.is_some() { "run" } else { "measurement" }.into(),
        samples: s.len(),
        sample_rate_hz: s.sample_rate,
        t_start_s: s.time[0],
        t_end_s: s.time[s.len() - 1],
        rpm_min: lo,
        rpm_max: hi,
        cost,
    }
}

/// The orders of a channel's overlay plot: order 1 and the three others with the largest peak
/// on the grid on either side.
fn overlay_orders(c: &ChannelOverSpeed) -> Vec<f64> {
    let mut others: Vec<(f64, f64)> = c
        .orders
        .iter()
        .filter(|o| o.order != 1.0)
        .map(|o| {
            (
                o.order,
                o.peak_a.unwrap_or(0.0).max(o.peak_b.unwrap_or(0.0)),
            )
        })
        .filter(|o| o.1 > 0.0)
        .collect();
    others.sort_by(|x, y| y.1.total_cmp(&x.1));
    std::iter::once(1.0)
        .chain(others.iter().take(3).map(|o| o.0))
        .collect()
}

/// Per channel the two order plots side by side on one colour scale over drum speed (B, the
/// measurement, left as in the paper's Figure 10) and the tracks overlaid over speed (B solid,
/// A dashed); B's label carries the calibration factor where it was applied.
fn plots(
    o: &OverSpeed,
    labels: &[String; 2],
    opts: &AnalysisOptions,
    out: &Path,
) -> Result<Vec<PathBuf>, AnalysisError> {
    let stems = unique_stems(o.channels.iter().map(|c| c.channel.as_str()));
    let mut files = Vec::new();
    for ((c, [ra, rb]), stem) in o.channels.iter().zip(&o.runs).zip(&stems) {
        let label_b = match c.calibration.factor {
            Some(f) if c.calibration.applied => format!("{} x {f:.4}", labels[1]),
            _ => labels[1].clone(),
        };
        let pair = [label_b.as_str(), labels[0].as_str()];
        let base = out.join(format!("{stem}_order_compare"));
        files.extend(plot::order_plot_pair([rb, ra], pair, opts, &base)?);
        let base = out.join(format!("{stem}_tracks_compare"));
        files.extend(plot::track_overlay_plot(
            [rb, ra],
            pair,
            &overlay_orders(c),
            opts,
            &base,
        )?);
    }
    Ok(files)
}

/// Compare over speed: read A (a run) and B (a measurement file, or a run's directory), analyse
/// both with the same options, write the report and plots into `args.out`.
pub fn compare_over_speed(
    args: &SpeedArgs,
) -> Result<(SpeedComparison, Vec<PathBuf>), CompareError> {
    check_edges(&args.range_edges)?;
    let (sa, ca) = load(&args.run, &args.labels[0])?;
    let (sb, cb) = if args.other.is_dir() {
        let (s, c) = load(&args.other, &args.labels[1])?;
        (s, Some(c))
    } else {
        (load_measured(&args.other)?, None)
    };
    let defaults = options(args.motor_ratio, args.svg);
    defaults.validate()?;
    // The shorter side sets a block shorter than the default (one block over all of it).
    let shorter = if sa.len() as f64 / sa.sample_rate <= sb.len() as f64 / sb.sample_rate {
        &sa
    } else {
        &sb
    };
    let opts = defaults.fit_to(shorter.len(), shorter.sample_rate)?;
    let names = [args.run.as_path(), args.other.as_path()];
    let o = compare_signals_over_speed(&sa, &sb, &opts, args.calibrate, &args.range_edges, names)?;
    std::fs::create_dir_all(&args.out).map_err(|e| CompareError::Write {
        path: args.out.clone(),
        message: e.to_string(),
    })?;
    let c = SpeedComparison {
        sources: [
            source(&sa, &args.labels[0], &args.run, Some(ca)),
            source(&sb, &args.labels[1], &args.other, cb),
        ],
        grid_step_rpm: SPEED_STEP_RPM,
        floor_db: LEVEL_FLOOR_DB,
        prominence_db: RESONANCE_PROMINENCE_DB,
        order_block_revs: opts.order_block_revs,
        samples_per_rev: opts.samples_per_rev,
        range_edges_rpm: args.range_edges.clone(),
        calibrate: args.calibrate,
        channels: o.channels.clone(),
        only_a: o.only_a.clone(),
        only_b: o.only_b.clone(),
        zero_in_both: o.zero_in_both.clone(),
    };
    let mut files = super::speed_report::write(&c, &args.out)?;
    files.extend(plots(&o, &args.labels, &opts, &args.out)?);
    Ok((c, files))
}
