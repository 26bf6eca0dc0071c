//! Angle and speed between pulses: a local quadratic fit at each pulse, a monotone cubic
//! Hermite curve through the fitted pulses.
//!
//! The speed is not the angle curve's derivative but its own cubic Hermite curve through the
//! fitted speeds and accelerations. Any curve through the fitted angles turns their
//! pulse-to-pulse jitter (what is left of the edge noise, ~1e-5 rad) into a speed error of
//! jitter / interval, which doubled the speed error of a motor-side tacho (0.14 instead of
//! 0.07 rpm); the two curves differ by that jitter only.
//!
//! Why not Fritsch-Carlson's PCHIP as is: its harmonic-mean slopes are only first-order
//! accurate on uneven intervals, which a run-up's pulses are: at 50 rpm, one pulse per
//! revolution and 22.5 rpm/s, the slope errs by ~3 rpm. The local quadratic's slope is exact
//! for a constant acceleration, and Hyman's limiter (`0 <= slope <= 3 min(secants)`) keeps
//! the curve monotone where the data would otherwise make it overshoot. A piecewise-linear
//! speed matching each interval's angle is the other choice, but it is a recurrence that
//! rings on edge-timing noise.

/// Fitted pulses and the curve through them.
pub(super) struct AngleCurve {
    /// Pulse times, s.
    t: Vec<f64>,
    /// Fitted angle at each pulse, rad.
    phi: Vec<f64>,
    /// Slope of the curve at each pulse (fitted, then limited), rad/s.
    w: Vec<f64>,
    /// Fitted speed at each pulse, rad/s.
    speed: Vec<f64>,
    /// Fitted acceleration at each pulse, rad/s^2.
    acc: Vec<f64>,
}

/// Least weight of a pulse in a fit: pulses at (or, to make up three, beyond) the window's
/// edge still count a little, so a fit never rests on fewer than three pulses (an
/// ill-conditioned system), yet one entering the window moves the fit by only ~1e-3 of its
/// residual.
const WEIGHT_FLOOR: f64 = 1e-3;

/// Weighted least-squares quadratic through `(t_j - t_k, phi_j - phi_k)`: value, slope and
/// second derivative at `t_k`. Tricube weights over `half` s, so pulses enter and leave the
/// fit smoothly from one pulse's fit to the next: with a hard window the fitted angles of
/// neighbouring pulses jump by the noise of the pulse that enters, and the short secant
/// between them turns that into a speed error. Times are scaled to order 1 for the normal
/// equations.
fn local_quadratic(t: &[f64], phi: &[f64], k: usize, half: f64) -> [f64; 3] {
    let scale = t
        .iter()
        .map(|tj| (tj - t[k]).abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut s = [0.0; 5];
    let mut r = [0.0; 3];
    for (tj, pj) in t.iter().zip(phi) {
        let d = tj - t[k];
        let q = (1.0 - (d.abs() / half.max(f64::MIN_POSITIVE)).powi(3)).max(0.0);
        let wt = (q * q * q).max(WEIGHT_FLOOR);
        let x = d / scale;
        let y = pj - phi[k];
        let mut xp = wt;
        for (i, si) in s.iter_mut().enumerate() {
            *si += xp;
            if i < 3 {
                r[i] += xp * y;
            }
            xp *= x;
        }
    }
    let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    let c = solve3(a, r).unwrap_or([0.0, 0.0, 0.0]);
    [c[0], c[1] / scale, 2.0 * c[2] / (scale * scale)]
}

/// Cramer's rule for a symmetric positive definite 3x3 system (`None` if singular).
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if !d.is_finite() || d.abs() <= 1e-300 {
        return None;
    }
    let mut x = [0.0; 3];
    for (col, xi) in x.iter_mut().enumerate() {
        let mut m = a;
        for row in 0..3 {
            m[row][col] = b[row];
        }
        *xi = det(m) / d;
    }
    Some(x)
}

/// Pulses `lo..=hi` of pulse `k`'s fit: those within `half` s, at least one on each side
/// where there is one, at least three in all. Not widened near the record's ends: a
/// one-sided fit over more time errs more on a changing acceleration (a 0.5 Hz speed ripple:
/// 0.12 rpm instead of 0.07 rpm with a 1.5-fold window) than it gains on noise.
fn fit_range(t: &[f64], k: usize, half: f64) -> (usize, usize) {
    let n = t.len();
    let mut lo = t.partition_point(|&x| x < t[k] - half).min(k);
    let mut hi = (t.partition_point(|&x| x <= t[k] + half) - 1).max(k);
    if k > 0 {
        lo = lo.min(k - 1);
    }
    if k + 1 < n {
        hi = hi.max(k + 1);
    }
    while hi - lo < 2 {
        if lo > 0 {
            lo -= 1;
        } else {
            hi += 1;
        }
    }
    (lo, hi)
}

