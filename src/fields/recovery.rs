//! The recovery on a body's mesh: which bodies have a field, and at a state q each node's
//! position and displacement (rigid motion of its frame plus W q) and its stresses.

use crate::error::fields::FieldsError;
use nalgebra::DMatrix;
use std::path::Path;
use washdyn_fe::field::Field;
use washdyn_model::equations::{Body, BodyState, Equations, Frame, rotate};
use washdyn_model::geom::V;
use washdyn_model::geom::f::{add, sub};
use washdyn_model::ir::{Effect, Model};

use super::projection::modal;

/// One body's mesh and how its nodes follow q: the scene's body (its frame says how the mesh
/// moves: floating, spinning on its mount, or fixed).
pub struct BodyField {
    pub name: String,
    pub field: Field,
    pub(super) body: Body,
    /// (first q index, file modes x scene modes) of the body's modes, when elastic.
    pub(super) modes: Option<(usize, DMatrix<f64>)>,
}

/// The bodies of a scene that have a field file in `fe_dir`.
pub struct Recovery {
    pub bodies: Vec<BodyField>,
    pub n: usize,
    /// What the reader should know: a field re-projected onto its modal data's modes.
    pub notes: Vec<String>,
}

impl Recovery {
    /// The scene's bodies whose `<body>.field.bin` is in `fe_dir`.
    pub fn new(eq: &Equations, fe_dir: &Path) -> Result<Recovery, FieldsError> {
        let (mut bodies, mut notes) = (Vec::new(), Vec::new());
        for body in &eq.bodies.list {
            let name = body.id.name();
            let path = fe_dir.join(format!("{name}.field.bin"));
            // A rigid body on a fixed frame does not move.
            if !path.exists() || (body.frame == Frame::Fixed && body.modal().is_none()) {
                continue;
            }
            let field = Field::read(&path)?;
            let modes = body
                .modal()
                .map(|b| modal(b, &field, &mut notes))
                .transpose()?;
            bodies.push(BodyField {
                name: name.into(),
                field,
                body: body.clone(),
                modes,
            });
        }
        if bodies.is_empty() {
            return Err(FieldsError::NoFieldFiles {
                dir: fe_dir.to_path_buf(),
            });
        }
        Ok(Recovery {
            bodies,
            n: eq.layout.n(),
            notes,
        })
    }

    /// Why `dir`'s field files serve no body of the run's scene (`Recovery::new` found none):
    /// none there ([`FieldsError::NoFieldFiles`]), or only of bodies the scene keeps rigid and
    /// fixed ([`FieldsError::NoMovingBody`], with the model's scenes that keep one elastic).
    pub fn no_field_for(model: &Model, scene: &str, dir: &Path) -> FieldsError {
        let mut files: Vec<String> = std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .filter_map(|e| e.file_name().into_string().ok())
            .filter(|n| n.ends_with(".field.bin"))
            .collect();
        files.sort();
        if files.is_empty() {
            return FieldsError::NoFieldFiles {
                dir: dir.to_path_buf(),
            };
        }
        let elastic_scenes = model
            .every_scene()
            .into_iter()
            .filter(|name| {
                model.scene(Some(name)).is_ok_and(|set| {
                    files.iter().any(|f| {
                        let body = f.trim_end_matches(".field.bin").to_string();
                        set.has(&Effect::Elastic(body))
                    })
                })
            })
            .map(str::to_string)
            .collect();
        FieldsError::NoMovingBody {
            dir: dir.to_path_buf(),
            scene: scene.to_string(),
            files,
            elastic_scenes,
        }
    }

    /// The body's coordinates in its field's (file) modes, q_file = T q_scene.
    pub(super) fn file_coordinates(b: &BodyField, q: &[f64]) -> Option<Vec<f64>> {
        b.modes.as_ref().map(|(start, t)| {
            let qs = &q[*start..*start + t.ncols()];
            (0..t.nrows())
                .map(|k| (0..t.ncols()).map(|j| t[(k, j)] * qs[j]).sum())
                .collect()
        })
    }

