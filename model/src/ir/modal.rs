//! Modal data of an elastic body: the Ritz basis reduced to what the equations use (the seed
//! paper's elementary matrices, the mode shapes at the points markers use, and for the drum the
//! geometric stiffness). It is written by the FE front end (`washdyn fe write`) and read by both
//! model front ends through `read_file`; nothing here knows CalculiX.
//!
//! File format: TOML (documented in `docs/modal-data.md`), one file per body, written with
//! round-trip floats. Matrices are flat row-major lists; index k runs over the kept modes.

use super::V3;
use super::check::{CheckError, Path};
use super::files::DataFiles;
use serde::{Deserialize, Serialize};
use std::path::{Path as FsPath, PathBuf};

/// Which body of the machine a modal basis describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ElasticBodyKind {
    /// Free-free modes; the body's 6 rigid DOF are the multibody's.
    Tub,
    /// Clamped at its bearing; it rides on the tub's bearing point and spins.
    Drum,
    /// On its feet springs; no rigid DOF.
    Cabinet,
}

/// How the FE model was held when its modes were computed (the seed paper: the same rigid-body
/// DOF as the multibody model).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Support {
    FreeFree,
    Clamped,
    OnSprings,
}

/// The modal data of one body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalData {
    pub body: ElasticBodyKind,
    pub support: Support,
    /// Where the data came from (deck, solver), for the reader.
    pub source: String,
    /// Eigenfrequencies of the kept elastic modes, Hz, ascending.
    pub frequencies: Vec<f64>,
    /// The FE body (its consistent mass): mass kg, CoG m, inertia about the CoG kg m^2 (global
    /// axes).
    pub mass: f64,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub cog: V3,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub inertia: [[f64; 3]; 3],
    /// Elementary matrices (seed paper, "Equations of motion"), sums over the FE model with its
    /// consistent mass matrix plus the attached rigid parts (docs/modal-data.md); positions x0
    /// in the machine frame at rest.
    pub elementary: Elementary,
    /// Mode shapes at the points force elements and sensors use.
    #[serde(default)]
    pub points: Vec<ModalPoint>,
    /// Drum only: stiffness per Omega^2 from the centrifugal prestress.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometric_stiffness: Option<GeometricStiffness>,
    /// Static correction modes, if the body has them: the last `correction.modes` modes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correction: Option<Correction>,
    /// After truncation: the file's modes in terms of these, q_file = T q (file modes x modes,
    /// row-major), so that fields on the FE mesh can be recovered. None: the file's own modes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub basis: Option<Vec<f64>>,
    /// After truncation: the file's own modes at the points, so that a field on the FE mesh
    /// (in the file's modes) can be checked against them (`washdyn fields`). None: the file's
    /// own modes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file_modes: Option<FileModes>,
    /// The FE model's springs to the ground (the cabinet's feet), for damping by modal strain
    /// energy (`support_energy`). Empty: none recorded.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support_springs: Vec<SupportSpring>,
}

/// The file's modes before truncation, as a field of them is checked: frequencies, the number
/// of eigenmodes, and each point's w (in the order of `ModalData::points`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileModes {
    pub frequencies: Vec<f64>,
    pub eigenmodes: usize,
    pub w: Vec<[Vec<f64>; 3]>,
}

/// A spring from a one-node modal point to the ground: `stiffness` N/m along x, y, z.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpring {
    pub point: String,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub stiffness: V3,
}

/// Static correction (residual flexibility) modes: the static response to unit forces at the
/// attachment points, less what the eigenmodes hold, made mass- and stiffness-orthogonal.
/// Eigenmodes alone miss the local flexibility under a point load (a rail bending under a
/// spring); these modes carry it, so a static load at a listed point is answered exactly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Correction {
    /// The load cases: a unit force or moment along `direction` at the modal point `point`.
    pub loads: Vec<LoadCase>,
    /// How many of the body's modes, at the end, are correction modes.
    pub modes: usize,
    /// Generalised force of each load case on each eigenmode, f_j . Phi_k = w_point . direction
    /// for a force, phi_point . direction for a moment (`LoadCase::participation`; row k,
    /// column j, row-major; eigenmodes only). Truncating eigenmodes folds their static
    /// share at the load points into extra correction modes (`ModalData::truncate`).
    pub participation: Vec<f64>,
}

/// A unit force (or moment) along `direction` at a modal point. In the file:
/// `{ point = "BEARING", direction = [0.0, 0.0, 1.0] }` is a force; a moment adds
/// `kind = "moment"` (files without `kind` hold forces).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadCase {
    pub point: String,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub direction: V3,
    #[serde(default, skip_serializing_if = "LoadKind::is_force")]
    pub kind: LoadKind,
}

/// What a load case applies at its point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadKind {
    /// A force, N: its generalised force on mode k is w_point,k . direction.
    #[default]
    Force,
    /// A moment, N m: phi_point,k . direction (the point's rigid-fit rotation).
    Moment,
}

impl LoadKind {
    fn is_force(&self) -> bool {
        *self == LoadKind::Force
    }
}

impl LoadCase {
    pub fn force(point: &str, direction: V3) -> LoadCase {
        LoadCase {
            point: point.into(),
            direction,
            kind: LoadKind::Force,
        }
    }
    pub fn moment(point: &str, direction: V3) -> LoadCase {
        LoadCase {
            point: point.into(),
            direction,
            kind: LoadKind::Moment,
        }
    }
    /// Its generalised force on mode k at point `p`: w . direction or phi . direction.
    pub fn participation(&self, p: &ModalPoint, k: usize) -> f64 {
        let v = match self.kind {
            LoadKind::Force => &p.w,
            LoadKind::Moment => &p.phi,
        };
        (0..3).map(|a| v[a][k] * self.direction[a]).sum()
    }
}

/// The seed paper's elementary matrices for n modes; a, b run over x, y, z.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Elementary {
    /// c[a][k] = sum dm W_a,k (zero for free-free modes: orthogonal to translation).
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub c: [Vec<f64>; 3],
    /// s[a][b][k] = sum dm x0_a W_b,k (3 x 3 rows of n).
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub s: [[Vec<f64>; 3]; 3],
    /// g[a][b][k n + l] = sum dm W_a,k W_b,l (3 x 3 blocks of n x n, row-major);
    /// g_xx + g_yy + g_zz is the modal mass matrix (identity for mass-normalised modes).
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub g: [[Vec<f64>; 3]; 3],
}

/// A point on the body: a node set's rigid-fit motion evaluated at `position`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalPoint {
    /// The FE model's node set (upper case, as in the deck).
    pub name: String,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub position: V3,
    /// Number of FE nodes in the set; with fewer than 3 (non-collinear) the rotation is zero.
    pub nodes: usize,
    /// Translation per mode: w[a][k], m per unit modal coordinate.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub w: [Vec<f64>; 3],
    /// Rotation per mode: phi[a][k], rad per unit modal coordinate.
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub phi: [Vec<f64>; 3],
}