impl AngleCurve {
    /// Fit pulses at `times` (at least three), each `dphi` after the previous, over `window` s.
    pub fn new(times: &[f64], dphi: f64, window: f64) -> AngleCurve {
        let n = times.len();
        let raw: Vec<f64> = (0..n).map(|k| k as f64 * dphi).collect();
        let fits: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let (lo, hi) = fit_range(times, k, 0.5 * window);
                local_quadratic(&times[lo..=hi], &raw[lo..=hi], k - lo, 0.5 * window)
            })
            .collect();
        let mut phi: Vec<f64> = raw.iter().zip(&fits).map(|(p, f)| p + f[0]).collect();
        // The fit moves each pulse by the edge-timing noise, a tiny fraction of a pulse
        // angle; should it ever reorder them, the measured angles are used.
        if phi.windows(2).any(|p| p[1] <= p[0]) {
            phi = raw;
        }
        let secant = |k: usize| (phi[k + 1] - phi[k]) / (times[k + 1] - times[k]);
        let w: Vec<f64> = (0..n)
            .map(|k| {
                let left = if k > 0 { secant(k - 1) } else { f64::INFINITY };
                let right = if k + 1 < n { secant(k) } else { f64::INFINITY };
                fits[k][1].clamp(0.0, 3.0 * left.min(right))
            })
            .collect();
        AngleCurve {
            t: times.to_vec(),
            phi,
            w,
            speed: fits.iter().map(|f| f[1].max(0.0)).collect(),
            acc: fits.iter().map(|f| f[2]).collect(),
        }
    }

    /// Valid time span within the record `[t0, t1]`: one pulse interval beyond the first
    /// and the last pulse, and no farther than where the extrapolated speed reaches zero.
    pub fn span(&self, t0: f64, t1: f64) -> (f64, f64) {
        let n = self.t.len();
        let mut start = self.t[0] - (self.t[1] - self.t[0]);
        if self.acc[0] > 0.0 {
            start = start.max(self.t[0] - self.speed[0] / self.acc[0]);
        }
        let mut end = self.t[n - 1] + (self.t[n - 1] - self.t[n - 2]);
        if self.acc[n - 1] < 0.0 {
            end = end.min(self.t[n - 1] - self.speed[n - 1] / self.acc[n - 1]);
        }
        (start.max(t0), end.min(t1))
    }

    /// Angle (rad) and speed (rad/s) at sorted `times` inside the span.
    pub fn evaluate(&self, times: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = self.t.len();
        let mut seg = 0;
        times
            .iter()
            .map(|&t| {
                if t < self.t[0] {
                    return self.extrapolate(0, t);
                }
                if t > self.t[n - 1] {
                    return self.extrapolate(n - 1, t);
                }
                while seg + 2 < n && t > self.t[seg + 1] {
                    seg += 1;
                }
                self.hermite(seg, t)
            })
            .unzip()
    }

    /// Constant acceleration from pulse `k`'s fit.
    fn extrapolate(&self, k: usize, t: f64) -> (f64, f64) {
        let d = t - self.t[k];
        let (w, a) = (self.speed[k], self.acc[k]);
        (self.phi[k] + w * d + 0.5 * a * d * d, (w + a * d).max(0.0))
    }

    /// Segment `k` (pulse `k` to `k + 1`) at `t`: the angle's cubic Hermite curve through the
    /// fitted angles and limited slopes, and the speed's through the fitted speeds and
    /// accelerations (not the angle curve's derivative: see the module's notes).
    fn hermite(&self, k: usize, t: f64) -> (f64, f64) {
        let h = self.t[k + 1] - self.t[k];
        let u = (t - self.t[k]) / h;
        let angle = cubic(
            u,
            [self.phi[k], self.phi[k + 1]],
            [self.w[k] * h, self.w[k + 1] * h],
        );
        let speed = cubic(
            u,
            [self.speed[k], self.speed[k + 1]],
            [self.acc[k] * h, self.acc[k + 1] * h],
        );
        (angle, speed.max(0.0))
    }
}

/// Cubic Hermite basis at `u` in [0, 1]: end values `p`, end slopes `m` (per unit `u`).
fn cubic(u: f64, p: [f64; 2], m: [f64; 2]) -> f64 {
    let u2 = u * u;
    let u3 = u2 * u;
    (2.0 * u3 - 3.0 * u2 + 1.0) * p[0]
        + (u3 - 2.0 * u2 + u) * m[0]
        + (3.0 * u2 - 2.0 * u3) * p[1]
        + (u3 - u2) * m[1]
}
