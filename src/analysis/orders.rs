//! Order analysis of a run-up: block spectra tagged with drum speed and an order
//! axis, and order tracks by a synchronous (angle-domain) DFT of the same blocks.
//!
//! Order tracks do not read the block spectra: during a run-up an order sweeps
//! through several bins within one block (motor order 1 at 20 rpm/s: ~4 Hz per
//! second), and at low speed neighbouring orders share bins. Instead each block is
//! demodulated with the drum angle `phi(t) = 2 pi ∫ rpm/60 dt`: the DFT is evaluated
//! at `e^{-i o phi}` rather than `e^{-i 2 pi f t}`, so a component locked to the drum
//! lands on one "bin" whatever the sweep, and the bin spacing is `1 / revolutions`
//! in orders. That keeps orders 1 and 2 apart from 2 revolutions per block on
//! (120 rpm with 1 s blocks) instead of ~4 bins of the time spectrum (~250 rpm).

use std::f64::consts::PI;

use realfft::num_complex::Complex;

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::signals::{Channel, Quantity, Signals};
use super::spectrum::{Spectrum, SpectrumAnalyzer, Window};

/// Half-width in order bins of the energy band of a resolved order. The Hann main
/// lobe is ±2 bins: the band captures the whole lobe, so a small speed error (the
/// order off its exact bin) still reads the right amplitude.
pub const BAND_HALF_WIDTH_BINS: usize = 2;

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

/// Drum angle in rad at every sample: trapezoidal integral of the speed (exact
/// for speed varying linearly between samples).
pub fn drum_angle(rpm: &[f64], sample_rate: f64) -> Vec<f64> {
    let k = 2.0 * PI / 60.0 * 0.5 / sample_rate;
    let mut angle = Vec::with_capacity(rpm.len());
    let mut acc = 0.0;
    angle.push(acc);
    for w in rpm.windows(2) {
        acc += k * (w[0] + w[1]);
        angle.push(acc);
    }
    angle
}

/// Synchronous DFT of one block at drum orders: Hann window, drum angle instead of time.
pub struct OrderTracker {
    window: Window,
    demeaned: Vec<f64>,
}

impl OrderTracker {
    /// Tracker for blocks of `len` samples.
    pub fn new(len: usize) -> OrderTracker {
        OrderTracker {
            window: Window::hann(len),
            demeaned: vec![0.0; len],
        }
    }

    /// Peak amplitude of drum order `order` in a block with samples `x` and drum
    /// angles `angle`, or `None` if it is not resolved: a neighbour order (from
    /// `neighbours`, DC = 0) closer than 2 order bins (inside the Hann main lobe),
    /// or the order above Nyquist. Where the neighbours are at least 4 bins away
    /// the amplitude comes from the energy of ±2 bins (robust to small speed
    /// errors); closer, from the amplitude-corrected value of the exact bin, with
    /// crosstalk from a neighbour of equal size below 3 % (Hann sidelobes at 2 to
    /// 4 bins), below 0.4 % from 4 bins on.
    pub fn amplitude(
        &mut self,
        x: &[f64],
        angle: &[f64],
        order: f64,
        neighbours: &[f64],
        sample_rate: f64,
        remove_mean: bool,
    ) -> Option<f64> {
        let n = self.window.len();
        assert!(x.len() == n && angle.len() == n, "block length mismatch");
        let span = angle[n - 1] - angle[0];
        let revs = span / (2.0 * PI) * n as f64 / (n - 1) as f64;
        if revs.is_nan() || revs <= 0.0 {
            return None;
        }
        let bin = 1.0 / revs;
        // Highest frequency of the band must stay below Nyquist.
        let max_rate =
            angle.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max) * sample_rate / (2.0 * PI);
        let band = BAND_HALF_WIDTH_BINS as f64;
        if (order + band * bin) * max_rate >= 0.5 * sample_rate {
            return None;
        }
        let separation = neighbours
            .iter()
            .filter(|&&o| (o - order).abs() > 1e-9)
            .map(|&o| (o - order).abs() * revs)
            .fold(f64::INFINITY, f64::min);
        let half = (separation - 2.0).floor().min(band);
        if half < 0.0 {
            return None;
        }
        let half = half as i64;
        let mean = if remove_mean {
            x.iter().sum::<f64>() / n as f64
        } else {
            0.0
        };
        for ((d, &v), &w) in self.demeaned.iter_mut().zip(x).zip(self.window.coeffs()) {
            *d = (v - mean) * w;
        }
        // Sums for bins m = -half..=half at orders `order + m / revs`.
        let mut sums = vec![Complex::new(0.0, 0.0); (2 * half + 1) as usize];
        let a0 = angle[0];
        for (&v, &a) in self.demeaned.iter().zip(angle) {
            let da = a - a0;
            let base = Complex::from_polar(v, -order * da);
            let step = Complex::from_polar(1.0, -bin * da);
            let step_inv = step.conj();
            let mid = half as usize;
            sums[mid] += base;
            let (mut up, mut down) = (base, base);
            for m in 1..=mid {
                up *= step;
                down *= step_inv;
                sums[mid + m] += up;
                sums[mid - m] += down;
            }
        }
        let scale = 2.0 / n as f64;
        if half == 0 {
            Some(self.window.amplitude_correction() * scale * sums[0].norm())
        } else {
            let ce = self.window.energy_correction() * scale;
            Some(
                sums.iter()
                    .map(|s| (ce * s.norm()).powi(2))
                    .sum::<f64>()
                    .sqrt(),
            )
        }
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
        let angle = drum_angle(&signals.drum_rpm, signals.sample_rate);
        let starts: Vec<usize> = layout.starts(n).collect();
        let blocks: Vec<Block> = starts
            .iter()
            .map(|&s| {
                let rpm = &signals.drum_rpm[s..s + layout.len];
                let mean = rpm.iter().sum::<f64>() / rpm.len() as f64;
                let (lo, hi) = rpm
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &r| {
                        (lo.min(r), hi.max(r))
                    });
                let span = angle[s + layout.len - 1] - angle[s];
                Block {
                    time_s: signals.time[s] + 0.5 * (layout.len - 1) as f64 / signals.sample_rate,
                    rpm: mean,
                    rpm_min: lo,
                    rpm_max: hi,
                    revolutions: span / (2.0 * PI) * layout.len as f64 / (layout.len - 1) as f64,
                    spectrum: analyzer.spectrum(&channel.data[s..s + layout.len], opts.remove_mean),
                }
            })
            .collect();
        let tracked = opts.tracked_orders();
        let neighbours = neighbour_orders(&tracked.iter().map(|(o, _)| *o).collect::<Vec<_>>());
        let mut tracker = OrderTracker::new(layout.len);
        let tracks = tracked
            .into_iter()
            .map(|(order, label)| OrderTrack {
                order,
                label,
                amplitude: starts
                    .iter()
                    .zip(&blocks)
                    .map(|(&s, b)| {
                        if b.rpm < opts.min_rpm {
                            return None;
                        }
                        let r = s..s + layout.len;
                        tracker.amplitude(
                            &channel.data[r.clone()],
                            &angle[r],
                            order,
                            &neighbours,
                            signals.sample_rate,
                            opts.remove_mean,
                        )
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
