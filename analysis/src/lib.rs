//! Run-up analysis: order plots, cascades and speed plots from sensor signals.
//!
//! A washing machine is judged by its vibration over a stationary run-up of the
//! drum (Wagner & Pfeiffer, DETC99): each channel is cut into Hann-windowed blocks,
//! each block's spectrum is tagged with its mean drum speed, and frequency becomes
//! drum order `f / (rpm/60)`. Motor orders sit at `motor_ratio * n` drum orders.
//!
//! Entry points: [`analyse_file`] (Parquet or CSV in, files out) and [`analyse_signals`]
//! (in-memory signals from the simulator). For every channel they write
//! `<channel>_order`, `<channel>_cascade` and `<channel>_speed` plots (PNG, and SVG unless
//! turned off), plus `displacements_speed` if there are displacement channels; the spectra
//! and order tracks of all channels go to one table each (`spectra`, `orders`: see
//! [`export`]). The result files themselves (`results`: Parquet/CSV writers and readers, the
//! sensor, state and energy recorders) are here too: the analysis reads and writes them, and the
//! energy table draws with the plots. [`study`] analyses many runs at once: designs of variant
//! studies, Sobol indices, Pareto fronts and their plots.
//! [`tacho`] turns a test rig's tacho pulse channel into the drum's angle and speed.

pub mod angle;
pub mod error;
pub mod export;
pub mod metrics;
pub mod options;
pub mod orders;
pub mod plot;
pub mod results;
pub mod signals;
pub mod spectrum;
pub mod study;
pub mod tacho;
/// Measured time histories from test rigs: Universal File Format dataset 58 and 58b, read
/// into SI channels (issue 51).
pub mod uff58;

use std::fmt;
use std::path::{Path, PathBuf};

pub use error::AnalysisError;
pub use options::{AnalysisOptions, ColourScale, MIN_BLOCK_LENGTH_S};
pub use orders::{Block, BlockLayout, OrderTrack, RunUp};
pub use signals::{Channel, Quantity, Signals, parse_signals, read_signals};
pub use spectrum::{Spectrum, SpectrumAnalyzer, Window};

/// Largest amplitude of one tracked order over the run-up.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderMax {
    /// Drum order.
    pub order: f64,
    /// Legend label (`order 1`, `motor order 1 (= 11.25)`).
    pub label: String,
    /// Largest peak amplitude in SI units (`None` if the order was never resolved).
    pub max_amplitude: Option<f64>,
    /// Drum speed (rpm) of the block with the largest amplitude.
    pub rpm_at_max: Option<f64>,
}

/// Summary of one channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelReport {
    /// Channel name.
    pub name: String,
    /// Quantity (decides the unit).
    pub quantity: Quantity,
    /// Maximum per tracked order.
    pub orders: Vec<OrderMax>,
}

/// What [`analyse_file`] / [`analyse_signals`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisReport {
    /// Every file written, in writing order.
    pub files: Vec<PathBuf>,
    /// Per-channel maxima of the tracked orders.
    pub channels: Vec<ChannelReport>,
    /// Block geometry used.
    pub layout: BlockLayout,
    /// Number of blocks per channel.
    pub blocks: usize,
    /// Wall time, s: resampling to drum angle; spectra, order tracks and plots; tables.
    pub wall_s: [f64; 3],
}

impl fmt::Display for AnalysisReport {
    /// Table for the CLI: channel, order, max amplitude with unit, speed at max.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} blocks of {} samples ({:.3} s, df = {:.3} Hz), {} files written; wall time: \
             resampling {:.2} s, spectra, tracks and plots {:.2} s, tables {:.2} s",
            self.blocks,
            self.layout.len,
            self.layout.len as f64 / self.layout.sample_rate,
            self.layout.df(),
            self.files.len(),
            self.wall_s[0],
            self.wall_s[1],
            self.wall_s[2]
        )?;
        for c in &self.channels {
            writeln!(f, "{} [{}]", c.name, c.quantity.si_unit())?;
            for o in &c.orders {
                match (o.max_amplitude, o.rpm_at_max) {
                    (Some(a), Some(r)) => {
                        writeln!(f, "  {:<28} max {a:.4e} at {r:.0} rpm", o.label)?
                    }
                    _ => writeln!(f, "  {:<28} (never resolved)", o.label)?,
                }
            }
        }
        Ok(())
    }
}

/// Read `csv_path` and analyse every channel into `out_dir` (created if missing).
pub fn analyse_file(
    csv_path: impl AsRef<Path>,
    out_dir: impl AsRef<Path>,
    opts: &AnalysisOptions,
) -> Result<AnalysisReport, AnalysisError> {
    opts.validate()?;
    let signals = read_signals(csv_path)?;
    analyse_signals(&signals, out_dir, opts)
}

