//! Options of the run-up analysis and their defaults.

use super::error::AnalysisError;

/// How amplitudes map to colours (and to the y axis of the order-track plot).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ColourScale {
    /// Linear from 0 to the channel maximum: shows only the dominant orders.
    Linear,
    /// Logarithmic over `range_db` below the maximum, ticks in the channel's unit.
    Log {
        /// Dynamic range shown, in dB (20 dB per decade).
        range_db: f64,
    },
    /// Level in dB re the ISO 1683 reference (1 µm/s², 1 pm; 1 for unknown units),
    /// over `range_db` below the maximum.
    Decibel {
        /// Dynamic range shown, in dB.
        range_db: f64,
    },
}

impl Default for ColourScale {
    /// dB over 80 dB: a run-up spans orders from the unbalance (order 1, large)
    /// to motor orders two or three decades smaller; a linear scale hides the latter,
    /// and 60 dB did too (reference run-up: motor order 1 at tub2 x sits 62 dB below
    /// order 1's peak).
    fn default() -> Self {
        ColourScale::Decibel { range_db: 80.0 }
    }
}

/// Shortest block [`AnalysisOptions::fit_to`] shortens the blocks to for a short signal, s:
/// 0.25 s has 4 Hz bins: drum orders 1 and 2 two bins apart (the Hann main lobe) from 480 rpm,
/// motor orders 1 and 2 from 45 rpm; a shorter block's bins blur even those.
pub const MIN_BLOCK_LENGTH_S: f64 = 0.25;

/// Settings of [`super::analyse_file`] / [`super::analyse_signals`].
///
/// Defaults are chosen for the simulator's 2 kHz output and drum speeds up to
/// 1400 rpm (23.3 Hz):
/// * `block_length_s = 1.0`: 1 Hz resolution, i.e. order resolution of the order
///   plot `60 / (T rpm)` = 0.6 at 100 rpm, 0.15 at 400 rpm, 0.04 at 1400 rpm.
///   Longer blocks resolve better but smear more: during a run-up of ~20 rpm/s
///   motor order 1 (drum order 11.25) sweeps ~4 Hz (4 bins) within a 1 s block, at
///   2 s it would be 15 bins of a 0.5 Hz grid. The order tracks do not smear (they
///   follow the drum angle) and resolve orders 1 and 2 from 2 revolutions per
///   block, i.e. from 120 rpm, below the usual suspension resonance (150-300 rpm).
/// * `overlap = 0.5`: Hann windows at 50 % overlap sum to a constant, so every
///   sample counts equally; a 60 s run-up gives ~120 blocks (~11 rpm apart at 20 rpm/s).
/// * `max_order = 25`: covers the drum harmonics and motor orders 1 and 2 (11.25,
///   22.5) and stays below Nyquist (order 42.9 at 1400 rpm, 2 kHz).
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisOptions {
    /// Block length in s.
    pub block_length_s: f64,
    /// Fraction of a block shared with the next, in `[0, 1)`.
    pub overlap: f64,
    /// Subtract each block's mean before windowing (static offsets would leak into order 1 at low speed).
    pub remove_mean: bool,
    /// Motor speed / drum speed (belt ratio): motor order n is drum order `motor_ratio * n`.
    pub motor_ratio: f64,
    /// How many motor orders to mark (and track), limited to those up to `max_order`.
    pub motor_orders: usize,
    /// Drum orders tracked over speed in the speed plot and the report.
    pub track_orders: Vec<f64>,
    /// Upper limit of the order axis.
    pub max_order: f64,
    /// Upper limit of the cascade's frequency axis in Hz (`None`: Nyquist).
    pub max_frequency_hz: Option<f64>,
    /// Blocks slower than this (rpm) are left out of order views: the order axis
    /// `f / (rpm/60)` is meaningless near standstill.
    pub min_rpm: f64,
    /// Colour scale of order plot and cascade, and y scale of order tracks.
    pub colour_scale: ColourScale,
    /// Pixel size of the PNG plots (the SVGs use the same layout).
    pub plot_size: (u32, u32),
    /// Revolutions per block of the order tracks (angle domain): the order resolution is
    /// 1 / this; orders closer than 2 / this to a neighbour are not resolved.
    pub order_block_revs: usize,
    /// Angle samples per revolution of the order tracks; orders up to 0.45 x this are tracked.
    pub samples_per_rev: usize,
    /// Format of the spectra and order-track tables.
    pub format: crate::results::Format,
    /// Also write each plot as SVG (PNG is always written).
    pub svg: bool,
    /// Compute the time-block spectra and write the cascades and the spectra table; the order
    /// plots, speed plots and order tracks are always written. Without, `Block::spectrum` is
    /// empty.
    pub cascades: bool,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            block_length_s: 1.0,
            overlap: 0.5,
            remove_mean: true,
            motor_ratio: 11.25,
            motor_orders: 2,
            track_orders: vec![1.0, 2.0, 3.0],
            max_order: 25.0,
            max_frequency_hz: None,
            min_rpm: 30.0,
            colour_scale: ColourScale::default(),
            plot_size: (1024, 640),
            order_block_revs: 8,
            samples_per_rev: 64,
            format: crate::results::Format::Parquet,
            svg: true,
            cascades: true,
        }
    }
}

