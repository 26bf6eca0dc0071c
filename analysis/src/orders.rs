//! Order analysis of a run-up: block spectra tagged with drum speed and an order
//! axis (time blocks, for the order plot and the cascade), and order tracks in the angle
//! domain (see [`super::angle`]).
//!
//! Order tracks do not read the block spectra: during a run-up an order sweeps through
//! several bins within one time block, and at low speed neighbouring orders share bins.
//! Instead each channel is resampled to uniform drum angle, and each track value is the
//! Hann-windowed DFT at the order over `order_block_revs` whole revolutions centred on the
//! time block: a component locked to the drum is exactly periodic there, so orders a whole
//! number of bins apart (1 / revolutions each) do not leak into each other.

use std::f64::consts::PI;

use super::angle::{AngleGrid, FLAT_BAND, Kernel, MAX_ORDER_PER_SAMPLE, OrderDft};
use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::signals::{Channel, Quantity, Signals};
use super::spectrum::{Spectrum, SpectrumAnalyzer, Window};

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
    /// Drum revolutions within the block: the inverse of the order resolution of
    /// the order tracks.
    pub revolutions: f64,
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
}

/// Orders a tracked order must be resolved from: DC, the other tracked orders,
/// and for integer (drum harmonic) orders the adjacent harmonics, which a real
/// drum always has to some degree.
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
/// minimum speed, above Nyquist, or where a neighbouring order is too close, see
/// [`OrderTracker::amplitude`] and [`neighbour_orders`]).
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
    /// Angle-domain order spectrum (amplitude-corrected peak, Hann over the order-track
    /// block) of each block of [`RunUp::order_blocks`]; NaN above the orders the block resolves,
    /// `None` where no whole angle block fits.
    pub order_spectra: Vec<Option<Vec<f64>>>,
    /// Bins per drum order of the order spectra (revolutions per block).
    pub order_bins_per_order: f64,
}

impl RunUp {
    /// Analyse channel `channel` of `signals`.
    pub fn analyse(
        signals: &Signals,
        channel: &Channel,
        opts: &AnalysisOptions,
    ) -> Result<RunUp, AnalysisError> {
        let grid = AngleGrid::new(&signals.drum_rpm, signals.sample_rate, opts.samples_per_rev);
        let xa = grid.resample(&Kernel::new(), &channel.data);
        Self::analyse_resampled(signals, channel, opts, &grid, &xa)
    }

