//! Characteristic curves of a modal body (issue 52) by implicit condensation: Hollkamp and
//! Gordon, "Reduced-order models for nonlinear response prediction: implicit condensation and
//! expansion", J. Sound Vib. 318 (2008) 1139-1153; McEwan, Wright, Cooper and Leung, "A combined
//! modal/finite element analysis technique for the dynamic response of a non-linear beam to
//! harmonic excitation", J. Sound Vib. 243 (2001) 601-624.
//!
//! For the chosen mass-normalised modes Phi (the body's linear modal solve), each load case
//! applies F = M Phi lambda, ccx solves it geometrically nonlinearly (`*STATIC`, `NLGEOM`), and
//! the static displacement x is projected on the modes, q = G^-1 Phi^T M x (G = Phi^T M Phi, the
//! identity up to our mass matrix's difference from ccx's). The modal restoring force is then
//! Phi^T F = w^2 q + dV/dq: its nonlinear part at every q fits the energy polynomial's cubic and
//! quartic coefficients by linear least squares (`fit.rs`). Membrane motion that the chosen modes
//! do not hold (the arch's axial stretch, a panel's in-plane strain) stays in x and is condensed
//! into the coefficients: that is why the loads, not the displacements, are prescribed.

#[cfg(test)]
mod cabinet;
mod fit;

pub use fit::{Sample, curves as fit_samples, fit, level, monomials, residual};

use crate::consistent::{MassMatrix, consistent};
use crate::correction::work;
use crate::deck::Deck;
use crate::error::{Error, PipelineError, Within};
use crate::mesh::Mesh;
use crate::modal::Shapes;
use nalgebra::{DMatrix, DVector};
use std::collections::HashMap;
use std::path::Path;
use washdyn_model::ir::modal::{Curves, Fit};

/// One static load case: the modal load amplitudes lambda (one per chosen mode, N / kg^0.5;
/// the load is M Phi lambda), and whether the fit sees it or it is kept to check the fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub lambda: Vec<f64>,
    pub seen: bool,
}

/// The load cases of a plan: each mode alone at +-`levels` and +-`unseen`, and with `pairs`
/// every pair of modes at the four sign combinations of each fitted level (their coupling
/// terms). Levels are modal coordinates a linear body would reach (kg^0.5 m): lambda = w^2
/// level, so one list serves modes of different stiffness.
pub fn plan(frequencies_hz: &[f64], levels: &[f64], unseen: &[f64], pairs: bool) -> Vec<Case> {
    let n = frequencies_hz.len();
    let w2: Vec<f64> = frequencies_hz
        .iter()
        .map(|f| (2.0 * std::f64::consts::PI * f).powi(2))
        .collect();
    let mut out = Vec::new();
    let mut push = |amp: &[(usize, f64)], seen| {
        let mut lambda = vec![0.0; n];
        for &(r, q) in amp {
            lambda[r] = w2[r] * q;
        }
        out.push(Case { lambda, seen });
    };
    for (list, seen) in [(levels, true), (unseen, false)] {
        for &l in list {
            for r in 0..n {
                for s in [1.0, -1.0] {
                    push(&[(r, s * l)], seen);
                }
            }
        }
    }
    if pairs {
        for &l in levels {
            for r in 0..n {
                for t in r + 1..n {
                    for (a, b) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                        push(&[(r, a * l), (t, b * l)], true);
                    }
                }
            }
        }
    }
    out
}

/// What to identify: the body's mesh, the chosen modes' shapes (mass-normalised, from its
/// linear solve) with their indices in the modal data file, the load cases and the bound.
pub struct Spec<'a> {
    pub body: String,
    /// Where the modes come from (a deck, a modal data file), for `Curves::source`.
    pub source: String,
    pub mesh: &'a Mesh,
    pub shapes: &'a [Shapes],
    pub file_modes: Vec<usize>,
    pub cases: Vec<Case>,
    /// The largest relative residual allowed, at fitted and unseen loads.
    pub bound: f64,
}

