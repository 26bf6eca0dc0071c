//! Times and other computed values in messages: `{}` of an f64 prints every digit of its
//! binary value (`0.013000000000000001 s`, a sum of steps); [`Rounded`] prints it rounded to 12
//! significant digits (`0.013 s`), far below any tolerance a run works to.

use std::fmt;

/// An f64 displayed rounded to 12 significant digits; infinities and NaN as `{}` prints them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rounded(pub f64);

impl Rounded {
    /// The value rounded to 12 significant digits.
    pub fn value(self) -> f64 {
        if !self.0.is_finite() {
            return self.0;
        }
        format!("{:.11e}", self.0).parse().unwrap_or(self.0)
    }
}

impl fmt::Display for Rounded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.value(), f)
    }
}

#[cfg(test)]
mod tests {
    use super::Rounded;

    #[test]
    fn sums_of_steps_print_as_written() {
        assert_eq!(Rounded(0.013000000000000001).to_string(), "0.013");
        assert_eq!(Rounded(0.1 + 0.2).to_string(), "0.3");
        assert_eq!(Rounded(178.375).to_string(), "178.375");
        assert_eq!(Rounded(1.0 / 3.0).to_string(), "0.333333333333");
        assert_eq!(Rounded(-2.5e-9).to_string(), "-0.0000000025");
        assert_eq!(Rounded(0.0).to_string(), "0");
        assert_eq!(Rounded(f64::INFINITY).to_string(), "inf");
        assert_eq!(Rounded(f64::NAN).to_string(), "NaN");
    }
}