/// K_G / Omega^2 in modal coordinates (n x n, row-major), for spin about `axis` through
/// `axis_point`, Omega in rad/s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometricStiffness {
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub axis_point: V3,
    #[serde(deserialize_with = "crate::ir::exact::exact")]
    pub axis: V3,
    pub per_omega2: Vec<f64>,
    /// The speed (rad/s) of the prestressed solution it was extracted from.
    pub reference_speed: f64,
}

impl ModalData {
    pub fn modes(&self) -> usize {
        self.frequencies.len()
    }
    /// The eigenmodes (the modes before the correction modes).
    pub fn eigenmodes(&self) -> usize {
        self.modes() - self.correction.as_ref().map_or(0, |c| c.modes)
    }
    /// Each mode's share of its strain energy stored in the support springs:
    /// e_k = sum_springs sum_a k_a w_a,k^2 / omega_k^2 (modal stiffness diag(omega^2), the
    /// modes K-orthogonal: eigenmodes, correction modes and folded ones alike). In [0, 1]: 1
    /// for a mode that only rides on the springs. Zeros without springs; a spring at an
    /// unknown point counts nothing (the checker reports it).
    pub fn support_energy(&self) -> Vec<f64> {
        let mut e = vec![0.0; self.modes()];
        for s in &self.support_springs {
            let Some(p) = self.point(&s.point) else {
                continue;
            };
            for (k, ek) in e.iter_mut().enumerate() {
                *ek += (0..3)
                    .map(|a| s.stiffness[a] * p.w[a][k].powi(2))
                    .sum::<f64>();
            }
        }
        for (ek, f) in e.iter_mut().zip(&self.frequencies) {
            *ek /= (2.0 * std::f64::consts::PI * f).powi(2);
        }
        e
    }
    /// The modal mass matrix sum dm W^T W (n x n, row-major).
    pub fn modal_mass(&self) -> Vec<f64> {
        let n = self.modes();
        (0..n * n)
            .map(|i| (0..3).map(|a| self.elementary.g[a][a][i]).sum())
            .collect()
    }
    /// Largest deviation of the modal mass matrix from the identity: how far the mass the sums
    /// were formed with is from the one ccx normalised the shapes with (consistent mass: ~1e-4,
    /// the section rotations the translations do not show; HRZ lumping: per cent).
    pub fn mass_normalisation_error(&self) -> f64 {
        let n = self.modes();
        self.modal_mass()
            .iter()
            .enumerate()
            .map(|(i, v)| (v - if i / n == i % n { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max)
    }
    /// Keep the first `n` eigenmodes. Correction modes stay; the dropped eigenmodes' static
    /// response to the load cases (the correction's and `loads`, the scene's elements' at this
    /// body, `Model::element_loads`), sum_k Phi_k (f_j . Phi_k) / omega_k^2, becomes new
    /// correction modes, so that truncation never loses flexibility at the load points.
    pub fn truncate(&mut self, n: usize, loads: &[LoadCase]) {
        let (m, e) = (self.modes(), self.eigenmodes());
        if n >= e {
            return;
        }
        let w2: Vec<f64> = self
            .frequencies
            .iter()
            .map(|f| (2.0 * std::f64::consts::PI * f).powi(2))
            .collect();
        // Columns over the dropped modes n..e: the static shapes of the load cases.
        let mut cols: Vec<Vec<f64>> = Vec::new();
        if let Some(c) = &self.correction {
            let j = c.loads.len();
            cols.extend((0..j).map(|col| {
                (n..e)
                    .map(|k| c.participation[k * j + col] / w2[k])
                    .collect()
            }));
        }
        for l in loads {
            if let Some(p) = self.point(&l.point) {
                cols.push((n..e).map(|k| l.participation(p, k) / w2[k]).collect());
            }
        }
        let folded = if cols.is_empty() {
            (nalgebra::DMatrix::zeros(e - n, 0), Vec::new())
        } else {
            let u = nalgebra::DMatrix::from_fn(e - n, cols.len(), |r, c| cols[c][r]);
            orthonormal_static_basis(&u, &w2[n..e])
        };
        let (p, r) = (folded.1.len(), m - e);
        let mut t = nalgebra::DMatrix::zeros(m, n + p + r);
        for k in 0..n {
            t[(k, k)] = 1.0;
        }
        t.view_mut((n, n), (e - n, p)).copy_from(&folded.0);
        for k in 0..r {
            t[(e + k, n + p + k)] = 1.0;
        }
        let mut frequencies = self.frequencies[..n].to_vec();
        frequencies.extend(folded.1);
        frequencies.extend_from_slice(&self.frequencies[e..]);
        self.change_basis(&t, frequencies);
        match &mut self.correction {
            Some(c) => {
                c.modes = p + r;
                c.participation.truncate(n * c.loads.len());
            }
            // Data without correction modes (the drum): the folded shapes are correction
            // modes all the same, so that `eigenmodes()` counts only eigenmodes.
            None if p > 0 => {
                self.correction = Some(Correction {
                    loads: Vec::new(),
                    modes: p,
                    participation: Vec::new(),
                })
            }
            None => {}
        }
    }

    /// Cut as a scene with `cutoff` Hz cuts it: the eigenmodes up to it (at least one), the
    /// correction modes, and the dropped modes' static response to `loads` (`truncate`).
    pub fn cut(&mut self, cutoff: f64, loads: &[LoadCase]) {
        let keep = self.frequencies[..self.eigenmodes()]
            .iter()
            .filter(|f| **f <= cutoff)
            .count()
            .max(1);
        self.truncate(keep, loads);
    }

    /// The eigenmodes alone, without the correction modes (to measure what they buy).
    pub fn without_correction(&self) -> ModalData {
        let mut d = self.clone();
        let e = d.eigenmodes();
        let m = d.modes();
        d.correction = None;
        let t = nalgebra::DMatrix::from_fn(m, e, |r, c| if r == c { 1.0 } else { 0.0 });
        let f = d.frequencies[..e].to_vec();
        d.change_basis(&t, f);
        d
    }

    /// Express the data in new coordinates q_old = T q_new (T: modes x new modes) whose
    /// stiffness is diagonal with `frequencies`: every field is linear or bilinear in the shapes.
    fn change_basis(&mut self, t: &nalgebra::DMatrix<f64>, frequencies: Vec<f64>) {
        let (m, n) = t.shape();
        if self.file_modes.is_none() {
            self.file_modes = Some(self.own_modes());
        }
        let row = |v: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|j| (0..m).map(|k| v[k] * t[(k, j)]).sum())
                .collect()
        };
        let square = |v: &[f64]| -> Vec<f64> {
            let a = nalgebra::DMatrix::from_row_slice(m, m, v);
            let b = t.transpose() * a * t;
            (0..n * n).map(|i| b[(i / n, i % n)]).collect()
        };
        let file = match &self.basis {
            Some(b) => nalgebra::DMatrix::from_row_slice(b.len() / m, m, b) * t,
            None => t.clone(),
        };
        self.basis = Some(
            (0..file.nrows() * n)
                .map(|i| file[(i / n, i % n)])
                .collect(),
        );
        let e = &mut self.elementary;
        for a in 0..3 {
            e.c[a] = row(&e.c[a]);
            for b in 0..3 {
                e.s[a][b] = row(&e.s[a][b]);
                e.g[a][b] = square(&e.g[a][b]);
            }
        }
        for p in &mut self.points {
            for a in 0..3 {
                p.w[a] = row(&p.w[a]);
                p.phi[a] = row(&p.phi[a]);
            }
        }
        if let Some(k) = &mut self.geometric_stiffness {
            k.per_omega2 = square(&k.per_omega2);
        }
        self.frequencies = frequencies;
    }
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("modal data serialises")
    }
}

