//! The error measures of comparisons between runs (the accuracy study's, `washdyn compare`'s):
//! relative RMS of the acceleration channels (raw, or in the analysis band), and the order
//! tracks' dB errors.

use crate::{AnalysisOptions, Channel, RunUp, Signals};
use washdyn_runtime::output::MemorySink;

/// The band of the acceleration error of model comparisons, Hz (`band_error`): the analysis
/// band, where the order plots are.
pub const BAND_HZ: f64 = 300.0;
/// Orders compared in the order tracks.
pub const ORDERS: [f64; 3] = [1.0, 2.0, 3.0];
/// Blocks of an order track whose reference amplitude is below this fraction of the track's
/// peak (-40 dB) are not compared: there the order is noise, and dB errors mean nothing.
pub const ORDER_FLOOR: f64 = 1e-2;
/// The strong part of an order track: at least this fraction of its peak (within 20 dB), where
/// a model comparison's 0.1 dB target applies (issue 21).
pub const STRONG_FLOOR: f64 = 0.1;

/// The median of `v` (the mean of the middle two for an even count); NaN when empty. One for
/// the tacho's pulse intervals and the full-mesh study's amplitude differences.
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// `m` from `skip` samples on, with only the channels whose name starts with `prefix`.
pub fn trim(m: &MemorySink, skip: usize, prefix: &str) -> MemorySink {
    let keep: Vec<usize> = (0..m.channels.len())
        .filter(|&c| m.channels[c].starts_with(prefix))
        .collect();
    let nc = m.channels.len();
    let mut out = MemorySink {
        channels: keep.iter().map(|&c| m.channels[c].clone()).collect(),
        ..MemorySink::default()
    };
    for k in skip.min(m.time.len())..m.time.len() {
        out.time.push(m.time[k]);
        out.rpm.push(m.rpm[k]);
        out.values
            .extend(keep.iter().map(|&c| m.values[k * nc + c]));
    }
    out
}

/// An acceleration channel: its name ends in `_ax`, `_ay` or `_az`.
pub fn is_accel(name: &str) -> bool {
    name.ends_with("_ax") || name.ends_with("_ay") || name.ends_with("_az")
}

/// The acceleration channels present in both runs.
fn accel_channels(a: &MemorySink, b: &MemorySink) -> Vec<(usize, usize, String)> {
    a.channels
        .iter()
        .enumerate()
        .filter(|(_, n)| is_accel(n))
        .filter_map(|(i, n)| {
            b.channels
                .iter()
                .position(|m| m == n)
                .map(|j| (i, j, n.clone()))
        })
        .collect()
}

/// Largest relative RMS difference of `x` against `r` over the shared acceleration channels.
pub fn rms_error(x: &MemorySink, r: &MemorySink) -> Option<f64> {
    if x.time.len() != r.time.len() || x.time.is_empty() {
        return None;
    }
    let mut worst = 0.0f64;
    for (i, j, _) in accel_channels(x, r) {
        if let Some(e) = relative_rms(&x.column(i), &r.column(j)) {
            worst = worst.max(e);
        }
    }
    Some(worst)
}

/// Largest `band_error` (to [`BAND_HZ`]) of `x` against `r` over the shared acceleration
/// channels, both sampled at `rate`.
pub fn band_rms_error(x: &MemorySink, r: &MemorySink, rate: f64) -> Option<f64> {
    if x.time.len() != r.time.len() || x.time.is_empty() {
        return None;
    }
    accel_channels(x, r)
        .into_iter()
        .filter_map(|(i, j, _)| band_error(&x.column(i), &r.column(j), rate, BAND_HZ))
        .reduce(f64::max)
}

/// RMS of `x - r` over the RMS of `r` (one channel of [`rms_error`]); `None` where `r` is zero
/// throughout or the lengths differ.
pub fn relative_rms(x: &[f64], r: &[f64]) -> Option<f64> {
    if x.len() != r.len() {
        return None;
    }
    let num: f64 = x.iter().zip(r).map(|(p, q)| (p - q) * (p - q)).sum();
    let den: f64 = r.iter().map(|q| q * q).sum();
    (den > 0.0).then(|| (num / den).sqrt())
}

/// Relative error of `x` against `r` (sampled at `fs`) in the band up to `f_max`: the RMS of
/// the Hann-windowed spectrum of x - r over the bins to `f_max`, over that of r. A model's
/// accelerations carry its highest modes (the tub's to 6.6 kHz); compared raw, or sampled
/// below twice their frequency (aliased), a model with fewer modes differs by what no order
/// plot shows. `None` where r has nothing in the band or the lengths differ.
pub fn band_error(x: &[f64], r: &[f64], fs: f64, f_max: f64) -> Option<f64> {
    let n = r.len();
    if x.len() != n || n < 2 {
        return None;
    }
    let hann = crate::spectrum::Window::hann(n);
    let w = hann.coeffs();
    let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let spectrum = |v: Vec<f64>| {
        let mut v = v;
        let mut out = fft.make_output_vec();
        fft.process(&mut v, &mut out)
            .expect("lengths from the plan");
        out
    };
    let d = spectrum((0..n).map(|k| (x[k] - r[k]) * w[k]).collect());
    let s = spectrum((0..n).map(|k| r[k] * w[k]).collect());
    let bins = ((f_max * n as f64 / fs).floor() as usize + 1).min(s.len());
    let num: f64 = d[..bins].iter().map(|c| c.norm_sqr()).sum();
    let den: f64 = s[..bins].iter().map(|c| c.norm_sqr()).sum();
    (den > 0.0).then(|| (num / den).sqrt())
}

