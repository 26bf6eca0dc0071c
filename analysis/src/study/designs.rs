//! Designs of experiments as data: which parameter values to run, chosen without any knowledge of
//! the simulation. Every design is a list of variants, each one value per parameter in the order
//! of `bounds` (`(lo, hi)` per parameter): points of the unit cube mapped linearly to the ranges.
//!
//! - [`grid`]: every combination of evenly spaced levels (small studies, plots over one or two
//!   parameters);
//! - [`lhs`]: a Latin hypercube (each parameter's range cut into `n` strata, one point in each);
//! - [`sobol`]: Burley's Owen-scrambled Sobol sequence (quasi-random, fills the cube evenly);
//! - [`saltelli`]: Saltelli's scheme for first-order and total Sobol indices
//!   ([`super::sobol::indices`]), in SALib's row layout.
//!
//! The random designs are reproducible: the same seed gives the same points on every platform
//! (ChaCha8 for the Latin hypercube, hash-based scrambling for Sobol).

use rand::rngs::ChaCha8Rng;
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};

use crate::error::AnalysisError;

/// Points the Sobol sequence gives (sobol_burley's limit, 2^16).
pub const MAX_SOBOL_POINTS: usize = 1 << 16;
/// Dimensions of the Sobol sequence: [`saltelli`] takes two per parameter, so at most half.
pub const MAX_SOBOL_DIMS: usize = sobol_burley::NUM_DIMENSIONS as usize;
/// Most variants a design may hold: a mistyped level count fails here instead of filling memory.
pub const MAX_VARIANTS: usize = 10_000_000;

fn invalid(msg: String) -> AnalysisError {
    AnalysisError::InvalidStudy(msg)
}

/// Every parameter needs a finite range with `lo < hi`: a fixed value is no study parameter.
fn check_bounds(bounds: &[(f64, f64)]) -> Result<(), AnalysisError> {
    if bounds.is_empty() {
        return Err(invalid("no parameters".into()));
    }
    for (j, &(lo, hi)) in bounds.iter().enumerate() {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(invalid(format!(
                "parameter {j}: bounds ({lo}, {hi}) must be finite with lo < hi"
            )));
        }
    }
    Ok(())
}

fn check_count(n: usize, what: &str) -> Result<(), AnalysisError> {
    if n == 0 || n > MAX_VARIANTS {
        return Err(invalid(format!("{what} {n} not in 1..={MAX_VARIANTS}")));
    }
    Ok(())
}

/// A unit-cube point mapped to the parameters' ranges.
fn to_bounds(bounds: &[(f64, f64)], unit: impl Iterator<Item = f64>) -> Vec<f64> {
    bounds
        .iter()
        .zip(unit)
        .map(|(&(lo, hi), u)| lo + u * (hi - lo))
        .collect()
}

/// Full factorial grid: `levels[j]` evenly spaced values of parameter `j` from `lo` to `hi`
/// inclusive (one level: the midpoint), every combination once. Rows in row-major order: the
/// first parameter changes slowest, the last fastest (as nested loops in parameter order).
pub fn grid(bounds: &[(f64, f64)], levels: &[usize]) -> Result<Vec<Vec<f64>>, AnalysisError> {
    check_bounds(bounds)?;
    if levels.len() != bounds.len() {
        return Err(invalid(format!(
            "{} level counts for {} parameters",
            levels.len(),
            bounds.len()
        )));
    }
    let count = levels
        .iter()
        .try_fold(1usize, |acc, &k| acc.checked_mul(k))
        .unwrap_or(usize::MAX);
    check_count(count, "grid variants")?;
    let unit = |j: usize, k: usize| match levels[j] {
        1 => 0.5,
        m => k as f64 / (m - 1) as f64,
    };
    Ok((0..count)
        .map(|mut r| {
            // Digits of r in the mixed radix `levels`, last parameter least significant.
            let mut digit = vec![0; levels.len()];
            for j in (0..levels.len()).rev() {
                digit[j] = r % levels[j];
                r /= levels[j];
            }
            to_bounds(bounds, (0..levels.len()).map(|j| unit(j, digit[j])))
        })
        .collect())
}

/// Latin hypercube of `n` variants: each parameter's range cut into `n` equal strata, exactly one
/// variant in each, at a uniformly random place within it; the strata paired at random across
/// parameters. Seeded (ChaCha8), so the same seed gives the same design.
pub fn lhs(bounds: &[(f64, f64)], n: usize, seed: u64) -> Result<Vec<Vec<f64>>, AnalysisError> {
    check_bounds(bounds)?;
    check_count(n, "Latin hypercube variants")?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut unit = vec![vec![0.0; bounds.len()]; n];
    let mut strata: Vec<usize> = (0..n).collect();
    for j in 0..bounds.len() {
        strata.shuffle(&mut rng);
        for (row, &s) in unit.iter_mut().zip(&strata) {
            row[j] = (s as f64 + rng.random::<f64>()) / n as f64;
        }
    }
    Ok(unit
        .into_iter()
        .map(|u| to_bounds(bounds, u.into_iter()))
        .collect())
}

