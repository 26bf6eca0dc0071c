//! Windowed FFT of one block: single-sided amplitude spectra with Hann window and
//! the two usual corrections.
//!
//! * Amplitude correction `N / Σw` (2.0 for Hann): a sine of amplitude `A` whose
//!   frequency sits on a bin reads `A` at that bin. Use it to read peaks.
//! * Energy correction `sqrt(N / Σw²)` (sqrt(8/3) for Hann): the spectrum keeps the
//!   block's energy, so `Σ A_k²/2` (DC and Nyquist counted as `A²`) is the mean
//!   square of the block (window-weighted, see [`Spectrum::mean_square`]). Use it for
//!   RMS, band levels and order extraction, which then do not depend on where the
//!   frequency falls between bins.
//!
//! Amplitudes are peak values (a sine `A sin ωt` gives `A`), in the channel's unit.

use std::f64::consts::PI;
use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

/// A window's coefficients and the correction factors derived from them.
#[derive(Debug, Clone, PartialEq)]
pub struct Window {
    coeffs: Vec<f64>,
}

impl Window {
    /// Periodic (DFT-even) Hann window `w_n = 0.5 (1 - cos(2πn/N))`. Periodic rather
    /// than symmetric because that is the one whose sums are exactly `N/2` and `3N/8`,
    /// so the corrections are exactly 2 and sqrt(8/3), and it has no leakage for
    /// sines on bins.
    pub fn hann(n: usize) -> Window {
        let coeffs = (0..n)
            .map(|i| 0.5 * (1.0 - (2.0 * PI * i as f64 / n as f64).cos()))
            .collect();
        Window { coeffs }
    }

    /// Rectangular window (no weighting), mainly to check Parseval exactly.
    pub fn rectangular(n: usize) -> Window {
        Window {
            coeffs: vec![1.0; n],
        }
    }

    /// Window coefficients.
    pub fn coeffs(&self) -> &[f64] {
        &self.coeffs
    }

    /// Block length.
    pub fn len(&self) -> usize {
        self.coeffs.len()
    }

    /// True for a zero-length window.
    pub fn is_empty(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// `N / Σw`: restores the amplitude of a sine on a bin (coherent gain).
    pub fn amplitude_correction(&self) -> f64 {
        self.len() as f64 / self.coeffs.iter().sum::<f64>()
    }

    /// `sqrt(N / Σw²)`: restores the energy (RMS) of a broadband signal.
    pub fn energy_correction(&self) -> f64 {
        (self.len() as f64 / self.coeffs.iter().map(|w| w * w).sum::<f64>()).sqrt()
    }

    /// Equivalent noise bandwidth in bins, `N Σw² / (Σw)²` (1.5 for Hann): the
    /// squared ratio of amplitude to energy correction.
    pub fn enbw_bins(&self) -> f64 {
        (self.amplitude_correction() / self.energy_correction()).powi(2)
    }
}

/// Single-sided spectrum of one block, bins `0..=N/2`.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// Bin spacing in Hz (`sample_rate / N`).
    pub df: f64,
    /// Amplitude-corrected peak amplitudes.
    pub amplitude: Vec<f64>,
    /// Energy-corrected peak amplitudes.
    pub energy: Vec<f64>,
    /// Block length the spectrum came from.
    pub block_len: usize,
}

