//! `washdyn compare RUN_A RUN_B`: two finished runs of the same speed profile side by side
//! (issue 21: what a model change, e.g. the friction dampers' moving parts, does to the order
//! plots, and what each run cost).
//!
//! Both runs' sensor files are read with the analysis' reader ([`read_signals`]); channels are
//! matched by name, and runs whose channel sets, sample rates or speed profiles differ beyond
//! round-off are refused. Every channel that is not zero in both runs goes through the same
//! order analysis as `washdyn analyse` ([`RunUp`] on one [`AngleGrid`] per run, the same
//! options for both); per channel and tracked order the report gives each run's peak over the
//! run with its speed, the difference of the peaks in dB, and the largest difference along the
//! track ([`crate::analysis::metrics::track_error`], the accuracy study's -40 dB floor), and per
//! acceleration channel the RMS difference relative to A ([`crate::analysis::metrics::relative_rms`]).
//! A is the reference: dB = 20 log10(B / A).
//!
//! [`read_signals`]: crate::analysis::read_signals
//!
//! Writes `compare.md`, `compare.json` and per channel `<channel>_order_compare.png` (the two
//! order plots on one colour scale) and `<channel>_tracks_compare.png` (order 1 and the largest
//! other orders, A solid, B dashed).
//!
//! This file holds the comparison itself (the options, the channels analysed and compared, the
//! plots); the runs' input (`runs.rs`: reading a run directory, its cost, whether two runs can be
//! compared) and the report (`report.rs`: compare.md and compare.json) have a file each.
//!
//! Runs of different speed profiles, or a run and a measurement, are compared at equal drum
//! speed instead ([`compare_over_speed`]: `over_speed.rs`, its arithmetic in [`speed`], its
//! report in `speed_report.rs`).

use crate::analysis::angle::{AngleGrid, Kernel};
use crate::analysis::metrics::{
    BAND_HZ, ORDER_FLOOR, STRONG_FLOOR, band_error, relative_rms, track_error, track_error_above,
};
use crate::analysis::{
    AnalysisError, AnalysisOptions, Quantity, RunUp, Signals, plot, unique_stems,
};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

mod over_speed;
mod report;
mod runs;
pub mod speed;
mod speed_report;

pub use over_speed::{
    Calibration, ChannelOverSpeed, OrderOverSpeed, OverSpeed, SpeedArgs, SpeedComparison,
    SpeedSource, check_edges, compare_over_speed, compare_signals_over_speed,
};
use report::write;
pub use report::{cost_table, markdown};
pub use runs::{Cost, check_comparable, load, load_measured, load_pair};
use washdyn_ode::Rounded;

/// Drum orders the comparison tracks (the friction dampers' odd harmonics lie among them); the
/// motor's first order is tracked beside them.
pub const DRUM_ORDERS: [f64; 6] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
/// Relative difference of the sample rates, and of the drum speeds against the top speed,
/// beyond which two runs are not the same profile (round-off of a CSV's printed digits stays
/// far below it).
pub const PROFILE_TOLERANCE: f64 = 1e-6;
/// Orders drawn in a channel's track overlay besides order 1: the largest others.
const OVERLAY_OTHERS: usize = 3;

/// What `washdyn compare` is asked to do.
#[derive(Debug, Clone)]
pub struct CompareArgs {
    /// The runs' directories (written by `washdyn run`): A is the reference of the differences.
    pub runs: [PathBuf; 2],
    /// Names of the runs in tables and plots.
    pub labels: [String; 2],
    /// Output directory.
    pub out: PathBuf,
    /// Motor speed / drum speed (the motor order tracked).
    pub motor_ratio: f64,
    /// Also write the plots as SVG.
    pub svg: bool,
    /// Compare up to this time only, s: the common span of a run that stopped early (or was
    /// cut short on purpose) and a longer one. Both runs must reach it. The cost table stays
    /// each whole run's (its summary.json).
    pub until: Option<f64>,
}

pub use crate::error::compare::CompareError;

/// One tracked order of one channel in both runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrderComparison {
    /// Drum order.
    pub order: f64,
    /// `order 1`, `motor order 1 (= 11.25)`.
    pub label: String,
    /// Largest track value over the run in A (SI units), `None` where never resolved.
    pub peak_a: Option<f64>,
    /// Drum speed of A's peak, rpm.
    pub rpm_a: Option<f64>,
    pub peak_b: Option<f64>,
    pub rpm_b: Option<f64>,
    /// 20 log10(peak B / peak A), where both are positive.
    pub db: Option<f64>,
    /// 20 log10(B / A) at the block of the track where its magnitude is largest, over the
    /// blocks where both tracks are at least [`ORDER_FLOOR`] of their own peak.
    pub worst_db: Option<f64>,
    /// Drum speed of that block, rpm.
    pub worst_rpm: Option<f64>,
    /// The same over the strong part of the track: the blocks where A is at least
    /// [`STRONG_FLOOR`] of its peak (within 20 dB of it).
    pub worst_strong_db: Option<f64>,
}

