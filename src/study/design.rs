//! A study's design points: one row per variant, one value per parameter, in design order (the
//! variants' ids follow it). `grid` is the product of the given levels; `lhs`, `sobol` and
//! `saltelli` are `washdyn_analysis::study::designs` on the unit cube (one implementation of
//! each), whose points map to each parameter's range linearly, or geometrically with
//! `scale = "log"`. A saltelli design's rows are in `SaltelliLayout`'s order with `samples`
//! base rows, so `samples (D + 2)` variants.

use serde::{Deserialize, Serialize};
use washdyn_analysis::study::designs;
use washdyn_model::ir::check::Path;

/// Design kinds of the study file's `[design] kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Grid,
    Lhs,
    Sobol,
    Saltelli,
}

/// How a range maps unit points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scale {
    #[default]
    Linear,
    Log,
}

/// What one parameter may take: given levels, or a range the design samples.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    Levels(Vec<f64>),
    Range { lo: f64, hi: f64, scale: Scale },
}

impl Axis {
    /// The value at unit coordinate `u` in [0, 1] of a range.
    fn at(lo: f64, hi: f64, scale: Scale, u: f64) -> f64 {
        match scale {
            Scale::Linear => lo + u * (hi - lo),
            Scale::Log => lo * (hi / lo).powf(u),
        }
    }
}

/// The `[design]` table, checked.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Design {
    pub kind: Kind,
    /// Points of a sampled design (lhs, sobol, saltelli); a grid's size is its levels'.
    pub samples: Option<usize>,
    /// Seed of a random design (default 0); a grid takes none.
    pub seed: Option<u64>,
}

/// Most variants a study may have: a million rows of the design would still fit in memory,
/// but a study that large is a typo in a grid (ten parameters of ten levels).
pub const MAX_VARIANTS: usize = 100_000;

/// Why a design has no points: the study file's field and the message.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignError {
    pub at: Path,
    pub message: String,
}

fn refuse(at: Path, message: impl Into<String>) -> DesignError {
    DesignError {
        at,
        message: message.into(),
    }
}

fn design_at(k: &str) -> Path {
    Path::default().key("design").key(k)
}

fn param_at(i: usize, k: &str) -> Path {
    Path::default().key("parameter").idx(i).key(k)
}

/// The design's points, in design order. `axes[i]` is parameter i's levels or range.
pub fn points(design: &Design, axes: &[Axis]) -> Result<Vec<Vec<f64>>, DesignError> {
    if axes.is_empty() {
        return Err(refuse(
            Path::default().key("parameter"),
            "no [[parameter]]: a study varies at least one",
        ));
    }
    match design.kind {
        Kind::Grid => grid(design, axes),
        Kind::Lhs | Kind::Sobol | Kind::Saltelli => {
            let n = sampled(design)?;
            let name = match design.kind {
                Kind::Lhs => "lhs",
                Kind::Sobol => "sobol",
                _ => "saltelli",
            };
            let ranges = ranges(axes, name)?;
            let unit_box = vec![(0.0, 1.0); ranges.len()];
            let seed = design.seed.unwrap_or(0);
            let unit = match design.kind {
                Kind::Lhs => designs::lhs(&unit_box, n, seed),
                Kind::Sobol => designs::sobol(&unit_box, n, seed),
                _ => designs::saltelli(&unit_box, n, seed).map(|s| s.points),
            }
            .map_err(|e| refuse(design_at("samples"), e.to_string()))?;
            if unit.len() > MAX_VARIANTS {
                return Err(refuse(
                    design_at("samples"),
                    format!("{} variants, more than {MAX_VARIANTS}", unit.len()),
                ));
            }
            Ok(unit
                .iter()
                .map(|u| {
                    u.iter()
                        .zip(&ranges)
                        .map(|(&u, &(lo, hi, s))| Axis::at(lo, hi, s, u))
                        .collect()
                })
                .collect())
        }
    }
}

/// Every combination of the levels, the last parameter varying fastest.
fn grid(design: &Design, axes: &[Axis]) -> Result<Vec<Vec<f64>>, DesignError> {
    if design.samples.is_some() {
        return Err(refuse(
            design_at("samples"),
            "a grid's size is the product of its levels; `samples` is for lhs, sobol and saltelli",
        ));
    }
    if design.seed.is_some() {
        return Err(refuse(
            design_at("seed"),
            "a grid draws nothing at random; `seed` is for lhs, sobol and saltelli",
        ));
    }
    let mut levels = Vec::new();
    for (i, a) in axes.iter().enumerate() {
        match a {
            Axis::Levels(l) => levels.push(l),
            Axis::Range { .. } => {
                return Err(refuse(
                    param_at(i, "range"),
                    "a grid takes `levels = [..]` for every parameter, not a range",
                ));
            }
        }
    }
    let total = levels
        .iter()
        .try_fold(1usize, |n, l| n.checked_mul(l.len()))
        .filter(|&n| n <= MAX_VARIANTS)
        .ok_or_else(|| {
            let sizes: Vec<String> = levels.iter().map(|l| l.len().to_string()).collect();
            refuse(
                design_at("kind"),
                format!(
                    "the grid has {} variants, more than {MAX_VARIANTS}",
                    sizes.join(" x ")
                ),
            )
        })?;
    let mut out = Vec::with_capacity(total);
    let mut idx = vec![0usize; levels.len()];
    for _ in 0..total {
        out.push(idx.iter().zip(&levels).map(|(&k, l)| l[k]).collect());
        for d in (0..idx.len()).rev() {
            idx[d] += 1;
            if idx[d] < levels[d].len() {
                break;
            }
            idx[d] = 0;
        }
    }
    Ok(out)
}