/// Relative size below which a static shape adds nothing new (it lies in the others' span).
pub const DEPENDENT_SHAPE: f64 = 1e-10;

/// The span of the columns of `u` (coordinates in modes with unit modal mass and stiffness
/// `w2`) as an orthonormal, stiffness-diagonal basis: (basis columns, their frequencies in Hz,
/// ascending). Directions whose modal mass is below `DEPENDENT_SHAPE` of the largest are dropped.
pub fn orthonormal_static_basis(
    u: &nalgebra::DMatrix<f64>,
    w2: &[f64],
) -> (nalgebra::DMatrix<f64>, Vec<f64>) {
    let k = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(w2));
    let mass = u.transpose() * u;
    let stiff = u.transpose() * k * u;
    let (b, lambda) = generalised_eigen(&mass, &stiff);
    let basis = u * b;
    let f = lambda
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    (basis, f)
}

/// Solve K x = lambda M x in the span where M (symmetric, semi-definite) is not negligible:
/// (X with X^T M X = E and X^T K X = diag(lambda), lambda ascending).
pub fn generalised_eigen(
    mass: &nalgebra::DMatrix<f64>,
    stiff: &nalgebra::DMatrix<f64>,
) -> (nalgebra::DMatrix<f64>, Vec<f64>) {
    let me = nalgebra::SymmetricEigen::new(0.5 * (mass + mass.transpose()));
    let top = me.eigenvalues.iter().fold(0.0f64, |a, v| a.max(*v));
    let keep: Vec<usize> = (0..me.eigenvalues.len())
        .filter(|&i| top > 0.0 && me.eigenvalues[i] > DEPENDENT_SHAPE * top)
        .collect();
    let b = nalgebra::DMatrix::from_fn(mass.nrows(), keep.len(), |r, c| {
        me.eigenvectors[(r, keep[c])] / me.eigenvalues[keep[c]].sqrt()
    });
    let a = b.transpose() * stiff * &b;
    let ke = nalgebra::SymmetricEigen::new(0.5 * (&a + a.transpose()));
    let mut order: Vec<usize> = (0..keep.len()).collect();
    order.sort_by(|&i, &j| ke.eigenvalues[i].total_cmp(&ke.eigenvalues[j]));
    let x = nalgebra::DMatrix::from_fn(mass.nrows(), keep.len(), |r, c| {
        (0..keep.len())
            .map(|l| b[(r, l)] * ke.eigenvectors[(l, order[c])])
            .sum()
    });
    (x, order.iter().map(|&i| ke.eigenvalues[i]).collect())
}

/// Read a modal data file; errors carry the file (as `shown`) and line.
pub fn read_file(path: &FsPath, shown: &str) -> Result<ModalData, String> {
    let src = std::fs::read_to_string(path).map_err(|e| format!("{shown}: cannot read: {e}"))?;
    read_str(&src, shown)
}

/// Parse modal data text; errors carry the file (as `shown`) and line.
pub fn read_str(src: &str, shown: &str) -> Result<ModalData, String> {
    from_toml(src).map_err(|(span, m)| {
        let line = span.map_or(0, |s| src[..s.start.min(src.len())].lines().count().max(1));
        format!("{shown}:{line}: {m}")
    })
}

/// Deserialize TOML text; an error gives its span and a message that names the field
/// (`points[2].position: invalid length 4, ...`), as serde_path_to_error tracks it.
pub fn from_toml<T: serde::de::DeserializeOwned>(
    src: &str,
) -> Result<T, (Option<std::ops::Range<usize>>, String)> {
    let de = toml::Deserializer::parse(src).map_err(|e| (e.span(), e.message().trim().into()))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let e = e.into_inner();
        let m = e.message().trim();
        // A message of its own that starts with the field (`missing field`, `unknown field`)
        // or an error at the top needs no path.
        let m = if path == "." || m.contains(&format!("`{path}`")) {
            m.to_string()
        } else {
            format!("{path}: {m}")
        };
        (e.span(), m)
    })
}

/// Read every elastic body's modal data file (from `files`: relative to the model's directory,
/// or compiled in) into the model: the one resolver of both front ends. Returns the files read
/// from disk (the macro makes cargo watch them) and the problems, each at `elastic[i].file` and
/// naming the file (an absolute path, or the embedded file's origin).
pub fn resolve(model: &mut super::Model, files: DataFiles) -> (Vec<PathBuf>, Vec<CheckError>) {
    let (mut read, mut errors) = (Vec::new(), Vec::new());
    for (i, e) in model.elastic.iter_mut().enumerate() {
        let data = files
            .read(&e.file)
            .map_err(|e| e.to_string())
            .and_then(|f| {
                read.extend(f.path.clone());
                read_str(&f.text, &f.shown)
            });
        match data {
            Ok(mut d) => {
                // The file's own rules before anything computes with it (truncation's
                // eigen-solver did not return on NaN); the checker skips a body without data.
                let found = problems(&d);
                if !found.is_empty() {
                    errors.extend(found.into_iter().map(|m| CheckError {
                        path: Path::default().key("elastic").idx(i).key("file"),
                        message: format!("elastic `{}`: {}: {m}", e.name, files.shown(&e.file)),
                    }));
                    continue;
                }
                if let Some(n) = e.modes {
                    if n > d.eigenmodes() {
                        errors.push(CheckError {
                            path: Path::default().key("elastic").idx(i).key("modes"),
                            message: format!(
                                "elastic `{}`: asks for {n} modes, `{}` has {}",
                                e.name,
                                files.shown(&e.file),
                                d.eigenmodes()
                            ),
                        });
                    }
                    d.truncate(n, &[]);
                }
                e.data = Some(d);
            }
            Err(m) => errors.push(CheckError {
                path: Path::default().key("elastic").idx(i).key("file"),
                message: format!("elastic `{}`: {m}", e.name),
            }),
        }
    }
    (read, errors)
}