impl Spectrum {
    /// Frequency of bin `k` in Hz.
    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.df
    }

    /// Index of the Nyquist bin if the block length is even (it is then counted
    /// once, like DC).
    fn nyquist_bin(&self) -> Option<usize> {
        (self.block_len & 1 == 0).then_some(self.block_len / 2)
    }

    /// Mean square from the energy-corrected spectrum: `Σ A_k²/2` over the bins
    /// that stand for a sine, plus `A_0²` for DC and `A_{N/2}²` for Nyquist (each
    /// exists once in the two-sided spectrum). With a rectangular window this is the
    /// block's mean square exactly (Parseval); with Hann it is the window-weighted
    /// mean square `Σ w²x² / Σ w²`, an unbiased estimate of the signal's mean square.
    pub fn mean_square(&self) -> f64 {
        self.band_mean_square(0, self.energy.len().saturating_sub(1))
    }

    /// Mean square of the bins `lo..=hi` (see [`Spectrum::mean_square`]).
    pub fn band_mean_square(&self, lo: usize, hi: usize) -> f64 {
        let hi = hi.min(self.energy.len().saturating_sub(1));
        let nyq = self.nyquist_bin();
        (lo..=hi)
            .map(|k| {
                let a2 = self.energy[k] * self.energy[k];
                if k == 0 || Some(k) == nyq {
                    a2
                } else {
                    0.5 * a2
                }
            })
            .sum()
    }

    /// Peak amplitude of the sine content in a frequency band, from the energy in
    /// the band: `sqrt(2 · mean square)`. For a sine whose main lobe lies inside the
    /// band this is its amplitude whatever its offset from the bins (no scalloping loss).
    pub fn band_amplitude(&self, f_lo: f64, f_hi: f64) -> f64 {
        let lo = (f_lo / self.df).ceil().max(0.0) as usize;
        let hi_f = (f_hi / self.df).floor();
        if hi_f < 0.0 || lo as f64 > hi_f {
            return 0.0;
        }
        let hi = (hi_f as usize).min(self.energy.len().saturating_sub(1));
        (2.0 * self.band_mean_square(lo, hi)).sqrt()
    }
}

/// Reusable FFT plan, window and buffers for blocks of one length.
pub struct SpectrumAnalyzer {
    window: Window,
    fft: Arc<dyn RealToComplex<f64>>,
    input: Vec<f64>,
    output: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
    sample_rate: f64,
}

impl SpectrumAnalyzer {
    /// Analyzer for blocks of `window.len()` samples at `sample_rate` Hz.
    pub fn new(window: Window, sample_rate: f64) -> SpectrumAnalyzer {
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(window.len());
        SpectrumAnalyzer {
            input: fft.make_input_vec(),
            output: fft.make_output_vec(),
            scratch: fft.make_scratch_vec(),
            fft,
            window,
            sample_rate,
        }
    }

    /// The window in use.
    pub fn window(&self) -> &Window {
        &self.window
    }

    /// Spectrum of `block` (length must equal the window length). With
    /// `remove_mean` the block mean is subtracted before windowing, so a static
    /// offset (tub sag, sensor bias) does not leak into the lowest orders.
    pub fn spectrum(&mut self, block: &[f64], remove_mean: bool) -> Spectrum {
        let n = self.window.len();
        assert_eq!(block.len(), n, "block length must equal window length");
        let mean = if remove_mean {
            block.iter().map(|x| x / n as f64).sum::<f64>()
        } else {
            0.0
        };
        // Scaled by the largest magnitude, so squares stay finite for values near f64::MAX
        // (a channel of 1e300 gave infinite amplitudes).
        let scale = block
            .iter()
            .fold(0.0f64, |m, x| m.max((x - mean).abs()))
            .max(f64::MIN_POSITIVE);
        for ((dst, &x), &w) in self.input.iter_mut().zip(block).zip(self.window.coeffs()) {
            *dst = (x - mean) / scale * w;
        }
        self.fft
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .expect("buffer sizes come from the plan");
        let ca = self.window.amplitude_correction();
        let ce = self.window.energy_correction();
        let nyq = (n & 1 == 0).then_some(n / 2);
        let mut amplitude = Vec::with_capacity(self.output.len());
        let mut energy = Vec::with_capacity(self.output.len());
        for (k, z) in self.output.iter().enumerate() {
            // Single-sided: the negative-frequency half doubles every bin except DC and Nyquist.
            let single = if k == 0 || Some(k) == nyq { 1.0 } else { 2.0 };
            // Plain sqrt, not hypot: the scaled values are far from overflow.
            let a = single * (z.re * z.re + z.im * z.im).sqrt() / n as f64 * scale;
            amplitude.push(a * ca);
            energy.push(a * ce);
        }
        Spectrum {
            df: self.sample_rate / n as f64,
            amplitude,
            energy,
            block_len: n,
        }
    }
}