    /// [`RunUp::analyse`] with the channel already resampled to drum angle on `grid` (one grid
    /// and one pass for all channels: see [`super::analyse_signals`]).
    pub fn analyse_resampled(
        signals: &Signals,
        channel: &Channel,
        opts: &AnalysisOptions,
        grid: &AngleGrid,
        xa: &[f64],
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
        let starts: Vec<usize> = layout.starts(n).collect();
        let blocks = time_blocks(signals, channel, opts, &layout, &grid.angle, &starts);
        let angle_blocks = angle_blocks(signals, opts, &layout, grid, xa, &starts, &blocks);
        let tracks = order_tracks(signals, opts, &angle_blocks);
        let order_spectra = order_spectra(signals, opts, &angle_blocks, &blocks);
        Ok(RunUp {
            order_spectra,
            order_bins_per_order: opts.order_block_revs as f64,
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

/// The time blocks starting at `starts`: their time, speed range, revolutions (from the drum
/// angle `angle`) and, for the cascades, their spectra.
fn time_blocks(
    signals: &Signals,
    channel: &Channel,
    opts: &AnalysisOptions,
    layout: &BlockLayout,
    angle: &[f64],
    starts: &[usize],
) -> Vec<Block> {
    let mut analyzer = SpectrumAnalyzer::new(Window::hann(layout.len), signals.sample_rate);
    starts
        .iter()
        .map(|&s| {
            let rpm = &signals.drum_rpm[s..s + layout.len];
            // Speeds as magnitudes: a reverse rotation has the same orders.
            let mean = rpm.iter().map(|r| r.abs()).sum::<f64>() / rpm.len() as f64;
            let (lo, hi) = rpm
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &r| {
                    (lo.min(r.abs()), hi.max(r.abs()))
                });
            let span = angle[s + layout.len - 1] - angle[s];
            Block {
                time_s: signals.time[s] + 0.5 * (layout.len - 1) as f64 / signals.sample_rate,
                rpm: mean,
                rpm_min: lo,
                rpm_max: hi,
                revolutions: span / (2.0 * PI) * layout.len as f64 / (layout.len - 1) as f64,
                // Time spectra feed the cascades and the spectra table only.
                spectrum: if opts.cascades {
                    analyzer.spectrum(&channel.data[s..s + layout.len], opts.remove_mean)
                } else {
                    Spectrum {
                        df: signals.sample_rate / layout.len as f64,
                        amplitude: Vec::new(),
                        energy: Vec::new(),
                        block_len: layout.len,
                    }
                },
            }
        })
        .collect()
}

/// Each time block's angle block and its highest drum speed, found once for the tracks and the
/// order spectra: None below the minimum speed or where no whole block fits. The blocks have
/// `order_block_revs` whole revolutions of the angle-resampled channel `xa`, centred on each
/// time block.
fn angle_blocks<'a>(
    signals: &Signals,
    opts: &AnalysisOptions,
    layout: &BlockLayout,
    grid: &AngleGrid,
    xa: &'a [f64],
    starts: &[usize],
    blocks: &[Block],
) -> Vec<Option<(&'a [f64], f64)>> {
    let n = signals.len();
    let nb = opts.order_block_revs * opts.samples_per_rev;
    starts
        .iter()
        .zip(blocks)
        .map(|(&s, b)| {
            if b.rpm < opts.min_rpm {
                return None;
            }
            let centre = s as f64 + 0.5 * (layout.len - 1) as f64;
            let kc = grid.pos.partition_point(|&p| p < centre);
            let k0 = kc.checked_sub(nb / 2)?;
            let block = xa.get(k0..k0 + nb)?;
            let (t0, t1) = (grid.pos[k0] as usize, grid.pos[k0 + nb - 1].ceil() as usize);
            let top = signals.drum_rpm[t0..=t1.min(n - 1)]
                .iter()
                .fold(0.0f64, |m, r| m.max(r.abs()));
            Some((block, top))
        })
        .collect()
}

/// Highest order a block whose top speed is `top_rpm` resolves: its frequency in the kernel's
/// flat pass band, and below the angle grid's Nyquist order.
fn top_order(signals: &Signals, opts: &AnalysisOptions, top_rpm: f64) -> f64 {
    let per_rev = opts.samples_per_rev;
    (FLAT_BAND * signals.sample_rate / (top_rpm / 60.0).max(1e-12))
        .min(MAX_ORDER_PER_SAMPLE * per_rev as f64)
}

/// Order tracks in the angle domain (see `angle`) for [`AnalysisOptions::tracked_orders`] over
/// the angle blocks; none for orders whose neighbours share the Hann main lobe or beyond what a
/// block resolves.
fn order_tracks(
    signals: &Signals,
    opts: &AnalysisOptions,
    angle_blocks: &[Option<(&[f64], f64)>],
) -> Vec<OrderTrack> {
    let tracked = opts.tracked_orders();
    let neighbours = neighbour_orders(&tracked.iter().map(|(o, _)| *o).collect::<Vec<_>>());
    let per_rev = opts.samples_per_rev;
    let revs = opts.order_block_revs;
    let nb = revs * per_rev;
    tracked
        .into_iter()
        .map(|(order, label)| (OrderDft::new(nb, per_rev, order), order, label))
        .map(|(dft, order, label)| {
            // Neighbours closer than 2 bins (1 / revs orders each) share the Hann main lobe.
            let close = neighbours.iter().any(|&o| {
                (o - order).abs() > 1e-9 && (o - order).abs() * (revs as f64) < 2.0 - 1e-9
            });
            OrderTrack {
                order,
                label,
                amplitude: angle_blocks
                    .iter()
                    .map(|ab| {
                        let (block, top) = (*ab)?;
                        (!close && order < top_order(signals, opts, top))
                            .then(|| dft.amplitude(block))
                    })
                    .collect(),
            }
        })
        .collect()
}

/// Order spectra for the order plot: the same angle blocks (of the blocks above the minimum
/// speed), all orders at once; NaN above the orders a block resolves.
fn order_spectra(
    signals: &Signals,
    opts: &AnalysisOptions,
    angle_blocks: &[Option<(&[f64], f64)>],
    blocks: &[Block],
) -> Vec<Option<Vec<f64>>> {
    let revs = opts.order_block_revs;
    let nb = revs * opts.samples_per_rev;
    let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(nb);
    let hann: Vec<f64> = (0..nb)
        .map(|k| 0.5 - 0.5 * (2.0 * PI * k as f64 / nb as f64).cos())
        .collect();
    let wsum: f64 = hann.iter().sum();
    angle_blocks
        .iter()
        .zip(blocks)
        .filter(|(_, b)| b.rpm >= opts.min_rpm)
        .map(|(ab, _)| {
            let (block, top) = (*ab)?;
            let mean = block.iter().map(|v| v / nb as f64).sum::<f64>();
            // Scaled by the largest magnitude (finite squares near f64::MAX).
            let scale = block
                .iter()
                .fold(0.0f64, |m, v| m.max((v - mean).abs()))
                .max(f64::MIN_POSITIVE);
            let mut buf: Vec<f64> = block
                .iter()
                .zip(&hann)
                .map(|(v, w)| (v - mean) / scale * w)
                .collect();
            let mut out = fft.make_output_vec();
            fft.process(&mut buf, &mut out).ok()?;
            // Orders the block does not resolve: no data.
            let top = top_order(signals, opts, top);
            Some(
                out.iter()
                    .enumerate()
                    .map(|(k, c)| {
                        if k as f64 / revs as f64 > top {
                            f64::NAN
                        } else {
                            2.0 * (c.re * c.re + c.im * c.im).sqrt() / wsum * scale
                        }
                    })
                    .collect(),
            )
        })
        .collect()
}