/// Relative tolerance of the stored participation against the point's shapes (both come from
/// the same rigid fit, so they agree to round-off).
pub const PARTICIPATION_TOLERANCE: f64 = 1e-6;

/// Mass-normalisation tolerance of the checker: a sanity check (the consistent mass gives
/// ~1e-4 on the built-in bodies; HRZ lumping gave a few per cent and grew with the modes).
pub const MASS_NORMALISATION_TOLERANCE: f64 = 0.05;

/// How far a mode's support strain energy share may exceed 1: the shapes' print precision
/// (ccx's `.frd`, 6 digits) with margin.
pub const SUPPORT_ENERGY_TOLERANCE: f64 = 1e-3;

/// The modal data's own consistency: dimensions, frequencies, mass-normalisation, points. Each
/// finding names the field inside the file; the caller adds the file and the model's path.
pub fn problems(d: &ModalData) -> Vec<String> {
    let mut out = Vec::new();
    let n = d.modes();
    if n == 0 {
        out.push("frequencies: no modes".into());
    }
    let (f_lo, f_hi) = FREQUENCY_RANGE;
    for (k, f) in d.frequencies.iter().enumerate() {
        if !(*f >= f_lo && *f <= f_hi) {
            out.push(format!(
                "frequencies[{k}]: must be positive and finite, within [{f_lo:e}, {f_hi:e}] Hz, \
                 got {f}"
            ));
        }
    }
    let corr = d.correction.as_ref().map_or(0, |c| c.modes);
    if corr > n {
        out.push(format!("correction.modes: {corr} of only {n} modes"));
    } else {
        let (eig, cor) = d.frequencies.split_at(n - corr);
        if eig.windows(2).any(|w| w[1] < w[0]) || cor.windows(2).any(|w| w[1] < w[0]) {
            out.push("frequencies: not ascending (eigenmodes, then correction modes)".into());
        }
    }
    mass_properties(d, &mut out);
    support(d, &mut out);
    let xyz = ["x", "y", "z"];
    let mut dims = |field: String, v: &[f64], len: usize| {
        if v.len() != len {
            out.push(format!(
                "{field}: expected {len} values for {n} modes, found {}",
                v.len()
            ));
        } else if v.iter().any(|x| !x.is_finite()) {
            out.push(format!("{field}: non-finite number"));
        }
    };
    let e = &d.elementary;
    for a in 0..3 {
        dims(format!("elementary.c[{}]", xyz[a]), &e.c[a], n);
        for b in 0..3 {
            dims(
                format!("elementary.s[{}][{}]", xyz[a], xyz[b]),
                &e.s[a][b],
                n,
            );
            dims(
                format!("elementary.g[{}][{}]", xyz[a], xyz[b]),
                &e.g[a][b],
                n * n,
            );
        }
    }
    for (i, p) in d.points.iter().enumerate() {
        for a in 0..3 {
            dims(
                format!("points[{i}] ({}).w[{}]", p.name, xyz[a]),
                &p.w[a],
                n,
            );
            dims(
                format!("points[{i}] ({}).phi[{}]", p.name, xyz[a]),
                &p.phi[a],
                n,
            );
        }
    }
    if let Some(k) = &d.geometric_stiffness {
        dims(
            "geometric_stiffness.per_omega2".into(),
            &k.per_omega2,
            n * n,
        );
    }
    if let Some(c) = &d.correction
        && corr <= n
    {
        dims(
            "correction.participation".into(),
            &c.participation,
            (n - corr) * c.loads.len(),
        );
        let loads = c.loads.len();
        for (j, l) in c.loads.iter().enumerate() {
            let Some(p) = d.point(&l.point) else {
                out.push(format!(
                    "correction.loads[{j}]: no point `{}` in `points`",
                    l.point
                ));
                continue;
            };
            if !at_most(
                (crate::geom::f::norm(l.direction) - 1.0).abs(),
                UNIT_TOLERANCE,
            ) {
                out.push(format!(
                    "correction.loads[{j}].direction: must be a unit vector, got {:?}",
                    l.direction
                ));
            }
            if l.kind == LoadKind::Moment && p.nodes < 3 {
                out.push(format!(
                    "correction.loads[{j}]: a moment at `{}`, whose {} node(s) give no rotation",
                    l.point, p.nodes
                ));
            }
            // The stored generalised forces are the point's w (phi for a moment) . direction:
            // a load case that names another point or kind than it was computed with shows.
            if c.participation.len() == (n - corr) * loads && p.w[0].len() == n {
                let col: Vec<f64> = (0..n - corr)
                    .map(|k| c.participation[k * loads + j])
                    .collect();
                let scale = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let worst = (0..n - corr)
                    .map(|k| (col[k] - l.participation(p, k)).abs())
                    .fold(0.0, f64::max);
                if worst > PARTICIPATION_TOLERANCE * scale {
                    out.push(format!(
                        "correction.participation (load {j}): differs from `{}`'s {} . direction \
                         by {:.1e} of its largest value",
                        l.point,
                        if l.kind == LoadKind::Moment {
                            "phi"
                        } else {
                            "w"
                        },
                        worst / scale
                    ));
                }
            }
        }
    }
    geometric_stiffness(d, &mut out);
    gram(d, &mut out);
    for (i, p) in d.points.iter().enumerate() {
        let at = format!("points[{i}] ({})", p.name);
        position(&format!("{at}.position"), &p.position, &mut out);
        for (what, v, max) in [("w", &p.w, MAX_W), ("phi", &p.phi, MAX_PHI)] {
            for a in 0..3 {
                let big = v[a].iter().map(|x| x.abs()).fold(0.0, f64::max);
                if big > max {
                    out.push(format!(
                        "{at}.{what}[{}]: {big:e} per unit modal coordinate, more than {max:e}",
                        xyz[a]
                    ));
                }
            }
        }
        if p.nodes < 3 && p.phi.iter().flatten().any(|x| *x != 0.0) {
            out.push(format!(
                "{at}.phi: a set of {} node(s) determines no rotation, so phi must be zero",
                p.nodes
            ));
        }
    }
    if let Some(b) = &d.basis {
        if n == 0 || b.len() % n != 0 {
            out.push(format!(
                "basis: {} values are no whole rows of {n}",
                b.len()
            ));
        }
        // Orthonormal columns (mass-normalised modes in mass-normalised modes): no entry
        // exceeds 1 beyond round-off.
        if let Some((i, v)) = b
            .iter()
            .enumerate()
            .find(|(_, v)| !at_most(v.abs(), 1.0 + GRAM_TOLERANCE))
        {
            out.push(format!(
                "basis[{i}]: {v}; the columns are orthonormal, so every entry lies in [-1, 1]"
            ));
        }
    }
    for (i, s) in d.support_springs.iter().enumerate() {
        match d.point(&s.point) {
            None => out.push(format!(
                "support_springs[{i}]: no point `{}` in `points`",
                s.point
            )),
            Some(p) if p.nodes != 1 => out.push(format!(
                "support_springs[{i}]: point `{}` reads {} nodes; a spring to the ground sits \
                 on one node",
                s.point, p.nodes
            )),
            Some(_) => {}
        }
        if s.stiffness
            .iter()
            .any(|k| !(*k >= 0.0 && *k <= MAX_SUPPORT_STIFFNESS))
        {
            out.push(format!(
                "support_springs[{i}].stiffness: must be in [0, {MAX_SUPPORT_STIFFNESS:e}] N/m, \
                 got {:?}",
                s.stiffness
            ));
        }
    }
    for (i, p) in d.points.iter().enumerate() {
        if p.nodes == 0 {
            out.push(format!(
                "points[{i}] ({}): the node set has no nodes",
                p.name
            ));
        }
        if d.points[..i].iter().any(|q| q.name == p.name) {
            out.push(format!("points[{i}]: `{}` appears twice", p.name));
        }
    }
    if out.is_empty()
        && let Some((k, e)) = d
            .support_energy()
            .into_iter()
            .enumerate()
            .find(|(_, e)| *e > 1.0 + SUPPORT_ENERGY_TOLERANCE)
    {
        out.push(format!(
            "support_springs: mode {k} would store {e:.4} of its strain energy in them (more \
             than all): the springs are not those of the FE model behind these modes"
        ));
    }
    if out.is_empty() {
        let err = d.mass_normalisation_error();
        if err > MASS_NORMALISATION_TOLERANCE {
            out.push(format!(
                "elementary.g: modes are not mass-normalised: sum dm W^T W differs from the \
                 identity by {err:.3} (allowed {MASS_NORMALISATION_TOLERANCE})"
            ));
        }
    }
    out
}