/// What the identification measured besides the curves.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// ccx's wall time per load case, s.
    pub solve_s: Vec<f64>,
    /// The samples, fitted and unseen.
    pub seen: Vec<Sample>,
    pub unseen: Vec<Sample>,
    /// max |G - E| of the chosen modes under our mass matrix (its difference from ccx's).
    pub normalisation: f64,
}

/// Solve every load case, fit the curves, and refuse them above their bound
/// ([`check`], naming `<body>.curves.toml`).
pub fn identify(spec: &Spec, dir: &Path) -> Result<(Curves, Report), Error> {
    let (mesh, shapes) = (spec.mesh, spec.shapes);
    let mass = consistent(mesh);
    let gram = mass.inner(mesh, shapes, shapes)?;
    let n = shapes.len();
    let normalisation = (0..n * n)
        .map(|i| (gram[(i / n, i % n)] - if i / n == i % n { 1.0 } else { 0.0 }).abs())
        .fold(0.0, f64::max);
    let inv = gram.try_inverse().ok_or(PipelineError::SingularInertia)?;
    let w2: Vec<f64> = shapes
        .iter()
        .map(|s| (2.0 * std::f64::consts::PI * s.frequency_hz).powi(2))
        .collect();
    let mut report = Report {
        normalisation,
        ..Report::default()
    };
    for (i, case) in spec.cases.iter().enumerate() {
        let job = format!("{}_nl{i}", spec.body);
        let (sample, wall) = solve_case(mesh, &mass, shapes, &inv, &w2, &case.lambda, dir, &job)
            .within(|| format!("{}: load case {i}", spec.body))?;
        report.solve_s.push(wall);
        if case.seen {
            report.seen.push(sample);
        } else {
            report.unseen.push(sample);
        }
    }
    let head = Curves {
        body: spec.body.clone(),
        source: spec.source.clone(),
        modes: spec.file_modes.clone(),
        frequencies: shapes.iter().map(|s| s.frequency_hz).collect(),
        cubic: Vec::new(),
        quartic: Vec::new(),
        fit: Fit {
            loads: Vec::new(),
            residual: 0.0,
            unseen_loads: Vec::new(),
            unseen_residual: 0.0,
            bound: spec.bound,
        },
    };
    let curves = fit_samples(head, &report.seen, &report.unseen);
    check(&curves, &format!("{}.curves.toml", spec.body))?;
    Ok((curves, report))
}

/// Refuse curves whose residual at fitted or unseen loads is above their bound, naming the
/// file and the field.
pub fn check(c: &Curves, file: &str) -> Result<(), PipelineError> {
    match c.fit.beyond_bound().next() {
        Some((field, residual)) => Err(PipelineError::CurveFit {
            file: file.to_string(),
            field,
            residual,
            bound: c.fit.bound,
        }),
        None => Ok(()),
    }
}

/// The static deck of one load case: the mesh, then one geometrically nonlinear `*STATIC` step
/// with the nodal loads, its 2-D displacements (and the rigid parts' prints) written at the
/// end of each increment; the last block is the solution.
pub fn nlgeom_deck(mesh: &Mesh, loads: &[(usize, [f64; 3])]) -> Deck {
    let mut d = mesh.model_deck();
    // Automatic increments from a tenth of the load; down to 1e-6 before ccx gives up
    // (a limit point, which the caller's levels must stay below).
    d.line("*STEP, NLGEOM, INC=1000")
        .line("*STATIC")
        .line("0.1, 1.0, 1e-6, 0.25")
        .line("*CLOAD");
    for (id, v) in loads {
        for (c, x) in v.iter().enumerate() {
            if *x != 0.0 {
                d.line(&format!("{id}, {}, {x:.12e}", c + 1));
            }
        }
    }
    d.line("*NODE FILE, OUTPUT=2D").line("U");
    if !mesh.rigid.is_empty() {
        d.line("*NODE PRINT, NSET=WD_PRINT").line("U");
    }
    d.line("*END STEP");
    d
}

