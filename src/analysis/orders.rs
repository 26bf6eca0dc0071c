//! Order analysis of a run-up: block spectra tagged with drum speed, order axis,
//! and order tracks extracted from the energy-corrected spectra.

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::signals::{Channel, Quantity, Signals};
use super::spectrum::{Spectrum, SpectrumAnalyzer, Window};

/// Half-width of the Hann main lobe in bins: a stationary sine keeps > 99.9 % of
/// its energy within ±2 bins of its frequency, whatever its offset from the bins.
pub const MAIN_LOBE_HALF_WIDTH_BINS: f64 = 2.0;

/// Block geometry resolved from the options and the sample rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockLayout {
    /// Samples per block.
    pub len: usize,
    /// Samples from one block start to the next.
    pub hop: usize,
    /// Sample rate in Hz.
    pub sample_rate: f64,
}

impl BlockLayout {
    /// Block layout for `opts` at `sample_rate`.
    pub fn new(opts: &AnalysisOptions, sample_rate: f64) -> Result<BlockLayout, AnalysisError> {
        opts.validate()?;
        let len = (opts.block_length_s * sample_rate).round() as usize;
        if len < 16 {
            return Err(AnalysisError::InvalidOptions(format!(
                "block length {} s is only {len} samples at {sample_rate} Hz; need at least 16",
                opts.block_length_s
            )));
        }
        let hop = ((len as f64) * (1.0 - opts.overlap)).round().max(1.0) as usize;
        Ok(BlockLayout {
            len,
            hop,
            sample_rate,
        })
    }

    /// Frequency resolution in Hz.
    pub fn df(&self) -> f64 {
        self.sample_rate / self.len as f64
    }

    /// Start indices of all full blocks in `n` samples.
    pub fn starts(&self, n: usize) -> impl Iterator<Item = usize> + use<> {
        let (len, hop) = (self.len, self.hop);
        (0..)
            .map(move |i| i * hop)
            .take_while(move |s| s + len <= n)
    }
}

/// One analysed block of a channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// Time of the block centre in s.
    pub time_s: f64,
    /// Mean drum speed over the block in rpm.
    pub rpm: f64,
    /// Lowest and highest drum speed within the block in rpm (speed change smears orders).
    pub rpm_min: f64,
    /// See `rpm_min`.
    pub rpm_max: f64,
    /// Spectrum of the block.
    pub spectrum: Spectrum,
}

impl Block {
    /// Drum rotation frequency in Hz.
    pub fn rotation_hz(&self) -> f64 {
        self.rpm / 60.0
    }

    /// Order of bin `k`: `f / (rpm/60)`; infinite at standstill.
    pub fn order_of_bin(&self, k: usize) -> f64 {
        self.spectrum.frequency(k) / self.rotation_hz()
    }

    /// Nearest bin to drum order `order`, `None` above Nyquist or at standstill.
    pub fn bin_of_order(&self, order: f64) -> Option<usize> {
        let f = order * self.rotation_hz();
        let k = (f / self.spectrum.df).round();
        (k.is_finite() && k >= 0.0 && (k as usize) < self.spectrum.amplitude.len())
            .then_some(k as usize)
    }

    /// Peak amplitude of drum order `order` from the energy in its band: main lobe
    /// (±2 bins) widened by the frequency sweep of that order within the block.
    /// `None` if the band reaches beyond Nyquist or the drum stands still. Does not
    /// check whether other orders fall into the band (see [`Block::order_resolved`]).
    pub fn order_amplitude(&self, order: f64) -> Option<f64> {
        let (f, half) = self.order_band(order)?;
        Some(self.spectrum.band_amplitude(f - half, f + half))
    }

    /// Centre frequency and half-width in Hz of the band of `order` (main lobe
    /// widened by the order's frequency sweep within the block); `None` if the band
    /// reaches beyond Nyquist or the drum stands still.
    pub fn order_band(&self, order: f64) -> Option<(f64, f64)> {
        let fr = self.rotation_hz();
        let f = order * fr;
        let half = self.band_half_width(order);
        let nyquist = self.spectrum.frequency(self.spectrum.amplitude.len() - 1);
        (fr > 0.0 && f.is_finite() && f + half <= nyquist).then_some((f, half))
    }

    /// Half-width in Hz of the band of `order`: ±2 bins plus half the sweep.
    pub fn band_half_width(&self, order: f64) -> f64 {
        let sweep = order.abs() * (self.rpm_max - self.rpm_min) / 60.0;
        MAIN_LOBE_HALF_WIDTH_BINS * self.spectrum.df + 0.5 * sweep
    }

    /// True if the band of `order` is clear of the bands of every order in
    /// `neighbours` (DC counts as order 0), so its energy is its own.
    pub fn order_resolved(&self, order: f64, neighbours: &[f64]) -> bool {
        let fr = self.rotation_hz();
        let h = self.band_half_width(order);
        neighbours
            .iter()
            .filter(|&&n| (n - order).abs() > 1e-9)
            .all(|&n| (order - n).abs() * fr >= h + self.band_half_width(n))
    }
}

