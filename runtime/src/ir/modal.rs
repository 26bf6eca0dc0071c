//! Modal data of an elastic body: the Ritz basis reduced to what the equations use (the seed
//! paper's elementary matrices, the mode shapes at the points markers use, and for the drum the
//! geometric stiffness). It is written by the FE front end (`washdyn fe write`) and read by both
//! model front ends through `read_file`; nothing here knows CalculiX.
//!
//! File format: TOML (documented in `docs/modal-data.md`), one file per body, written with
//! round-trip floats. Matrices are flat row-major lists; index k runs over the kept modes.

use super::V3;
use super::check::{CheckError, Path};
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
    /// The lumped FE body: mass kg, CoG m, inertia about the CoG kg m^2 (global axes).
    pub mass: f64,
    pub cog: V3,
    pub inertia: [[f64; 3]; 3],
    /// Elementary matrices (seed paper, "Equations of motion"), sums over the FE nodes with
    /// HRZ masses plus the attached rigid parts; positions x0 in the machine frame at rest.
    pub elementary: Elementary,
    /// Mode shapes at the points force elements and sensors use.
    #[serde(default)]
    pub points: Vec<ModalPoint>,
    /// Drum only: stiffness per Omega^2 from the centrifugal prestress.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometric_stiffness: Option<GeometricStiffness>,
}

/// The seed paper's elementary matrices for n modes; a, b run over x, y, z.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Elementary {
    /// c[a][k] = sum dm W_a,k (zero for free-free modes: orthogonal to translation).
    pub c: [Vec<f64>; 3],
    /// s[a][b][k] = sum dm x0_a W_b,k (3 x 3 rows of n).
    pub s: [[Vec<f64>; 3]; 3],
    /// g[a][b][k n + l] = sum dm W_a,k W_b,l (3 x 3 blocks of n x n, row-major);
    /// g_xx + g_yy + g_zz is the modal mass matrix (identity for mass-normalised modes).
    pub g: [[Vec<f64>; 3]; 3],
}

/// A point on the body: a node set's rigid-fit motion evaluated at `position`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModalPoint {
    /// The FE model's node set (upper case, as in the deck).
    pub name: String,
    pub position: V3,
    /// Number of FE nodes in the set; with fewer than 3 (non-collinear) the rotation is zero.
    pub nodes: usize,
    /// Translation per mode: w[a][k], m per unit modal coordinate.
    pub w: [Vec<f64>; 3],
    /// Rotation per mode: phi[a][k], rad per unit modal coordinate.
    pub phi: [Vec<f64>; 3],
}

/// K_G / Omega^2 in modal coordinates (n x n, row-major), for spin about `axis` through
/// `axis_point`, Omega in rad/s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometricStiffness {
    pub axis_point: V3,
    pub axis: V3,
    pub per_omega2: Vec<f64>,
    /// The speed (rad/s) of the prestressed solution it was extracted from.
    pub reference_speed: f64,
}

