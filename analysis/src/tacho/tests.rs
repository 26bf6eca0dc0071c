//! Tacho tests against closed-form drum angles.
//!
//! The pulse trains are synthesised from a known angle `phi(t)`: the sensor sees
//! `s = phi * ratio * ppr / 2 pi` pulse periods, high while `frac(s) < 0.1` (square pulses
//! 10 % of a period wide). Each sample is that square wave averaged over +-1 sample
//! interval, a symmetric 0.2 ms edge as a sensor with its anti-alias filter gives, with
//! uniform noise of +-5 % of the level span added. The true edge is where the averaged
//! wave crosses mid level, so the exact edge angle is `n` (rising) or `n + 0.1` (falling)
//! pulse periods.

use super::*;

/// Drum speed `w0 + a t + r sin(2 pi f t)` (rad/s) and its angle, 0 at t = 0.
#[derive(Clone, Copy)]
struct Profile {
    w0: f64,
    a: f64,
    ripple: f64,
    ripple_hz: f64,
}

impl Profile {
    /// The brief's run-up: 50 rpm to 1400 rpm over 60 s.
    fn run_up() -> Profile {
        Profile {
            w0: 50.0 * RPM,
            a: 1350.0 * RPM / 60.0,
            ripple: 0.0,
            ripple_hz: 0.0,
        }
    }

    fn speed(&self, t: f64) -> f64 {
        self.w0 + self.a * t + self.ripple * (2.0 * PI * self.ripple_hz * t).sin()
    }

    fn angle(&self, t: f64) -> f64 {
        let ripple = if self.ripple_hz > 0.0 {
            let om = 2.0 * PI * self.ripple_hz;
            self.ripple / om * (1.0 - (om * t).cos())
        } else {
            0.0
        };
        self.w0 * t + 0.5 * self.a * t * t + ripple
    }
}

/// Pulse width as a fraction of a pulse period.
const WIDTH: f64 = 0.1;
const LOW: f64 = 0.4;
const HIGH: f64 = 4.6;

/// Time spent high by the square wave up to sensor phase `s` (in pulse periods).
fn high_time(s: f64) -> f64 {
    s.floor() * WIDTH + (s - s.floor()).min(WIDTH)
}

/// Small deterministic generator (xorshift64*), uniform in [-1, 1).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        r as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Sample times and the tacho signal for a profile.
fn synthesise(p: &Profile, s: &TachoSettings, rate: f64, secs: f64, noise: f64) -> Signal {
    let dt = 1.0 / rate;
    let per_rad = s.ratio * s.pulses_per_rev as f64 / (2.0 * PI);
    let mut rng = Noise(0x9E37_79B9_7F4A_7C15);
    let n = (secs * rate) as usize + 1;
    let time: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let signal = time
        .iter()
        .map(|&t| {
            let (sa, sb) = (p.angle(t - dt) * per_rad, p.angle(t + dt) * per_rad);
            let duty = if sb > sa {
                (high_time(sb) - high_time(sa)) / (sb - sa)
            } else {
                f64::from(u8::from(sa - sa.floor() < WIDTH))
            };
            LOW + (HIGH - LOW) * (duty + noise * rng.next())
        })
        .collect();
    Signal { time, signal }
}

struct Signal {
    time: Vec<f64>,
    signal: Vec<f64>,
}

/// Largest errors of speed (rpm) and angle (rad) against the profile, at samples inside the
/// valid span and outside the `skip` time ranges.
fn errors(out: &TachoSpeed, p: &Profile, s: &TachoSettings, skip: &[(f64, f64)]) -> (f64, f64) {
    // The first pulse used is at the true edge angle (n + e) pulse angles, e = 0 for rising
    // edges and the pulse width for falling ones; n from the recovered angle at any sample.
    let dphi = s.pulse_angle();
    let e = if s.edge == Edge::Rising { 0.0 } else { WIDTH };
    let mid = out.time.len() / 2;
    let n = ((p.angle(out.time[mid]) - out.angle[mid]) / dphi - e).round();
    let offset = (n + e) * dphi;
    let mut worst = (0.0f64, 0.0f64);
    for (i, &t) in out.time.iter().enumerate() {
        if skip.iter().any(|&(a, b)| t >= a && t <= b) {
            continue;
        }
        worst.0 = worst.0.max((out.rpm[i] - p.speed(t) / RPM).abs());
        worst.1 = worst.1.max((out.angle[i] + offset - p.angle(t)).abs());
    }
    worst
}

