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
    fn zero() -> Self {
        Self::c(0.0)
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
}
