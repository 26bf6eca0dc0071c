//! Modal data of an elastic body: the Ritz basis reduced to what the equations use (the seed
//! paper's elementary matrices, the mode shapes at the points markers use, and for the drum the
//! geometric stiffness). It is written by the FE front end (`washdyn fe write`) and read by both
//! model front ends through `read_file`; nothing here knows CalculiX.
//!
//! File format: TOML (documented in `docs/modal-data.md`), one file per body, written with
//! round-trip floats. Matrices are flat row-major lists; index k runs over the kept modes.

mod curves;
mod limits;
mod read;
mod rules;
#[cfg(test)]
pub(crate) mod tests;
mod truncate;

pub use limits::{
    FREQUENCY_RANGE, GRAM_TOLERANCE, MASS_NORMALISATION_TOLERANCE, MASS_RANGE, MAX_EXTENT,
    MAX_PER_OMEGA2, MAX_PHI, MAX_SUPPORT_STIFFNESS, MAX_W, MOMENT_BOUND_MARGIN,
    PARTICIPATION_TOLERANCE, SUPPORT_ENERGY_TOLERANCE, UNIT_TOLERANCE,
};

pub use curves::{Curves, Fit, MAX_CURVE_MODES, Term};
pub use read::{from_toml, read_file, read_str, resolve};
pub use rules::problems;
pub use truncate::{DEPENDENT_SHAPE, FOLD_BLOCKS, generalised_eigen, orthonormal_static_basis};

use super::V3;
use serde::{Deserialize, Serialize};

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
    /// Only the spinning drum's equations use it (the frame turns its modes into each other);
    /// the cabinet's data leaves it out (all nine blocks empty): 9 n^2 numbers, 35 MB of a
    /// 36 MB file at 406 modes. Written even when empty: the error class's content hash
    /// serialises a rigid body's cleared `elementary` and must not change with this field.
    #[serde(default, deserialize_with = "crate::ir::exact::exact")]
    pub g: [[Vec<f64>; 3]; 3],
}

impl Elementary {
    /// Whether the data gives `g` (a body kind that needs it is refused without it).
    pub fn has_g(&self) -> bool {
        self.g.iter().flatten().any(|v| !v.is_empty())
    }
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
    /// the section rotations the translations do not show; HRZ lumping: per cent). 0 for data
    /// without `g` (nothing to measure it on; fe measures it before leaving g out).
    pub fn mass_normalisation_error(&self) -> f64 {
        if !self.elementary.has_g() {
            return 0.0;
        }
        let n = self.modes();
        self.modal_mass()
            .iter()
            .enumerate()
            .map(|(i, v)| (v - if i / n == i % n { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max)
    }
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("modal data serialises")
    }

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
