//! Recovery on the FE mesh after a run (`washdyn fields`): the stored states (`states.parquet`)
//! and each body's mode shapes on its mesh (`<body>.field.bin`, from `washdyn fe modal`) give
//! the nodal displacements, rigid motion + W q in the global frame, written as VTK grids with a
//! `.pvd` collection per body. It reads what the run wrote and never touches the run.
//!
//! Kinematics (linearised, as the equations): a tub node x moves u + alpha x (x - p0) + W q_tub;
//! the drum is drawn turned by its ratio x phi about its axis, p = B + R(ratio phi)(x - B), and
//! moves with the tub's material frame at its mount B (translation d_B, rotation theta_B) plus
//! its own modes: d_B + theta_B x (p - B) + R(ratio phi) W q_drum; a cabinet node moves W q_cab.

use crate::vtk::{Cell, Data, write_pvd, write_vtu};
use nalgebra::DMatrix;
use std::path::{Path, PathBuf};
use washdyn_fe::field::Field;
use washdyn_runtime::equations::{Body, BodyState, Equations, Frame, ModalBody, rotate};
use washdyn_runtime::geom::V;
use washdyn_runtime::geom::f::{add, sub};
use washdyn_runtime::ir::BodyRef;
use washdyn_runtime::ir::files::FileHash;
use washdyn_runtime::ir::modal::ModalData;

/// One body's mesh and how its nodes follow q: the scene's body (its frame says how the mesh
/// moves: floating, spinning on its mount, or fixed).
pub struct BodyField {
    pub name: String,
    pub field: Field,
    body: Body,
    /// (first q index, file modes x scene modes) of the body's modes, when elastic.
    modes: Option<(usize, DMatrix<f64>)>,
}

/// The bodies of a scene that have a field file in `fe_dir`.
pub struct Recovery {
    pub bodies: Vec<BodyField>,
    pub n: usize,
    /// What the reader should know: a field re-projected onto its modal data's modes.
    pub notes: Vec<String>,
}

/// q_file = T q_scene for a body's modal data (identity when not truncated).
fn basis(d: &ModalData, file_modes: usize) -> DMatrix<f64> {
    match &d.basis {
        Some(b) => DMatrix::from_row_slice(file_modes, b.len() / file_modes, b),
        None => DMatrix::identity(file_modes, d.modes()),
    }
}

/// The body's q index and q_field = R T q_scene: T the data's truncation, R the field's modes
/// onto the data file's (`Field::align`: identity for the same solve, a turn or flip per
/// degenerate group for another). A note when R re-projects.
fn modal(
    b: &ModalBody,
    field: &Field,
    notes: &mut Vec<String>,
) -> Result<(usize, DMatrix<f64>), String> {
    let al = field.align(b.data())?;
    let changed = al.changed();
    if !changed.is_empty() {
        let groups: Vec<String> = changed
            .iter()
            .map(|g| {
                if g.len() == 1 {
                    format!("{}", g.start + 1)
                } else {
                    format!("{}-{}", g.start + 1, g.end)
                }
            })
            .collect();
        notes.push(format!(
            "the field of `{}` is another solve of its modal data: modes {} turned or flipped \
             within their groups of equal frequency, re-projected (largest deviation {:.1e})",
            field.header.body,
            groups.join(", "),
            al.worst()
        ));
    }
    let t = basis(b.data(), field.modes());
    Ok((b.start, al.r * t))
}

impl Recovery {
    /// The scene's bodies whose `<body>.field.bin` is in `fe_dir`.
    pub fn new(eq: &Equations, fe_dir: &Path) -> Result<Recovery, String> {
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
            return Err(format!(
                "no field files (<body>.field.bin) in {}: `washdyn fe modal` writes them there \
                 (with CalculiX)",
                fe_dir.display()
            ));
        }
        Ok(Recovery {
            bodies,
            n: eq.layout.n(),
            notes,
        })
    }

    /// The body's coordinates in its field's (file) modes, q_file = T q_scene.
    fn file_coordinates(b: &BodyField, q: &[f64]) -> Option<Vec<f64>> {
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
fn peak_von_mises(f: &Field, qf: &[f64]) -> Option<(f64, usize)> {
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

/// The times of `--times` (or `--revolution`) as numbers: finite and not negative. `option`
/// names the flag in the error. Checked before any file is read or written; whether each lies
/// inside the run is checked against its states (`States::instants`).
pub fn check_times(option: &str, times: &[f64]) -> Result<(), String> {
    let bad: Vec<String> = times
        .iter()
        .filter(|t| !(t.is_finite() && **t >= 0.0))
        .map(|t| t.to_string())
        .collect();
    if bad.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{option}: {} is not a time in s (finite, >= 0)",
            bad.join(", ")
        ))
    }
}