/// The order tracks of orders 1-3 of every acceleration channel.
pub fn order_tracks(m: &MemorySink, t0: f64, rate: f64) -> Vec<(String, Vec<Vec<Option<f64>>>)> {
    let opts = AnalysisOptions {
        track_orders: ORDERS.to_vec(),
        motor_orders: 0,
        cascades: false,
        ..AnalysisOptions::default()
    };
    let names: Vec<(usize, String)> = m
        .channels
        .iter()
        .enumerate()
        .filter(|(_, n)| is_accel(n))
        .map(|(i, n)| (i, n.clone()))
        .collect();
    let mut out = Vec::new();
    for (i, name) in names {
        let ch = Channel::new(name.clone(), m.column(i));
        let Ok(sig) = Signals::from_uniform(t0, rate, m.rpm.clone(), vec![ch.clone()]) else {
            continue;
        };
        let Ok(ru) = RunUp::analyse(&sig, &ch, &opts) else {
            continue;
        };
        let tracks = ORDERS
            .iter()
            .map(|o| {
                ru.tracks
                    .iter()
                    .find(|t| (t.order - o).abs() < 1e-9)
                    .map_or_else(Vec::new, |t| t.amplitude.clone())
            })
            .collect();
        out.push((name, tracks));
    }
    out
}

pub type Tracks = Vec<(String, Vec<Vec<Option<f64>>>)>;

/// Largest |20 log10(x / r)| over channels, orders and the blocks where the reference is within
/// 40 dB of its track's peak.
pub fn order_error(x: &Tracks, r: &Tracks) -> Option<f64> {
    let mut worst: Option<f64> = None;
    for (name, rt) in r {
        let Some((_, xt)) = x.iter().find(|(n, _)| n == name) else {
            continue;
        };
        for (ra, xa) in rt.iter().zip(xt) {
            if let Some((db, _)) = track_error(xa, ra) {
                worst = Some(worst.map_or(db.abs(), |w: f64| w.max(db.abs())));
            }
        }
    }
    worst
}

/// One order track `x` against the reference track `r` (one value per block): 20 log10(x / r)
/// at the block where its magnitude is largest, and that block, over the blocks where both are
/// resolved and positive and `r` is at least [`ORDER_FLOOR`] of its own peak (one track of
/// [`order_error`]).
pub fn track_error(x: &[Option<f64>], r: &[Option<f64>]) -> Option<(f64, usize)> {
    track_error_above(x, r, ORDER_FLOOR)
}

/// [`track_error`] over the blocks where `r` is at least `floor` of its own peak (0.1: the
/// strong part of a track, within 20 dB of its peak).
pub fn track_error_above(x: &[Option<f64>], r: &[Option<f64>], floor: f64) -> Option<(f64, usize)> {
    let peak = r.iter().flatten().fold(0.0f64, |m, v| m.max(*v));
    let mut worst: Option<(f64, usize)> = None;
    for (k, (a, b)) in r.iter().zip(x).enumerate() {
        if let (Some(a), Some(b)) = (a, b)
            && *a >= floor * peak
            && *a > 0.0
            && *b > 0.0
        {
            let db = 20.0 * (b / a).log10();
            if worst.is_none_or(|(w, _)| db.abs() > w.abs()) {
                worst = Some((db, k));
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sink(ch: &[&str], rows: &[[f64; 2]]) -> MemorySink {
        let mut m = MemorySink {
            channels: ch.iter().map(|s| s.to_string()).collect(),
            ..Default::default()
        };
        for (k, r) in rows.iter().enumerate() {
            m.time.push(k as f64);
            m.rpm.push(0.0);
            m.values.extend_from_slice(r);
        }
        m
    }

    /// RMS error by hand: channel a_ax differs by 0.1 everywhere on a reference of RMS 1 ->
    /// 0.1; the displacement channel is ignored; different lengths give no number.
    #[test]
    fn band_error_sees_only_the_band() {
        // 1 s at 20 kHz: r = sin 50 Hz; x adds 1 % at 120 Hz (in the 300 Hz band) and a
        // tenfold tone at 1500 Hz (out of it). Closed form: a Hann-windowed tone's energy is
        // proportional to its amplitude squared, so the in-band error is 0.01.
        let fs = 20_000.0;
        let t: Vec<f64> = (0..20_000).map(|k| k as f64 / fs).collect();
        let s = |f: f64, a: f64| -> Vec<f64> {
            t.iter()
                .map(|t| a * (2.0 * std::f64::consts::PI * f * t).sin())
                .collect()
        };
        let (r, a, b) = (s(50.0, 1.0), s(120.0, 0.01), s(1500.0, 10.0));
        let x: Vec<f64> = (0..t.len()).map(|k| r[k] + a[k] + b[k]).collect();
        let e = band_error(&x, &r, fs, 300.0).expect("in band");
        assert!((e - 0.01).abs() < 1e-6, "{e}");
        // The raw RMS sees the out-of-band tone: 10.
        let raw = relative_rms(&x, &r).expect("raw");
        assert!((raw - 10.0).abs() < 1e-3, "{raw}");
    }

    #[test]
    fn rms_error_is_relative_and_only_on_accelerations() {
        let r = sink(&["a_ax", "d_ux"], &[[1.0, 5.0], [-1.0, 5.0]]);
        let x = sink(&["a_ax", "d_ux"], &[[1.1, 0.0], [-0.9, 0.0]]);
        assert!((rms_error(&x, &r).unwrap() - 0.1).abs() < 1e-12);
        let short = sink(&["a_ax", "d_ux"], &[[1.1, 0.0]]);
        assert_eq!(rms_error(&short, &r), None);
    }
}