/// Plausible mass of one elastic part of a washing machine, kg: the parts weigh kilograms to
/// tens of kilograms (the committed drum 9.5 kg, cabinet 29 kg, tub 44 kg). A gram or ten
/// tonnes is a unit slip (g or t for kg) or a broken deck, and 1e308 kg overflows the sums.
pub const MASS_RANGE: (f64, f64) = (1e-3, 1e4);

/// Elastic eigenfrequencies, Hz. Below 0.1 Hz a "mode" is a rigid-body motion left in (the
/// multibody's own DOF; the committed data start at 26 Hz); above 1 MHz no structural mode of
/// an appliance (the committed correction modes reach 6.6 kHz), and (2 pi f)^2 of 1e308
/// overflows.
pub const FREQUENCY_RANGE: (f64, f64) = (0.1, 1e6);

/// Largest distance of a CoG, point or axis point from the machine frame's origin, m: a washing
/// machine is under 1 m in each direction (the committed points within 0.91 m); 10 m still
/// refuses a position in mm read as m.
pub const MAX_EXTENT: f64 = 10.0;

/// Largest translation of a point per unit modal coordinate, m kg^-1/2. A mass-normalised mode
/// moves a node of mass dm by at most 1/sqrt(dm) (its share of the unit modal mass), and a
/// point is a rigid fit of nodes; 1e3 is a node of 1 mg, far below any node of a sheet-metal
/// or plastic mesh (the committed data: 1.7 at most).
pub const MAX_W: f64 = 1e3;

/// Largest rotation of a point per unit modal coordinate, rad kg^-1/2: `MAX_W` across a node
/// set 1 mm wide (the committed data: 29 at most).
pub const MAX_PHI: f64 = 1e6;

/// Largest entry of K_G / Omega^2 (mass-normalised modes, so dimensionless): the stress
/// stiffening of a ring's mode with n waves is of the order n^2; 1e4 is n = 100, beyond any
/// mode a drum's data keep (the committed drum: 7.8; its spin softening at most 0.71).
pub const MAX_PER_OMEGA2: f64 = 1e4;

/// Stiffest support spring, N/m: a washing machine's feet are 1e5-1e6 N/m (the committed
/// cabinet's 4e5 and 2e6); 1e10 N/m is a rigid support, a body clamped rather than on springs.
pub const MAX_SUPPORT_STIFFNESS: f64 = 1e10;

/// How far a direction given as a unit vector may be from unit length.
pub const UNIT_TOLERANCE: f64 = 1e-9;

/// Relative round-off allowed in the identities of a Gram matrix (symmetry, Cauchy-Schwarz):
/// the committed data hold them to 1e-15.
pub const GRAM_TOLERANCE: f64 = 1e-6;

/// Margin on the Cauchy-Schwarz bounds of `c` and `s` against the mass properties (both are
/// formed with the one consistent mass matrix, so the bounds hold exactly; the committed data
/// reach 0.99 of them); the margin allows a user's data whose mass properties come from another
/// integration of the same body.
pub const MOMENT_BOUND_MARGIN: f64 = 1.1;

/// `v <= max`, and false for NaN: a rule states what a value must be, so NaN fails it.
fn at_most(v: f64, max: f64) -> bool {
    v <= max
}

/// A position (CoG, point, axis point): finite and within `MAX_EXTENT` of the origin.
fn position(field: &str, v: &V3, out: &mut Vec<String>) {
    let r = crate::geom::f::norm(*v);
    if !at_most(r, MAX_EXTENT) {
        out.push(format!(
            "{field}: {v:?} must be finite and within {MAX_EXTENT} m of the origin (SI units)"
        ));
    }
}

/// Mass, CoG and inertia: a plausible mass, a finite CoG inside the machine, and an inertia
/// tensor some mass distribution has (symmetric, positive definite, the principal moments
/// within the triangle inequality, none beyond mass x `MAX_EXTENT`^2).
fn mass_properties(d: &ModalData, out: &mut Vec<String>) {
    let (lo, hi) = MASS_RANGE;
    if !(d.mass >= lo && d.mass <= hi) {
        out.push(format!(
            "mass: must be positive, within [{lo:e}, {hi:e}] kg for a part of a washing machine, \
             got {}",
            d.mass
        ));
    }
    position("cog", &d.cog, out);
    let m = &d.inertia;
    if m.iter().flatten().any(|v| !v.is_finite()) {
        out.push(format!("inertia: non-finite number in {m:?}"));
        return;
    }
    let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    for i in 0..3 {
        for j in i + 1..3 {
            if !at_most((m[i][j] - m[j][i]).abs(), 1e-9 * scale) {
                out.push(format!(
                    "inertia: not symmetric ([{i}][{j}] = {} but [{j}][{i}] = {})",
                    m[i][j], m[j][i]
                ));
                return;
            }
        }
    }
    let ev = super::check::sym_eigenvalues(m);
    if !(ev[0].is_finite() && ev[0] > 0.0) {
        out.push(format!(
            "inertia: not positive definite (principal moments {ev:?} kg m^2)"
        ));
    } else if ev[0] + ev[1] < ev[2] * (1.0 - 1e-12) {
        out.push(format!(
            "inertia: principal moments {ev:?} violate the triangle inequality (I1 + I2 >= I3), \
             no mass distribution has them"
        ));
    } else if d.mass > 0.0 && ev[2] > d.mass * MAX_EXTENT * MAX_EXTENT {
        out.push(format!(
            "inertia: principal moment {:e} kg m^2 is more than mass x ({MAX_EXTENT} m)^2",
            ev[2]
        ));
    }
}