/// Which instants to recover.
#[derive(Clone, Debug, PartialEq)]
pub enum Times {
    List(Vec<f64>),
    /// from, to, step (s).
    Range(f64, f64, f64),
    /// One drum revolution from this time, in `REVOLUTION_FRAMES` frames.
    Revolution(f64),
}

/// Frames of one revolution (every 10 degrees).
pub const REVOLUTION_FRAMES: usize = 36;

/// Most instants one `washdyn fields` call writes: each is a grid per body of 1-5 MB, so 1e4
/// frames are already tens of GB; a range with a tiny step is a typo.
pub const MAX_FRAMES: usize = 10_000;

/// The states a run wrote: time, drum angle and q per sample.
pub struct States {
    pub t: Vec<f64>,
    pub phi: Vec<f64>,
    pub q: Vec<Vec<f64>>,
}

impl States {
    pub fn read(path: &Path) -> Result<States, String> {
        let (names, cols) = crate::results::read_parquet_f64(path)?;
        if names.len() < 3 || names[0] != "time_s" || names[1] != "drum_angle_rad" {
            return Err(format!(
                "{}: not a states file (time_s, drum_angle_rad, q...)",
                path.display()
            ));
        }
        let mut cols = cols.into_iter();
        let t = cols.next().expect("checked");
        let phi = cols.next().expect("checked");
        Ok(States {
            t,
            phi,
            q: cols.collect(),
        })
    }

