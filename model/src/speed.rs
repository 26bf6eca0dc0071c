//! Prescribed drum speed: piecewise-linear rpm(t); the angle is its exact integral (piecewise
//! quadratic), the acceleration piecewise constant. Breakpoints are discontinuities of the
//! acceleration, so the driver restarts the integrator there.

use crate::equations::Drive;
use std::f64::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Speed {
    t: Vec<f64>,
    /// rad/s at the breakpoints.
    w: Vec<f64>,
    /// Drum angle at the breakpoints, rad.
    phi: Vec<f64>,
}

impl Speed {
    /// From (time s, rpm) rows, strictly increasing in time (the checker's job). The speed is
    /// constant before the first and after the last row; the angle is 0 at t = 0.
    pub fn new(table: &[[f64; 2]]) -> Speed {
        assert!(!table.is_empty(), "speed profile without points");
        let t: Vec<f64> = table.iter().map(|r| r[0]).collect();
        let w: Vec<f64> = table.iter().map(|r| r[1] * PI / 30.0).collect();
        let mut phi = vec![w[0] * t[0]];
        for i in 1..t.len() {
            phi.push(phi[i - 1] + 0.5 * (w[i - 1] + w[i]) * (t[i] - t[i - 1]));
        }
        Speed { t, w, phi }
    }

    /// Angle, speed and acceleration of the drum at time t.
    pub fn drive(&self, t: f64) -> Drive<f64> {
        let n = self.t.len();
        if t <= self.t[0] {
            return Drive {
                phi: self.phi[0] + self.w[0] * (t - self.t[0]),
                omega: self.w[0],
                omega_dot: 0.0,
            };
        }
        if t >= self.t[n - 1] {
            return Drive {
                phi: self.phi[n - 1] + self.w[n - 1] * (t - self.t[n - 1]),
                omega: self.w[n - 1],
                omega_dot: 0.0,
            };
        }
        // Segment i with t[i] <= t < t[i+1].
        let i = self.t.partition_point(|&x| x <= t) - 1;
        let dt = t - self.t[i];
        let a = (self.w[i + 1] - self.w[i]) / (self.t[i + 1] - self.t[i]);
        Drive {
            phi: self.phi[i] + self.w[i] * dt + 0.5 * a * dt * dt,
            omega: self.w[i] + a * dt,
            omega_dot: a,
        }
    }

    /// Drum speed in rpm at t.
    pub fn rpm(&self, t: f64) -> f64 {
        self.drive(t).omega * 30.0 / PI
    }

    /// Times where the acceleration jumps.
    pub fn breakpoints(&self) -> &[f64] {
        &self.t
    }

    /// Where an integration over (t0, t1] restarts: the breakpoints inside, then t1.
    pub fn stops(&self, t0: f64, t1: f64) -> Vec<f64> {
        let mut stops: Vec<f64> = self
            .t
            .iter()
            .copied()
            .filter(|&b| b > t0 && b < t1)
            .collect();
        stops.push(t1);
        stops
    }

    /// The profile's breakpoints, s (what [`Speed::stops`] filters, without allocating).
    pub fn knots(&self) -> &[f64] {
        &self.t
    }

    /// The last breakpoint: the end of the profile.
    pub fn end(&self) -> f64 {
        *self.t.last().expect("non-empty")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_is_the_integral_of_speed() {
        // Reference profile: 0 -> 93 rpm in 5 s, hold to 15 s, 8 rpm/s to 1400 rpm.
        let s = Speed::new(&[[0.0, 0.0], [5.0, 93.0], [15.0, 93.0], [178.375, 1400.0]]);
        // Closed form: 93 rpm * 5 s / 2 + 93 rpm * 10 s, in revolutions, times 2 pi.
        let rev = 93.0 / 60.0 * (2.5 + 10.0);
        assert!((s.drive(15.0).phi - rev * 2.0 * PI).abs() < 1e-9);
        let d = s.drive(100.0);
        assert!((d.omega * 30.0 / PI - (93.0 + 8.0 * 85.0)).abs() < 1e-9);
        assert!((d.omega_dot * 30.0 / PI - 8.0).abs() < 1e-12);
        // Numerical quadrature of omega cross-checks phi across all segments.
        let n = 200_000;
        let mut acc = 0.0;
        let t_end = 200.0;
        for k in 0..n {
            let t = (k as f64 + 0.5) * t_end / n as f64;
            acc += s.drive(t).omega * t_end / n as f64;
        }
        assert!((acc - s.drive(t_end).phi).abs() < 1e-6 * acc);
    }
}
