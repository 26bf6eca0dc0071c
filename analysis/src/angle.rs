//! Angle-domain resampling for order tracking (computed order tracking, as the field's tools do).
//!
//! A channel sampled uniformly in time is resampled to `M` samples per drum revolution. A
//! component locked to the drum is then exactly periodic in the angle samples, whatever the
//! speed does, so a Hann-windowed DFT over a whole number of revolutions puts every integer
//! order (and every order `k / R` for `R` revolutions per block) on its own bin, and the Hann
//! window's spectrum of an on-bin component is zero two bins away: orders 1 and 2 do not leak
//! into each other at all, in exact arithmetic.
//!
//! What is left is the resampler's error. Each angle sample's time follows exactly from the
//! drum angle (the integral of the speed, linear between samples: a quadratic in time, solved
//! in closed form), and its value from a Kaiser-windowed sinc (band-limited interpolation) with
//! `2 HALF_TAPS` taps. Where the angle grid is coarser than the time grid (low speed), the
//! kernel's cut-off follows the angle grid's Nyquist frequency, so content above it is filtered
//! out instead of aliasing into low orders.

use std::f64::consts::PI;

/// Half the number of taps of the interpolation kernel at full bandwidth.
pub const HALF_TAPS: usize = 16;
/// Kaiser window shape: beta = 12 gives about 120 dB stop-band attenuation.
const BETA: f64 = 12.0;
/// Table resolution of the kernel (entries per sample interval), linear in between.
const TABLE_STEPS: usize = 512;
/// Pass band of the kernel as a fraction of Nyquist: the transition band lies above it.
const PASS: f64 = 0.9;
/// Highest frequency, as a fraction of the sample rate, that the kernel passes flat (its
/// transition band starts above): orders beyond it in a block are not resolved.
pub const FLAT_BAND: f64 = 0.37;
/// Highest order per angle sample per revolution (below the angle grid's Nyquist, 0.5).
pub const MAX_ORDER_PER_SAMPLE: f64 = 0.45;

/// Modified Bessel function of the first kind, order 0 (series; converges for the betas used).
fn bessel_i0(x: f64) -> f64 {
    let mut sum = 1.0;
    let mut term = 1.0;
    let q = 0.25 * x * x;
    for k in 1..200 {
        term *= q / (k * k) as f64;
        sum += term;
        if term < 1e-17 * sum {
            break;
        }
    }
    sum
}

/// The windowed-sinc kernel at full bandwidth, tabulated over `[0, HALF_TAPS]`.
pub struct Kernel {
    table: Vec<f64>,
}

impl Default for Kernel {
    fn default() -> Self {
        Self::new()
    }
}

impl Kernel {
    pub fn new() -> Kernel {
        let n = HALF_TAPS * TABLE_STEPS + 2;
        let i0b = bessel_i0(BETA);
        let table = (0..n)
            .map(|i| {
                let d = i as f64 / TABLE_STEPS as f64;
                if d >= HALF_TAPS as f64 {
                    return 0.0;
                }
                let r = d / HALF_TAPS as f64;
                let w = bessel_i0(BETA * (1.0 - r * r).sqrt()) / i0b;
                let x = PI * PASS * d;
                let sinc = if d == 0.0 { 1.0 } else { x.sin() / x };
                PASS * sinc * w
            })
            .collect();
        Kernel { table }
    }

    /// Kernel value at distance `d` >= 0 (in units of its own width).
    #[inline]
    fn at(&self, d: f64) -> f64 {
        let u = d * TABLE_STEPS as f64;
        let i = u as usize;
        if i + 1 >= self.table.len() {
            return 0.0;
        }
        let f = u - i as f64;
        self.table[i] + f * (self.table[i + 1] - self.table[i])
    }
}

/// Where the angle samples lie in time: fractional sample index and the kernel's bandwidth
/// (1: full; below 1 where the angle grid is coarser than the time grid).
pub struct AngleGrid {
    /// Samples per revolution.
    pub per_rev: usize,
    /// Fractional time-sample index of each angle sample.
    pub pos: Vec<f64>,
    /// Kernel bandwidth at each angle sample, in (0, 1].
    pub band: Vec<f64>,
    /// Drum angle (rad) at every time sample, the integral the grid inverts.
    pub angle: Vec<f64>,
}