/// The profile at 10 kHz with 5 % noise: (max rpm error, max angle error, result).
fn run(p: &Profile, s: &TachoSettings, secs: f64) -> (f64, f64, TachoSpeed) {
    let sig = synthesise(p, s, 10e3, secs, 0.05);
    let out = speed_from_tacho(&sig.time, &sig.signal, s).unwrap();
    let (e_rpm, e_phi) = errors(&out, p, s, &[]);
    (e_rpm, e_phi, out)
}

/// The brief's bounds: speed within 0.1 rpm, angle within 1e-3 rad.
const MAX_RPM_ERROR: f64 = 0.1;
const MAX_ANGLE_ERROR: f64 = 1e-3;

/// Brief point 5(a)-(b): the 60 s run-up (50 to 1400 rpm) at 1 and 4 pulses per revolution,
/// both edges, within the brief's bounds at every sample of the valid span. The edge noise
/// (~5 µs rms, 0.2 rpm per 1-pulse interval at 1400 rpm) needs the 0.8 s window here
/// (measured with the default 0.5 s: up to 0.47 rpm at the record's ends and 1.2e-3 rad at
/// 1 pulse per revolution). Measured maxima: 1 pulse 0.03 / 0.05 rpm (rising / falling),
/// 4 pulses 0.08 rpm, angles 7e-4 to 9e-4 rad. No repair on a clean train; the span starts
/// within one interval (1.2 s at 50 rpm and 1 pulse) of the record's start.
#[test]
fn run_up_within_bounds_for_both_edges_and_pulse_counts() {
    let p = Profile::run_up();
    for ppr in [1, 4] {
        for edge in [Edge::Rising, Edge::Falling] {
            let s = TachoSettings {
                pulses_per_rev: ppr,
                edge,
                smoothing_s: 0.8,
                ..TachoSettings::default()
            };
            let (e_rpm, e_phi, out) = run(&p, &s, 60.0);
            eprintln!("{ppr} ppr, {edge:?}: max errors {e_rpm:.4} rpm, {e_phi:.2e} rad");
            assert!(e_rpm < MAX_RPM_ERROR, "{ppr} ppr {edge:?}: {e_rpm} rpm");
            assert!(e_phi < MAX_ANGLE_ERROR, "{ppr} ppr {edge:?}: {e_phi} rad");
            let q = &out.quality;
            assert!(q.missing.is_empty() && q.extra.is_empty(), "{q:?}");
            assert!(
                q.span.0 < 1.2 / ppr as f64 && q.span.1 > 59.9,
                "{:?}",
                q.span
            );
            assert_eq!(out.time.len(), out.rpm.len());
            assert_eq!(out.time[0], out.first as f64 / 10e3);
        }
    }
}

/// Brief point 5(c): a motor-side tacho, 2 pulses per motor revolution, belt ratio 11.25
/// (22.5 pulses per drum revolution), default window: same bounds on the drum's speed and
/// angle (measured 0.03 rpm, 5e-4 rad), and every pulse found: the drum turns
/// `phi(60 s) / 2 pi` = 725 times, 725 * 22.5 = 16312 pulses.
#[test]
fn motor_side_tacho_gives_drum_speed() {
    let p = Profile::run_up();
    let s = TachoSettings::motor(2, 11.25);
    let (e_rpm, e_phi, out) = run(&p, &s, 60.0);
    eprintln!("motor tacho: max errors {e_rpm:.4} rpm, {e_phi:.2e} rad");
    assert!(e_rpm < MAX_RPM_ERROR, "{e_rpm} rpm");
    assert!(e_phi < MAX_ANGLE_ERROR, "{e_phi} rad");
    let expected = p.angle(60.0) / s.pulse_angle();
    assert!((out.pulses.len() as f64 - expected).abs() <= 1.0);
    assert!(out.quality.missing.is_empty() && out.quality.extra.is_empty());
}

