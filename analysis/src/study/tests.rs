//! Closed forms for the study functions: analytic Sobol indices (Ishigami, a linear model), hand-
//! checked Pareto fronts, the strata of the designs. Bounds state the measured value in brackets.

use std::f64::consts::PI;

use super::designs::{MAX_SOBOL_POINTS, SaltelliLayout, grid, lhs, saltelli, sobol};
use super::normal::quantile;
use super::pareto::{Sense, dominates, front};
use super::plot::{Output, PlotOptions, pareto, sobol_bars};
use super::sobol::{Indices, SobolOptions, indices};
use super::table;

fn ishigami(x: &[f64]) -> f64 {
    let (a, b) = (7.0, 0.1);
    x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin()
}

/// Analytic (S1, ST) of the Ishigami function on [-pi, pi]^3 (Ishigami & Homma 1990), from its
/// ANOVA decomposition: V1 = (1 + b pi^4 / 5)^2 / 2, V2 = a^2 / 8, V13 = 8 b^2 pi^8 / 225, V3 = 0.
fn ishigami_analytic(a: f64, b: f64) -> ([f64; 3], [f64; 3]) {
    let v1 = 0.5 * (1.0 + b * PI.powi(4) / 5.0).powi(2);
    let v2 = a * a / 8.0;
    let v13 = 8.0 * b * b * PI.powi(8) / 225.0;
    let v = a * a / 8.0 + b * PI.powi(4) / 5.0 + b * b * PI.powi(8) / 18.0 + 0.5;
    // The same total as the sum of the parts (no other terms).
    assert!((v - (v1 + v2 + v13)).abs() < 1e-12 * v);
    ([v1 / v, v2 / v, 0.0], [(v1 + v13) / v, v2 / v, v13 / v])
}

fn evaluate(points: &[Vec<f64>], f: impl Fn(&[f64]) -> f64) -> Vec<f64> {
    points.iter().map(|p| f(p)).collect()
}

#[test]
fn normal_quantile_is_scipys() {
    // scipy.stats.norm.ppf at the same probabilities.
    for (p, z) in [
        (0.975, 1.959963984540054),
        (0.995, 2.5758293035489004),
        (0.95, 1.6448536269514722),
        (0.3, -0.5244005127080409),
        (0.02, -2.053748910631823),
        (1e-10, -6.361340902404056),
        (1.0 - 1e-12, 7.0344869100478356),
    ] {
        // Within 1e-15 relative [4.2e-16]: AS 241's accuracy.
        assert!(
            (quantile(p) - z).abs() <= 1e-15 * z.abs(),
            "{p}: {}",
            quantile(p)
        );
    }
}

#[test]
fn ishigami_indices_match_the_analytic_ones() {
    let (s1, st) = ishigami_analytic(7.0, 0.1);
    // The formula gives the four-decimal values the literature quotes (S1 as SALib's Ishigami
    // docstring cites them from Saltelli et al., The Primer, 2008; ST as quoted beside them).
    for (got, lit) in s1
        .iter()
        .chain(&st)
        .zip([0.3139, 0.4424, 0.0, 0.5576, 0.4424, 0.2437])
    {
        assert!((got - lit).abs() < 5e-5, "{got} against {lit}");
    }
    let s = saltelli(&[(-PI, PI); 3], 1 << 13, 1).unwrap();
    let y = evaluate(&s.points, ishigami);
    let idx = indices(&s.layout, &y, &SobolOptions::default()).unwrap();
    let err = |a: &[f64], b: &[f64; 3]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    // N = 8192 (40 960 runs): S1 within 1e-2 [2.4e-3], ST within 5e-3 [5.5e-4].
    assert!(err(&idx.s1, &s1) < 1e-2, "S1 {:?} against {s1:?}", idx.s1);
    assert!(err(&idx.st, &st) < 5e-3, "ST {:?} against {st:?}", idx.st);
    // The bootstrap treats the rows as independent, so on a scrambled Sobol sample (whose error
    // falls faster than 1/sqrt(N)) it is conservative: every half-width within 0.005 .. 0.06
    // [0.0095 .. 0.031], every error within its half-width [at most 0.12 of it].
    let pairs = idx.s1.iter().zip(&idx.s1_conf).zip(&s1);
    for ((v, c), exact) in pairs.chain(idx.st.iter().zip(&idx.st_conf).zip(&st)) {
        assert!(
            (0.005..0.06).contains(c),
            "{:?} {:?}",
            idx.s1_conf,
            idx.st_conf
        );
        assert!((v - exact).abs() < *c, "{v} +- {c} against {exact}");
    }
}