/// The first `n` points of a `dims`-dimensional Owen-scrambled Sobol sequence in the unit cube.
/// sobol_burley's seed is 32 bits: `seed`'s two halves are folded into it.
fn sobol_unit(n: usize, dims: usize, seed: u64) -> Result<Vec<Vec<f64>>, AnalysisError> {
    if n == 0 || n > MAX_SOBOL_POINTS {
        return Err(invalid(format!(
            "Sobol points {n} not in 1..={MAX_SOBOL_POINTS}"
        )));
    }
    if dims > MAX_SOBOL_DIMS {
        return Err(invalid(format!(
            "Sobol sequence of {dims} dimensions: at most {MAX_SOBOL_DIMS}"
        )));
    }
    let seed = (seed ^ (seed >> 32)) as u32;
    Ok((0..n as u32)
        .map(|i| {
            (0..dims as u32)
                .map(|d| sobol_burley::sample(i, d, seed) as f64)
                .collect()
        })
        .collect())
}

/// The first `n` points of a scrambled Sobol sequence (Burley's hash-based Owen scrambling, so
/// the first point is no corner and none is skipped): a quasi-random design that fills the
/// ranges more evenly than random points. Power-of-two `n` keeps the sequence's balance (each
/// parameter's range then holds one point in each of `n` equal strata). At most
/// [`MAX_SOBOL_POINTS`] points and [`MAX_SOBOL_DIMS`] parameters.
pub fn sobol(bounds: &[(f64, f64)], n: usize, seed: u64) -> Result<Vec<Vec<f64>>, AnalysisError> {
    check_bounds(bounds)?;
    Ok(sobol_unit(n, bounds.len(), seed)?
        .into_iter()
        .map(|u| to_bounds(bounds, u.into_iter()))
        .collect())
}

/// Which variant of a Saltelli sample is which: `base_rows` (N) blocks of `params + 2` (D + 2)
/// consecutive rows each, block `i` being `A_i, AB_1,i, .., AB_D,i, B_i`. This is SALib's layout
/// (`SALib.sample.sobol.sample(problem, N, calc_second_order=False)`), so outputs in this order
/// also go to `SALib.analyze.sobol.analyze(problem, Y, calc_second_order=False)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SaltelliLayout {
    /// N: rows of the base matrices A and B.
    pub base_rows: usize,
    /// D: parameters.
    pub params: usize,
}

impl SaltelliLayout {
    /// Variants to run: N (D + 2).
    pub fn rows(&self) -> usize {
        self.base_rows * (self.params + 2)
    }
    /// Row of `A_i`.
    pub fn a(&self, i: usize) -> usize {
        i * (self.params + 2)
    }
    /// Row of `AB_j,i`: `A_i` with parameter `j` (0-based) taken from `B_i`.
    pub fn ab(&self, i: usize, j: usize) -> usize {
        i * (self.params + 2) + 1 + j
    }
    /// Row of `B_i`.
    pub fn b(&self, i: usize) -> usize {
        i * (self.params + 2) + self.params + 1
    }
}

/// A Saltelli sample: the variants to run, in [`SaltelliLayout`]'s order.
#[derive(Debug, Clone, PartialEq)]
pub struct Saltelli {
    /// N (D + 2) variants, one value per parameter each.
    pub points: Vec<Vec<f64>>,
    /// Which row is which.
    pub layout: SaltelliLayout,
}

/// Saltelli's sample for first-order and total Sobol indices with `n` base rows: A is the first
/// D and B the last D dimensions of a 2D-dimensional scrambled Sobol sequence (as SALib builds
/// them), and each `AB_j` is A with column j from B; rows in [`SaltelliLayout`]'s order, N (D + 2)
/// in all. No point is skipped (SALib's default, `skip_values=0`, with scrambling). The points
/// are Burley's sequence, not scipy's, so they differ from SALib's numbers but not in layout.
/// Power-of-two `n` is best (see [`sobol`]); at most [`MAX_SOBOL_DIMS`] / 2 parameters.
pub fn saltelli(bounds: &[(f64, f64)], n: usize, seed: u64) -> Result<Saltelli, AnalysisError> {
    check_bounds(bounds)?;
    let d = bounds.len();
    let layout = SaltelliLayout {
        base_rows: n,
        params: d,
    };
    check_count(layout.rows(), "Saltelli variants")?;
    let base = sobol_unit(n, 2 * d, seed)?;
    let mut points = Vec::with_capacity(layout.rows());
    for row in &base {
        let (a, b) = row.split_at(d);
        points.push(to_bounds(bounds, a.iter().copied()));
        for j in 0..d {
            let ab = (0..d).map(|k| if k == j { b[k] } else { a[k] });
            points.push(to_bounds(bounds, ab));
        }
        points.push(to_bounds(bounds, b.iter().copied()));
    }
    Ok(Saltelli { points, layout })
}
