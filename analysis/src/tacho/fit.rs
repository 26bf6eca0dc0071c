//! Angle and speed between pulses: a local polynomial fit at each pulse, a monotone cubic
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
//! revolution and 22.5 rpm/s, the slope errs by ~3 rpm. The local fit's slope is exact
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

/// Most coefficients of a local fit (a quartic).
const MAX_TERMS: usize = 5;

/// Pulses in a window below which the fit is a quartic. On a symmetric window a quadratic's
/// slope is the straight line's and errs by the speed's curvature: a 0.5 Hz ripple of 2 rpm
/// sampled by a 1-pulse drum tacho at 300 rpm (pulses 0.2 s apart) errs by 0.13 rpm, the
/// three-point stencil's `(w h)^2 / 6`. A quartic's slope errs by the fifth derivative only
/// (0.01 rpm there) but carries ~2x the quadratic's noise over the same pulses: worth it
/// where the window holds too few pulses to average noise anyway, not where it holds many
/// (a motor-side tacho). Local polynomials of even degree for a slope, after Fan & Gijbels
/// (1996, Local Polynomial Modelling, sec. 3.3): odd degrees add variance, not accuracy.
const FEW_PULSES: usize = 7;

/// Weighted least-squares polynomial of `degree` (2 or 4) through
/// `(t_j - t_k, phi_j - phi_k)`: value, slope and second derivative at `t_k`. Tricube
/// weights over `half` s, so pulses enter and leave the fit smoothly from one pulse's fit to
/// the next: with a hard window the fitted angles of neighbouring pulses jump by the noise of
/// the pulse that enters, and the short secant between them turns that into a speed error.
/// Times are scaled to order 1 for the normal equations.
fn local_fit(t: &[f64], phi: &[f64], k: usize, half: f64, degree: usize) -> [f64; 3] {
    let terms = degree + 1;
    let scale = t
        .iter()
        .map(|tj| (tj - t[k]).abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut s = [0.0; 2 * MAX_TERMS - 1];
    let mut r = [0.0; MAX_TERMS];
    for (tj, pj) in t.iter().zip(phi) {
        let d = tj - t[k];
        let q = (1.0 - (d.abs() / half.max(f64::MIN_POSITIVE)).powi(3)).max(0.0);
        let wt = (q * q * q).max(WEIGHT_FLOOR);
        let x = d / scale;
        let y = pj - phi[k];
        let mut xp = wt;
        for (i, si) in s.iter_mut().take(2 * terms - 1).enumerate() {
            *si += xp;
            if i < terms {
                r[i] += xp * y;
            }
            xp *= x;
        }
    }
    let mut a = [[0.0; MAX_TERMS]; MAX_TERMS];
    for (i, row) in a.iter_mut().enumerate().take(terms) {
        for (j, aij) in row.iter_mut().enumerate().take(terms) {
            *aij = s[i + j];
        }
    }
    let c = solve(&mut a, &mut r, terms).unwrap_or([0.0; MAX_TERMS]);
    [c[0], c[1] / scale, 2.0 * c[2] / (scale * scale)]
}

/// Gaussian elimination with partial pivoting on the leading `m` rows and columns (`None` if
/// singular).
fn solve(
    a: &mut [[f64; MAX_TERMS]; MAX_TERMS],
    b: &mut [f64; MAX_TERMS],
    m: usize,
) -> Option<[f64; MAX_TERMS]> {
    let norm = a.iter().flatten().fold(0.0f64, |x, v| x.max(v.abs()));
    for col in 0..m {
        let piv = (col..m).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() <= 1e-14 * norm {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..m {
            let f = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (x, p) in a[row][col..m].iter_mut().zip(&pivot_row[col..m]) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; MAX_TERMS];
    for row in (0..m).rev() {
        let tail: f64 = (row + 1..m).map(|j| a[row][j] * x[j]).sum();
        x[row] = (b[row] - tail) / a[row][row];
    }
    Some(x)
}

/// Pulses `lo..=hi` of pulse `k`'s fit and the fit's degree. The pulses within `half` s, at
/// least one on each side where there is one, at least three in all: a quadratic. Where
/// those are fewer than [`FEW_PULSES`], a quartic over at least five, two on each side where
/// there are two (see [`FEW_PULSES`]); not at the first and last pulse, where a one-sided
/// quartic's slope carries 2.2x the one-sided quadratic's noise (its stencil
/// `(-25, 48, -36, 16, -3) / 12h` against `(-3, 4, -1) / 2h`). Not widened near the ends either: a one-sided fit over more
/// time errs more on a changing acceleration than it gains on noise.
fn fit_range(t: &[f64], k: usize, half: f64) -> (usize, usize, usize) {
    let n = t.len();
    let lo = t.partition_point(|&x| x < t[k] - half).min(k);
    let hi = (t.partition_point(|&x| x <= t[k] + half) - 1).max(k);
    if hi - lo + 1 < FEW_PULSES && k >= 1 && k + 1 < n && n >= 5 {
        let lo = lo.min(k.saturating_sub(2)).min(n - 5);
        let hi = hi.max(k + 2).max(4).min(n - 1);
        return (lo, hi, 4);
    }
    let mut lo = lo.min(k.saturating_sub(1));
    let mut hi = hi.max((k + 1).min(n - 1));
    while hi - lo < 2 {
        if lo > 0 {
            lo -= 1;
        } else {
            hi += 1;
        }
    }
    (lo, hi, 2)
}

impl AngleCurve {
    /// Fit pulses at `times` (at least three), each `dphi` after the previous, over `window` s.
    pub fn new(times: &[f64], dphi: f64, window: f64) -> AngleCurve {
        let n = times.len();
        let raw: Vec<f64> = (0..n).map(|k| k as f64 * dphi).collect();
        let fits: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let (lo, hi, degree) = fit_range(times, k, 0.5 * window);
                local_fit(&times[lo..=hi], &raw[lo..=hi], k - lo, 0.5 * window, degree)
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