#[test]
fn linear_model_indices_are_the_squared_weights_shares() {
    // Y = sum a_i x_i on ranges of equal width (the offsets do not matter): S1_i = ST_i =
    // a_i^2 / sum a_j^2.
    let a = [1.0, 2.0, -3.0, 0.5];
    let bounds = [(0.0, 1.0), (2.0, 3.0), (-5.0, -4.0), (10.0, 11.0)];
    let s = saltelli(&bounds, 1 << 12, 7).unwrap();
    let y = evaluate(&s.points, |x| x.iter().zip(&a).map(|(x, a)| x * a).sum());
    let idx = indices(&s.layout, &y, &SobolOptions::default()).unwrap();
    let sum: f64 = a.iter().map(|a| a * a).sum();
    for (j, a) in a.iter().enumerate() {
        let exact = a * a / sum;
        // N = 4096: S1 within 2e-4 [2.1e-5], ST within 2e-4 [1.9e-5].
        assert!((idx.s1[j] - exact).abs() < 2e-4, "S1 {:?}", idx.s1);
        assert!((idx.st[j] - exact).abs() < 2e-4, "ST {:?}", idx.st);
    }
}

#[test]
fn failed_variants_take_their_base_rows_out() {
    let s = saltelli(&[(-PI, PI); 3], 256, 3).unwrap();
    let mut y = evaluate(&s.points, ishigami);
    let whole = indices(&s.layout, &y, &SobolOptions::default()).unwrap();
    y[s.layout.ab(5, 1)] = f64::NAN;
    y[s.layout.b(17)] = f64::INFINITY;
    let idx = indices(&s.layout, &y, &SobolOptions::default()).unwrap();
    assert_eq!(idx.failed_base_rows, vec![5, 17]);
    assert_eq!(idx.base_rows, 254);
    // The same as the sample without those two base rows.
    let keep: Vec<usize> = (0..256).filter(|i| ![5, 17].contains(i)).collect();
    let rows = |i: usize| s.layout.a(i)..=s.layout.b(i);
    let y2: Vec<f64> = keep.iter().flat_map(|&i| y[rows(i)].to_vec()).collect();
    let layout = SaltelliLayout {
        base_rows: 254,
        params: 3,
    };
    let idx2 = indices(&layout, &y2, &SobolOptions::default()).unwrap();
    assert_eq!((&idx.s1, &idx.st), (&idx2.s1, &idx2.st));
    assert_ne!(whole.s1, idx.s1);
}

#[test]
fn constant_output_has_zero_indices_and_bad_input_is_refused() {
    let s = saltelli(&[(0.0, 1.0); 2], 64, 0).unwrap();
    let idx = indices(
        &s.layout,
        &vec![3.0; s.layout.rows()],
        &SobolOptions::default(),
    )
    .unwrap();
    assert_eq!(idx.s1, vec![0.0; 2]);
    assert_eq!(idx.st_conf, vec![0.0; 2]);
    assert!(indices(&s.layout, &[1.0; 5], &SobolOptions::default()).is_err());
    let bad = SobolOptions {
        conf_level: 1.0,
        ..SobolOptions::default()
    };
    assert!(indices(&s.layout, &vec![1.0; s.layout.rows()], &bad).is_err());
    assert!(saltelli(&[(1.0, 1.0)], 8, 0).is_err());
    assert!(saltelli(&[(0.0, 1.0)], MAX_SOBOL_POINTS + 1, 0).is_err());
    assert!(grid(&[(0.0, f64::NAN)], &[3]).is_err());
}

#[test]
fn saltelli_rows_follow_salibs_layout() {
    let bounds = [(0.0, 1.0), (-2.0, 2.0), (10.0, 20.0)];
    let s = saltelli(&bounds, 16, 5).unwrap();
    let l = s.layout;
    assert_eq!(s.points.len(), 16 * 5);
    assert_eq!((l.a(1), l.ab(1, 0), l.ab(1, 2), l.b(1)), (5, 6, 8, 9));
    for i in 0..16 {
        let (a, b) = (&s.points[l.a(i)], &s.points[l.b(i)]);
        for j in 0..3 {
            let ab = &s.points[l.ab(i, j)];
            for k in 0..3 {
                assert_eq!(ab[k], if k == j { b[k] } else { a[k] });
                assert!((bounds[k].0..bounds[k].1).contains(&ab[k]));
            }
            // A and B are different dimensions of the sequence.
            assert_ne!(a[j], b[j]);
        }
    }
    // Reproducible, and the seed matters.
    assert_eq!(s, saltelli(&bounds, 16, 5).unwrap());
    assert_ne!(s.points, saltelli(&bounds, 16, 6).unwrap().points);
}

