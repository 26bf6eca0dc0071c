//! A body's mode shapes on its whole FE mesh, for recovering displacement fields after a run
//! (the seed paper's closing argument: reverse the Ritz approximation). `washdyn fe modal`
//! writes one `<body>.field.bin` per body beside ccx's files; it is a cache of ccx's results (a
//! few MB per body), not committed, and tied to the modal data it was built with by the
//! frequencies and one point's shapes, so a field from another solve is refused, not misread.
//!
//! Format: the magic `WDFIELD1`, the header's length (u64 LE), the header (JSON), then the
//! shapes as f64 LE, mode-major: value[(k * nodes + i) * 3 + a], then the modal stresses at
//! the stress points, mode-major: value[(k * points + p) * 6 + c].

use crate::error::{Error, PipelineError, ResultsError};
use crate::mesh::{Mesh, Section};
use crate::modal::Shapes;
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"WDFIELD1";

/// Running sums: the first stress point of each node, and the total last.
fn starts(counts: &[u32]) -> Vec<usize> {
    let mut v = Vec::with_capacity(counts.len() + 1);
    let mut s = 0;
    v.push(0);
    for c in counts {
        s += *c as usize;
        v.push(s);
    }
    v
}

/// VTK cell types of the quadratic elements ccx uses.
pub const VTK_QUADRATIC_EDGE: u8 = 21;
pub const VTK_QUADRATIC_QUAD: u8 = 23;
pub const VTK_QUADRATIC_HEXAHEDRON: u8 = 25;

/// One cell: VTK type and 0-based indices into `FieldHeader::nodes`, in VTK order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    pub vtk: u8,
    pub nodes: Vec<u32>,
}

/// The mesh and what ties the shapes to the modal data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FieldHeader {
    pub body: String,
    /// FE node ids and rest positions (m, machine frame) of the structural nodes.
    pub ids: Vec<usize>,
    pub nodes: Vec<[f64; 3]>,
    pub cells: Vec<Cell>,
    /// The modal data's frequencies (Hz), eigenmodes then correction modes.
    pub frequencies: Vec<f64>,
    /// The modal data's first point (name) and its w[a][k] (fields written before `points`).
    pub check_point: String,
    pub check_w: [Vec<f64>; 3],
    /// The modal data's points (name, w[a][k]) from the same solve as the shapes: what
    /// `align` holds another solve's modal data to.
    #[serde(default)]
    pub points: Vec<(String, [Vec<f64>; 3])>,
    /// Stress points (ccx's expanded nodes: a shell node's two faces, a beam node's section
    /// corners, a solid's node itself) per node; empty when the field has no stresses.
    #[serde(default)]
    pub stress_points: Vec<u32>,
}

/// Mode shapes at every structural node of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub header: FieldHeader,
    /// value[(k * nodes + i) * 3 + a].
    pub shapes: Vec<f64>,
    /// Modal stresses, Pa per unit coordinate: value[(k * points + p) * 6 + c], stress points p
    /// in node order, c over xx, yy, zz, xy, yz, zx.
    pub stresses: Vec<f64>,
    /// First stress point of each node (len nodes + 1).
    pub stress_start: Vec<usize>,
}

