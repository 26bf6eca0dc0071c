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
//! Phi^T F = K q + dV/dq: its nonlinear part at every q fits the energy polynomial's cubic and
//! quartic coefficients by linear least squares (`fit.rs`). K is ccx's own linear stiffness in
//! these coordinates, measured by one linear static solve per mode (the same deck without
//! NLGEOM): it is diag(w^2) only up to our mass matrix's difference from ccx's, and whatever
//! that difference is, it must not be fitted as nonlinear force (the cabinet's panel modes:
//! K - w^2 6.8e-7 of w^2, so there the two agree). Membrane motion that the chosen modes
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
use crate::modal::{Shapes, Solved};
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
/// every pair of modes at the four sign combinations of a quarter of each fitted level (their
/// coupling terms; two modes of one panel add up at its peak, and the reference cabinet's side
/// panel snapped through with both at the full level, at 0.61-0.64 of it). Levels are modal
/// coordinates a linear body would reach (kg^0.5 m): lambda = w^2 level, so one list serves
/// modes of different stiffness.
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
        for l in levels.iter().map(|l| l / 4.0) {
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
    /// max |K - diag(w^2)| / w^2 of ccx's linear modal stiffness (what the linear solves
    /// take out of the nonlinear force).
    pub linear_mismatch: f64,
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
    let stiffness = linear_stiffness(spec, &mass, &inv, &w2, dir, &mut report)?;
    let solve = |i: usize| {
        let job = format!("{}_nl{i}", spec.body);
        solve_case(
            mesh,
            &mass,
            shapes,
            &inv,
            &spec.cases[i].lambda,
            true,
            dir,
            &job,
        )
        .within(|| format!("{}: load case {i}", spec.body))
    };
    for (case, solved) in spec.cases.iter().zip(in_parallel(spec.cases.len(), solve)) {
        let (q, work, wall) = solved?;
        report.solve_s.push(wall);
        let f = work - &stiffness * &q;
        let sample = Sample {
            q: q.iter().copied().collect(),
            f: f.iter().copied().collect(),
        };
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

/// `f` at 0..n on as many threads as the machine has (each ccx solve is one-threaded, to be
/// repeatable), the results in order.
fn in_parallel<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let workers = std::thread::available_parallelism()
        .map_or(1, |c| c.get())
        .min(n);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut out: Vec<(usize, T)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        if i >= n {
                            return mine;
                        }
                        mine.push((i, f(i)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a ccx worker panicked"))
            .collect()
    });
    out.sort_by_key(|x| x.0);
    out.into_iter().map(|x| x.1).collect()
}

/// ccx's linear modal stiffness K (Phi^T F = K q for a linear solve): one linear static solve
/// per chosen mode at the largest load the plan puts on it, K = W Q^-1 with the solves' works
/// and coordinates as columns. Records the solves' times and K's mismatch from diag(w^2).
fn linear_stiffness(
    spec: &Spec,
    mass: &MassMatrix,
    inv: &DMatrix<f64>,
    w2: &[f64],
    dir: &Path,
    report: &mut Report,
) -> Result<DMatrix<f64>, Error> {
    let n = spec.shapes.len();
    let (mut q, mut work) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
    for s in 0..n {
        let top = spec
            .cases
            .iter()
            .map(|c| c.lambda[s].abs())
            .fold(0.0, f64::max);
        let mut lambda = vec![0.0; n];
        lambda[s] = if top > 0.0 { top } else { w2[s] };
        let job = format!("{}_lin{s}", spec.body);
        let (qs, ws, wall) =
            solve_case(spec.mesh, mass, spec.shapes, inv, &lambda, false, dir, &job)
                .within(|| format!("{}: linear solve of mode {s}", spec.body))?;
        report.solve_s.push(wall);
        q.set_column(s, &qs);
        work.set_column(s, &ws);
    }
    let k = work * q.try_inverse().ok_or(PipelineError::SingularInertia)?;
    report.linear_mismatch = (0..n * n)
        .map(|i| {
            let (r, c) = (i / n, i % n);
            (k[(r, c)] - if r == c { w2[r] } else { 0.0 }).abs() / w2[r]
        })
        .fold(0.0, f64::max);
    Ok(k)
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

/// The static deck of one load case: the mesh, then one `*STATIC` step (geometrically
/// nonlinear with `nlgeom`) with the nodal loads, its 2-D displacements (and the rigid parts'
/// prints) written at the end of each increment; the last block is the solution.
pub fn static_deck(mesh: &Mesh, loads: &[(usize, [f64; 3])], nlgeom: bool) -> Deck {
    let mut d = mesh.model_deck();
    // Automatic increments from a quarter of the load (a tenth doubled the cabinet's solves:
    // 10 increments of 6 iterations), at most half; down to 1e-6 before ccx gives up (a limit
    // point, which the caller's levels must stay below).
    d.line(if nlgeom {
        "*STEP, NLGEOM, INC=1000"
    } else {
        "*STEP"
    })
    .line("*STATIC")
    .line("0.25, 1.0, 1e-6, 0.5")
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

/// ccx on `deck` as `job` in `dir`, unless an earlier identification in the same folder solved
/// this very deck (`<job>.inp` the same text, and `<job>.done` written after its results were
/// read): then its results, and the wall time the marker recorded. An identification of the
/// cabinet is 20 nonlinear solves; one that stops (a limit point in one case, a stopped session)
/// resumes where it stopped.
fn solve_once(mesh: &Mesh, deck: &Deck, dir: &Path, job: &str) -> Result<Solved, Error> {
    let text = deck.text();
    let done = dir.join(format!("{job}.done"));
    let same = std::fs::read_to_string(dir.join(format!("{job}.inp"))).is_ok_and(|t| t == text);
    if let (true, Ok(wall)) = (same, std::fs::read_to_string(&done)) {
        let run = crate::ccx::CcxRun {
            job: dir.join(job),
            wall_s: wall.trim().parse().unwrap_or(0.0),
            stdout: String::new(),
        };
        return crate::modal::read_solved(mesh, run, job);
    }
    let solved = crate::modal::solve_deck(mesh, deck, dir, job)?;
    std::fs::write(&done, format!("{}\n", solved.run.wall_s)).map_err(Error::io(&done))?;
    Ok(solved)
}

/// One load case solved (nonlinearly with `nlgeom`) and projected: the modal coordinates q,
/// the load's modal works Phi^T F and ccx's wall time.
#[allow(clippy::too_many_arguments)]
fn solve_case(
    mesh: &Mesh,
    mass: &MassMatrix,
    shapes: &[Shapes],
    inv_gram: &DMatrix<f64>,
    lambda: &[f64],
    nlgeom: bool,
    dir: &Path,
    job: &str,
) -> Result<(DVector<f64>, DVector<f64>, f64), Error> {
    let loads = mass.shape_load(mesh, &combine(shapes, lambda))?;
    let deck = static_deck(mesh, &loads, nlgeom);
    let solved = solve_once(mesh, &deck, dir, job)?;
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
    let w = DVector::from_iterator(shapes.len(), shapes.iter().map(|s| work(s, &loads)));
    Ok((q, w, solved.run.wall_s))
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

/// The share of the mode `s`'s translations on the nodes `of`: sum of |w|^2 over `of` against
/// over all nodes (0 for a shape without translations; a mesh of even elements makes it the
/// share of the kinetic energy).
pub fn share(s: &Shapes, of: &[usize]) -> f64 {
    let sq = |u: &[f64; 3]| u.iter().map(|x| x * x).sum::<f64>();
    let total: f64 = s.w.values().map(sq).sum();
    let part: f64 = of.iter().filter_map(|id| s.w.get(id)).map(sq).sum();
    if total > 0.0 { part / total } else { 0.0 }
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
    /// 1 x 2 x 2 unseen, 4 sign pairs per fitted level at a quarter of it; lambda = w^2 level.
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
        assert!(
            (pairs[0].lambda[0] - 0.25).abs() < 1e-12 && (pairs[0].lambda[1] - 1.0).abs() < 1e-12
        );
    }
}
