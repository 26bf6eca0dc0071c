//! The speed plot of one channel (its order tracks over drum speed above, its raw signal below)
//! and the overview of all displacement channels over speed: the line plots of one run.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{AmplitudeAxis, rpm_range};
use super::lines::{
    LEGEND_AREA, TRACK_COLOURS, draw_legend, draw_raw_panel, draw_track_chart, track_lines,
};
use super::{DynErr, PResult, framed, init_fonts, write_png};
use crate::error::AnalysisError;
use crate::options::AnalysisOptions;
use crate::orders::RunUp;
use crate::signals::{Channel, Quantity, Signals};

/// Speed plot: order tracks over speed (top) and the raw channel over speed (bottom).
pub fn speed_plot(
    run: &RunUp,
    channel: &Channel,
    signals: &Signals,
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    Ok(render_both!(
        base,
        opts,
        draw_speed_plot(run, channel, signals, opts)
    ))
}

fn draw_speed_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    run: &RunUp,
    channel: &Channel,
    signals: &Signals,
    opts: &AnalysisOptions,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(
        root,
        &format!("{}: speed plot ({})", run.channel, run.quantity.noun()),
        &format!(
            "top: order amplitudes (peak), angle domain, Hann over {} revolutions; gaps: \
                 not resolved or below the axis; bottom: raw signal",
            opts.order_block_revs
        ),
    )?;
    let (w, h) = body.dim_in_pixel();
    let (plots, legend) = body.split_horizontally(w.saturating_sub(LEGEND_AREA));
    let (top, bottom) = plots.split_vertically((h as f64 * 0.58) as u32);
    let x_range = rpm_range(run.order_blocks().map(|b| b.rpm));

    // Top: order tracks. 12 % headroom so the largest track is not drawn on the frame.
    let max = run
        .tracks
        .iter()
        .flat_map(|t| t.amplitude.iter().flatten())
        .fold(0.0, |m: f64, &a| m.max(a));
    let axis = AmplitudeAxis::new(opts.colour_scale, run.quantity, max * 1.12);
    let series = track_lines(run.tracks.iter(), &run.blocks, &axis);
    draw_track_chart(&top, &x_range, &axis, &[(&series, false)])?;
    let items: Vec<(String, RGBColor)> = series
        .iter()
        .enumerate()
        .map(|(i, (l, _))| (l.clone(), TRACK_COLOURS[i % TRACK_COLOURS.len()]))
        .collect();
    draw_legend(&legend, "drum orders:", &items, 30)?;
    let (_, top_h) = top.dim_in_pixel();
    draw_legend(
        &legend,
        "raw signal:",
        &[(run.channel.clone(), TRACK_COLOURS[0])],
        top_h as i32 + 30,
    )?;

    // Bottom: raw channel over speed, same speed axis.
    draw_raw_panel(
        &bottom,
        &x_range,
        &[(channel, TRACK_COLOURS[0])],
        &signals.drum_rpm,
        &format!("{} [{}]", run.channel, run.quantity.display_unit()),
        run.quantity.display_factor(),
    )?;
    Ok(())
}

/// All displacement channels' envelopes over speed in one plot.
pub fn displacement_plot(
    signals: &Signals,
    channels: &[&Channel],
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    Ok(render_both!(
        base,
        opts,
        draw_displacements(signals, channels)
    ))
}

fn draw_displacements<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    signals: &Signals,
    channels: &[&Channel],
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(
        root,
        "displacements over drum speed",
        "raw signals (band: every sample within a speed pixel)",
    )?;
    let (w, _) = body.dim_in_pixel();
    let (plot, legend) = body.split_horizontally(w.saturating_sub(LEGEND_AREA));
    let x = rpm_range(signals.drum_rpm.iter().copied());
    let coloured: Vec<(&Channel, RGBColor)> = channels
        .iter()
        .enumerate()
        .map(|(i, c)| (*c, TRACK_COLOURS[i % TRACK_COLOURS.len()]))
        .collect();
    let q = Quantity::Displacement;
    draw_raw_panel(
        &plot,
        &x,
        &coloured,
        &signals.drum_rpm,
        &format!("displacement [{}]", q.display_unit()),
        q.display_factor(),
    )?;
    let items: Vec<(String, RGBColor)> = coloured
        .iter()
        .map(|(c, col)| (c.name.clone(), *col))
        .collect();
    draw_legend(&legend, "channels:", &items, 30)
}