/// Orders whose bands a tracked order must stay clear of: DC, the other tracked
/// orders, and for integer (drum harmonic) orders the adjacent harmonics, which a
/// real drum always has to some degree.
pub fn neighbour_orders(tracked: &[f64]) -> Vec<f64> {
    let mut v = vec![0.0];
    for &o in tracked {
        v.push(o);
        if (o - o.round()).abs() < 1e-9 {
            v.push(o - 1.0);
            v.push(o + 1.0);
        }
    }
    v.retain(|o| *o >= 0.0);
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

/// Amplitude of one order over the run-up (one value per block, `None` below the
/// minimum speed, above Nyquist, or where its band would take in a neighbouring
/// order, see [`neighbour_orders`]).
#[derive(Debug, Clone, PartialEq)]
pub struct OrderTrack {
    /// Drum order.
    pub order: f64,
    /// Label for legends, e.g. `order 1` or `motor order 1 (11.25)`.
    pub label: String,
    /// Peak amplitude per block.
    pub amplitude: Vec<Option<f64>>,
}

impl OrderTrack {
    /// Largest amplitude and the drum speed (rpm) of the block where it occurs.
    pub fn max(&self, blocks: &[Block]) -> Option<(f64, f64)> {
        self.amplitude
            .iter()
            .zip(blocks)
            .filter_map(|(a, b)| a.map(|a| (a, b.rpm)))
            .fold(None, |best: Option<(f64, f64)>, (a, r)| match best {
                Some((ba, _)) if ba >= a => best,
                _ => Some((a, r)),
            })
    }
}

/// Order analysis of one channel over a run-up.
#[derive(Debug, Clone, PartialEq)]
pub struct RunUp {
    /// Channel name.
    pub channel: String,
    /// Channel quantity (units).
    pub quantity: Quantity,
    /// Block geometry.
    pub layout: BlockLayout,
    /// All full blocks in time order.
    pub blocks: Vec<Block>,
    /// Order tracks for [`AnalysisOptions::tracked_orders`].
    pub tracks: Vec<OrderTrack>,
    /// Blocks below this speed (rpm) have no order axis and are left out of order views.
    pub min_rpm: f64,
}

impl RunUp {
    /// Analyse channel `channel` of `signals`.
    pub fn analyse(
        signals: &Signals,
        channel: &Channel,
        opts: &AnalysisOptions,
    ) -> Result<RunUp, AnalysisError> {
        let layout = BlockLayout::new(opts, signals.sample_rate)?;
        let n = signals.len();
        if n < layout.len {
            return Err(AnalysisError::TooFewSamples {
                context: format!(
                    "channel `{}` ({} s blocks at {:.6} Hz)",
                    channel.name, opts.block_length_s, signals.sample_rate
                ),
                found: n,
                needed: layout.len,
            });
        }
        let mut analyzer = SpectrumAnalyzer::new(Window::hann(layout.len), signals.sample_rate);
        let blocks: Vec<Block> = layout
            .starts(n)
            .map(|s| {
                let rpm = &signals.drum_rpm[s..s + layout.len];
                let mean = rpm.iter().sum::<f64>() / rpm.len() as f64;
                let (lo, hi) = rpm
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &r| {
                        (lo.min(r), hi.max(r))
                    });
                Block {
                    time_s: signals.time[s] + 0.5 * (layout.len - 1) as f64 / signals.sample_rate,
                    rpm: mean,
                    rpm_min: lo,
                    rpm_max: hi,
                    spectrum: analyzer.spectrum(&channel.data[s..s + layout.len], opts.remove_mean),
                }
            })
            .collect();
        let tracked = opts.tracked_orders();
        let neighbours = neighbour_orders(&tracked.iter().map(|(o, _)| *o).collect::<Vec<_>>());
        let tracks = tracked
            .into_iter()
            .map(|(order, label)| OrderTrack {
                order,
                label,
                amplitude: blocks
                    .iter()
                    .map(|b| {
                        if b.rpm < opts.min_rpm || !b.order_resolved(order, &neighbours) {
                            None
                        } else {
                            b.order_amplitude(order)
                        }
                    })
                    .collect(),
            })
            .collect();
        Ok(RunUp {
            channel: channel.name.clone(),
            quantity: channel.quantity,
            layout,
            blocks,
            tracks,
            min_rpm: opts.min_rpm,
        })
    }

    /// Blocks fast enough to have a meaningful order axis.
    pub fn order_blocks(&self) -> impl Iterator<Item = &Block> {
        self.blocks.iter().filter(move |b| b.rpm >= self.min_rpm)
    }

    /// Largest amplitude-corrected spectral value over all blocks.
    pub fn max_amplitude(&self) -> f64 {
        self.blocks
            .iter()
            .flat_map(|b| b.spectrum.amplitude.iter().skip(1))
            .fold(0.0, |m, &a| m.max(a))
    }
}