impl AngleGrid {
    /// The grid for `|rpm|` sampled at `sample_rate` (reverse rotation is analysed as forward:
    /// an order is a multiple of the rotation frequency either way).
    pub fn new(rpm: &[f64], sample_rate: f64, per_rev: usize) -> AngleGrid {
        let h = 1.0 / sample_rate;
        let c = 2.0 * PI / 60.0;
        let dphi = 2.0 * PI / per_rev as f64;
        let mut pos = Vec::new();
        let mut band = Vec::new();
        let mut angle = Vec::with_capacity(rpm.len());
        angle.push(0.0);
        let mut phi = 0.0;
        let mut next = 0.0;
        for (j, w) in rpm.windows(2).enumerate() {
            let (r0, r1) = (w[0].abs(), w[1].abs());
            // phi(tau) = phi_j + b tau + a tau^2 over this interval.
            let b = c * r0;
            let a = c * (r1 - r0) / (2.0 * h);
            let end = phi + b * h + a * h * h;
            while next < end {
                let need = next - phi;
                // Stable root of a tau^2 + b tau - need = 0.
                let disc = (b * b + 4.0 * a * need).max(0.0);
                let den = b + disc.sqrt();
                let tau = if den > 0.0 { 2.0 * need / den } else { 0.0 };
                let tau = tau.clamp(0.0, h);
                pos.push(j as f64 + tau / h);
                // Angle-grid rate (samples per second) against the time grid's.
                let rate = (r0 + (r1 - r0) * tau / h) / 60.0 * per_rev as f64;
                band.push((rate / sample_rate).clamp(1e-3, 1.0));
                next += dphi;
            }
            phi = end;
            angle.push(phi);
        }
        AngleGrid {
            per_rev,
            pos,
            band,
            angle,
        }
    }

    /// Every channel at every angle sample: the kernel weights of a sample are computed once
    /// for all channels, and chunks of samples run on all cores.
    pub fn resample_all(&self, kernel: &Kernel, xs: &[&[f64]]) -> Vec<Vec<f64>> {
        use rayon::prelude::*;
        let m = self.pos.len();
        let chunk = 4096;
        let parts: Vec<Vec<Vec<f64>>> = (0..m.div_ceil(chunk))
            .into_par_iter()
            .map(|c| {
                let r = c * chunk..((c + 1) * chunk).min(m);
                let mut out: Vec<Vec<f64>> = vec![Vec::with_capacity(r.len()); xs.len()];
                let mut w = Vec::new();
                for k in r {
                    let (p, bw) = (self.pos[k], self.band[k]);
                    let n = xs.first().map_or(0, |x| x.len()) as isize;
                    let reach = HALF_TAPS as f64 / bw;
                    let lo = ((p - reach).ceil() as isize).max(0);
                    let hi = ((p + reach).floor() as isize).min(n - 1);
                    w.clear();
                    w.extend((lo..=hi).map(|i| kernel.at((p - i as f64).abs() * bw) * bw));
                    for (o, x) in out.iter_mut().zip(xs) {
                        let seg = &x[lo as usize..=hi as usize];
                        o.push(seg.iter().zip(&w).map(|(a, b)| a * b).sum());
                    }
                }
                out
            })
            .collect();
        let mut out: Vec<Vec<f64>> = vec![Vec::with_capacity(m); xs.len()];
        for part in parts {
            for (o, p) in out.iter_mut().zip(part) {
                o.extend(p);
            }
        }
        out
    }

    /// `x` at every angle sample (band-limited interpolation).
    pub fn resample(&self, kernel: &Kernel, x: &[f64]) -> Vec<f64> {
        let n = x.len() as isize;
        self.pos
            .iter()
            .zip(&self.band)
            .map(|(&p, &bw)| {
                let reach = HALF_TAPS as f64 / bw;
                let lo = ((p - reach).ceil() as isize).max(0);
                let hi = ((p + reach).floor() as isize).min(n - 1);
                let mut acc = 0.0;
                for i in lo..=hi {
                    let d = (p - i as f64).abs() * bw;
                    acc += kernel.at(d) * x[i as usize];
                }
                acc * bw
            })
            .collect()
    }
}

