//! The drum's front edge over a run (`washdyn fields --drum-edge`): the rim's largest elastic
//! displacement and the drum's peak stress against speed, as a table and a plot. Separate from
//! the grids: every stored sample, one number per sample, no mesh written.

use crate::error::fields::FieldsError;
use crate::error::{FileError, PlotError};
use std::path::{Path, PathBuf};
use washdyn_model::ir::BodyRef;

use super::recovery::{Recovery, peak_von_mises};
use super::states::States;

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
pub fn drum_edge(
    rec: &Recovery,
    states: &States,
    stride: usize,
) -> Result<Vec<EdgeRow>, FieldsError> {
    let drum = rec
        .bodies
        .iter()
        .find(|b| b.body.id == BodyRef::Drum)
        .ok_or(FieldsError::NoDrumField)?;
    if drum.modes.is_none() {
        return Err(FieldsError::RigidDrum);
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
pub fn write_drum_edge(
    rows: &[EdgeRow],
    out: &Path,
    svg: bool,
) -> Result<Vec<PathBuf>, FieldsError> {
    use plotters::prelude::*;
    let io = FileError::at::<FieldsError>;
    let plot = PlotError::at::<FieldsError>;
    std::fs::create_dir_all(out).map_err(io(out))?;
    let csv = out.join("drum_edge.csv");
    let mut text =
        String::from("time_s,drum_rpm,front_edge_max_m,node,peak_von_mises_Pa,peak_node\n");
    for r in rows {
        let (p, pn) = r.peak.map_or((f64::NAN, 0), |p| p);
        text += &format!("{},{},{},{},{p},{pn}\n", r.t, r.rpm, r.max_m, r.node);
    }
    std::fs::write(&csv, text).map_err(io(&csv))?;
    let mut files = vec![csv];
    crate::analysis::plot::init_fonts();
    let size = if rows.iter().any(|r| r.peak.is_some()) {
        (1024, 1100)
    } else {
        (1024, 640)
    };
    let png = out.join("drum_edge.png");
    draw_edge(&BitMapBackend::new(&png, size).into_drawing_area(), rows).map_err(plot(&png))?;
    files.push(png);
    if svg {
        let p = out.join("drum_edge.svg");
        draw_edge(&SVGBackend::new(&p, size).into_drawing_area(), rows).map_err(plot(&p))?;
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
