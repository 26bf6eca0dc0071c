//! The linear least-squares fit of implicit condensation: the coefficients of the strain-energy
//! polynomial's cubic and quartic terms from static samples (modal coordinates q and the
//! nonlinear modal force f = lambda - w^2 q at each). The unknowns enter the force linearly
//! (f = dV/dq), so one least-squares solve over all samples and modes finds them.

use washdyn_model::ir::modal::{Curves, Fit, Term};

/// One static solution: the chosen modes' coordinates and the nonlinear modal force there.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Mass-normalised modal coordinates, kg^0.5 m.
    pub q: Vec<f64>,
    /// Nonlinear modal force (modal load less w^2 q), N / kg^0.5.
    pub f: Vec<f64>,
}

/// Every monomial of `degree` in `n` coordinates, as ascending index lists (with repeats for
/// powers): the terms a full polynomial energy has.
pub fn monomials(n: usize, degree: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut cur = Vec::with_capacity(degree);
    fn rec(n: usize, degree: usize, from: usize, cur: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
        if cur.len() == degree {
            out.push(cur.clone());
            return;
        }
        for i in from..n {
            cur.push(i);
            rec(n, degree, i, cur, out);
            cur.pop();
        }
    }
    rec(n, degree, 0, &mut cur, &mut out);
    out
}

/// d/dq_r of the monomial `m` at `q`.
fn derivative(m: &[usize], q: &[f64], r: usize) -> f64 {
    let mut sum = 0.0;
    for p in 0..m.len() {
        if m[p] != r {
            continue;
        }
        let mut others = 1.0;
        for (i, &k) in m.iter().enumerate() {
            if i != p {
                others *= q[k];
            }
        }
        sum += others;
    }
    sum
}

