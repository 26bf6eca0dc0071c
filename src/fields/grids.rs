//! The output of `washdyn fields` at instants: a VTK grid per body and instant with
//! displacements and stresses, a `.pvd` collection per body, and what was written.

use crate::error::FileError;
use crate::error::fields::FieldsError;
use crate::vtk::{Cell, Data, write_pvd, write_vtu};
use std::path::{Path, PathBuf};

use super::recovery::Recovery;
use super::states::States;

/// What `washdyn fields` wrote.
#[derive(Debug)]
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
) -> Result<Written, FieldsError> {
    write_fields_with(rec, states, instants, out, &mut |_, _, _| {})
}

/// [`write_fields`], telling `frame` of each grid written: how many so far, of how many, the
/// file (a long recovery's progress, and what Ctrl-C keeps).
pub fn write_fields_with(
    rec: &Recovery,
    states: &States,
    instants: &[f64],
    out: &Path,
    frame: &mut dyn FnMut(usize, usize, &Path),
) -> Result<Written, FieldsError> {
    let start = std::time::Instant::now();
    if states.q.len() != rec.n {
        return Err(FieldsError::Coordinates {
            states: states.q.len(),
            scene: rec.n,
        });
    }
    // Every instant before the first file: a refused one leaves no partial output.
    for &t in instants {
        states.at(t)?;
    }
    std::fs::create_dir_all(out).map_err(FileError::at::<FieldsError>(out))?;
    let mut w = Written {
        files: Vec::new(),
        bytes: 0,
        seconds: 0.0,
        largest: None,
        peak_stress: None,
        notes: rec.notes.clone(),
    };
    let total = rec.bodies.len() * instants.len();
    let mut frames = 0;
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
            frames += 1;
            frame(frames, total, &path);
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