/// The support the equations assume for each body: the tub's modes free-free (its 6 rigid DOF
/// are the multibody's), the drum's clamped at its bearing, the cabinet's on its feet.
fn support(d: &ModalData, out: &mut Vec<String>) {
    let want = match d.body {
        ElasticBodyKind::Tub => Support::FreeFree,
        ElasticBodyKind::Drum => Support::Clamped,
        ElasticBodyKind::Cabinet => Support::OnSprings,
    };
    if d.support != want {
        out.push(format!(
            "support: {:?} for the {:?}, whose modes the equations take as {want:?}",
            d.support, d.body
        ));
    }
}

/// The sums of `elementary` are inner products in the body's mass, so they obey Gram
/// identities whatever the modes: g[a][b][k n + l] = g[b][a][l n + k],
/// |g[a][b][k n + l]| <= sqrt(g[a][a][k n + k] g[b][b][l n + l]), and by Cauchy-Schwarz
/// |c[a][k]| <= sqrt(mass g[a][a][kk]), |s[a][b][k]| <= sqrt(J_aa g[b][b][kk]) with
/// J_aa = sum dm x_a^2 = mass cog_a^2 + tr(I) / 2 - I_aa. A value outside is no sum over a
/// body (an entry of -1e308 in an off-diagonal block hung the Campbell diagram).
fn gram(d: &ModalData, out: &mut Vec<String>) {
    let n = d.modes();
    let e = &d.elementary;
    let fine = |v: &[f64], len: usize| v.len() == len && v.iter().all(|x| x.is_finite());
    if n == 0
        || !(0..3).all(|a| {
            fine(&e.c[a], n) && (0..3).all(|b| fine(&e.s[a][b], n) && fine(&e.g[a][b], n * n))
        })
    {
        return; // `problems` reports the sizes and numbers
    }
    let xyz = ["x", "y", "z"];
    let diag = |a: usize, k: usize| e.g[a][a][k * n + k];
    for a in 0..3 {
        // The three add up to the modal mass, 1 for a mass-normalised mode.
        let top = 1.0 + MASS_NORMALISATION_TOLERANCE;
        if let Some(k) = (0..n).find(|&k| !(diag(a, k) >= 0.0 && diag(a, k) <= top)) {
            out.push(format!(
                "elementary.g[{0}][{0}][{1}]: {2:e}, but sum dm W_a,k^2 of a mass-normalised \
                 mode lies in [0, {top}]",
                xyz[a],
                k * n + k,
                diag(a, k)
            ));
            return;
        }
    }
    let scale = (0..3)
        .flat_map(|a| (0..n).map(move |k| (a, k)))
        .fold(0.0f64, |m, (a, k)| m.max(diag(a, k)));
    for a in 0..3 {
        for b in 0..3 {
            for k in 0..n {
                for l in 0..n {
                    let v = e.g[a][b][k * n + l];
                    let bound = (diag(a, k) * diag(b, l)).sqrt();
                    let tol = GRAM_TOLERANCE * scale;
                    if !at_most(v.abs(), bound + tol) {
                        out.push(format!(
                            "elementary.g[{}][{}][{}]: {v:e} exceeds sqrt(g_aa,kk g_bb,ll) = \
                             {bound:e} (sum dm W_a,k W_b,l obeys Cauchy-Schwarz)",
                            xyz[a],
                            xyz[b],
                            k * n + l
                        ));
                        return;
                    }
                    if !at_most((v - e.g[b][a][l * n + k]).abs(), tol) {
                        out.push(format!(
                            "elementary.g[{}][{}][{}]: {v:e}, but elementary.g[{}][{}][{}] = \
                             {:e} (sum dm W_a,k W_b,l is symmetric)",
                            xyz[a],
                            xyz[b],
                            k * n + l,
                            xyz[b],
                            xyz[a],
                            l * n + k,
                            e.g[b][a][l * n + k]
                        ));
                        return;
                    }
                }
            }
        }
    }
    if !(d.mass > 0.0 && d.mass.is_finite()) || d.cog.iter().any(|x| !x.is_finite()) {
        return;
    }
    let i = &d.inertia;
    let tr = i[0][0] + i[1][1] + i[2][2];
    for a in 0..3 {
        let j = d.mass * d.cog[a] * d.cog[a] + tr / 2.0 - i[a][a];
        for k in 0..n {
            let bound = MOMENT_BOUND_MARGIN * (d.mass * diag(a, k)).sqrt();
            if !at_most(e.c[a][k].abs(), bound) {
                out.push(format!(
                    "elementary.c[{}][{k}]: {:e} exceeds sqrt(mass g_aa,kk) = {bound:e} \
                     (x{MOMENT_BOUND_MARGIN}; sum dm W obeys Cauchy-Schwarz)",
                    xyz[a], e.c[a][k]
                ));
                return;
            }
            for b in 0..3 {
                let bound = MOMENT_BOUND_MARGIN * (j.max(0.0) * diag(b, k)).sqrt();
                if !at_most(e.s[a][b][k].abs(), bound) {
                    out.push(format!(
                        "elementary.s[{}][{}][{k}]: {:e} exceeds sqrt(J_aa g_bb,kk) = {bound:e} \
                         (x{MOMENT_BOUND_MARGIN}; J from mass, cog and inertia)",
                        xyz[a], xyz[b], e.s[a][b][k]
                    ));
                    return;
                }
            }
        }
    }
}