/// One channel in both runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelComparison {
    pub channel: String,
    /// SI unit of the peaks and RMS values.
    pub unit: String,
    /// RMS over the run in A and B.
    pub rms_a: f64,
    pub rms_b: f64,
    /// RMS(B - A) / RMS(A) (acceleration channels; `None` where A is zero).
    pub rms_diff: Option<f64>,
    /// The same in the analysis band to [`BAND_HZ`] ([`band_error`]: the Hann-windowed spectra
    /// of the whole run): a model with modes above the band differs there by content no order
    /// plot shows.
    pub band_diff: Option<f64>,
    pub orders: Vec<OrderComparison>,
}

/// The whole comparison (compare.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// The two runs and what they cost, A first.
    pub runs: [Cost; 2],
    pub samples: usize,
    pub sample_rate_hz: f64,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub max_rpm: f64,
    /// The analysis: revolutions per order block, angle samples per revolution.
    pub order_block_revs: usize,
    pub samples_per_rev: usize,
    /// Fraction of its own peak below which a track's blocks are not compared (-40 dB).
    pub floor: f64,
    pub channels: Vec<ChannelComparison>,
    /// Channels that are zero throughout in both runs (a fixed cabinet's): not analysed.
    pub zero_in_both: Vec<String>,
    /// What was fitted to a span shorter than the analysis' block (one shorter block).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The analysis settings both runs are analysed with: `washdyn analyse`'s defaults, tracking
/// drum orders 1-6 and motor order 1, without time spectra (the comparison uses none).
pub fn options(motor_ratio: f64, svg: bool) -> AnalysisOptions {
    AnalysisOptions {
        track_orders: DRUM_ORDERS.to_vec(),
        motor_orders: 1,
        motor_ratio,
        cascades: false,
        svg,
        ..AnalysisOptions::default()
    }
}

/// 20 log10(b / a) where both are positive.
fn db(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) if a > 0.0 && b > 0.0 => Some(20.0 * (b / a).log10()),
        _ => None,
    }
}

/// The comparison of two analysed channels (the same options, so the same tracks in order),
/// their samples `xa` and `xb` taken at `fs` Hz.
pub fn compare_channel(
    ra: &RunUp,
    rb: &RunUp,
    xa: &[f64],
    xb: &[f64],
    fs: f64,
) -> ChannelComparison {
    let orders = ra
        .tracks
        .iter()
        .zip(&rb.tracks)
        .map(|(ta, tb)| {
            let (ma, mb) = (ta.max(&ra.blocks), tb.max(&rb.blocks));
            // Both above their own floor: B's blocks below its floor are left out here, A's by
            // track_error (A is its reference).
            let floor_b = ORDER_FLOOR * mb.map_or(0.0, |m| m.0);
            let masked: Vec<Option<f64>> = tb
                .amplitude
                .iter()
                .map(|v| v.filter(|v| *v >= floor_b))
                .collect();
            let worst = track_error(&masked, &ta.amplitude);
            let strong = track_error_above(&masked, &ta.amplitude, STRONG_FLOOR);
            OrderComparison {
                order: ta.order,
                label: ta.label.clone(),
                peak_a: ma.map(|m| m.0),
                rpm_a: ma.map(|m| m.1),
                peak_b: mb.map(|m| m.0),
                rpm_b: mb.map(|m| m.1),
                db: db(ma.map(|m| m.0), mb.map(|m| m.0)),
                worst_db: worst.map(|w| w.0),
                worst_rpm: worst.map(|w| ra.blocks[w.1].rpm),
                worst_strong_db: strong.map(|w| w.0),
            }
        })
        .collect();
    let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt();
    let accel = ra.quantity == Quantity::Acceleration;
    ChannelComparison {
        channel: ra.channel.clone(),
        unit: ra.quantity.si_unit().to_string(),
        rms_a: rms(xa),
        rms_b: rms(xb),
        rms_diff: accel.then(|| relative_rms(xb, xa)).flatten(),
        band_diff: accel.then(|| band_error(xb, xa, fs, BAND_HZ)).flatten(),
        orders,
    }
}

