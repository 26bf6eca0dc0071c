//! 3-vectors over any `Scalar`: just what the derivation needs, so it stays traceable.

use crate::scalar::Scalar;
use std::ops::{Add, Mul, Neg, Sub};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct V<T>(pub [T; 3]);

impl<T: Scalar> V<T> {
    pub fn zero() -> Self {
        V([T::zero(); 3])
    }
    /// A constant vector.
    pub fn c(v: [f64; 3]) -> Self {
        V(v.map(T::c))
    }
    /// k c for a constant c, the constant kept on the f64 side (a dual number's lanes are
    /// scaled, not multiplied out against zero lanes; same bits over f64).
    #[inline(always)]
    pub fn scaled(c: [f64; 3], k: T) -> Self {
        V([k * c[0], k * c[1], k * c[2]])
    }
    /// self . c for a constant c (as `scaled`).
    #[inline(always)]
    pub fn dot_c(self, c: [f64; 3]) -> T {
        self.0[0] * c[0] + self.0[1] * c[1] + self.0[2] * c[2]
    }
    pub fn from_slice(s: &[T]) -> Self {
        V([s[0], s[1], s[2]])
    }
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        let (a, b) = (self.0, o.0);
        V([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }
    #[inline(always)]
    pub fn scale(self, k: T) -> Self {
        V(self.0.map(|x| x * k))
    }
    pub fn norm(self) -> T {
        self.dot(self).sqrt()
    }
    /// Component normal to the unit vector `n`.
    pub fn reject(self, n: Self) -> Self {
        self - n.scale(self.dot(n))
    }
    /// Add into a slice at offset `at`.
    pub fn add_to(self, out: &mut [T], at: usize) {
        for k in 0..3 {
            out[at + k] += self.0[k];
        }
    }
}

impl<T: Scalar> Add for V<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}
impl<T: Scalar> Sub for V<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}
impl<T: Scalar> Neg for V<T> {
    type Output = Self;
    fn neg(self) -> Self {
        V(self.0.map(|x| -x))
    }
}
impl<T: Scalar> Mul<f64> for V<T> {
    type Output = Self;
    fn mul(self, k: f64) -> Self {
        V(self.0.map(|x| x * k))
    }
}

/// Plain f64 helpers for set-up code (constants of the model).
pub mod f {
    pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }
    pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    pub fn scale(a: [f64; 3], k: f64) -> [f64; 3] {
        [a[0] * k, a[1] * k, a[2] * k]
    }
    pub fn norm(a: [f64; 3]) -> f64 {
        (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
    }
    pub fn unit(a: [f64; 3]) -> [f64; 3] {
        let n = norm(a);
        [a[0] / n, a[1] / n, a[2] / n]
    }
    /// Two unit normals to the unit `axis`, with it a right-handed frame (axis, n1, n2): n1
    /// from the global axis least aligned with `axis`, made orthogonal (a rod's bending axes,
    /// a bolt's tangents).
    pub fn normals(axis: [f64; 3]) -> [[f64; 3]; 2] {
        let k = (0..3)
            .min_by(|&i, &j| axis[i].abs().total_cmp(&axis[j].abs()))
            .expect("three axes");
        let mut e = [0.0; 3];
        e[k] = 1.0;
        let n1 = unit(cross(axis, e));
        [n1, cross(axis, n1)]
    }
    /// Distance of `p` from the line through `point` along `axis` (any nonzero length): how
    /// far a point lies off a rotor's or a spin's axis.
    pub fn off_line(p: [f64; 3], point: [f64; 3], axis: [f64; 3]) -> f64 {
        norm(cross(sub(p, point), unit(axis)))
    }
}