/// sum_r lambda_r Phi_r as one shape (translations and rigid rotations).
fn combine(shapes: &[Shapes], lambda: &[f64]) -> Shapes {
    let mut w: HashMap<usize, [f64; 3]> = HashMap::new();
    let mut rot: HashMap<usize, [f64; 3]> = HashMap::new();
    for (s, l) in shapes.iter().zip(lambda) {
        for (map, src) in [(&mut w, &s.w), (&mut rot, &s.rot)] {
            for (id, u) in src {
                let e = map.entry(*id).or_insert([0.0; 3]);
                for a in 0..3 {
                    e[a] += l * u[a];
                }
            }
        }
    }
    Shapes {
        frequency_hz: 0.0,
        w,
        rot,
    }
}

/// One load case solved and projected: the sample (q, Phi^T F - w^2 q) and ccx's wall time.
#[allow(clippy::too_many_arguments)]
fn solve_case(
    mesh: &Mesh,
    mass: &MassMatrix,
    shapes: &[Shapes],
    inv_gram: &DMatrix<f64>,
    w2: &[f64],
    lambda: &[f64],
    dir: &Path,
    job: &str,
) -> Result<(Sample, f64), Error> {
    let loads = mass.shape_load(mesh, &combine(shapes, lambda))?;
    let deck = nlgeom_deck(mesh, &loads);
    let solved = crate::modal::solve_deck(mesh, &deck, dir, job)?;
    let last = solved
        .frd
        .statics
        .last()
        .ok_or_else(|| PipelineError::NoStaticResult {
            job: job.to_string(),
        })?;
    let rot_ids: Vec<usize> = mesh.rigid.iter().map(|r| r.rot_node).collect();
    let mut w: HashMap<usize, [f64; 3]> = last.iter().copied().collect();
    let mut rot = HashMap::new();
    for &(id, v) in solved.prints.last().into_iter().flatten() {
        if rot_ids.contains(&id) {
            rot.insert(id, v);
        } else {
            w.entry(id).or_insert(v);
        }
    }
    let x = Shapes {
        frequency_hz: 0.0,
        w,
        rot,
    };
    let p = mass.inner(mesh, shapes, std::slice::from_ref(&x))?;
    let q: DVector<f64> = inv_gram * p.column(0);
    let f: Vec<f64> = shapes
        .iter()
        .enumerate()
        .map(|(r, s)| work(s, &loads) - w2[r] * q[r])
        .collect();
    Ok((
        Sample {
            q: q.iter().copied().collect(),
            f,
        },
        solved.run.wall_s,
    ))
}

/// The body's linear modal solve: `modes` eigenmodes, kept as the modal pipeline keeps them
/// (`keep`), so that their indices are the modal data file's.
pub fn linear_modes(
    body: &str,
    mesh: &Mesh,
    modes: usize,
    keep: crate::modal::Keep,
    dir: &Path,
) -> Result<Vec<Shapes>, Error> {
    let solved = crate::modal::solve(mesh, dir, &format!("{body}_modes"), modes, false)?;
    Ok(crate::modal::select(
        mesh,
        &solved.frd,
        &solved.prints,
        keep,
    )?)
}

/// The `count` modes of `all` that move the nodes `of` most, as a share of the mode's
/// translations over every node (sum of |w|^2 over `of` against over all nodes; a mesh of even
/// elements makes it the share of the kinetic energy): a panel's dominant modes. Ascending.
pub fn dominant(all: &[Shapes], of: &[usize], count: usize) -> Vec<usize> {
    let share = |s: &Shapes| {
        let sq = |u: &[f64; 3]| u.iter().map(|x| x * x).sum::<f64>();
        let total: f64 = s.w.values().map(sq).sum();
        let part: f64 = of.iter().filter_map(|id| s.w.get(id)).map(sq).sum();
        if total > 0.0 { part / total } else { 0.0 }
    };
    let mut order: Vec<(usize, f64)> = all.iter().map(share).enumerate().collect();
    order.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut out: Vec<usize> = order.into_iter().take(count).map(|x| x.0).collect();
    out.sort_unstable();
    out
}

