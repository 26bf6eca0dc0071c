//! Spectra and order analysis against closed forms: Hann sums, Parseval, sines of
//! known amplitude, and a synthetic run-up with orders whose phase is the integral
//! of the drum speed (so each order is exact at every instant).

use std::f64::consts::PI;

use washdyn::analysis::{
    AnalysisOptions, BlockLayout, Channel, RunUp, Signals, SpectrumAnalyzer, Window,
};

/// xorshift64*: a seeded, dependency-free broadband signal in [-1, 1).
fn noise(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            let u = s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
            2.0 * (u as f64 / (1u64 << 53) as f64) - 1.0
        })
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn hann_correction_factors_from_window_sums() {
    for n in [16, 1000, 1001, 2000, 2048] {
        let w = Window::hann(n);
        let sum: f64 = w.coeffs().iter().sum();
        let sum_sq: f64 = w.coeffs().iter().map(|x| x * x).sum();
        let amplitude = n as f64 / sum;
        let energy = (n as f64 / sum_sq).sqrt();
        assert!((amplitude - 2.0).abs() < 1e-12, "n={n}: {amplitude}");
        assert!(
            (energy - (8.0f64 / 3.0).sqrt()).abs() < 1e-12,
            "n={n}: {energy}"
        );
        assert!((w.amplitude_correction() - 2.0).abs() < 1e-12);
        assert!((w.energy_correction() - (8.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!((w.enbw_bins() - 1.5).abs() < 1e-12);
    }
}

#[test]
fn parseval_energy_corrected_spectrum() {
    let mut worst_rect: f64 = 0.0;
    let mut worst_hann: f64 = 0.0;
    for (n, seed) in [(2000usize, 1u64), (2048, 2), (1001, 3), (4000, 4)] {
        // DC offset so the DC bin (counted once) matters; odd n has no Nyquist bin.
        let x: Vec<f64> = noise(seed, n).iter().map(|v| v + 0.3).collect();
        let mean_square = x.iter().map(|v| v * v).sum::<f64>() / n as f64;

        // Rectangular window: the spectrum's mean square is the signal's, exactly.
        let mut rect = SpectrumAnalyzer::new(Window::rectangular(n), 2000.0);
        let s = rect.spectrum(&x, false);
        worst_rect = worst_rect.max(rel(s.mean_square(), mean_square));

        // Hann, energy-corrected: equals the window-weighted mean square Σw²x²/Σw²
        // (the block's window-corrected energy), exactly.
        let w = Window::hann(n);
        let weighted = x
            .iter()
            .zip(w.coeffs())
            .map(|(v, w)| w * w * v * v)
            .sum::<f64>()
            / w.coeffs().iter().map(|w| w * w).sum::<f64>();
        let mut hann = SpectrumAnalyzer::new(w, 2000.0);
        let s = hann.spectrum(&x, false);
        worst_hann = worst_hann.max(rel(s.mean_square(), weighted));
    }
    println!(
        "Parseval rel. error: rectangular {worst_rect:.2e}, Hann energy-corrected {worst_hann:.2e}"
    );
    assert!(worst_rect < 1e-10, "{worst_rect}");
    assert!(worst_hann < 1e-10, "{worst_hann}");
}

#[test]
fn hann_energy_correction_estimates_mean_square_of_noise() {
    // Over many blocks the energy-corrected Hann spectrum gives the plain mean square
    // (the amplitude correction would overestimate it by 8/3 / 4 * 4 / 1.5 = 1.5x in energy).
    let n = 1000;
    let blocks = 400;
    let x = noise(42, n * blocks);
    let mut a = SpectrumAnalyzer::new(Window::hann(n), 1000.0);
    let (mut est, mut amp_est, mut truth) = (0.0, 0.0, 0.0);
    for b in x.chunks(n) {
        let s = a.spectrum(b, false);
        est += s.mean_square();
        amp_est += s.amplitude.iter().map(|v| 0.5 * v * v).sum::<f64>();
        truth += b.iter().map(|v| v * v).sum::<f64>() / n as f64;
    }
    let ratio = est / truth;
    println!("Hann energy-corrected / true mean square over {blocks} blocks: {ratio:.4}");
    assert!((ratio - 1.0).abs() < 0.02, "{ratio}");
    assert!((amp_est / truth - 1.5).abs() < 0.03, "{}", amp_est / truth);
}

#[test]
fn sine_amplitudes_on_and_between_bins() {
    let (n, fs) = (2000, 2000.0);
    let mut a = SpectrumAnalyzer::new(Window::hann(n), fs);
    // On a bin (37 Hz, df = 1 Hz): amplitude correction reads A exactly.
    let x: Vec<f64> = (0..n)
        .map(|i| 0.7 * (2.0 * PI * 37.0 * i as f64 / fs + 0.4).sin())
        .collect();
    let s = a.spectrum(&x, true);
    assert!(rel(s.amplitude[37], 0.7) < 1e-12, "{}", s.amplitude[37]);
    assert!(rel(s.band_amplitude(35.0, 39.0), 0.7) < 1e-12);
    // Half a bin off: the peak bin shows the Hann scalloping loss
    // |W(1/2)| = sinc(1/2) / (1 - 1/4) = 8 / (3 pi); the band energy still gives A.
    let x: Vec<f64> = (0..n)
        .map(|i| 0.7 * (2.0 * PI * 37.5 * i as f64 / fs).sin())
        .collect();
    let s = a.spectrum(&x, true);
    let scallop = 8.0 / (3.0 * PI);
    assert!(
        rel(s.amplitude[37], 0.7 * scallop) < 1e-4,
        "{}",
        s.amplitude[37]
    );
    let band = s.band_amplitude(35.5, 39.5);
    println!(
        "half-bin sine: peak bin {:.5}, band {:.6} (true 0.7)",
        s.amplitude[37], band
    );
    assert!(rel(band, 0.7) < 1e-3, "{band}");
}

#[test]
fn default_blocks_at_2_khz() {
    let l = BlockLayout::new(&AnalysisOptions::default(), 2000.0).unwrap();
    assert_eq!((l.len, l.hop), (2000, 1000));
    assert!((l.df() - 1.0).abs() < 1e-12);
}

/// Orders and amplitudes of the synthetic signal: drum orders 1 and 3, motor order 1.
const COMPONENTS: [(f64, f64); 3] = [(1.0, 1.0), (3.0, 0.3), (11.25, 0.05)];

/// Samples at `fs` Hz with speed `rpm(t)` and phase `phi(t) = 2 pi ∫ rpm/60 dt`.
fn synth(fs: f64, duration: f64, rpm: impl Fn(f64) -> f64, phi: impl Fn(f64) -> f64) -> Signals {
    let n = (duration * fs) as usize;
    let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let x: Vec<f64> = t
        .iter()
        .map(|&t| COMPONENTS.iter().map(|(o, a)| a * (o * phi(t)).sin()).sum())
        .collect();
    Signals::from_uniform(
        0.0,
        fs,
        t.iter().map(|&t| rpm(t)).collect(),
        vec![Channel::new("tub1_ax", x)],
    )
    .unwrap()
}

/// Worst relative amplitude errors of one order: over all resolved blocks, over
/// blocks at or above 300 rpm, and the lowest speed at which the order is resolved.
struct TrackCheck {
    worst: f64,
    worst_above_300: f64,
    first_rpm: f64,
}

/// Checks every resolved track value against the true amplitude and the peak of
/// the amplitude spectrum near every order against the true order (within one bin).
fn check_run(run: &RunUp, min_defined: usize) -> Vec<TrackCheck> {
    COMPONENTS
        .iter()
        .map(|&(order, amplitude)| {
            let track = run.tracks.iter().find(|t| t.order == order).unwrap();
            let mut c = TrackCheck {
                worst: 0.0,
                worst_above_300: 0.0,
                first_rpm: f64::INFINITY,
            };
            let mut defined = 0;
            for (a, b) in track.amplitude.iter().zip(&run.blocks) {
                let Some(a) = a else { continue };
                defined += 1;
                let e = rel(*a, amplitude);
                c.worst = c.worst.max(e);
                if b.rpm >= 300.0 {
                    c.worst_above_300 = c.worst_above_300.max(e);
                }
                c.first_rpm = c.first_rpm.min(b.rpm);
                // Peak of the amplitude spectrum near the order: within one bin of it
                // (where the order plot can tell the orders apart, >= 4 bins apart).
                let fr = b.rotation_hz();
                let df = b.spectrum.df;
                if fr < 4.0 * df {
                    continue;
                }
                let lo = ((order - 0.5) * fr / df).ceil() as usize;
                let hi = ((order + 0.5) * fr / df).floor() as usize;
                let k = (lo..=hi)
                    .max_by(|&i, &j| b.spectrum.amplitude[i].total_cmp(&b.spectrum.amplitude[j]))
                    .unwrap();
                let bin_in_orders = df / fr;
                assert!(
                    (b.order_of_bin(k) - order).abs() <= bin_in_orders,
                    "order {order} at {:.0} rpm: peak at order {:.4}, bin = {bin_in_orders:.4} orders",
                    b.rpm,
                    b.order_of_bin(k)
                );
            }
            assert!(
                defined >= min_defined,
                "order {order}: only {defined} resolved blocks"
            );
            c
        })
        .collect()
}

#[test]
fn run_up_orders_and_amplitudes() {
    // 100 -> 1400 rpm in 65 s (20 rpm/s), 2 kHz, default 1 s blocks at 50 % overlap.
    let (r0, r1, dur, fs) = (100.0, 1400.0, 65.0, 2000.0);
    let k = (r1 - r0) / dur;
    let s = synth(
        fs,
        dur,
        |t| r0 + k * t,
        |t| 2.0 * PI / 60.0 * (r0 * t + 0.5 * k * t * t),
    );
    let opts = AnalysisOptions::default();
    let run = RunUp::analyse(&s, &s.channels[0], &opts).unwrap();
    assert_eq!(run.blocks.len(), 129);
    // Block speeds are the mean of the ramp over each block.
    let b = &run.blocks[10];
    assert!(
        (b.rpm - (r0 + k * b.time_s)).abs() < 1e-6,
        "{} {}",
        b.rpm,
        b.time_s
    );

    let checks = check_run(&run, 120);
    for ((order, _), c) in COMPONENTS.iter().zip(&checks) {
        println!(
            "run-up order {order}: worst amplitude error {:.2e} (from {:.0} rpm), {:.2e} at >= 300 rpm",
            c.worst, c.first_rpm, c.worst_above_300
        );
        assert!(c.worst < 0.01, "order {order}: {}", c.worst);
        assert!(
            c.worst_above_300 < 1e-3,
            "order {order}: {}",
            c.worst_above_300
        );
        // The 8-revolution angle blocks fit into the signal from t = 2.4 s on (~150 rpm).
        assert!(
            c.first_rpm < 152.0,
            "order {order} first resolved at {}",
            c.first_rpm
        );
    }
    // Max over the run-up, as in the report.
    for (order, amplitude) in COMPONENTS {
        let t = run.tracks.iter().find(|t| t.order == order).unwrap();
        let (m, _) = t.max(&run.blocks).unwrap();
        assert!(rel(m, amplitude) < 0.01, "order {order}: max {m}");
    }
    // A motor order that is absent stays far below the ones present.
    let m2 = run.tracks.iter().find(|t| t.order == 22.5).unwrap();
    let (m, _) = m2.max(&run.blocks).unwrap();
    assert!(m < 1e-3 * 0.05, "absent motor order 2 reads {m}");
}

#[test]
fn constant_speed_segment_is_exact() {
    // 800 rpm: order 1 at 13.33 Hz, between bins; order 11.25 at 150 Hz, on a bin.
    let (rpm, fs) = (800.0, 2000.0);
    let s = synth(fs, 8.0, |_| rpm, |t| 2.0 * PI * rpm / 60.0 * t);
    let run = RunUp::analyse(&s, &s.channels[0], &AnalysisOptions::default()).unwrap();
    let checks = check_run(&run, 10);
    for ((order, _), c) in COMPONENTS.iter().zip(&checks) {
        println!(
            "constant speed order {order}: worst amplitude error {:.2e}",
            c.worst
        );
        assert!(c.worst < 1e-5, "order {order}: {}", c.worst);
    }
    // On-bin component reads its amplitude at its bin in the amplitude-corrected spectrum.
    let b = &run.blocks[3];
    let k = b.bin_of_order(11.25).unwrap();
    assert_eq!(k, 150);
    assert!(
        rel(b.spectrum.amplitude[k], 0.05) < 1e-5,
        "{}",
        b.spectrum.amplitude[k]
    );
}

#[test]
fn too_short_signal_for_one_block() {
    let s = synth(2000.0, 0.5, |_| 600.0, |t| 2.0 * PI * 10.0 * t);
    let e = RunUp::analyse(&s, &s.channels[0], &AnalysisOptions::default()).unwrap_err();
    assert!(e.to_string().contains("too few samples"), "{e}");
}

#[test]
fn invalid_options_are_rejected() {
    let s = synth(2000.0, 2.0, |_| 600.0, |t| 2.0 * PI * 10.0 * t);
    for opts in [
        AnalysisOptions {
            overlap: 1.0,
            ..Default::default()
        },
        AnalysisOptions {
            block_length_s: 0.0,
            ..Default::default()
        },
        AnalysisOptions {
            block_length_s: 0.001,
            ..Default::default()
        },
        AnalysisOptions {
            motor_ratio: -1.0,
            ..Default::default()
        },
    ] {
        assert!(
            RunUp::analyse(&s, &s.channels[0], &opts).is_err(),
            "{opts:?}"
        );
    }
}

/// Phantom content of absent orders on a run-up like the reference's (0 -> 93 rpm in 5 s, hold
/// to 15 s, 8 rpm/s to 1400 rpm, 2 kHz): orders 1, 3, 5 and motor order 1 (11.25) present,
/// orders 2 and 4 and motor order 2 (22.5) absent. Crosstalk = largest absent-order amplitude
/// over the amplitude of its present neighbour, per speed range. Expected: nothing (the signal
/// holds no such content); the bound -100 dB is issue 7's, met wherever an 8-revolution block
/// fits (blocks below the 30 rpm minimum speed are left out).
#[test]
fn crosstalk_below_minus_100_db_on_a_synthetic_run_up() {
    let fs = 2000.0;
    let (t1, t2, t3) = (5.0, 15.0, 178.375);
    let rpm = |t: f64| {
        if t < t1 {
            93.0 * t / t1
        } else if t < t2 {
            93.0
        } else {
            93.0 + 8.0 * (t - t2)
        }
    };
    let c = 2.0 * PI / 60.0;
    let phi = |t: f64| {
        if t < t1 {
            c * 93.0 * t * t / (2.0 * t1)
        } else if t < t2 {
            c * (93.0 * t1 / 2.0 + 93.0 * (t - t1))
        } else {
            let d = t - t2;
            c * (93.0 * t1 / 2.0 + 93.0 * (t2 - t1) + 93.0 * d + 4.0 * d * d)
        }
    };
    let present = [(1.0, 1.0), (3.0, 0.3), (5.0, 0.1), (11.25, 0.05)];
    let n = (t3 * fs) as usize;
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            present.iter().map(|(o, a)| a * (o * phi(t)).sin()).sum()
        })
        .collect();
    let s = Signals::from_uniform(
        0.0,
        fs,
        (0..n).map(|i| rpm(i as f64 / fs)).collect(),
        vec![Channel::new("tub1_ax", x)],
    )
    .unwrap();
    let opts = AnalysisOptions {
        track_orders: vec![1.0, 2.0, 3.0, 4.0, 5.0],
        ..AnalysisOptions::default()
    };
    let run = RunUp::analyse(&s, &s.channels[0], &opts).unwrap();
    let track = |o: f64| run.tracks.iter().find(|t| t.order == o).unwrap();
    // (absent order, present neighbour, its amplitude)
    let pairs = [(2.0, 1.0, 1.0), (4.0, 3.0, 0.3), (22.5, 11.25, 0.05)];
    let ranges = [
        (30.0, 150.0),
        (150.0, 400.0),
        (400.0, 800.0),
        (800.0, 1400.0),
    ];
    let mut worst_present: f64 = 0.0;
    for (lo, hi) in ranges {
        let mut worst: f64 = 0.0;
        let mut resolved = 0;
        for (i, b) in run.blocks.iter().enumerate() {
            if b.rpm < lo || b.rpm >= hi {
                continue;
            }
            for &(absent, near, amp) in &pairs {
                if let (Some(a), Some(_)) = (track(absent).amplitude[i], track(near).amplitude[i]) {
                    worst = worst.max(a / amp);
                    resolved += 1;
                }
            }
            for &(o, amp) in &present {
                if let Some(a) = track(o).amplitude[i] {
                    worst_present = worst_present.max(rel(a, amp));
                }
            }
        }
        println!(
            "{lo:.0}-{hi:.0} rpm: crosstalk {:.1} dB over {resolved} track values",
            20.0 * worst.max(1e-300).log10()
        );
        assert!(resolved > 0, "{lo}-{hi} rpm: nothing resolved");
        assert!(worst < 1e-5, "{lo}-{hi} rpm: crosstalk {worst:e}");
    }
    println!("present orders: worst relative amplitude error {worst_present:.1e}");
    // The kernel's pass-band ripple (Kaiser, beta 12) and Hann over a whole number of
    // revolutions: measured 2.4e-6 (crosstalk -127, -120, -117, -108 dB by speed range).
    assert!(worst_present < 3e-5, "{worst_present:e}");
}

/// Issue 7: a channel of amplitude 1e300 gave infinite order amplitudes (squares overflow), and
/// a reverse rotation (negative rpm) was not analysed. Expected: the same orders and amplitudes
/// as for forward rotation at ordinary scale, here 1e300 and 0.5e300 in orders 1 and 3.
#[test]
fn huge_amplitudes_and_reverse_rotation() {
    let fs = 2000.0;
    let n = 40_000;
    let rpm: f64 = -600.0;
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let phi = 2.0 * PI * rpm.abs() / 60.0 * i as f64 / fs;
            1e300 * phi.sin() + 0.5e300 * (3.0 * phi).cos()
        })
        .collect();
    let s = Signals::from_uniform(0.0, fs, vec![rpm; n], vec![Channel::new("tub1_ax", x)]).unwrap();
    let run = RunUp::analyse(&s, &s.channels[0], &AnalysisOptions::default()).unwrap();
    for (order, amp) in [(1.0, 1e300), (3.0, 0.5e300)] {
        let t = run.tracks.iter().find(|t| t.order == order).unwrap();
        let (m, at) = t.max(&run.blocks).unwrap();
        assert!(rel(m, amp) < 1e-6, "order {order}: {m:e}");
        assert!((at - 600.0).abs() < 1e-9, "speed {at}");
    }
    // The time spectra stay finite too.
    assert!(run.max_amplitude().is_finite());
    assert!(
        run.order_spectra
            .iter()
            .flatten()
            .flatten()
            .all(|v| v.is_nan() || v.is_finite())
    );
}