/// The point count of a sampled design.
fn sampled(design: &Design) -> Result<usize, DesignError> {
    match design.samples {
        None => Err(refuse(
            design_at("kind"),
            "a sampled design needs `samples = N` (its point count)",
        )),
        Some(0) => Err(refuse(design_at("samples"), "samples must be at least 1")),
        Some(n) if n > MAX_VARIANTS => Err(refuse(
            design_at("samples"),
            format!("samples {n} is more than {MAX_VARIANTS}"),
        )),
        Some(n) => Ok(n),
    }
}

/// Every parameter's range, for a design that samples them.
fn ranges(axes: &[Axis], kind: &str) -> Result<Vec<(f64, f64, Scale)>, DesignError> {
    axes.iter()
        .enumerate()
        .map(|(i, a)| match a {
            Axis::Range { lo, hi, scale } => Ok((*lo, *hi, *scale)),
            Axis::Levels(_) => Err(refuse(
                param_at(i, "levels"),
                format!("an {kind} design samples ranges: give `range = [lo, hi]`, not levels"),
            )),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn design(kind: Kind, samples: Option<usize>) -> Design {
        Design {
            kind,
            samples,
            seed: None,
        }
    }

    #[test]
    fn grid_is_the_product_last_parameter_fastest() {
        let axes = [
            Axis::Levels(vec![1.0, 2.0]),
            Axis::Levels(vec![10.0, 20.0, 30.0]),
        ];
        let p = points(&design(Kind::Grid, None), &axes).unwrap();
        assert_eq!(
            p,
            [
                [1.0, 10.0],
                [1.0, 20.0],
                [1.0, 30.0],
                [2.0, 10.0],
                [2.0, 20.0],
                [2.0, 30.0]
            ]
        );
    }

    /// A linear range [2, 4] and a log range [1, 1e3].
    fn lin_and_log() -> [Axis; 2] {
        [
            Axis::Range {
                lo: 2.0,
                hi: 4.0,
                scale: Scale::Linear,
            },
            Axis::Range {
                lo: 1.0,
                hi: 1e3,
                scale: Scale::Log,
            },
        ]
    }

    /// The defining property: every stratum of every dimension holds one point; the log scale
    /// puts the strata's edges at lo (hi/lo)^(k/n).
    #[test]
    fn lhs_fills_every_stratum_once_and_is_seeded() {
        let n = 7;
        let axes = lin_and_log();
        let d = Design {
            kind: Kind::Lhs,
            samples: Some(n),
            seed: Some(42),
        };
        let p = points(&d, &axes).unwrap();
        assert_eq!(p.len(), n);
        let mut lin: Vec<usize> = p
            .iter()
            .map(|x| ((x[0] - 2.0) / 2.0 * n as f64) as usize)
            .collect();
        let mut log: Vec<usize> = p
            .iter()
            .map(|x| (x[1].log10() / 3.0 * n as f64) as usize)
            .collect();
        lin.sort();
        log.sort();
        assert_eq!(lin, (0..n).collect::<Vec<_>>());
        assert_eq!(log, (0..n).collect::<Vec<_>>());
        assert_eq!(points(&d, &axes).unwrap(), p, "same seed, same points");
        let other = Design {
            seed: Some(43),
            ..d.clone()
        };
        assert_ne!(points(&other, &axes).unwrap(), p);
    }

    /// Saltelli's rows in SALib's layout (per base row: A, AB_1..AB_D, B): AB_j is A with
    /// parameter j from B, mapped through each parameter's scale.
    #[test]
    fn saltelli_rows_follow_the_layout() {
        let axes = lin_and_log();
        let p = points(&design(Kind::Saltelli, Some(8)), &axes).unwrap();
        assert_eq!(p.len(), 8 * 4);
        for r in p.chunks(4) {
            let (a, b) = (&r[0], &r[3]);
            assert_eq!(r[1], vec![b[0], a[1]]);
            assert_eq!(r[2], vec![a[0], b[1]]);
            assert!((1.0..=1e3).contains(&a[1]) && (2.0..=4.0).contains(&a[0]));
        }
    }

    #[test]
    fn refusals_name_the_field() {
        let lv = [Axis::Levels(vec![1.0])];
        let rg = [Axis::Range {
            lo: 0.0,
            hi: 1.0,
            scale: Scale::Linear,
        }];
        for (d, axes, at, says) in [
            (
                design(Kind::Grid, Some(4)),
                &lv[..],
                "design.samples",
                "product",
            ),
            (
                design(Kind::Grid, None),
                &rg[..],
                "parameter[0].range",
                "levels",
            ),
            (
                design(Kind::Lhs, Some(4)),
                &lv[..],
                "parameter[0].levels",
                "range",
            ),
            (design(Kind::Lhs, None), &rg[..], "design.kind", "samples"),
            (
                design(Kind::Saltelli, Some(8)),
                &lv[..],
                "parameter[0].levels",
                "range",
            ),
            (
                design(Kind::Grid, None),
                &[][..],
                "parameter",
                "no [[parameter]]",
            ),
        ] {
            let e = points(&d, axes).unwrap_err();
            assert_eq!(e.at.to_string(), at, "{}", e.message);
            assert!(e.message.contains(says), "{}", e.message);
        }
        let big: Vec<Axis> = (0..6).map(|_| Axis::Levels(vec![0.0; 10])).collect();
        let e = points(&design(Kind::Grid, None), &big).unwrap_err();
        assert!(
            e.message.contains("10 x 10 x 10 x 10 x 10 x 10"),
            "{}",
            e.message
        );
    }
}