impl Field {
    /// From the mesh and the shapes the modal data was built from (same order).
    pub fn new(
        mesh: &Mesh,
        modes: &[Shapes],
        data: &washdyn_model::ir::modal::ModalData,
        stress: Option<&crate::stress::ModalStress>,
    ) -> Result<Field, PipelineError> {
        let ids = mesh.element_nodes();
        let ids: Vec<usize> = ids
            .into_iter()
            .filter(|id| modes.first().is_some_and(|m| m.w.contains_key(id)))
            .collect();
        let index: std::collections::HashMap<usize, u32> = ids
            .iter()
            .enumerate()
            .map(|(i, id)| (*id, i as u32))
            .collect();
        let mut cells = Vec::new();
        for p in &mesh.parts {
            let (vtk, order): (u8, &[usize]) = match p.section {
                // ccx's S8R and C3D20 node orders are VTK's; B32 has its middle node second.
                Section::Shell { .. } => (VTK_QUADRATIC_QUAD, &[0, 1, 2, 3, 4, 5, 6, 7]),
                Section::Solid { .. } | Section::ReducedSolid { .. } => (
                    VTK_QUADRATIC_HEXAHEDRON,
                    &[
                        0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
                    ],
                ),
                Section::Beam { .. } => (VTK_QUADRATIC_EDGE, &[0, 2, 1]),
                Section::Mass { .. } | Section::Ground { .. } => continue,
            };
            for e in &p.elements {
                let nodes = order
                    .iter()
                    .map(|&i| {
                        index
                            .get(&e[i])
                            .copied()
                            .ok_or(PipelineError::NoShape { node: e[i] })
                    })
                    .collect::<Result<_, _>>()?;
                cells.push(Cell { vtk, nodes });
            }
        }
        let n = ids.len();
        let mut shapes = vec![0.0; modes.len() * n * 3];
        for (k, m) in modes.iter().enumerate() {
            for (i, id) in ids.iter().enumerate() {
                let w = m.w[id];
                shapes[(k * n + i) * 3..(k * n + i) * 3 + 3].copy_from_slice(&w);
            }
        }
        let mut stress_points = Vec::new();
        let mut stresses = Vec::new();
        if let Some(st) = stress {
            let none = Vec::new();
            let pts: Vec<&Vec<usize>> = ids
                .iter()
                .map(|id| st.points.get(id).unwrap_or(&none))
                .collect();
            stress_points = pts.iter().map(|v| v.len() as u32).collect();
            for m in &st.per_mode {
                for e in pts.iter().copied().flatten() {
                    stresses.extend_from_slice(&m.get(e).copied().unwrap_or([0.0; 6]));
                }
            }
        }
        let p = data.points.first().ok_or(PipelineError::NoPoints)?;
        let stress_start = starts(&stress_points);
        Ok(Field {
            header: FieldHeader {
                body: format!("{:?}", data.body).to_lowercase(),
                nodes: ids.iter().map(|id| mesh.nodes[id - 1]).collect(),
                ids,
                cells,
                frequencies: data.frequencies.clone(),
                check_point: p.name.clone(),
                check_w: p.w.clone(),
                points: data
                    .points
                    .iter()
                    .map(|p| (p.name.clone(), p.w.clone()))
                    .collect(),
                stress_points,
            },
            shapes,
            stresses,
            stress_start,
        })
    }

    /// Does the field carry stresses?
    pub fn has_stresses(&self) -> bool {
        !self.stresses.is_empty()
    }

    /// The stress points of node index i (a range into the points).
    pub fn stress_points(&self, i: usize) -> std::ops::Range<usize> {
        self.stress_start[i]..self.stress_start[i + 1]
    }

    /// Modal stress of mode k at stress point p.
    pub fn stress(&self, k: usize, p: usize) -> [f64; 6] {
        let n = *self.stress_start.last().unwrap_or(&0);
        let o = (k * n + p) * 6;
        std::array::from_fn(|c| self.stresses[o + c])
    }

    pub fn modes(&self) -> usize {
        self.header.frequencies.len()
    }

    /// Shape of mode k at node index i.
    pub fn shape(&self, k: usize, i: usize) -> [f64; 3] {
        let n = self.header.nodes.len();
        let s = &self.shapes[(k * n + i) * 3..(k * n + i) * 3 + 3];
        [s[0], s[1], s[2]]
    }

    pub fn write(&self, path: &Path) -> Result<(), Error> {
        let err = |e| Error::io(path)(e);
        let head = serde_json::to_vec(&self.header).map_err(ResultsError::from)?;
        let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
        f.write_all(MAGIC).map_err(err)?;
        f.write_all(&(head.len() as u64).to_le_bytes())
            .map_err(err)?;
        f.write_all(&head).map_err(err)?;
        for v in self.shapes.iter().chain(&self.stresses) {
            f.write_all(&v.to_le_bytes()).map_err(err)?;
        }
        f.flush().map_err(err)
    }