/// Hann-weighted DFT kernel of one order over blocks of `n` angle samples, tabulated once for
/// all blocks.
pub struct OrderDft {
    re: Vec<f64>,
    im: Vec<f64>,
    wsum: f64,
}

impl OrderDft {
    pub fn new(n: usize, per_rev: usize, order: f64) -> OrderDft {
        let step = 2.0 * PI * order / per_rev as f64;
        let w: Vec<f64> = (0..n)
            .map(|k| 0.5 - 0.5 * (2.0 * PI * k as f64 / n as f64).cos())
            .collect();
        OrderDft {
            re: (0..n).map(|k| w[k] * (step * k as f64).cos()).collect(),
            im: (0..n).map(|k| -w[k] * (step * k as f64).sin()).collect(),
            wsum: w.iter().sum(),
        }
    }

    /// Peak amplitude of the order in `block` (same length as the table; the block mean is
    /// removed, and the block scaled by its largest magnitude so values near f64::MAX stay
    /// finite).
    pub fn amplitude(&self, block: &[f64]) -> f64 {
        let n = block.len() as f64;
        let mean = block.iter().map(|v| v / n).sum::<f64>();
        let scale = block.iter().fold(0.0f64, |m, v| m.max((v - mean).abs()));
        if scale == 0.0 || !scale.is_finite() {
            return 0.0;
        }
        let (mut re, mut im) = (0.0, 0.0);
        for ((v, a), b) in block.iter().zip(&self.re).zip(&self.im) {
            let y = (v - mean) / scale;
            re += y * a;
            im += y * b;
        }
        2.0 * (re * re + im * im).sqrt() / self.wsum * scale
    }
}

/// Peak amplitude of order `order` in `block` (angle samples over whole revolutions, `per_rev`
/// a revolution): Hann window, DFT at the order's angle frequency, amplitude correction.
pub fn order_amplitude(block: &[f64], per_rev: usize, order: f64) -> f64 {
    OrderDft::new(block.len(), per_rev, order).amplitude(block)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_speed_grid_is_uniform() {
        // 600 rpm at 1 kHz: 10 rev/s, 64 samples per rev = 640 angle samples per second, one
        // every 1000/640 time samples.
        let g = AngleGrid::new(&vec![600.0; 1001], 1000.0, 64);
        // 640 in [0, 1) s, and the one at 1 s where rounding puts it just inside.
        assert!((640..=641).contains(&g.pos.len()), "{}", g.pos.len());
        for (k, p) in g.pos.iter().enumerate() {
            assert!((p - k as f64 * 1000.0 / 640.0).abs() < 1e-9, "{k}: {p}");
        }
        assert!((g.band[0] - 0.64).abs() < 1e-12);
    }

    #[test]
    fn interpolates_a_band_limited_sine() {
        // A 0.3 fs sine, interpolated between samples: error far below 1e-5.
        let fs = 1000.0;
        let x: Vec<f64> = (0..2000)
            .map(|i| (2.0 * PI * 300.0 * i as f64 / fs).sin())
            .collect();
        let g = AngleGrid {
            per_rev: 1,
            pos: (0..500).map(|k| 700.0 + 1.37 * k as f64).collect(),
            band: vec![1.0; 500],
            angle: Vec::new(),
        };
        let y = g.resample(&Kernel::new(), &x);
        let worst = g
            .pos
            .iter()
            .zip(&y)
            .map(|(p, v)| (v - (2.0 * PI * 300.0 * p / fs).sin()).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-5, "{worst}");
    }

    #[test]
    fn huge_values_do_not_overflow() {
        let b: Vec<f64> = (0..256)
            .map(|k| 1e300 * (2.0 * PI * 3.0 * k as f64 / 32.0).cos())
            .collect();
        let a = order_amplitude(&b, 32, 3.0);
        assert!((a / 1e300 - 1.0).abs() < 1e-12, "{a}");
    }
}