/// Analyse in-memory signals (e.g. straight from the simulator) into `out_dir`.
pub fn analyse_signals(
    signals: &Signals,
    out_dir: impl AsRef<Path>,
    opts: &AnalysisOptions,
) -> Result<AnalysisReport, AnalysisError> {
    opts.validate()?;
    signals.validate()?;
    let out_dir = out_dir.as_ref();
    std::fs::create_dir_all(out_dir).map_err(|source| AnalysisError::Write {
        path: out_dir.to_path_buf(),
        source,
    })?;
    let layout = BlockLayout::new(opts, signals.sample_rate)?;
    let stems = unique_stems(signals.channels.iter().map(|c| c.name.as_str()));

    // Channels are independent: spread them over the cores (plot encoding dominates).
    use rayon::prelude::*;
    let clock = std::time::Instant::now();
    let mut wall_s = [0.0; 3];
    // One drum-angle grid and one resampling pass for every channel's order tracks.
    let grid = angle::AngleGrid::new(&signals.drum_rpm, signals.sample_rate, opts.samples_per_rev);
    let xs: Vec<&[f64]> = signals.channels.iter().map(|c| c.data.as_slice()).collect();
    let resampled = grid.resample_all(&angle::Kernel::new(), &xs);
    wall_s[0] = clock.elapsed().as_secs_f64();
    // Each channel's numbers and plots in one task (no barrier between them), the displacement
    // overview beside them; then the tables of all channels.
    let displacements: Vec<&Channel> = signals
        .channels
        .iter()
        .filter(|c| c.quantity == Quantity::Displacement)
        .collect();
    let (per_channel, overview) = rayon::join(
        || {
            signals
                .channels
                .par_iter()
                .zip(&stems)
                .zip(&resampled)
                .map(|((c, stem), xa)| {
                    let run = RunUp::analyse_resampled(signals, c, opts, &grid, xa)?;
                    let files = plot_channel(signals, c, &run, stem, out_dir, opts)?;
                    Ok((run, files))
                })
                .collect::<Result<Vec<_>, AnalysisError>>()
        },
        || {
            if displacements.is_empty() {
                return Ok(Vec::new());
            }
            plot::displacement_plot(
                signals,
                &displacements,
                opts,
                &out_dir.join(format!("{DISPLACEMENT_OVERVIEW}_speed")),
            )
        },
    );
    drop(resampled);
    let (runs, plots): (Vec<RunUp>, Vec<Vec<PathBuf>>) = per_channel?.into_iter().unzip();
    wall_s[1] = clock.elapsed().as_secs_f64() - wall_s[0];
    let nyquist = signals.sample_rate / 2.0;
    let max_f = opts.max_frequency_hz.unwrap_or(nyquist).min(nyquist);
    let (spectra, orders) = rayon::join(
        || {
            opts.cascades
                .then(|| export::write_spectra(&runs, max_f, out_dir, opts.format))
                .transpose()
        },
        || export::write_orders(&runs, out_dir, opts.format),
    );
    let mut files: Vec<PathBuf> = plots.into_iter().flatten().collect();
    let channels = runs.iter().map(report).collect();
    let blocks = runs.first().map_or(0, |r| r.blocks.len());
    files.extend(spectra?);
    files.push(orders?);
    files.extend(overview?);
    Ok(AnalysisReport {
        files,
        channels,
        layout,
        blocks,
        wall_s,
    })
}

/// Write one channel's plots.
fn plot_channel(
    signals: &Signals,
    channel: &Channel,
    run: &RunUp,
    stem: &str,
    out_dir: &Path,
    opts: &AnalysisOptions,
) -> Result<Vec<PathBuf>, AnalysisError> {
    let mut files = Vec::new();
    files.extend(plot::order_plot(
        run,
        opts,
        &out_dir.join(format!("{stem}_order")),
    )?);
    if opts.cascades {
        files.extend(plot::cascade_plot(
            run,
            opts,
            &out_dir.join(format!("{stem}_cascade")),
        )?);
    }
    files.extend(plot::speed_plot(
        run,
        channel,
        signals,
        opts,
        &out_dir.join(format!("{stem}_speed")),
    )?);
    Ok(files)
}

/// A channel's largest order amplitudes for the report.
fn report(run: &RunUp) -> ChannelReport {
    ChannelReport {
        name: run.channel.clone(),
        quantity: run.quantity,
        orders: run
            .tracks
            .iter()
            .map(|t| {
                let m = t.max(&run.blocks);
                OrderMax {
                    order: t.order,
                    label: t.label.clone(),
                    max_amplitude: m.map(|m| m.0),
                    rpm_at_max: m.map(|m| m.1),
                }
            })
            .collect(),
    }
}

/// Base name of the all-displacements plot; no channel may get it as its stem.
const DISPLACEMENT_OVERVIEW: &str = "displacements";

/// One file stem per channel, unique even where sanitising maps two names to one
/// (`a/b`, `a b`) or a name to the overview's: later ones get `_<column number>`.
pub fn unique_stems<'a>(names: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut seen = std::collections::HashSet::from([DISPLACEMENT_OVERVIEW.to_string()]);
    names
        .enumerate()
        .map(|(i, name)| {
            let mut stem = file_stem(name);
            while !seen.insert(stem.clone()) {
                stem = format!("{stem}_{}", i + 3);
            }
            stem
        })
        .collect()
}

/// File-name-safe version of a channel name (measured files may use `/`, spaces, units).
pub fn file_stem(channel: &str) -> String {
    let s: String = channel
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with('.') {
        format!("ch{s}")
    } else {
        s
    }
}