/// Brief point 5(e): the run-up with a motor controller's 0.5 Hz ripple of 2 rpm, measured
/// on the motor side (22.5 pulses per drum turn), default window: within the bounds at
/// every sample (measured 0.07 rpm, the window's flattening of the ripple). A drum tacho
/// samples the ripple once per pulse: at 1 pulse per revolution it cannot resolve 0.5 Hz
/// below 60 rpm at all; above 300 rpm see `a_one_pulse_drum_tacho_follows_a_controller_ripple`.
#[test]
fn speed_ripple_is_followed() {
    let p = Profile {
        ripple: 2.0 * RPM,
        ripple_hz: 0.5,
        ..Profile::run_up()
    };
    let s = TachoSettings::motor(2, 11.25);
    let (e_rpm, e_phi, _) = run(&p, &s, 60.0);
    eprintln!("ripple, motor tacho: max errors {e_rpm:.4} rpm, {e_phi:.2e} rad");
    assert!(e_rpm < MAX_RPM_ERROR, "{e_rpm} rpm");
    assert!(e_phi < MAX_ANGLE_ERROR, "{e_phi} rad");
}

/// Brief point 4: a start from standstill (0 to 450 rpm in 20 s) has long first intervals
/// (2.3 s, then 0.96 s, 0.74 s at 1 pulse per revolution: `t_n = sqrt(2 n 2 pi / a)`) that
/// must not count as missing pulses; the speed stays within the bounds (a constant
/// acceleration is exact for the local quadratic), and the span starts no earlier than the
/// zero-speed point (t = 0).
#[test]
fn start_from_standstill_is_not_a_defect() {
    let p = Profile {
        w0: 0.0,
        ..Profile::run_up()
    };
    for s in [
        TachoSettings::default(),
        TachoSettings {
            pulses_per_rev: 4,
            ..TachoSettings::default()
        },
        TachoSettings::motor(2, 11.25),
    ] {
        let (e_rpm, e_phi, out) = run(&p, &s, 20.0);
        eprintln!(
            "standstill, {} pulses/drum rev: {e_rpm:.4} rpm, {e_phi:.2e} rad, span {:?}",
            s.pulses_per_rev as f64 * s.ratio,
            out.quality.span
        );
        let q = &out.quality;
        assert!(q.missing.is_empty() && q.extra.is_empty(), "{q:?}");
        assert!(e_rpm < MAX_RPM_ERROR, "{e_rpm} rpm");
        assert!(e_phi < MAX_ANGLE_ERROR, "{e_phi} rad");
        assert!(q.span.0 >= 0.0);
    }
}

/// Brief point 5(d): one pulse removed near 20 s and one spurious pulse added near 40 s
/// (0.4 of an interval after a real one, so it splits it 0.4 : 0.6, below the 0.5 limit),
/// 1 pulse per revolution, 0.8 s window as in 5(a): each counted once, at its time, and
/// repaired (the pulse count is the clean train's); away from the defects (two windows and
/// two intervals each side) the bounds of 5(a) hold.
#[test]
fn missing_and_extra_pulses_are_counted_and_repaired() {
    let p = Profile::run_up();
    let s = TachoSettings {
        smoothing_s: 0.8,
        ..TachoSettings::default()
    };
    let mut sig = synthesise(&p, &s, 10e3, 60.0, 0.0);
    let clean = speed_from_tacho(&sig.time, &sig.signal, &s).unwrap();
    let per_rad = 1.0 / (2.0 * PI);
    let (n_missing, n_extra) = (
        (p.angle(20.0) * per_rad).ceil(),
        (p.angle(40.0) * per_rad).floor(),
    );
    for (t, y) in sig.time.iter().zip(sig.signal.iter_mut()) {
        let ph = p.angle(*t) * per_rad;
        if (-0.02..WIDTH + 0.02).contains(&(ph - n_missing)) {
            *y = LOW;
        }
        if (0.0..0.02).contains(&(ph - n_extra - 0.4)) {
            *y = HIGH;
        }
    }
    let mut rng = Noise(7);
    for y in sig.signal.iter_mut() {
        *y += 0.05 * (HIGH - LOW) * rng.next();
    }
    let out = speed_from_tacho(&sig.time, &sig.signal, &s).unwrap();
    let q = &out.quality;
    let exact_time = |n: f64| {
        // Root of w0 t + a t^2 / 2 = 2 pi n.
        let phi = 2.0 * PI * n;
        (-p.w0 + (p.w0 * p.w0 + 2.0 * p.a * phi).sqrt()) / p.a
    };
    assert_eq!(q.missing.len(), 1, "{q:?}");
    assert_eq!(q.extra.len(), 1, "{q:?}");
    // The inserted pulse splits its interval in two equal halves: within a few ms of the
    // true time at 500 rpm (the acceleration shifts the true one by a T^2 / 8 / w).
    assert!((q.missing[0] - exact_time(n_missing)).abs() < 2e-3, "{q:?}");
    assert!(
        (q.extra[0] - exact_time(n_extra + 0.4)).abs() < 1e-3,
        "{q:?}"
    );
    assert_eq!(out.pulses.len(), clean.pulses.len());
    let skip = [
        (q.missing[0] - 2.0, q.missing[0] + 2.0),
        (q.extra[0] - 2.0, q.extra[0] + 2.0),
    ];
    let (e_rpm, e_phi) = errors(&out, &p, &s, &skip);
    eprintln!("defects: away from them {e_rpm:.4} rpm, {e_phi:.2e} rad; {q:?}");
    assert!(e_rpm < MAX_RPM_ERROR, "{e_rpm} rpm");
    assert!(e_phi < MAX_ANGLE_ERROR, "{e_phi} rad");
}