/// Orders of a channel's overlay plot: order 1 and the [`OVERLAY_OTHERS`] others with the
/// largest peak in either run.
fn overlay_orders(c: &ChannelComparison) -> Vec<f64> {
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
        .filter(|(_, p)| *p > 0.0)
        .collect();
    others.sort_by(|x, y| y.1.total_cmp(&x.1));
    let mut v = vec![1.0];
    v.extend(others.iter().take(OVERLAY_OTHERS).map(|o| o.0));
    v
}

/// Compare the runs: read, check, analyse both with the same options, write the tables and
/// plots into `args.out`. Returns the comparison and the files written.
pub fn compare(args: &CompareArgs) -> Result<(Comparison, Vec<PathBuf>), CompareError> {
    let ([sa, sb], [ca, cb]) = load_pair(args)?;
    let defaults = options(args.motor_ratio, args.svg);
    defaults.validate()?;
    // A span shorter than a block (`--until 0.5`) is analysed in one block over all of it, down
    // to the analysis' shortest; shorter is refused.
    let opts = defaults.fit_to(sa.len(), sa.sample_rate)?;
    let note = (opts.block_length_s < defaults.block_length_s).then(|| {
        format!(
            "the span compared, {} s, is shorter than the analysis' {} s blocks: both runs are \
             analysed in one block of it",
            Rounded(opts.block_length_s),
            defaults.block_length_s
        )
    });
    // Channels by A's order; a channel zero in both (a fixed cabinet's) has nothing to compare.
    let mut pairs = Vec::new();
    let mut zero_in_both = Vec::new();
    for c in &sa.channels {
        let other = sb.channel(&c.name).expect("the channel sets are equal");
        if c.data.iter().chain(&other.data).all(|v| *v == 0.0) {
            zero_in_both.push(c.name.clone());
        } else {
            pairs.push((c, other));
        }
    }
    std::fs::create_dir_all(&args.out).map_err(|e| CompareError::Write {
        path: args.out.clone(),
        message: e.to_string(),
    })?;
    // One angle grid and one resampling pass per run, as `analyse` does.
    let kernel = Kernel::new();
    let grid = |s: &Signals| AngleGrid::new(&s.drum_rpm, s.sample_rate, opts.samples_per_rev);
    let (ga, gb) = (grid(&sa), grid(&sb));
    let xa = ga.resample_all(
        &kernel,
        &pairs
            .iter()
            .map(|p| p.0.data.as_slice())
            .collect::<Vec<_>>(),
    );
    let xb = gb.resample_all(
        &kernel,
        &pairs
            .iter()
            .map(|p| p.1.data.as_slice())
            .collect::<Vec<_>>(),
    );
    let labels = [args.labels[0].as_str(), args.labels[1].as_str()];
    let stems = unique_stems(pairs.iter().map(|p| p.0.name.as_str()));
    use rayon::prelude::*;
    let per_channel = pairs
        .par_iter()
        .zip(&stems)
        .zip(xa.par_iter().zip(&xb))
        .map(|(((ca_, cb_), stem), (ya, yb))| {
            let ra = RunUp::analyse_resampled(&sa, ca_, &opts, &ga, ya)?;
            let rb = RunUp::analyse_resampled(&sb, cb_, &opts, &gb, yb)?;
            let cmp = compare_channel(&ra, &rb, &ca_.data, &cb_.data, sa.sample_rate);
            let mut files = plot::order_plot_pair(
                [&ra, &rb],
                labels,
                &opts,
                &args.out.join(format!("{stem}_order_compare")),
            )?;
            files.extend(plot::track_overlay_plot(
                [&ra, &rb],
                labels,
                &overlay_orders(&cmp),
                &opts,
                &args.out.join(format!("{stem}_tracks_compare")),
            )?);
            Ok((cmp, files))
        })
        .collect::<Result<Vec<_>, AnalysisError>>()?;
    let (channels, plots): (Vec<_>, Vec<_>) = per_channel.into_iter().unzip();
    let comparison = Comparison {
        runs: [ca, cb],
        samples: sa.len(),
        sample_rate_hz: sa.sample_rate,
        t_start_s: sa.time[0],
        t_end_s: sa.time[sa.len() - 1],
        max_rpm: sa.drum_rpm.iter().fold(0.0f64, |m, r| m.max(r.abs())),
        order_block_revs: opts.order_block_revs,
        samples_per_rev: opts.samples_per_rev,
        floor: ORDER_FLOOR,
        channels,
        zero_in_both,
        note,
    };
    let mut files = write(&comparison, &args.out, &opts)?;
    files.extend(plots.into_iter().flatten());
    Ok((comparison, files))
}
