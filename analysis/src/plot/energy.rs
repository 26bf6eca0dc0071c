//! The energy balance of `run --energy` over time: the drive's work, kinetic, stored and
//! dissipated energy and the residual. Separate from the run-up plots: it draws the energy
//! table (`results::EnergyRecorder::lines`), not a channel's spectra.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::lines::{LEGEND_AREA, TRACK_COLOURS, draw_legend};
use super::{DESC_SIZE, DynErr, PResult, TICK_SIZE, font, framed, init_fonts, write_png};
use crate::error::AnalysisError;
use crate::options::AnalysisOptions;

/// One line of the energy plot: its name, colour and values (J) at the rows' times.
pub struct EnergyLine {
    pub name: String,
    pub values: Vec<f64>,
}

fn draw_energy<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    t: &[f64],
    lines: &[EnergyLine],
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(
        root,
        "energy balance by category",
        "work done by the drive, energy stored, dissipated and kinetic, since the start",
    )?;
    let (w, _) = body.dim_in_pixel();
    let (plot, legend) = body.split_horizontally(w.saturating_sub(LEGEND_AREA + 80));
    let (lo, hi) = lines
        .iter()
        .flat_map(|l| l.values.iter().copied())
        .filter(|v| v.is_finite())
        .fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let pad = 0.05 * (hi - lo).max(1e-12);
    let x = t.first().copied().unwrap_or(0.0)..t.last().copied().unwrap_or(1.0).max(1e-9);
    let mut chart = ChartBuilder::on(&plot)
        .margin(12)
        .margin_right(20)
        .x_label_area_size(50)
        .y_label_area_size(100)
        .build_cartesian_2d(x, (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("energy [J]")
        .axis_desc_style(font(DESC_SIZE))
        .label_style(font(TICK_SIZE))
        .draw()?;
    let mut items = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let c = TRACK_COLOURS[i % TRACK_COLOURS.len()];
        let style = if i < TRACK_COLOURS.len() {
            c.stroke_width(2)
        } else {
            c.stroke_width(1)
        };
        chart.draw_series(LineSeries::new(
            t.iter().copied().zip(l.values.iter().copied()),
            style,
        ))?;
        items.push((l.name.clone(), c));
    }
    draw_legend(&legend, "energy:", &items, 30)
}

/// The energy balance over a run (`run --energy`): `<base>.png` (and .svg).
pub fn energy_plot(
    t: &[f64],
    lines: &[EnergyLine],
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    Ok(render_both!(base, opts, draw_energy(t, lines)))
}