/// The drum's geometric stiffness: a unit axis through a point inside the machine, a reference
/// speed of the machine's range, K_G / Omega^2 symmetric (a stiffness) and within
/// `MAX_PER_OMEGA2`.
fn geometric_stiffness(d: &ModalData, out: &mut Vec<String>) {
    let Some(k) = &d.geometric_stiffness else {
        return;
    };
    let f = "geometric_stiffness";
    position(&format!("{f}.axis_point"), &k.axis_point, out);
    if !at_most((crate::geom::f::norm(k.axis) - 1.0).abs(), UNIT_TOLERANCE) {
        out.push(format!("{f}.axis: must be a unit vector, got {:?}", k.axis));
    }
    let top = super::check::MAX_RPM * std::f64::consts::PI / 30.0;
    if !(k.reference_speed > 0.0 && k.reference_speed <= top) {
        out.push(format!(
            "{f}.reference_speed: must be in (0, {top:.1}] rad/s ({} rpm), got {}",
            super::check::MAX_RPM,
            k.reference_speed
        ));
    }
    let n = d.modes();
    let g = &k.per_omega2;
    if g.len() != n * n || g.iter().any(|v| !v.is_finite()) {
        return; // `problems` reports it
    }
    if let Some((i, v)) = g
        .iter()
        .enumerate()
        .find(|(_, v)| !at_most(v.abs(), MAX_PER_OMEGA2))
    {
        out.push(format!(
            "{f}.per_omega2[{i}]: {v:e} exceeds {MAX_PER_OMEGA2:e} (stress stiffening per \
             Omega^2 of mass-normalised modes)"
        ));
        return;
    }
    let scale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for r in 0..n {
        for c in r + 1..n {
            let (a, b) = (g[r * n + c], g[c * n + r]);
            if !at_most((a - b).abs(), GRAM_TOLERANCE * scale) {
                out.push(format!(
                    "{f}.per_omega2[{}]: {a:e}, but [{}] = {b:e}: a stiffness is symmetric",
                    r * n + c,
                    c * n + r
                ));
                return;
            }
        }
    }
}

/// How far (m) a marker's point may lie from the modal point (FE node set) it uses: a side
/// panel's 2 mm bulge puts its centre node outside the rigid model's panel plane.
pub const POINT_TOLERANCE: f64 = 5e-3;

/// The modal point at `p` (within `POINT_TOLERANCE`), if any.
pub fn point_at(d: &ModalData, p: V3) -> Option<&ModalPoint> {
    let dist = |q: &ModalPoint| crate::geom::f::norm(crate::geom::f::sub(q.position, p));
    d.points
        .iter()
        .filter(|q| dist(q) <= POINT_TOLERANCE)
        .min_by(|a, b| dist(a).total_cmp(&dist(b)))
}

impl ModalData {
    /// The point called `name` (a node set of the FE model).
    pub fn point(&self, name: &str) -> Option<&ModalPoint> {
        self.points.iter().find(|p| p.name == name)
    }

    /// The file's modes at the points: kept from before truncation, else the data's own.
    pub fn file_modes(&self) -> FileModes {
        self.file_modes.clone().unwrap_or_else(|| self.own_modes())
    }