    pub fn read(path: &Path) -> Result<Field, Error> {
        let path_buf = || path.to_path_buf();
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|mut f| f.read_to_end(&mut bytes))
            .map_err(Error::io(path))?;
        if bytes.len() < 16 || &bytes[..8] != MAGIC {
            return Err(ResultsError::NotAField { path: path_buf() }.into());
        }
        let len = u64::from_le_bytes(bytes[8..16].try_into().expect("8 bytes")) as usize;
        let body = bytes
            .get(16..16 + len)
            .ok_or_else(|| ResultsError::TruncatedHeader { path: path_buf() })?;
        let header: FieldHeader =
            serde_json::from_slice(body).map_err(|source| ResultsError::Header {
                path: path_buf(),
                source,
            })?;
        let rest = &bytes[16 + len..];
        let stress_start = starts(&header.stress_points);
        let n_shapes = header.frequencies.len() * header.nodes.len() * 3;
        let n_stress = header.frequencies.len() * stress_start.last().unwrap_or(&0) * 6;
        if rest.len() != (n_shapes + n_stress) * 8 {
            return Err(ResultsError::FieldSize {
                path: path_buf(),
                values: rest.len() / 8,
                expected: n_shapes + n_stress,
            }
            .into());
        }
        let mut values = rest
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")));
        let shapes = values.by_ref().take(n_shapes).collect();
        let stresses = values.collect();
        Ok(Field {
            header,
            shapes,
            stresses,
            stress_start,
        })
    }

    /// Map this field's modes onto `data`'s file modes (`ModalData::file_modes`: the file's
    /// own modes, also after truncation): `r` with data shapes = field shapes x r, per group
    /// of (near-)degenerate modes the best orthogonal map, so a basis that another solve only
    /// turned or flipped is re-projected. Compared at every point of the data that the field
    /// records (a field written before `points`: its one check point). Refuses, naming the
    /// body and the modes, when a group's subspace or size differs by more than
    /// `subspace::SUBSPACE_TOLERANCE` (another mesh, deck or mode count).
    pub fn align(
        &self,
        data: &washdyn_model::ir::modal::ModalData,
    ) -> Result<crate::subspace::Alignment, ResultsError> {
        let h = &self.header;
        let how = crate::error::Regenerate::of(&data.source);
        let file = data.file_modes();
        let m = file.frequencies.len();
        if m != self.modes() {
            return Err(ResultsError::FieldModes {
                body: h.body.clone(),
                field: self.modes(),
                data: m,
                how,
            });
        }
        let legacy = [(h.check_point.clone(), h.check_w.clone())];
        let recorded: &[(String, [Vec<f64>; 3])] = if h.points.is_empty() {
            &legacy
        } else {
            &h.points
        };
        let mut rows: Vec<(&[f64], &[f64])> = Vec::new();
        for (name, w) in recorded {
            let i = data
                .points
                .iter()
                .position(|p| &p.name == name)
                .ok_or_else(|| ResultsError::FieldPoint {
                    body: h.body.clone(),
                    point: name.clone(),
                    how: how.clone(),
                })?;
            for a in 0..3 {
                let (f, d) = (&w[a], &file.w[i][a]);
                if f.len() != m || d.len() != m {
                    return Err(ResultsError::FieldValues {
                        body: h.body.clone(),
                        point: name.clone(),
                        field: f.len(),
                        data: d.len(),
                        how,
                    });
                }
                rows.push((f, d));
            }
        }
        let a = nalgebra::DMatrix::from_fn(rows.len(), m, |r, k| rows[r].0[k]);
        let b = nalgebra::DMatrix::from_fn(rows.len(), m, |r, k| rows[r].1[k]);
        let groups = crate::subspace::groups(&file.frequencies, file.eigenmodes);
        crate::subspace::align(&a, &b, &groups).map_err(|fit| ResultsError::FieldShapes {
            body: h.body.clone(),
            frequency: file.frequencies[fit.modes.start],
            fit,
            points: recorded.len(),
            how,
        })
    }

    /// Displacement of node index i for modal coordinates q (the file's modes): sum W_k q_k.
    pub fn displacement(&self, i: usize, q: &[f64]) -> [f64; 3] {
        let mut u = [0.0; 3];
        for (k, x) in q.iter().enumerate() {
            let s = self.shape(k, i);
            for c in 0..3 {
                u[c] += s[c] * x;
            }
        }
        u
    }

    /// Stress at stress point p for modal coordinates q: sum S_k q_k.
    pub fn stress_at(&self, p: usize, q: &[f64]) -> [f64; 6] {
        let mut s = [0.0; 6];
        for (k, x) in q.iter().enumerate() {
            let sk = self.stress(k, p);
            for c in 0..6 {
                s[c] += sk[c] * x;
            }
        }
        s
    }

    /// The stress at node index i's most loaded face for modal coordinates q: (von Mises,
    /// tensor); zeros for a node without stress points.
    pub fn node_stress(&self, i: usize, q: &[f64]) -> (f64, [f64; 6]) {
        let mut best = (0.0f64, [0.0; 6]);
        for p in self.stress_points(i) {
            let s = self.stress_at(p, q);
            let vm = crate::stress::von_mises(&s);
            if vm >= best.0 {
                best = (vm, s);
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Regenerate;
    use washdyn_model::ir::modal::ModalData;

    /// A field recording `data`'s points with `w` changed by `f` (no nodes: `align` reads the
    /// header only).
    fn field(data: &ModalData, f: impl Fn(&mut [Vec<f64>; 3])) -> Field {
        let p = &data.points[0];
        Field {
            header: FieldHeader {
                body: "drum".into(),
                ids: Vec::new(),
                nodes: Vec::new(),
                cells: Vec::new(),
                frequencies: data.frequencies.clone(),
                check_point: p.name.clone(),
                check_w: p.w.clone(),
                points: data
                    .points
                    .iter()
                    .map(|p| {
                        let mut w = p.w.clone();
                        f(&mut w);
                        (p.name.clone(), w)
                    })
                    .collect(),
                stress_points: Vec::new(),
            },
            shapes: Vec::new(),
            stresses: Vec::new(),
            stress_start: Vec::new(),
        }
    }

    fn turn(w: &mut [Vec<f64>; 3], k: usize, j: usize, degrees: f64) {
        let (c, s) = (degrees.to_radians().cos(), degrees.to_radians().sin());
        for row in w.iter_mut() {
            let (x, y) = (row[k], row[j]);
            row[k] = c * x - s * y;
            row[j] = s * x + c * y;
        }
    }

    /// Against the committed drum data (degenerate pairs 1-2, 4-5, 7-8, 9-10): its own shapes
    /// align to the identity; 1e-6 round-off (another machine's ccx, issue 23), a flipped
    /// mode and a pair turned within itself are accepted and re-projected; modes of different
    /// frequency mixed by 10 degrees, or another mode count, are refused naming the modes.
    #[test]
    fn align_reprojects_turns_and_flips_and_refuses_another_basis() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../models/fe/drum.modal.toml");
        let data = washdyn_model::ir::modal::read_file(std::path::Path::new(path), path).unwrap();
        let n = data.modes();
        let al = field(&data, |_| {}).align(&data).unwrap();
        assert!(
            (&al.r - nalgebra::DMatrix::identity(n, n)).amax() < 1e-12,
            "{}",
            al.r
        );
        let noisy = field(&data, |w| {
            for (a, row) in w.iter_mut().enumerate() {
                for (k, x) in row.iter_mut().enumerate() {
                    *x *= 1.0 + 1e-6 * if (a + k) % 2 == 0 { 1.0 } else { -1.0 };
                }
            }
        });
        let al = noisy.align(&data).unwrap();
        assert!(al.worst() < 1e-5, "{}", al.worst());
        assert!(al.changed().is_empty());
        let flipped = field(&data, |w| w.iter_mut().for_each(|row| row[2] = -row[2]));
        let al = flipped.align(&data).unwrap();
        assert_eq!(al.changed(), vec![2..3]);
        assert!((al.r[(2, 2)] + 1.0).abs() < 1e-9);
        let turned = field(&data, |w| turn(w, 3, 4, 40.0));
        let al = turned.align(&data).unwrap();
        assert_eq!(al.changed(), vec![3..5]);
        // Modes 3 and 4 (121 Hz, 147 Hz) mixed: refused.
        let e = field(&data, |w| turn(w, 2, 3, 10.0))
            .align(&data)
            .unwrap_err();
        assert!(
            matches!(&e, ResultsError::FieldShapes { fit, .. } if fit.modes.start == 2),
            "{e}"
        );
        let e = e.to_string();
        assert!(
            e.contains("the field of `drum` has other mode shapes") && e.contains("mode 3 "),
            "{e}"
        );
        let mut fewer = data.clone();
        fewer.truncate(4, &[]);
        fewer.file_modes = None;
        fewer.basis = None;
        let e = field(&data, |_| {}).align(&fewer).unwrap_err();
        assert!(
            matches!(&e, ResultsError::FieldModes { how, .. } if *how == Regenerate::BuiltIn),
            "{e}"
        );
        assert!(e.to_string().contains("modes, its modal data"), "{e}");
        assert!(e.to_string().contains("`washdyn fe modal`"), "{e}");
        // A user's deck's data: the advice is its own command and spec (issue 50).
        let spec = std::path::Path::new("specs/my_drum.toml");
        fewer.source = crate::user::deck_source(&fewer.source, spec);
        let e = field(&data, |_| {}).align(&fewer).unwrap_err();
        let deck = Regenerate::Deck {
            spec: "specs/my_drum.toml".into(),
        };
        assert!(
            matches!(&e, ResultsError::FieldModes { how, .. } if *how == deck),
            "{e}"
        );
        assert!(
            e.to_string()
                .contains("regenerate both with `washdyn fe deck specs/my_drum.toml`"),
            "{e}"
        );
    }

    /// Truncated data keeps the file's modes at the points: a field of the file aligns with it.
    #[test]
    fn align_checks_the_file_modes_of_truncated_data() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../models/fe/drum.modal.toml");
        let data = washdyn_model::ir::modal::read_file(std::path::Path::new(path), path).unwrap();
        let mut cut = data.clone();
        cut.truncate(3, &[]);
        assert!(cut.modes() < data.modes());
        let al = field(&data, |w| turn(w, 0, 1, 25.0)).align(&cut).unwrap();
        assert_eq!(al.changed(), vec![0..2]);
    }
}