/// [`identify`] on the modes of `all` (the body's kept modes) at `chosen`, with the load plan
/// of `levels` (fitted, unseen; [`plan`]).
#[allow(clippy::too_many_arguments)]
pub fn from_modes(
    body: &str,
    mesh: &Mesh,
    mut all: Vec<Shapes>,
    chosen: &[usize],
    levels: (&[f64], &[f64]),
    pairs: bool,
    bound: f64,
    dir: &Path,
) -> Result<(Curves, Report), Error> {
    let count = all.len();
    let mut shapes = Vec::with_capacity(chosen.len());
    for (k, &m) in chosen.iter().enumerate() {
        if m >= count || chosen[..k].contains(&m) {
            return Err(PipelineError::NoSuchMode {
                body: body.to_string(),
                mode: m,
                modes: count,
            }
            .into());
        }
        // Take the shape out of the list (each index once; later ones keep their place).
        shapes.push(std::mem::replace(
            &mut all[m],
            Shapes {
                frequency_hz: 0.0,
                w: HashMap::new(),
                rot: HashMap::new(),
            },
        ));
    }
    let freqs: Vec<f64> = shapes.iter().map(|s| s.frequency_hz).collect();
    let spec = Spec {
        body: body.to_string(),
        source: format!(
            "{}: ccx {} *STATIC NLGEOM, implicit condensation (Hollkamp and Gordon 2008), \
             levels {:?} fitted, {:?} unseen (kg^0.5 m, linear estimate), pairs {pairs}",
            mesh.title,
            crate::ccx::version().unwrap_or_default(),
            levels.0,
            levels.1
        ),
        mesh,
        shapes: &shapes,
        file_modes: chosen.to_vec(),
        cases: plan(&freqs, levels.0, levels.1, pairs),
        bound,
    };
    identify(&spec, dir)
}

/// [`linear_modes`], then [`from_modes`].
#[allow(clippy::too_many_arguments)]
pub fn from_mesh(
    body: &str,
    mesh: &Mesh,
    modes: usize,
    keep: crate::modal::Keep,
    chosen: &[usize],
    levels: (&[f64], &[f64]),
    pairs: bool,
    bound: f64,
    dir: &Path,
) -> Result<(Curves, Report), Error> {
    let all = linear_modes(body, mesh, modes, keep, dir)?;
    from_modes(body, mesh, all, chosen, levels, pairs, bound, dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curves(residual: f64, unseen: f64) -> Curves {
        Curves {
            body: "cabinet".into(),
            source: "test".into(),
            modes: vec![2],
            frequencies: vec![40.0],
            cubic: Vec::new(),
            quartic: Vec::new(),
            fit: Fit {
                loads: vec![0.01],
                residual,
                unseen_loads: vec![0.02],
                unseen_residual: unseen,
                bound: 0.01,
            },
        }
    }

    /// Each residual above the bound is refused under its own field name and the file's;
    /// a NaN residual (a failed projection) too; at the bound it passes.
    #[test]
    fn a_fit_above_its_bound_is_refused_naming_file_and_field() {
        assert!(check(&curves(0.01, 0.005), "c.toml").is_ok());
        let e = check(&curves(0.02, 0.005), "c.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.toml: fit.residual = 2.00e-2"), "{e}");
        let e = check(&curves(0.001, 0.03), "c.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("c.toml: fit.unseen_residual = 3.00e-2"),
            "{e}"
        );
        assert!(check(&curves(f64::NAN, 0.0), "c.toml").is_err());
    }

    /// Two modes, levels [1, 2] fitted and [1.5] unseen, with pairs: 2 x 2 x 2 singles and
    /// 1 x 2 x 2 unseen, 4 sign pairs per fitted level; lambda = w^2 level.
    #[test]
    fn plan_covers_both_signs_and_pairs() {
        let f = 1.0 / (2.0 * std::f64::consts::PI);
        let p = plan(&[f, 2.0 * f], &[1.0, 2.0], &[1.5], true);
        assert_eq!(p.iter().filter(|c| c.seen).count(), 8 + 8);
        assert_eq!(p.iter().filter(|c| !c.seen).count(), 4);
        assert!((p[1].lambda[0] + 1.0).abs() < 1e-12 && p[1].lambda[1] == 0.0);
        assert!((p[2].lambda[1] - 4.0).abs() < 1e-12);
        let pairs: Vec<&Case> = p
            .iter()
            .filter(|c| c.lambda.iter().all(|&l| l != 0.0))
            .collect();
        assert_eq!(pairs.len(), 8);
    }
}
