//! The scalar the one derivation is written over. With `f64` the derivation is the interpreter;
//! with a symbolic scalar that records an expression graph it is the code generator's input.
//! Rule for the derivation: branch on the model's structure only, never on a scalar's value, so
//! a traced graph is valid for every state.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
{
    /// A constant.
    fn c(v: f64) -> Self;
    fn sqrt(self) -> Self;
    fn atan(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    /// The larger of two values (`f64::max`): a clamp that the derivation writes without
    /// branching on a value, so a traced graph holds on both sides of it. Its derivative is the
    /// larger operand's (the first's at a tie).
    fn max(self, o: Self) -> Self;
    /// self^e for a constant exponent (`f64::powf`); the derivative e self^(e-1) is 0 at 0 for
    /// e > 1 (a Hertzian contact force is C1 at first touch).
    fn powf(self, e: f64) -> Self;
    fn zero() -> Self {
        Self::c(0.0)
    }
    /// y += A x for a constant matrix A (column-major: `y.len()` rows, `x.len()` columns): the
    /// modal projections (W q at a marker, W^T F into the modes). Written as this one hook so
    /// the symbolic scalar records it as one node over a static table, and generated code
    /// loops over the table (and vectorises) instead of spelling out every entry. Every
    /// implementation adds in this order (column by column, y_i + a_ij x_j), so the
    /// interpreter and generated code agree to the bit.
    #[inline]
    fn mat_vec(a: &[f64], x: &[Self], y: &mut [Self]) {
        let r = y.len();
        debug_assert_eq!(a.len(), r * x.len());
        for (col, xj) in a.chunks_exact(r.max(1)).zip(x) {
            for (yi, aij) in y.iter_mut().zip(col) {
                *yi += *xj * *aij;
            }
        }
    }
}

impl Scalar for f64 {
    #[inline(always)]
    fn c(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn atan(self) -> Self {
        f64::atan(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f64::max(self, o)
    }
    #[inline(always)]
    fn powf(self, e: f64) -> Self {
        f64::powf(self, e)
    }
}

/// y += A x (A column-major, `cols` columns) with x given entry by entry: for an x that is
/// formed first (scaled coordinates) without a heap buffer. The columns go through
/// `Scalar::mat_vec` in chunks of 16, in order, so the sum is the one a single call makes.
pub fn mat_vec_from<T: Scalar>(a: &[f64], cols: usize, x: impl Fn(usize) -> T, y: &mut [T]) {
    const CHUNK: usize = 16;
    let r = y.len();
    debug_assert_eq!(a.len(), r * cols);
    let mut buf = [T::zero(); CHUNK];
    let mut j = 0;
    while j < cols {
        let m = (cols - j).min(CHUNK);
        for (k, b) in buf[..m].iter_mut().enumerate() {
            *b = x(j + k);
        }
        T::mat_vec(&a[j * r..(j + m) * r], &buf[..m], y);
        j += m;
    }
}