/// The least-squares energy coefficients (cubic terms, then quartic) of `samples` over `n`
/// modes: minimises sum over samples and modes of (dV/dq_r - f_r)^2. Coordinates and forces
/// are scaled to their largest magnitude first (q ~ 1e-2 kg^0.5 m makes the quartic columns
/// 1e-6 of the cubic ones), and the solve is an SVD, so a term the samples cannot see gets the
/// minimum-norm zero rather than noise.
pub fn fit(samples: &[Sample], n: usize) -> (Vec<Term>, Vec<Term>) {
    let cubic = monomials(n, 3);
    let quartic = monomials(n, 4);
    let s = samples
        .iter()
        .flat_map(|x| x.q.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let fs = samples
        .iter()
        .flat_map(|x| x.f.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let terms: Vec<&Vec<usize>> = cubic.iter().chain(&quartic).collect();
    let rows = samples.len() * n;
    let mut a = nalgebra::DMatrix::zeros(rows, terms.len());
    let mut b = nalgebra::DVector::zeros(rows);
    for (i, x) in samples.iter().enumerate() {
        let qs: Vec<f64> = x.q.iter().map(|v| v / s).collect();
        for r in 0..n {
            b[i * n + r] = x.f[r] / fs;
            for (j, m) in terms.iter().enumerate() {
                a[(i * n + r, j)] = derivative(m, &qs, r);
            }
        }
    }
    // c_t q^deg = c_t s^deg qs^deg: the scaled unknown is c_t s^(deg - 1) / fs (a force).
    let svd = a.svd(true, true);
    let tol = 1e-10 * svd.singular_values.max();
    let x = svd.solve(&b, tol).expect("both factors were computed");
    let unscale = |j: usize, m: &Vec<usize>| x[j] * fs / s.powi(m.len() as i32 - 1);
    let out: Vec<Term> = terms
        .iter()
        .enumerate()
        .map(|(j, m)| Term {
            modes: (*m).clone(),
            c: unscale(j, m),
        })
        .collect();
    let (c, q) = out.split_at(cubic.len());
    (c.to_vec(), q.to_vec())
}

/// The largest difference between the curves' force and the samples', relative to the samples'
/// largest nonlinear force (0 for no samples).
pub fn residual(curves: &Curves, samples: &[Sample]) -> f64 {
    let top = samples
        .iter()
        .flat_map(|x| x.f.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for x in samples {
        let mut f = vec![0.0; x.f.len()];
        curves.force_into(&x.q, &mut f);
        for (a, b) in f.iter().zip(&x.f) {
            worst = worst.max((a - b).abs());
        }
    }
    if top > 0.0 { worst / top } else { 0.0 }
}

/// The sample's signed largest coordinate: how `Fit::loads` records a load level.
pub fn level(x: &Sample) -> f64 {
    x.q.iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(0.0)
}

/// Fit `seen`, check on `unseen`, and fill in the record (`body`, `source`, the chosen modes'
/// file indices and frequencies, the bound).
pub fn curves(head: Curves, seen: &[Sample], unseen: &[Sample]) -> Curves {
    let n = head.modes.len();
    let (cubic, quartic) = fit(seen, n);
    let mut c = Curves {
        cubic,
        quartic,
        ..head
    };
    c.fit = Fit {
        loads: seen.iter().map(level).collect(),
        residual: residual(&c, seen),
        unseen_loads: unseen.iter().map(level).collect(),
        unseen_residual: residual(&c, unseen),
        bound: c.fit.bound,
    };
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head(n: usize) -> Curves {
        Curves {
            body: "test".into(),
            source: "synthetic".into(),
            modes: (0..n).collect(),
            frequencies: vec![10.0; n],
            cubic: vec![],
            quartic: vec![],
            fit: Fit {
                loads: vec![],
                residual: 0.0,
                unseen_loads: vec![],
                unseen_residual: 0.0,
                bound: 0.05,
            },
        }
    }

    fn sample(truth: &Curves, q: Vec<f64>) -> Sample {
        let mut f = vec![0.0; q.len()];
        truth.force_into(&q, &mut f);
        Sample { q, f }
    }

    fn coefficient(terms: &[Term], modes: &[usize]) -> f64 {
        terms.iter().find(|t| t.modes == modes).unwrap().c
    }

    #[test]
    fn monomials_count_as_combinations_with_repeats() {
        // C(n + d - 1, d): 2 modes -> 4 cubic, 5 quartic; 3 modes -> 10, 15.
        assert_eq!(monomials(2, 3).len(), 4);
        assert_eq!(monomials(2, 4).len(), 5);
        assert_eq!(monomials(3, 3).len(), 10);
        assert_eq!(monomials(3, 4).len(), 15);
        assert_eq!(monomials(1, 3), vec![vec![0, 0, 0]]);
    }

    /// One mode, V = a q^3 + b q^4 at the magnitudes of a real body (q ~ 1e-2 kg^0.5 m,
    /// a ~ 1e8, b ~ 1e10): samples of both signs recover a and b to round-off, and the
    /// unseen levels (one between, one beyond the fitted ones) have zero residual.
    #[test]
    fn one_mode_exact_recovery_both_signs() {
        let mut truth = head(1);
        truth.cubic = vec![Term {
            modes: vec![0, 0, 0],
            c: 3.1e8,
        }];
        truth.quartic = vec![Term {
            modes: vec![0, 0, 0, 0],
            c: -7.4e9,
        }];
        let seen: Vec<Sample> = [-0.02, -0.01, 0.01, 0.02]
            .iter()
            .map(|&q| sample(&truth, vec![q]))
            .collect();
        let unseen = vec![sample(&truth, vec![0.015]), sample(&truth, vec![-0.025])];
        let c = curves(head(1), &seen, &unseen);
        assert!((c.cubic[0].c / 3.1e8 - 1.0).abs() < 1e-10, "{:?}", c.cubic);
        assert!(
            (c.quartic[0].c / -7.4e9 - 1.0).abs() < 1e-10,
            "{:?}",
            c.quartic
        );
        assert!(
            c.fit.residual < 1e-12 && c.fit.unseen_residual < 1e-12,
            "{:?}",
            c.fit
        );
        assert_eq!(c.fit.loads, vec![-0.02, -0.01, 0.01, 0.02]);
        assert_eq!(c.fit.unseen_loads, vec![0.015, -0.025]);
    }

    /// Two modes with every coupling term: single-mode and paired samples of both signs
    /// recover all nine coefficients; an odd energy (cubic) flips sign with q, which only
    /// samples of both signs separate from the even (quartic) part.
    #[test]
    fn coupled_two_modes_exact_recovery() {
        let mut truth = head(2);
        let cubic = [2.0e8, -5.0e7, 8.0e7, 1.5e8];
        let quartic = [4.0e9, 1.0e9, -2.0e9, 3.0e8, 6.0e9];
        truth.cubic = monomials(2, 3)
            .into_iter()
            .zip(cubic)
            .map(|(modes, c)| Term { modes, c })
            .collect();
        truth.quartic = monomials(2, 4)
            .into_iter()
            .zip(quartic)
            .map(|(modes, c)| Term { modes, c })
            .collect();
        let mut seen = Vec::new();
        for l in [0.01, 0.02] {
            for s in [-1.0, 1.0] {
                seen.push(sample(&truth, vec![s * l, 0.1 * l]));
                seen.push(sample(&truth, vec![-0.2 * l, s * l]));
                for t in [-1.0, 1.0] {
                    seen.push(sample(&truth, vec![s * l, t * 0.7 * l]));
                }
            }
        }
        let unseen = vec![sample(&truth, vec![0.013, -0.009])];
        let c = curves(head(2), &seen, &unseen);
        for t in truth.cubic.iter().chain(&truth.quartic) {
            let got = coefficient(
                if t.modes.len() == 3 {
                    &c.cubic
                } else {
                    &c.quartic
                },
                &t.modes,
            );
            assert!((got / t.c - 1.0).abs() < 1e-9, "{:?}: {got}", t.modes);
        }
        assert!(c.fit.unseen_residual < 1e-12, "{:?}", c.fit);
    }

    /// An error in the data shows in the residual (relative to the largest force): one
    /// sample's force 50 % off leaves a residual no cubic-quartic energy can remove.
    #[test]
    fn residual_sees_noise() {
        let mut truth = head(1);
        truth.quartic = vec![Term {
            modes: vec![0, 0, 0, 0],
            c: 1e9,
        }];
        let mut seen: Vec<Sample> = [-0.02, -0.01, 0.01, 0.02, 0.03]
            .iter()
            .map(|&q| sample(&truth, vec![q]))
            .collect();
        seen[1].f[0] *= 1.5;
        let c = curves(head(1), &seen, &[]);
        assert!(c.fit.residual > 1e-3, "{:?}", c.fit);
    }
}