impl AnalysisOptions {
    /// Reject settings that would give no or meaningless blocks.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        let bad = |m: String| Err(AnalysisError::InvalidOptions(m));
        if !(self.block_length_s.is_finite() && self.block_length_s > 0.0) {
            return bad(format!(
                "block_length_s must be positive, got {}",
                self.block_length_s
            ));
        }
        if !(0.0..1.0).contains(&self.overlap) {
            return bad(format!("overlap must be in [0, 1), got {}", self.overlap));
        }
        if !(self.motor_ratio.is_finite() && self.motor_ratio > 0.0) {
            return bad(format!(
                "motor_ratio must be positive, got {}",
                self.motor_ratio
            ));
        }
        if !(self.max_order.is_finite() && self.max_order > 0.0) {
            return bad(format!(
                "max_order must be positive, got {}",
                self.max_order
            ));
        }
        if let Some(f) = self
            .max_frequency_hz
            .filter(|f| !(f.is_finite() && *f > 0.0))
        {
            return bad(format!("max_frequency_hz must be positive, got {f}"));
        }
        if !(self.min_rpm.is_finite() && self.min_rpm > 0.0) {
            return bad(format!("min_rpm must be positive, got {}", self.min_rpm));
        }
        if let Some(o) = self
            .track_orders
            .iter()
            .find(|o| !(o.is_finite() && **o > 0.0))
        {
            return bad(format!("track_orders must be positive, got {o}"));
        }
        match self.colour_scale {
            ColourScale::Log { range_db } | ColourScale::Decibel { range_db }
                if !(range_db.is_finite() && range_db > 0.0) =>
            {
                return bad(format!("colour range must be positive, got {range_db} dB"));
            }
            _ => {}
        }
        if !(2..=10_000).contains(&self.order_block_revs) {
            return bad(format!(
                "order_block_revs must be in [2, 10000], got {}",
                self.order_block_revs
            ));
        }
        if !(16..=4096).contains(&self.samples_per_rev) {
            return bad(format!(
                "samples_per_rev must be in [16, 4096], got {}",
                self.samples_per_rev
            ));
        }
        if self.plot_size.0 < 400 || self.plot_size.1 < 300 {
            return bad(format!(
                "plot_size {:?} too small for readable labels (min 400x300)",
                self.plot_size
            ));
        }
        Ok(())
    }

    /// These options for a signal of `samples` samples at `sample_rate` Hz: unchanged where one
    /// block fits, else one block over the whole signal (a run shorter than a block), down to
    /// [`MIN_BLOCK_LENGTH_S`] (or the options' own block, if shorter) and the 16 samples a
    /// block needs. `TooFewSamples` below that.
    pub fn fit_to(
        &self,
        samples: usize,
        sample_rate: f64,
    ) -> Result<AnalysisOptions, AnalysisError> {
        let len = |s: f64| (s * sample_rate).round();
        if len(self.block_length_s) <= samples as f64 {
            return Ok(self.clone());
        }
        let needed = len(MIN_BLOCK_LENGTH_S.min(self.block_length_s)).max(16.0) as usize;
        if samples < needed {
            return Err(AnalysisError::TooFewSamples {
                context: format!(
                    "the signal spans {} s at {sample_rate} Hz, shorter than the shortest \
                     analysis block ({} s)",
                    samples as f64 / sample_rate,
                    needed as f64 / sample_rate
                ),
                found: samples,
                needed,
            });
        }
        Ok(AnalysisOptions {
            block_length_s: samples as f64 / sample_rate,
            ..self.clone()
        })
    }

    /// Drum orders of the motor orders to mark: `motor_ratio * n` up to `max_order`.
    pub fn motor_drum_orders(&self) -> Vec<(usize, f64)> {
        (1..=self.motor_orders)
            .map(|n| (n, n as f64 * self.motor_ratio))
            .filter(|&(_, o)| o <= self.max_order)
            .collect()
    }

    /// Orders tracked over speed with legend labels: `track_orders` and the marked motor orders.
    pub fn tracked_orders(&self) -> Vec<(f64, String)> {
        let mut v: Vec<(f64, String)> = self
            .track_orders
            .iter()
            .map(|&o| (o, format!("order {}", fmt_order(o))))
            .collect();
        for (n, o) in self.motor_drum_orders() {
            if !v.iter().any(|(x, _)| (x - o).abs() < 1e-9) {
                v.push((o, format!("motor order {n} (= {})", fmt_order(o))));
            }
        }
        v
    }
}

/// Order for labels: `1`, `11.25`, `2.5`.
pub fn fmt_order(o: f64) -> String {
    let s = format!("{o:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