impl ModalData {
    pub fn modes(&self) -> usize {
        self.frequencies.len()
    }
    /// The modal mass matrix sum dm W^T W (n x n, row-major).
    pub fn modal_mass(&self) -> Vec<f64> {
        let n = self.modes();
        (0..n * n)
            .map(|i| (0..3).map(|a| self.elementary.g[a][a][i]).sum())
            .collect()
    }
    /// Largest deviation of the modal mass matrix from the identity: the lumping error the
    /// equations inherit from using HRZ masses with ccx's consistently normalised shapes.
    pub fn mass_normalisation_error(&self) -> f64 {
        let n = self.modes();
        self.modal_mass()
            .iter()
            .enumerate()
            .map(|(i, v)| (v - if i / n == i % n { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max)
    }
    /// Keep the first `n` modes only.
    pub fn truncate(&mut self, n: usize) {
        let m = self.modes();
        if n >= m {
            return;
        }
        self.frequencies.truncate(n);
        let e = &mut self.elementary;
        for a in 0..3 {
            e.c[a].truncate(n);
            for b in 0..3 {
                e.s[a][b].truncate(n);
                e.g[a][b] = square_head(&e.g[a][b], m, n);
            }
        }
        for p in &mut self.points {
            for a in 0..3 {
                p.w[a].truncate(n);
                p.phi[a].truncate(n);
            }
        }
        if let Some(k) = &mut self.geometric_stiffness {
            k.per_omega2 = square_head(&k.per_omega2, m, n);
        }
    }
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("modal data serialises")
    }
}

fn square_head(v: &[f64], m: usize, n: usize) -> Vec<f64> {
    (0..n * n).map(|i| v[(i / n) * m + i % n]).collect()
}

/// Read a modal data file; errors carry the file (as `shown`) and line.
pub fn read_file(path: &FsPath, shown: &str) -> Result<ModalData, String> {
    let name = shown;
    let src = std::fs::read_to_string(path).map_err(|e| format!("{name}: cannot read: {e}"))?;
    toml::from_str(&src).map_err(|e| {
        let line = e
            .span()
            .map_or(0, |s| src[..s.start.min(src.len())].lines().count().max(1));
        format!("{name}:{line}: {}", e.message().trim())
    })
}

/// Read every elastic body's modal data file (relative to `base`) into the model: the one
/// resolver of both front ends. Returns the files read (the macro makes cargo watch them) and
/// the problems, each at `elastic[i].file` and naming the file.
pub fn resolve(model: &mut super::Model, base: &FsPath) -> (Vec<PathBuf>, Vec<CheckError>) {
    let (mut files, mut errors) = (Vec::new(), Vec::new());
    for (i, e) in model.elastic.iter_mut().enumerate() {
        let path = base.join(&e.file);
        match read_file(&path, &e.file) {
            Ok(mut d) => {
                if let Some(n) = e.modes {
                    if n > d.modes() {
                        errors.push(CheckError {
                            path: Path::default().key("elastic").idx(i).key("modes"),
                            message: format!(
                                "elastic `{}`: asks for {n} modes, `{}` has {}",
                                e.name,
                                e.file,
                                d.modes()
                            ),
                        });
                    }
                    d.truncate(n);
                }
                e.data = Some(d);
            }
            Err(m) => errors.push(CheckError {
                path: Path::default().key("elastic").idx(i).key("file"),
                message: format!("elastic `{}`: {m}", e.name),
            }),
        }
        files.push(path);
    }
    (files, errors)
}

/// Mass-normalisation tolerance of the checker: the HRZ lumping error of a reasonable mesh
/// (a few per cent on the modal mass matrix; the built-in bodies stay below it).
pub const MASS_NORMALISATION_TOLERANCE: f64 = 0.05;

/// The modal data's own consistency: dimensions, frequencies, mass-normalisation, points. Each
/// finding names the field inside the file; the caller adds the file and the model's path.
pub fn problems(d: &ModalData) -> Vec<String> {
    let mut out = Vec::new();
    let n = d.modes();
    if n == 0 {
        out.push("frequencies: no modes".into());
    }
    for (k, f) in d.frequencies.iter().enumerate() {
        if !(f.is_finite() && *f > 0.0) {
            out.push(format!(
                "frequencies[{k}]: must be positive and finite, got {f}"
            ));
        }
    }
    if d.frequencies.windows(2).any(|w| w[1] < w[0]) {
        out.push("frequencies: not ascending".into());
    }
    if !(d.mass.is_finite() && d.mass > 0.0) {
        out.push(format!("mass: must be positive, got {}", d.mass));
    }
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
        let mut d = tiny();
        d.elementary.g[2][2][3] = 1.2;
        let p = problems(&d);
        assert_eq!(p.len(), 1);
        assert!(p[0].contains("not mass-normalised"), "{p:?}");
    }

    #[test]
    fn truncation_keeps_the_leading_block() {
        let mut d = tiny();
        d.elementary.g[2][2] = vec![1.0, 0.1, 0.2, 1.0];
        d.truncate(1);
        assert_eq!(d.elementary.g[2][2], vec![1.0]);
        assert_eq!(d.points[0].w[2], vec![1.0]);
        assert_eq!(problems(&d), Vec::<String>::new());
    }
}