    /// Stresses at each node of `b` (global components), from the modal stresses: per node,
    /// the stress point (face) with the largest von Mises stress. None for a rigid body or a
    /// field without stresses.
    pub fn stresses(&self, b: &BodyField, phi: f64, q: &[f64]) -> Option<NodeStresses> {
        let f = &b.field;
        if !f.has_stresses() {
            return None;
        }
        let qf = Self::file_coordinates(b, q)?;
        // The drum's modal stresses are in its own frame: sigma_global = R sigma R^T.
        let rot = match &b.body.frame {
            Frame::Spinning { axis, ratio, .. } => {
                let e = V::c(*axis);
                let (c, s) = ((phi * ratio).cos(), (phi * ratio).sin());
                let cols: Vec<[f64; 3]> = (0..3)
                    .map(|j| {
                        let mut u = [0.0; 3];
                        u[j] = 1.0;
                        rotate(e, c, s, V::c(u)).0
                    })
                    .collect();
                Some(nalgebra::Matrix3::from_fn(|i, j| cols[j][i]))
            }
            _ => None,
        };
        let n = f.header.nodes.len();
        let mut out = NodeStresses {
            von_mises: Vec::with_capacity(n),
            tensor: Vec::with_capacity(n),
            principal: Vec::with_capacity(n),
        };
        for i in 0..n {
            let best = f.node_stress(i, &qf);
            let [xx, yy, zz, xy, yz, zx] = best.1;
            let mut m = nalgebra::Matrix3::new(xx, xy, zx, xy, yy, yz, zx, yz, zz);
            if let Some(r) = &rot {
                m = r * m * r.transpose();
            }
            let mut ev: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
            ev.sort_by(|a, b| b.total_cmp(a));
            out.von_mises.push(best.0);
            out.tensor.push([
                m[(0, 0)],
                m[(1, 1)],
                m[(2, 2)],
                m[(0, 1)],
                m[(1, 2)],
                m[(0, 2)],
            ]);
            out.principal.push([ev[0], ev[1], ev[2]]);
        }
        Some(out)
    }

    /// Points (the drum turned by its ratio x phi) and nodal displacements (m, global) of `b` at state q.
    pub fn displacement(
        &self,
        b: &BodyField,
        phi: f64,
        q: &[f64],
    ) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let h = &b.field.header;
        let qf = Self::file_coordinates(b, q);
        let elastic = |i: usize| {
            qf.as_ref()
                .map_or([0.0; 3], |qf| b.field.displacement(i, qf))
        };
        let zero = vec![0.0; q.len()];
        let state = BodyState::new(q, &zero);
        let mut points = Vec::with_capacity(h.nodes.len());
        let mut disp = Vec::with_capacity(h.nodes.len());
        match &b.body.frame {
            Frame::Floating { start, p0 } => {
                let u = V::from_slice(&q[*start..start + 3]);
                let alpha = V::from_slice(&q[start + 3..start + 6]);
                for (i, x) in h.nodes.iter().enumerate() {
                    let d = u + alpha.cross(V::c(sub(*x, *p0)));
                    points.push(*x);
                    disp.push(add(d.0, elastic(i)));
                }
            }
            // The mount's motion and the turn (ratio x phi) are the same for every node.
            Frame::Spinning {
                mount, axis, ratio, ..
            } => {
                let m = mount.state(&state);
                let (c, s) = ((phi * ratio).cos(), (phi * ratio).sin());
                let e = V::c(*axis);
                for (i, x) in h.nodes.iter().enumerate() {
                    let r = rotate(e, c, s, V::c(sub(*x, mount.point)));
                    let d = (m.pos - V::c(mount.point))
                        + m.rot.cross(r)
                        + rotate(e, c, s, V::c(elastic(i)));
                    points.push(add(mount.point, r.0));
                    disp.push(d.0);
                }
            }
            Frame::Fixed => {
                for (i, x) in h.nodes.iter().enumerate() {
                    points.push(*x);
                    disp.push(elastic(i));
                }
            }
        }
        (points, disp)
    }
}

/// The largest von Mises stress over a field's nodes for file coordinates qf, and its node
/// id; None without stresses.
pub(super) fn peak_von_mises(f: &Field, qf: &[f64]) -> Option<(f64, usize)> {
    if !f.has_stresses() {
        return None;
    }
    let mut best = (0.0f64, 0);
    for i in 0..f.header.nodes.len() {
        let vm = f.node_stress(i, qf).0;
        if vm > best.0 {
            best = (vm, f.header.ids[i]);
        }
    }
    Some(best)
}

/// Recovered stresses per node: von Mises (Pa), the tensor (xx, yy, zz, xy, yz, xz; Pa,
/// global) and the principal stresses (descending) at the node's most loaded face.
pub struct NodeStresses {
    pub von_mises: Vec<f64>,
    pub tensor: Vec<[f64; 6]>,
    pub principal: Vec<[f64; 3]>,
}
