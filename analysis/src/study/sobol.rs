//! Sobol sensitivity indices of one output from a Saltelli sample ([`super::designs::saltelli`]):
//! how much of the output's variance each parameter explains alone (first order, S1) and with
//! all its interactions (total, ST), with bootstrap confidence intervals.
//!
//! The estimators and their normalisation are SALib's (`SALib.analyze.sobol.analyze(...,
//! calc_second_order=False)`, version 1.6), so the numbers agree with it to round-off
//! (tests/study_sobol.rs):
//! - the outputs are first standardised with the mean and the population standard deviation
//!   (ddof 0) of all N (D + 2) outputs;
//! - S1_j = mean(f_B (f_ABj - f_A)) / var([f_A; f_B]) (Saltelli et al. 2010, eq. (b) of table 2);
//! - ST_j = mean((f_A - f_ABj)^2) / 2 / var([f_A; f_B]) (Jansen 1999);
//! - var is the population variance (ddof 0) of the 2N outputs of A and B together;
//! - an estimate whose A and B outputs span no more than machine epsilon, or whose variance is
//!   no more than it, is 0 (constant output: no parameter matters);
//! - confidence: `num_resamples` bootstrap resamples of the N base rows (drawn with replacement,
//!   the same draw for every parameter), the half-width `z * std(ddof 1)` of the resampled
//!   estimates, `z` the normal quantile at `(1 + conf_level) / 2`. Only the random draws differ
//!   from SALib's (ChaCha8 seeded here, numpy there).
//!
//! A variant that failed (any non-finite output in its block of D + 2 rows) takes its whole base
//! row out: the estimators need all D + 2 outputs of a row. The indices then rest on the rows
//! left, and [`Indices::failed_base_rows`] names the ones dropped.

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

use super::designs::SaltelliLayout;
use super::normal;
use crate::error::AnalysisError;

/// Settings of [`indices`]; the defaults are SALib's.
#[derive(Debug, Clone, PartialEq)]
pub struct SobolOptions {
    /// Bootstrap resamples for the confidence intervals (at least 2).
    pub num_resamples: usize,
    /// Confidence level of the intervals, in (0, 1).
    pub conf_level: f64,
    /// Seed of the bootstrap draws: the same seed gives the same intervals.
    pub seed: u64,
}

impl Default for SobolOptions {
    fn default() -> Self {
        SobolOptions {
            num_resamples: 100,
            conf_level: 0.95,
            seed: 0,
        }
    }
}

/// First-order and total Sobol indices of one output, per parameter (in the design's order).
#[derive(Debug, Clone, PartialEq)]
pub struct Indices {
    /// First-order indices S1.
    pub s1: Vec<f64>,
    /// Half-widths of S1's confidence intervals.
    pub s1_conf: Vec<f64>,
    /// Total indices ST.
    pub st: Vec<f64>,
    /// Half-widths of ST's confidence intervals.
    pub st_conf: Vec<f64>,
    /// Confidence level of the intervals.
    pub conf_level: f64,
    /// Base rows the estimates rest on.
    pub base_rows: usize,
    /// Base rows left out because one of their variants failed (a non-finite output), ascending.
    pub failed_base_rows: Vec<usize>,
}

/// The standardised outputs of the usable base rows: `a[i]`, `b[i]` and `ab[j][i]`.
struct Outputs {
    a: Vec<f64>,
    b: Vec<f64>,
    ab: Vec<Vec<f64>>,
}

impl Outputs {
    /// Numerators of S1 and ST of every parameter, and their common denominator, over `rows`
    /// (indices into the usable base rows, repeats allowed): SALib's `first_order`, `total_order`.
    fn estimate(&self, rows: &[usize]) -> (Vec<f64>, Vec<f64>) {
        let d = self.ab.len();
        let n = rows.len() as f64;
        let (mut lo, mut hi, mut sum) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
        for &i in rows {
            for y in [self.a[i], self.b[i]] {
                lo = lo.min(y);
                hi = hi.max(y);
                sum += y;
            }
        }
        let mean = sum / (2.0 * n);
        let var = rows
            .iter()
            .flat_map(|&i| [self.a[i], self.b[i]])
            .map(|y| (y - mean) * (y - mean))
            .sum::<f64>()
            / (2.0 * n);
        if hi - lo <= f64::EPSILON || var <= f64::EPSILON {
            return (vec![0.0; d], vec![0.0; d]);
        }
        let mut s1 = Vec::with_capacity(d);
        let mut st = Vec::with_capacity(d);
        for ab in &self.ab {
            let (mut first, mut total) = (0.0, 0.0);
            for &i in rows {
                first += self.b[i] * (ab[i] - self.a[i]);
                total += (self.a[i] - ab[i]) * (self.a[i] - ab[i]);
            }
            s1.push(first / n / var);
            st.push(0.5 * total / n / var);
        }
        (s1, st)
    }
}

