//! Forward-mode dual numbers with `N` derivative lanes: the one derivation evaluated over
//! `Dual<N>` gives h and its derivatives along N seeded directions at once, exactly (no
//! step size), so the Jacobians dh/dq and dh/dq' come from the same code as h itself.

use crate::scalar::Scalar;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// Lanes of the dual numbers the Jacobians are evaluated with: 8 f64 are one cache line and
/// two AVX-512 or four AVX registers.
pub const LANES: usize = 8;

/// v + sum_k d_k eps_k with eps_k eps_l = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<const N: usize> {
    pub v: f64,
    pub d: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// A variable with derivative 1 along lane `k` (no lane: `k >= N`).
    pub fn seed(v: f64, k: usize) -> Self {
        let mut d = [0.0; N];
        if k < N {
            d[k] = 1.0;
        }
        Dual { v, d }
    }
    /// Chain rule for a function with value `v` and derivative `dv` at self.v.
    #[inline(always)]
    fn chain(self, v: f64, dv: f64) -> Self {
        let mut d = self.d;
        for x in &mut d {
            *x *= dv;
        }
        Dual { v, d }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for k in 0..N {
            self.d[k] += o.d[k];
        }
        self
    }
}
impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: Self) -> Self {
        self.v -= o.v;
        for k in 0..N {
            self.d[k] -= o.d[k];
        }
        self
    }
}
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut d = [0.0; N];
        for k in 0..N {
            d[k] = self.d[k] * o.v + self.v * o.d[k];
        }
        Dual { v: self.v * o.v, d }
    }
}
impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        let v = self.v * inv;
        let mut d = [0.0; N];
        for k in 0..N {
            d[k] = (self.d[k] - v * o.d[k]) * inv;
        }
        Dual { v, d }
    }
}
impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.chain(-self.v, -1.0)
    }
}
impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: f64) -> Self {
        self.v += o;
        self
    }
}
impl<const N: usize> Sub<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: f64) -> Self {
        self.v -= o;
        self
    }
}
impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: f64) -> Self {
        self.chain(self.v * o, o)
    }
}
impl<const N: usize> Div<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: f64) -> Self {
        self.chain(self.v / o, 1.0 / o)
    }
}
impl<const N: usize> AddAssign for Dual<N> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl<const N: usize> SubAssign for Dual<N> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl<const N: usize> Scalar for Dual<N> {
    #[inline(always)]
    fn c(v: f64) -> Self {
        Dual { v, d: [0.0; N] }
    }
    /// At 0 the derivative is infinite: only lanes that move keep it, a constant stays
    /// constant (sqrt(omega^2) of the prescribed speed at rest, in the gasket's law).
    fn sqrt(self) -> Self {
        let r = self.v.sqrt();
        let dv = 0.5 / r;
        let mut d = self.d;
        for x in &mut d {
            if *x != 0.0 {
                *x *= dv;
            }
        }
        Dual { v: r, d }
    }
    fn atan(self) -> Self {
        self.chain(self.v.atan(), 1.0 / (1.0 + self.v * self.v))
    }
    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn max(self, o: Self) -> Self {
        if self.v >= o.v { self } else { o }
    }
    /// As `sqrt`: only lanes that move take e v^(e-1), so a constant stays constant where the
    /// factor is infinite (v = 0, e < 1).
    fn powf(self, e: f64) -> Self {
        let dv = e * self.v.powf(e - 1.0);
        let mut d = self.d;
        for x in &mut d {
            if *x != 0.0 {
                *x *= dv;
            }
        }
        Dual {
            v: self.v.powf(e),
            d,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each rule against its closed-form derivative at one point (d/dx of the textbook
    /// functions), through a composite so that the chain rule is exercised too.
    #[test]
    fn derivatives_match_closed_forms() {
        let x = Dual::<2>::seed(0.7, 0);
        let y = Dual::<2>::seed(-1.3, 1);
        // f = sin(x) y + atan(x y) / sqrt(x) - cos(y) / (x + 2) * 3
        let f = x.sin() * y + (x * y).atan() / x.sqrt() - y.cos() / (x + 2.0) * 3.0;
        let (xv, yv) = (0.7f64, -1.3f64);
        let a = 1.0 / (1.0 + (xv * yv).powi(2));
        let dfdx = xv.cos() * yv + a * yv / xv.sqrt() - 0.5 * (xv * yv).atan() / xv.powf(1.5)
            + 3.0 * yv.cos() / (xv + 2.0).powi(2);
        let dfdy = xv.sin() + a * xv / xv.sqrt() + 3.0 * yv.sin() / (xv + 2.0);
        assert!((f.d[0] - dfdx).abs() < 1e-14, "{} vs {dfdx}", f.d[0]);
        assert!((f.d[1] - dfdy).abs() < 1e-14, "{} vs {dfdy}", f.d[1]);
        let g = -(x - y) * 2.0;
        assert_eq!(g.d, [-2.0, 2.0]);
        // A constant under a root at 0 stays a constant (no 0 x inf).
        assert_eq!(Dual::<2>::c(0.0).sqrt().d, [0.0, 0.0]);
        // max takes the larger operand's derivatives; powf's is e x^(e-1), 0 at 0 for e > 1.
        assert_eq!(x.max(y).d, [1.0, 0.0]);
        assert_eq!(y.max(x * 0.0).d, [0.0, 0.0]);
        let p = (x * 2.0).powf(1.5);
        assert!((p.v - 1.4f64.powf(1.5)).abs() < 1e-15);
        assert!((p.d[0] - 3.0 * 1.4f64.sqrt()).abs() < 1e-14, "{:?}", p.d);
        assert_eq!((x - 0.7).powf(1.5).d, [0.0, 0.0]);
    }
}