/// Stratum (of `n` equal ones in `lo..hi`) of every variant's parameter `j`, sorted.
fn strata(points: &[Vec<f64>], j: usize, (lo, hi): (f64, f64), n: usize) -> Vec<usize> {
    let mut s: Vec<usize> = points
        .iter()
        .map(|p| ((p[j] - lo) / (hi - lo) * n as f64).floor() as usize)
        .collect();
    s.sort_unstable();
    s
}

#[test]
fn latin_hypercube_has_one_point_per_stratum() {
    let bounds = [(0.0, 1.0), (-3.0, 5.0), (100.0, 100.5)];
    for n in [1, 7, 100] {
        let d = lhs(&bounds, n, 42).unwrap();
        assert_eq!(d.len(), n);
        for (j, &b) in bounds.iter().enumerate() {
            assert_eq!(strata(&d, j, b, n), (0..n).collect::<Vec<_>>());
        }
    }
    assert_eq!(lhs(&bounds, 50, 1).unwrap(), lhs(&bounds, 50, 1).unwrap());
    assert_ne!(lhs(&bounds, 50, 1).unwrap(), lhs(&bounds, 50, 2).unwrap());
}

#[test]
fn sobol_design_fills_every_stratum_at_powers_of_two() {
    let bounds = [(0.0, 1.0), (-1.0, 1.0), (5.0, 9.0), (0.0, 2.0), (1.0, 2.0)];
    for n in [16, 256] {
        let d = sobol(&bounds, n, 9).unwrap();
        for (j, &b) in bounds.iter().enumerate() {
            assert_eq!(strata(&d, j, b, n), (0..n).collect::<Vec<_>>());
        }
    }
}

#[test]
fn grid_has_every_combination_once() {
    let d = grid(&[(0.0, 1.0), (10.0, 20.0), (-1.0, 1.0)], &[3, 1, 4]).unwrap();
    assert_eq!(d.len(), 3 * 4);
    assert_eq!(d[0], vec![0.0, 15.0, -1.0]);
    assert_eq!(d[1], vec![0.0, 15.0, -1.0 + 2.0 / 3.0]);
    assert_eq!(d[4], vec![0.5, 15.0, -1.0]);
    assert_eq!(d[11], vec![1.0, 15.0, 1.0]);
    let mut seen = d.clone();
    seen.sort_by(|a, b| a.partial_cmp(b).unwrap());
    seen.dedup();
    assert_eq!(seen.len(), 12);
    assert!(grid(&[(0.0, 1.0)], &[0]).is_err());
    assert!(grid(&[(0.0, 1.0); 2], &[3]).is_err());
    assert!(grid(&[(0.0, 1.0); 3], &[10_000, 10_000, 10_000]).is_err());
}

/// Hand-checked: (displacement, acceleration), both minimised.
fn hand_set() -> Vec<[f64; 2]> {
    vec![
        [1.0, 5.0],      // 0: front (best displacement)
        [2.0, 3.0],      // 1: front
        [3.0, 3.0],      // 2: dominated by 1
        [2.5, 2.0],      // 3: front
        [4.0, 1.0],      // 4: front (best acceleration)
        [4.0, 1.5],      // 5: dominated by 4
        [2.0, 3.0],      // 6: tie with 1: front too
        [f64::NAN, 0.0], // 7: failed
        [5.0, 5.0],      // 8: dominated
    ]
}

#[test]
fn pareto_front_of_a_hand_checked_set() {
    let set = hand_set();
    let both = [Sense::Minimise; 2];
    assert_eq!(front(&set, &both), vec![0, 1, 3, 4, 6]);
    // Maximising the first output instead: the largest x (8) and the best y for x = 4 (4).
    let mixed = [Sense::Maximise, Sense::Minimise];
    assert_eq!(front(&set, &mixed), vec![4, 8]);
    assert!(dominates(&set[1], &set[2], &both));
    assert!(!dominates(&set[1], &set[6], &both));
    assert!(!dominates(&set[7], &set[8], &both) && !dominates(&set[8], &set[7], &both));
    // -0.0 and 0.0 are one value: (0, 1) dominates (-0, 2) whatever the sort makes of them.
    assert_eq!(front(&[[-0.0, 2.0], [0.0, 1.0]], &both), vec![1]);
    let empty: [[f64; 2]; 0] = [];
    assert!(front(&empty, &both).is_empty());
    assert!(front(&[[f64::NAN, 1.0]], &both).is_empty());
    // Three outputs: none of these beats another in all three.
    let three = [
        [1.0, 2.0, 3.0],
        [2.0, 1.0, 3.0],
        [3.0, 3.0, 0.0],
        [3.0, 3.0, 3.0],
    ];
    assert_eq!(front(&three, &[Sense::Minimise; 3]), vec![0, 1, 2]);
}