    fn own_modes(&self) -> FileModes {
        FileModes {
            frequencies: self.frequencies.clone(),
            eigenmodes: self.eigenmodes(),
            w: self.points.iter().map(|p| p.w.clone()).collect(),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Two unit-mass nodes, two modes: a small, valid body.
    pub fn tiny() -> ModalData {
        let id = vec![1.0, 0.0, 0.0, 1.0];
        let z = vec![0.0; 4];
        ModalData {
            body: ElasticBodyKind::Cabinet,
            support: Support::OnSprings,
            source: "test".into(),
            frequencies: vec![10.0, 20.0],
            mass: 2.0,
            cog: [0.0; 3],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            elementary: Elementary {
                c: [vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]],
                s: std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; 2])),
                g: [
                    [z.clone(), z.clone(), z.clone()],
                    [z.clone(), z.clone(), z.clone()],
                    [z.clone(), z.clone(), id],
                ],
            },
            points: vec![ModalPoint {
                name: "FOOT_1".into(),
                position: [0.0; 3],
                nodes: 1,
                w: [vec![0.0; 2], vec![0.0; 2], vec![1.0, 0.0]],
                phi: [vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]],
            }],
            geometric_stiffness: None,
            correction: None,
            basis: None,
            file_modes: None,
            support_springs: Vec::new(),
        }
    }

    #[test]
    fn a_valid_body_has_no_problems_and_round_trips_through_toml() {
        let d = tiny();
        assert_eq!(problems(&d), Vec::<String>::new());
        let back: ModalData = toml::from_str(&d.to_toml()).unwrap();
        assert_eq!(back, d);
    }

    #[test]
    fn each_rule_names_its_field() {
        let mut d = tiny();
        d.elementary.g[2][2].pop();
        d.frequencies[0] = -1.0;
        d.points[0].w[1].push(0.0);
        let p = problems(&d);
        assert!(
            p.iter()
                .any(|m| m.starts_with("elementary.g[z][z]: expected 4"))
        );
        assert!(
            p.iter()
                .any(|m| m.starts_with("frequencies[0]: must be positive"))
        );
        assert!(p.iter().any(|m| m.starts_with("points[0] (FOOT_1).w[y]")));
        // Each block's diagonal is within [0, 1.05]; their sum is the modal mass.
        let mut d = tiny();
        d.elementary.g[2][2][3] = 1.2;
        let p = problems(&d);
        assert_eq!(p.len(), 1);
        assert!(p[0].starts_with("elementary.g[z][z][3]: 1.2e0"), "{p:?}");
        let mut d = tiny();
        d.elementary.g[0][0][3] = 0.5;
        let p = problems(&d);
        assert_eq!(p.len(), 1);
        assert!(p[0].contains("not mass-normalised"), "{p:?}");
    }

    #[test]
    fn gram_identities_and_magnitudes_name_their_field() {
        type Case = (fn(&mut ModalData), &'static str);
        let cases: Vec<Case> = vec![
            (
                |d| d.elementary.g[0][2][1] = 0.5,
                "elementary.g[x][z][1]: 5e-1 exceeds",
            ),
            (
                |d| d.elementary.g[2][2][1] = 0.5,
                "elementary.g[z][z][1]: 5e-1, but",
            ),
            (|d| d.elementary.c[2][0] = 2.0, "elementary.c[z][0]"),
            (|d| d.elementary.s[0][2][0] = 1e3, "elementary.s[x][z][0]"),
            (|d| d.points[0].w[2][0] = 1e4, "points[0] (FOOT_1).w[z]"),
            (
                |d| d.points[0].phi[0][0] = 1.0,
                "points[0] (FOOT_1).phi: a set of 1",
            ),
            (|d| d.mass = 1e5, "mass: must be positive, within"),
            (
                |d| d.cog = [f64::NAN; 3],
                "cog: [NaN, NaN, NaN] must be finite",
            ),
            (|d| d.inertia[1][1] = 5.0, "inertia: principal moments"),
            (
                |d| d.support = Support::Clamped,
                "support: Clamped for the Cabinet",
            ),
            (
                |d| d.basis = Some(vec![1.0, 0.0, 0.0, 1.5]),
                "basis[3]: 1.5",
            ),
        ];
        for (f, want) in cases {
            let mut d = tiny();
            f(&mut d);
            let p = problems(&d);
            assert!(p.iter().any(|m| m.starts_with(want)), "{want}: {p:?}");
        }
    }

    #[test]
    fn truncation_keeps_the_leading_block() {
        let mut d = tiny();
        d.elementary.g[2][2] = vec![1.0, 0.1, 0.2, 1.0];
        d.truncate(1, &[]);
        assert_eq!(d.elementary.g[2][2], vec![1.0]);
        assert_eq!(d.points[0].w[2], vec![1.0]);
        assert_eq!(problems(&d), Vec::<String>::new());
    }

    /// A body of 6 modes whose last is a correction mode, with one load case at point P.
    fn with_correction() -> ModalData {
        let n = 6;
        let mut d = tiny();
        let f = vec![5.0, 8.0, 13.0, 21.0, 34.0, 80.0];
        let eye: Vec<f64> = (0..n * n)
            .map(|i| if i / n == i % n { 1.0 } else { 0.0 })
            .collect();
        d.frequencies = f;
        d.elementary = Elementary {
            c: std::array::from_fn(|_| vec![0.0; n]),
            s: std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; n])),
            g: std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    if a == 2 && b == 2 {
                        eye.clone()
                    } else {
                        vec![0.0; n * n]
                    }
                })
            }),
        };
        let wz = vec![0.3, -0.2, 0.5, 0.1, -0.4, 0.7];
        let wy = vec![0.1, 0.2, -0.1, 0.3, 0.2, -0.2];
        d.points = vec![ModalPoint {
            name: "P".into(),
            position: [0.0; 3],
            nodes: 4,
            w: [vec![0.0; n], wy, wz.clone()],
            phi: std::array::from_fn(|_| vec![0.0; n]),
        }];
        d.correction = Some(Correction {
            loads: vec![LoadCase::force("P", [0.0, 0.0, 1.0])],
            modes: 1,
            participation: wz[..5].to_vec(),
        });
        d
    }

    /// Static displacement at P along `a` under a unit force along `b` there:
    /// sum w_a w_b / omega^2.
    fn static_at_p(d: &ModalData, a: usize, b: usize) -> f64 {
        let p = &d.points[0];
        (0..d.modes())
            .map(|k| {
                p.w[a][k] * p.w[b][k] / (2.0 * std::f64::consts::PI * d.frequencies[k]).powi(2)
            })
            .sum()
    }

    #[test]
    fn truncation_folds_the_dropped_modes_static_share_at_the_load_points() {
        let full = with_correction();
        assert_eq!(problems(&full), Vec::<String>::new());
        let mut d = full.clone();
        d.truncate(2, &[]);
        // 2 eigenmodes, 1 folded shape (one load case), the correction mode.
        assert_eq!(d.modes(), 4);
        assert_eq!(d.eigenmodes(), 2);
        // The file's modes in the new ones: 6 x 4, the kept eigenmodes and the correction
        // mode map to themselves; the folded column lives on the dropped modes 3-5.
        let t = d.basis.clone().unwrap();
        assert_eq!(t.len(), 24);
        assert_eq!((t[0], t[5], t[23]), (1.0, 1.0, 1.0));
        assert!((0..6).all(|r| (2..5).contains(&r) == (t[r * 4 + 2] != 0.0)));
        assert_eq!(problems(&d), Vec::<String>::new());
        // The folded shape is a combination of modes 3-5, so its frequency lies among theirs.
        assert!(
            d.frequencies[2] > 13.0 && d.frequencies[2] < 34.0,
            "{:?}",
            d.frequencies
        );
        // Modal mass stays the identity, and the static response along the load is the full
        // model's to round-off (the closed form: the same sum over all modes).
        assert!(d.mass_normalisation_error() < 1e-12);
        for a in [1, 2] {
            let (x, y) = (static_at_p(&full, a, 2), static_at_p(&d, a, 2));
            assert!((x - y).abs() < 1e-12 * x.abs(), "{a}: {x} {y}");
        }
        let a = static_at_p(&full, 2, 2);
        // Plain truncation would have lost modes 3-5's share.
        let mut plain = full.clone();
        plain.correction = None;
        plain.truncate(2, &[]);
        assert!((static_at_p(&plain, 2, 2) - a).abs() > 0.05 * a.abs());
        // A force along y is no load case: its response is not held (the fold is for the listed
        // loads only).
        let yy = static_at_p(&full, 1, 1);
        assert!((static_at_p(&d, 1, 1) - yy).abs() > 1e-3 * yy.abs());
    }

    #[test]
    fn moment_load_cases_read_old_files_and_fold_through_phi() {
        // The serde form: files without `kind` hold forces (and write back without it); a
        // moment says `kind = "moment"`.
        let force: LoadCase = toml::from_str("point = \"P\"\ndirection = [0.0, 0.0, 1.0]").unwrap();
        assert_eq!(force, LoadCase::force("P", [0.0, 0.0, 1.0]));
        assert!(!toml::to_string(&force).unwrap().contains("kind"));
        let moment = LoadCase::moment("P", [1.0, 0.0, 0.0]);
        let text = toml::to_string(&moment).unwrap();
        assert!(text.contains("kind = \"moment\""), "{text}");
        assert_eq!(toml::from_str::<LoadCase>(&text).unwrap(), moment);

        // A moment about x at P, whose rotation phi_x per mode is `tx`: the participation is
        // phi . direction, and truncation folds the dropped modes' static rotation at P.
        let mut full = with_correction();
        let tx = vec![0.2, 0.1, -0.3, 0.25, 0.15, -0.1];
        full.points[0].phi[0] = tx.clone();
        let c = full.correction.as_mut().unwrap();
        c.loads.push(moment);
        c.participation = (0..5)
            .flat_map(|k| [full.points[0].w[2][k], tx[k]])
            .collect();
        assert_eq!(problems(&full), Vec::<String>::new());
        let rot = |d: &ModalData| -> f64 {
            let p = &d.points[0];
            (0..d.modes())
                .map(|k| {
                    p.phi[0][k].powi(2) / (2.0 * std::f64::consts::PI * d.frequencies[k]).powi(2)
                })
                .sum()
        };
        let mut d = full.clone();
        d.truncate(2, &[]);
        // 2 eigenmodes, 2 folded shapes (two load cases), the correction mode.
        assert_eq!(d.modes(), 5);
        assert!((rot(&d) - rot(&full)).abs() < 1e-12 * rot(&full));
        assert_eq!(problems(&d), Vec::<String>::new());

        // Checker rules: a moment at a point without rotation, a participation that is not
        // the point's, a direction that is no unit vector.
        let mut bad = full.clone();
        bad.points[0].nodes = 2;
        let c = bad.correction.as_mut().unwrap();
        c.loads[1].kind = LoadKind::Force;
        c.loads[0].direction = [0.0, 0.0, 2.0];
        let p = problems(&bad);
        assert!(
            p.iter()
                .any(|m| m.starts_with("correction.participation (load 1)")),
            "{p:?}"
        );
        assert!(
            p.iter()
                .any(|m| m.starts_with("correction.loads[0].direction")),
            "{p:?}"
        );
        bad.correction.as_mut().unwrap().loads[1].kind = LoadKind::Moment;
        let p = problems(&bad);
        assert!(p.iter().any(|m| m.contains("give no rotation")), "{p:?}");
    }
}