/// Brief point 5(f): settings out of range name their field; too few pulses, a flat signal
/// and noise without two levels are refused; bad input is an error, never a panic.
#[test]
fn refusals() {
    let field = |s: TachoSettings| match s.validate() {
        Err(TachoError::InvalidSetting { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    let base = TachoSettings::default();
    assert_eq!(
        field(TachoSettings {
            pulses_per_rev: 0,
            ..base.clone()
        }),
        "pulses_per_rev"
    );
    for ratio in [0.0, -11.25, f64::NAN, f64::INFINITY] {
        assert_eq!(field(TachoSettings::motor(2, ratio)), "ratio");
    }
    assert_eq!(
        field(TachoSettings {
            hysteresis: Some(-0.1),
            ..base.clone()
        }),
        "hysteresis"
    );
    assert_eq!(
        field(TachoSettings {
            threshold: Some(f64::NAN),
            ..base.clone()
        }),
        "threshold"
    );
    assert_eq!(
        field(TachoSettings {
            smoothing_s: -1.0,
            ..base.clone()
        }),
        "smoothing_s"
    );

    let time: Vec<f64> = (0..10_000).map(|i| i as f64 * 1e-3).collect();
    // Two pulses (rising edges at 2 s and 6 s): fewer than three.
    let two: Vec<f64> = time
        .iter()
        .map(|&t| f64::from(u8::from((2.0..2.5).contains(&t) || (6.0..6.5).contains(&t))))
        .collect();
    assert_eq!(
        speed_from_tacho(&time, &two, &base),
        Err(TachoError::TooFewPulses {
            found: 2,
            needed: 3
        })
    );
    let flat = vec![2.5; time.len()];
    assert!(matches!(
        speed_from_tacho(&time, &flat, &base),
        Err(TachoError::NoPulses { .. })
    ));
    let mut rng = Noise(3);
    let noise: Vec<f64> = time.iter().map(|_| 2.5 + 0.01 * rng.next()).collect();
    assert!(matches!(
        speed_from_tacho(&time, &noise, &base),
        Err(TachoError::NoPulses { .. })
    ));
    assert!(matches!(
        speed_from_tacho(&[], &[], &base),
        Err(TachoError::NoPulses { .. })
    ));
    assert_eq!(
        speed_from_tacho(&time[..5], &two[..4], &base),
        Err(TachoError::LengthMismatch { time: 5, signal: 4 })
    );
    let mut bad = two.clone();
    bad[7] = f64::NAN;
    assert_eq!(
        speed_from_tacho(&time, &bad, &base),
        Err(TachoError::NotFinite {
            what: "signal",
            index: 7
        })
    );
    let mut back = time.clone();
    back[3] = back[2];
    assert!(matches!(
        speed_from_tacho(&back, &two, &base),
        Err(TachoError::TimeNotIncreasing { index: 3, .. })
    ));
    assert_eq!(
        speed_from_tacho(&time, &two, &TachoSettings::motor(0, 11.25)),
        Err(TachoError::InvalidSetting {
            field: "pulses_per_rev",
            value: 0.0,
            expected: "an integer >= 1"
        })
    );
}

/// `drum_rpm_columns` gives what `Signals` takes: the valid span's sample times and the
/// drum speed there (here a constant 600 rpm with 1 pulse per revolution: 10 Hz pulses).
#[test]
fn drum_rpm_columns_match_the_speed() {
    let p = Profile {
        w0: 600.0 * RPM,
        a: 0.0,
        ripple: 0.0,
        ripple_hz: 0.0,
    };
    let s = TachoSettings::default();
    let sig = synthesise(&p, &s, 5e3, 5.0, 0.0);
    let (time, rpm) = drum_rpm_columns(&sig.time, &sig.signal, &s).unwrap();
    assert_eq!(time.len(), rpm.len());
    assert!(
        rpm.iter().all(|r| (r - 600.0).abs() < 1e-3),
        "{:?}",
        &rpm[..3]
    );
    assert!(time.windows(2).all(|w| w[1] > w[0]));
}

/// Brief point 2: without noise the edge times are exact to sub-sample accuracy (the edge
/// spans two samples, the threshold crossing lies on it), so even at 2 kHz, with no
/// averaging (window 0: each pulse's fit interpolates its two neighbours), the speed of the
/// run-up is far below 0.1 rpm off (measured 1e-5 rpm), at 1 and 4 pulses per revolution.
/// (Not the motor side: its 0.2 ms pulses at 1400 drum rpm are shorter than a 2 kHz sample.)
#[test]
fn noise_free_edges_are_sub_sample_accurate() {
    let p = Profile::run_up();
    for ppr in [1, 4] {
        let s = TachoSettings {
            pulses_per_rev: ppr,
            smoothing_s: 0.0,
            ..TachoSettings::default()
        };
        let sig = synthesise(&p, &s, 2e3, 60.0, 0.0);
        let out = speed_from_tacho(&sig.time, &sig.signal, &s).unwrap();
        let (e_rpm, e_phi) = errors(&out, &p, &s, &[]);
        eprintln!("noise-free, 2 kHz, {ppr} ppr: {e_rpm:.2e} rpm, {e_phi:.2e} rad");
        assert!(e_rpm < 1e-3, "{e_rpm} rpm");
        assert!(e_phi < 1e-5, "{e_phi} rad");
    }
}

/// Issue 51 point 4's rig: a 1-pulse drum tacho on a 300 to 700 rpm ramp with a
/// controller's 0.5 Hz ripple of 2 rpm, pulses 0.2 to 0.09 s apart. A window this short
/// holds too few pulses to average, so the fit is a quartic over the nearest five: within
/// 0.1 rpm from the third to the third-to-last pulse, with the 0.25 s window and the
/// default (measured 0.077 rpm with the tests' 5 % edge noise, both windows). A quadratic
/// there (the three-point stencil) errs by the ripple's curvature alone, `2 rpm (w h)^2 / 6`
/// = 0.13 rpm at 300 rpm. The first and last two intervals rest on one-sided fits: 0.13 rpm
/// at 700 rpm, where the edge noise is largest.
#[test]
fn a_one_pulse_drum_tacho_follows_a_controller_ripple() {
    let p = Profile {
        w0: 300.0 * RPM,
        a: 50.0 * RPM,
        ripple: 2.0 * RPM,
        ripple_hz: 0.5,
    };
    for window in [0.25, DEFAULT_SMOOTHING_S] {
        let s = TachoSettings {
            smoothing_s: window,
            ..TachoSettings::default()
        };
        let sig = synthesise(&p, &s, 10e3, 8.0, 0.05);
        let out = speed_from_tacho(&sig.time, &sig.signal, &s).unwrap();
        let n = out.pulses.len();
        let inner = [
            (f64::NEG_INFINITY, out.pulses[2]),
            (out.pulses[n - 3], f64::INFINITY),
        ];
        let (e_rpm, e_phi) = errors(&out, &p, &s, &inner);
        eprintln!("1 ppr with ripple, window {window} s: {e_rpm:.4} rpm, {e_phi:.2e} rad");
        assert!(e_rpm < MAX_RPM_ERROR, "window {window}: {e_rpm} rpm");
        assert!(e_phi < MAX_ANGLE_ERROR, "window {window}: {e_phi} rad");
    }
}