#[test]
fn pareto_front_is_permutation_invariant() {
    let set = hand_set();
    let both = [Sense::Minimise; 2];
    let base = front(&set, &both);
    // Every rotation and the reversal, and a larger random set under a shuffle.
    let n = set.len();
    for r in 0..n {
        let perm: Vec<usize> = (0..n).map(|k| (k + r) % n).collect();
        let permuted: Vec<[f64; 2]> = perm.iter().map(|&k| set[k]).collect();
        let mut back: Vec<usize> = front(&permuted, &both).iter().map(|&k| perm[k]).collect();
        back.sort_unstable();
        assert_eq!(back, base, "rotation {r}");
    }
    let cloud = lhs(&[(0.0, 1.0); 3], 500, 3).unwrap();
    let senses = [Sense::Minimise, Sense::Maximise, Sense::Minimise];
    let f = front(&cloud, &senses);
    // Brute force: non-dominated by any variant.
    let brute: Vec<usize> = (0..cloud.len())
        .filter(|&k| !cloud.iter().any(|o| dominates(o, &cloud[k], &senses)))
        .collect();
    assert_eq!(f, brute);
    let rev: Vec<Vec<f64>> = cloud.iter().rev().cloned().collect();
    let mut back: Vec<usize> = front(&rev, &senses).iter().map(|&k| 499 - k).collect();
    back.sort_unstable();
    assert_eq!(back, f);
}

fn example_indices() -> Indices {
    Indices {
        s1: vec![0.31, 0.44, -0.004],
        s1_conf: vec![0.03, 0.025, 0.01],
        st: vec![0.56, 0.45, 0.24],
        st_conf: vec![0.04, 0.03, 0.02],
        conf_level: 0.95,
        base_rows: 1024,
        failed_base_rows: vec![3],
    }
}

#[test]
fn table_lists_every_parameter() {
    let t = table(&["damper friction [N]", "x2", "x3"], &example_indices());
    let lines: Vec<&str> = t.lines().collect();
    assert_eq!(
        lines[0],
        "| parameter           |      S1 | S1_conf |      ST | ST_conf |"
    );
    assert_eq!(
        lines[2],
        "| damper friction [N] |  0.3100 |  0.0300 |  0.5600 |  0.0400 |"
    );
    assert_eq!(
        lines[4],
        "| x3                  | -0.0040 |  0.0100 |  0.2400 |  0.0200 |"
    );
    assert!(t.contains("95 % bootstrap") && t.contains("base rows [3]"));
}

#[test]
fn plots_are_written_as_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let set = hand_set();
    let ids: Vec<String> = (0..set.len()).map(|k| format!("v{k:02}")).collect();
    let ids: Vec<&str> = ids.iter().map(String::as_str).collect();
    let (x, y): (Vec<f64>, Vec<f64>) = set.iter().map(|p| (p[0], p[1])).unzip();
    let out = |name, unit, values| Output {
        name,
        unit,
        sense: Sense::Minimise,
        values,
    };
    let files = pareto(
        &ids,
        &out("tub displacement, peak", "mm", &x),
        &out("cabinet acceleration, peak", "m/s^2", &y),
        &PlotOptions::default(),
        &dir.path().join("pareto"),
    )
    .unwrap();
    let params = [
        "damper friction [N]",
        "spring stiffness [N/mm]",
        "gasket damping [Ns/m]",
    ];
    let files2 = sobol_bars(
        "tub displacement, peak [mm]",
        &params,
        &example_indices(),
        &PlotOptions::default(),
        &dir.path().join("sobol"),
    )
    .unwrap();
    for f in files.iter().chain(&files2) {
        assert!(std::fs::metadata(f).unwrap().len() > 5_000, "{f:?}");
    }
    let svg = std::fs::read_to_string(dir.path().join("pareto.svg")).unwrap();
    assert!(svg.contains("v06") && svg.contains("[m/s^2]"));
}