    /// (phi, q) at time `t`, linear between samples; an error outside the run.
    pub fn at(&self, t: f64) -> Result<(f64, Vec<f64>), String> {
        let n = self.t.len();
        // Negated: a NaN time is outside too.
        if n == 0 || !(t >= self.t[0] - 1e-12 && t <= self.t[n - 1] + 1e-12) {
            return Err(format!(
                "t = {t} s is outside the stored states ({} to {} s)",
                self.t.first().unwrap_or(&0.0),
                self.t.last().unwrap_or(&0.0)
            ));
        }
        let i = self.t.partition_point(|&x| x <= t).clamp(1, n.max(2) - 1);
        let (t0, t1) = (self.t[i - 1], self.t[i.min(n - 1)]);
        let f = if t1 > t0 {
            ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let lerp = |v: &[f64]| v[i - 1] + f * (v[i.min(n - 1)] - v[i - 1]);
        Ok((lerp(&self.phi), self.q.iter().map(|c| lerp(c)).collect()))
    }

    /// The instants `times` asks for, every one inside the stored states (all checked before
    /// the first file is written).
    pub fn instants(&self, times: &Times) -> Result<Vec<f64>, String> {
        let (option, list) = self.requested(times)?;
        if list.len() > MAX_FRAMES {
            return Err(format!(
                "{option}: {} instants, more than {MAX_FRAMES}",
                list.len()
            ));
        }
        let bad: Vec<String> = list.iter().filter_map(|&t| self.at(t).err()).collect();
        if !bad.is_empty() {
            return Err(format!("{option}: {}", bad.join("; ")));
        }
        Ok(list)
    }

    /// The option's name and the instants it lists.
    fn requested(&self, times: &Times) -> Result<(&'static str, Vec<f64>), String> {
        Ok(match times {
            Times::List(v) => ("--times", v.clone()),
            Times::Range(a, b, dt) => {
                if !(*dt > 0.0 && b >= a && a.is_finite() && b.is_finite()) {
                    return Err(format!(
                        "--range {a}:{b}:{dt}: need from <= to and step > 0, all finite"
                    ));
                }
                let n = ((b - a) / dt + 1e-9).floor();
                if n >= MAX_FRAMES as f64 {
                    return Err(format!(
                        "--range {a}:{b}:{dt}: {n:e} instants, more than {MAX_FRAMES}"
                    ));
                }
                let n = n as usize;
                ("--range", (0..=n).map(|k| a + k as f64 * dt).collect())
            }
            Times::Revolution(t0) => {
                // Frames at equal drum angles over one turn.
                let (phi0, _) = self.at(*t0)?;
                let mut out = vec![*t0];
                let step = 2.0 * std::f64::consts::PI / REVOLUTION_FRAMES as f64;
                for k in 1..REVOLUTION_FRAMES {
                    let target = phi0 + k as f64 * step;
                    let i = self.phi.partition_point(|&p| p < target);
                    if i == 0 || i >= self.t.len() {
                        return Err(format!(
                            "the run ends before one revolution from t = {t0} s"
                        ));
                    }
                    let f = (target - self.phi[i - 1]) / (self.phi[i] - self.phi[i - 1]);
                    out.push(self.t[i - 1] + f * (self.t[i] - self.t[i - 1]));
                }
                ("--revolution", out)
            }
        })
    }
}

/// What `washdyn fields` wrote.
pub struct Written {
    pub files: Vec<PathBuf>,
    pub bytes: u64,
    pub seconds: f64,
    /// Largest displacement: (body, m, node id, time).
    pub largest: Option<(String, f64, usize, f64)>,
    /// Largest von Mises stress: (body, Pa, node id, time).
    pub peak_stress: Option<(String, f64, usize, f64)>,
    /// The recovery's notes (`Recovery::notes`).
    pub notes: Vec<String>,
}

/// Recover the fields of every body at `instants` into `out` (`<body>_<k>.vtu`, `<body>.pvd`).
pub fn write_fields(
    rec: &Recovery,
    states: &States,
    instants: &[f64],
    out: &Path,
) -> Result<Written, String> {
    let start = std::time::Instant::now();
    if states.q.len() != rec.n {
        return Err(format!(
            "the states have {} coordinates, the scene {}: another scene's run?",
            states.q.len(),
            rec.n
        ));
    }
    // Every instant before the first file: a refused one leaves no partial output.
    for &t in instants {
        states.at(t)?;
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut w = Written {
        files: Vec::new(),
        bytes: 0,
        seconds: 0.0,
        largest: None,
        peak_stress: None,
        notes: rec.notes.clone(),
    };
    for b in &rec.bodies {
        let cells: Vec<Cell> = b
            .field
            .header
            .cells
            .iter()
            .map(|c| Cell {
                vtk: c.vtk,
                nodes: &c.nodes,
            })
            .collect();
        let mut steps = Vec::new();
        for (k, &t) in instants.iter().enumerate() {
            let (phi, q) = states.at(t)?;
            let (points, disp) = rec.displacement(b, phi, &q);
            for (i, d) in disp.iter().enumerate() {
                let m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if w.largest.as_ref().is_none_or(|l| m > l.1) {
                    w.largest = Some((b.name.clone(), m, b.field.header.ids[i], t));
                }
            }
            let flat: Vec<f64> = disp.iter().flatten().copied().collect();
            let file = format!("{}_{k:05}.vtu", b.name);
            let path = out.join(&file);
            let mut data = vec![Data {
                name: "displacement_m",
                components: 3,
                values: &flat,
            }];
            let st = rec.stresses(b, phi, &q);
            let (tensor, principal): (Vec<f64>, Vec<f64>) = st.as_ref().map_or_else(
                || (Vec::new(), Vec::new()),
                |s| {
                    (
                        s.tensor.iter().flatten().copied().collect(),
                        s.principal.iter().flatten().copied().collect(),
                    )
                },
            );
            if let Some(s) = &st {
                data.push(Data {
                    name: "von_mises_Pa",
                    components: 1,
                    values: &s.von_mises,
                });
                data.push(Data {
                    name: "stress_Pa",
                    components: 6,
                    values: &tensor,
                });
                data.push(Data {
                    name: "principal_stress_Pa",
                    components: 3,
                    values: &principal,
                });
                for (i, v) in s.von_mises.iter().enumerate() {
                    if w.peak_stress.as_ref().is_none_or(|l| *v > l.1) {
                        w.peak_stress = Some((b.name.clone(), *v, b.field.header.ids[i], t));
                    }
                }
            }
            w.bytes += write_vtu(&path, &points, &cells, &data, &[])?;
            w.files.push(path);
            steps.push((t, file));
        }
        let pvd = out.join(format!("{}.pvd", b.name));
        write_pvd(&pvd, &steps)?;
        w.files.push(pvd);
    }
    w.seconds = start.elapsed().as_secs_f64();
    Ok(w)
}

/// What `washdyn fields` makes.
pub enum Request {
    /// Grids at these instants.
    Fields(Times),
    /// The drum's front edge over the run, every `stride`-th sample (`svg`: also SVG).
    DrumEdge { stride: usize, svg: bool },
}

/// `washdyn fields`: the run in `run_dir` (its summary names model and scene; `model` overrides
/// the model, for model files), into `out` (default `run_dir/fields`).
pub fn fields_command(
    run_dir: &Path,
    model: Option<&str>,
    request: &Request,
    fe_dir: &Path,
    out: Option<&Path>,
) -> Result<Written, String> {
    let summary = std::fs::read_to_string(run_dir.join("summary.json"))
        .map_err(|e| format!("{}/summary.json: {e}", run_dir.display()))?;
    let summary: serde_json::Value =
        serde_json::from_str(&summary).map_err(|e| format!("summary.json: {e}"))?;
    let text = |k: &str| {
        summary[k]
            .as_str()
            .map(str::to_string)
            .ok_or_else(|| format!("summary.json: no {k}"))
    };
    // The run's model: `--model`, else the file the summary names (refused if it or a data
    // file it names changed since), else the built-in model of the summary's name.
    let files: Vec<FileHash> = match summary.get("model_files") {
        Some(v) => serde_json::from_value(v.clone())
            .map_err(|e| format!("summary.json: model_files: {e}"))?,
        None => Vec::new(),
    };
    let spec = match (model, files.first()) {
        (Some(m), _) => m.to_string(),
        (None, Some(first)) => {
            for f in &files {
                f.unchanged().map_err(|e| {
                    format!(
                        "{e}: the run's model differs now (give it with --model to recover anyway)"
                    )
                })?;
            }
            first.path.clone()
        }
        (None, None) => text("model")?,
    };
    let (model, _) = crate::commands::resolve_model(&spec)?;
    let scene = model
        .scene(Some(&text("scene")?))
        .map_err(|e| e.to_string())?;
    let eq = Equations::new(&model, &scene);
    let rec = Recovery::new(&eq, fe_dir)?;
    let states = States::read(&run_dir.join("states.parquet"))
        .map_err(|e| format!("{e} (run with --states to keep the states for field recovery)"))?;
    let out = out.map_or_else(|| run_dir.join("fields"), Path::to_path_buf);
    match request {
        Request::Fields(times) => {
            let instants = states.instants(times)?;
            write_fields(&rec, &states, &instants, &out)
        }
        Request::DrumEdge { stride, svg } => {
            let start = std::time::Instant::now();
            let rows = drum_edge(&rec, &states, *stride)?;
            let files = write_drum_edge(&rows, &out, *svg)?;
            let top = rows.iter().max_by(|a, b| a.max_m.total_cmp(&b.max_m));
            let peak = rows
                .iter()
                .filter_map(|r| r.peak.map(|p| (p, r.t)))
                .max_by(|a, b| a.0.0.total_cmp(&b.0.0));
            Ok(Written {
                bytes: files
                    .iter()
                    .filter_map(|f| std::fs::metadata(f).ok())
                    .map(|m| m.len())
                    .sum(),
                files,
                seconds: start.elapsed().as_secs_f64(),
                largest: top.map(|r| ("drum front edge".into(), r.max_m, r.node, r.t)),
                peak_stress: peak.map(|((pa, node), t)| (BodyRef::Drum.name().into(), pa, node, t)),
                notes: rec.notes.clone(),
            })
        }
    }
}

/// One row of the drum's front edge over a run.
pub struct EdgeRow {
    pub t: f64,
    pub rpm: f64,
    /// Largest elastic displacement (the drum's own modes, drum frame) over the front rim, m.
    pub max_m: f64,
    /// FE node id where it occurs.
    pub node: usize,
    /// The drum's largest von Mises stress (Pa) and its node, when the field has stresses.
    pub peak: Option<(f64, usize)>,
}

/// The drum's front edge (the rim nodes within 1 mm of its front) over the stored states, every
/// `stride`-th sample: the seed paper's Figure 11 (drum deformation against speed). Only the
/// drum's own modes count: its deformation, not the tub's motion that carries it.
pub fn drum_edge(rec: &Recovery, states: &States, stride: usize) -> Result<Vec<EdgeRow>, String> {
    let drum = rec
        .bodies
        .iter()
        .find(|b| b.body.id == BodyRef::Drum)
        .ok_or("no drum field")?;
    if drum.modes.is_none() {
        return Err("the drum is rigid in this scene: no deformation to show".into());
    }
    let h = &drum.field.header;
    let front = h.nodes.iter().map(|x| x[0]).fold(f64::MIN, f64::max);
    let rim: Vec<usize> = (0..h.nodes.len())
        .filter(|&i| h.nodes[i][0] >= front - 1e-3)
        .collect();
    let n = states.t.len();
    let mut rows = Vec::new();
    for s in (0..n).step_by(stride.max(1)) {
        let (a, b) = (s.saturating_sub(1), (s + 1).min(n - 1));
        let rpm = if b > a {
            (states.phi[b] - states.phi[a]) / (states.t[b] - states.t[a]) * 30.0
                / std::f64::consts::PI
        } else {
            0.0
        };
        let q: Vec<f64> = states.q.iter().map(|c| c[s]).collect();
        let qf = Recovery::file_coordinates(drum, &q).expect("checked: the drum is elastic");
        let (mut max_m, mut node) = (0.0f64, 0);
        for &i in &rim {
            let w = drum.field.displacement(i, &qf);
            let m = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            if m > max_m {
                (max_m, node) = (m, h.ids[i]);
            }
        }
        rows.push(EdgeRow {
            t: states.t[s],
            rpm,
            max_m,
            node,
            peak: peak_von_mises(&drum.field, &qf),
        });
    }
    Ok(rows)
}

/// `drum_edge.csv` and its plot over speed (PNG, and SVG with `svg`).
pub fn write_drum_edge(rows: &[EdgeRow], out: &Path, svg: bool) -> Result<Vec<PathBuf>, String> {
    use plotters::prelude::*;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let csv = out.join("drum_edge.csv");
    let mut text =
        String::from("time_s,drum_rpm,front_edge_max_m,node,peak_von_mises_Pa,peak_node\n");
    for r in rows {
        let (p, pn) = r.peak.map_or((f64::NAN, 0), |p| p);
        text += &format!("{},{},{},{},{p},{pn}\n", r.t, r.rpm, r.max_m, r.node);
    }
    std::fs::write(&csv, text).map_err(|e| format!("{}: {e}", csv.display()))?;
    let mut files = vec![csv];
    crate::analysis::plot::init_fonts();
    let size = if rows.iter().any(|r| r.peak.is_some()) {
        (1024, 1100)
    } else {
        (1024, 640)
    };
    let png = out.join("drum_edge.png");
    draw_edge(&BitMapBackend::new(&png, size).into_drawing_area(), rows)
        .map_err(|x| format!("{}: {x}", png.display()))?;
    files.push(png);
    if svg {
        let p = out.join("drum_edge.svg");
        draw_edge(&SVGBackend::new(&p, size).into_drawing_area(), rows)
            .map_err(|x| format!("{}: {x}", p.display()))?;
        files.push(p);
    }
    Ok(files)
}

type PResult = Result<(), Box<dyn std::error::Error + Send + Sync>>;

/// The front edge's displacement over speed and, below it when the field has stresses, the
/// drum's peak von Mises stress.
fn draw_edge<DB: plotters::prelude::DrawingBackend>(
    root: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    rows: &[EdgeRow],
) -> PResult
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    root.fill(&WHITE)?;
    let stressed = rows.iter().any(|r| r.peak.is_some());
    let areas = if stressed {
        root.split_evenly((2, 1))
    } else {
        vec![root.clone()]
    };
    scatter(
        &areas[0],
        rows,
        "drum front edge: largest elastic displacement over speed",
        "displacement [mm]",
        |r| Some(r.max_m * 1e3),
    )?;
    if stressed {
        scatter(
            &areas[1],
            rows,
            "drum: peak von Mises stress over speed",
            "von Mises [MPa]",
            |r| r.peak.map(|p| p.0 * 1e-6),
        )?;
    }
    root.present()?;
    Ok(())
}

fn scatter<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    rows: &[EdgeRow],
    caption: &str,
    y_desc: &str,
    value: impl Fn(&EdgeRow) -> Option<f64>,
) -> PResult
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let rpm_max = rows.iter().map(|r| r.rpm).fold(1.0, f64::max);
    let y_max = rows.iter().filter_map(&value).fold(1e-6, f64::max) * 1.05;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 24))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..rpm_max, 0.0..y_max)?;
    chart
        .configure_mesh()
        .x_desc("drum speed [rpm]")
        .y_desc(y_desc)
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 20))
        .draw()?;
    chart.draw_series(
        rows.iter()
            .filter_map(|r| value(r).map(|v| Circle::new((r.rpm, v), 1, BLUE.filled()))),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bad requests are refused with a message before anything is written.
    #[test]
    fn bad_requests_are_refused() {
        let st = States {
            t: vec![0.0, 1.0, 2.0],
            phi: vec![0.0, 0.5, 1.0],
            q: vec![vec![0.0; 3]],
        };
        let e = st.at(2.5).unwrap_err();
        assert!(e.contains("outside the stored states (0 to 2 s)"), "{e}");
        let e = st.instants(&Times::Range(1.0, 0.0, 0.1)).unwrap_err();
        assert!(e.contains("need from <= to and step > 0"), "{e}");
        let e = st.instants(&Times::Revolution(0.0)).unwrap_err();
        assert!(e.contains("ends before one revolution"), "{e}");
        // Every instant is checked, not just the first: NaN (which compares false) included.
        let e = st
            .instants(&Times::List(vec![0.5, f64::NAN, 9.0]))
            .unwrap_err();
        assert!(
            e.starts_with("--times: t = NaN s is outside") && e.contains("t = 9 s"),
            "{e}"
        );
        let e = st
            .instants(&Times::Range(0.0, 1.0, f64::MIN_POSITIVE))
            .unwrap_err();
        assert!(e.contains("more than 10000"), "{e}");
        assert!(st.instants(&Times::Revolution(f64::NAN)).is_err());
        // A run directory without a summary, and one whose model has no field files.
        let dir = tempfile::tempdir().unwrap();
        let req = Request::Fields(Times::List(vec![0.0]));
        let e = fields_command(dir.path(), None, &req, dir.path(), None)
            .err()
            .unwrap();
        assert!(e.contains("summary.json"), "{e}");
        std::fs::write(
            dir.path().join("summary.json"),
            r#"{"model": "reference", "scene": "full"}"#,
        )
        .unwrap();
        let e = fields_command(dir.path(), None, &req, dir.path(), None)
            .err()
            .unwrap();
        assert!(e.contains("no field files"), "{e}");
        assert!(!dir.path().join("fields").exists());
        // Not a field file.
        std::fs::write(dir.path().join("tub.field.bin"), b"garbage").unwrap();
        let e = washdyn_fe::field::Field::read(&dir.path().join("tub.field.bin")).unwrap_err();
        assert!(e.contains("not a washdyn field file"), "{e}");
    }

    /// A run on a model file: `fields` without --model takes the file summary.json names, and
    /// refuses it, naming it, once its content changed.
    #[test]
    fn the_run_s_model_file_is_used_and_a_changed_one_refused() {
        let dir = tempfile::tempdir().unwrap();
        let model = dir.path().join("m.toml");
        std::fs::write(&model, washdyn_models::REFERENCE_TOML).unwrap();
        let hashed = FileHash::of(&model).unwrap();
        let summary = serde_json::json!({
            "model": "reference", "scene": "full", "model_files": [hashed],
        });
        std::fs::write(dir.path().join("summary.json"), summary.to_string()).unwrap();
        let req = Request::Fields(Times::List(vec![0.0]));
        // The file as run: loaded (its `../fe/` data is not beside it here: named absolute).
        let e = fields_command(dir.path(), None, &req, dir.path(), None)
            .err()
            .unwrap();
        assert!(e.contains(&format!("{}:", model.display())), "{e}");
        assert!(e.contains("tub.modal.toml: cannot read"), "{e}");
        std::fs::write(&model, "name = \"other\"").unwrap();
        let e = fields_command(dir.path(), None, &req, dir.path(), None)
            .err()
            .unwrap();
        assert!(
            e.starts_with(&format!("{}: changed since the run", hashed.path)),
            "{e}"
        );
        assert!(e.contains("--model"), "{e}");
    }

    #[test]
    fn drum_edge_table_and_plot() {
        let rows: Vec<EdgeRow> = (0..50)
            .map(|i| {
                let rpm = 30.0 * i as f64;
                EdgeRow {
                    t: i as f64,
                    rpm,
                    max_m: 1e-8 * rpm * rpm,
                    node: 7,
                    peak: Some((1e2 * rpm * rpm, 9)),
                }
            })
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let files = write_drum_edge(&rows, dir.path(), true).unwrap();
        assert_eq!(files.len(), 3);
        let csv = std::fs::read_to_string(&files[0]).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "time_s,drum_rpm,front_edge_max_m,node,peak_von_mises_Pa,peak_node"
        );
        assert_eq!(lines.len(), 51);
        assert_eq!(lines[2], "1,30,0.000009,7,90000,9");
        assert!(std::fs::metadata(&files[1]).unwrap().len() > 10_000);
    }
}