/// First-order and total Sobol indices of one output with confidence intervals. `outputs` holds
/// one value per variant of the Saltelli sample, in `layout`'s row order (NaN or infinite for a
/// variant that failed). Errors if the lengths disagree, the options are out of range, or fewer
/// than two base rows have every variant finite.
pub fn indices(
    layout: &SaltelliLayout,
    outputs: &[f64],
    opts: &SobolOptions,
) -> Result<Indices, AnalysisError> {
    let invalid = |m: String| Err(AnalysisError::InvalidStudy(m));
    if outputs.len() != layout.rows() {
        return invalid(format!(
            "{} outputs for a Saltelli sample of {} variants ({} base rows, {} parameters)",
            outputs.len(),
            layout.rows(),
            layout.base_rows,
            layout.params
        ));
    }
    if opts.num_resamples < 2 || !(opts.conf_level > 0.0 && opts.conf_level < 1.0) {
        return invalid(format!(
            "Sobol options: num_resamples {} (at least 2), conf_level {} (in (0, 1))",
            opts.num_resamples, opts.conf_level
        ));
    }
    let d = layout.params;
    let block = |i: usize| &outputs[layout.a(i)..=layout.b(i)];
    let (kept, failed): (Vec<usize>, Vec<usize>) =
        (0..layout.base_rows).partition(|&i| block(i).iter().all(|y| y.is_finite()));
    let n = kept.len();
    if n < 2 {
        return invalid(format!(
            "{n} of {} base rows have every variant finite: at least 2 needed",
            layout.base_rows
        ));
    }
    // SALib standardises all outputs first; the same shift keeps the round-off of S1's numerator.
    let all = || kept.iter().flat_map(|&i| block(i).iter().copied());
    let count = (n * (d + 2)) as f64;
    let mean = all().sum::<f64>() / count;
    let sd = (all().map(|y| (y - mean) * (y - mean)).sum::<f64>() / count).sqrt();
    let scale = if sd > 0.0 { 1.0 / sd } else { 0.0 };
    let z = |row: usize| (outputs[row] - mean) * scale;
    let y = Outputs {
        a: kept.iter().map(|&i| z(layout.a(i))).collect(),
        b: kept.iter().map(|&i| z(layout.b(i))).collect(),
        ab: (0..d)
            .map(|j| kept.iter().map(|&i| z(layout.ab(i, j))).collect())
            .collect(),
    };
    let rows: Vec<usize> = (0..n).collect();
    let (s1, st) = y.estimate(&rows);

    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let mut boot_s1 = vec![Vec::with_capacity(opts.num_resamples); d];
    let mut boot_st = vec![Vec::with_capacity(opts.num_resamples); d];
    // SALib: no interval where the drawn A and B outputs span nothing at all.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut draw = vec![0; n];
    for _ in 0..opts.num_resamples {
        for r in draw.iter_mut() {
            *r = rng.random_range(0..n);
            lo = lo.min(y.a[*r]).min(y.b[*r]);
            hi = hi.max(y.a[*r]).max(y.b[*r]);
        }
        let (s, t) = y.estimate(&draw);
        for j in 0..d {
            boot_s1[j].push(s[j]);
            boot_st[j].push(t[j]);
        }
    }
    let z = normal::quantile(0.5 + opts.conf_level / 2.0);
    let conf = |boot: &[f64]| {
        if hi - lo == 0.0 {
            return 0.0;
        }
        let m = boot.iter().sum::<f64>() / boot.len() as f64;
        let v = boot.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (boot.len() - 1) as f64;
        z * v.sqrt()
    };
    Ok(Indices {
        s1,
        s1_conf: boot_s1.iter().map(|b| conf(b)).collect(),
        st,
        st_conf: boot_st.iter().map(|b| conf(b)).collect(),
        conf_level: opts.conf_level,
        base_rows: n,
        failed_base_rows: failed,
    })
}
