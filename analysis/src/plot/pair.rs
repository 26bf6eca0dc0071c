//! Two runs of one channel in one picture, for `washdyn compare`: their order plots side by side
//! on one colour scale, and their order tracks overlaid (A solid, B dashed). Separate from the
//! single-run plots, whose layers they reuse.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{AmplitudeAxis, rpm_range};
use super::heat::draw_heat_pair;
use super::lines::{LEGEND_AREA, TRACK_COLOURS, draw_legend, draw_track_chart, track_lines};
use super::order::heat_plot_order;
use super::{COLOUR_BAR_AREA, DynErr, PResult, TICK_SIZE, font, framed, init_fonts, write_png};
use crate::error::AnalysisError;
use crate::options::{AnalysisOptions, fmt_order};
use crate::orders::{OrderTrack, RunUp};

/// Two runs' order plots of one channel side by side: `runs[0]` left, `runs[1]` right, each
/// titled with its label, on one colour scale and the same axes (the same drawing as
/// [`order_plot`](super::order_plot), panel by panel). Writes `<base>.png` (and `.svg` where
/// `opts.svg`), twice as wide as a single order plot less one colour bar.
pub fn order_plot_pair(
    runs: [&RunUp; 2],
    labels: [&str; 2],
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    let mut panels = runs.map(|r| heat_plot_order(r, opts));
    let x = rpm_range(panels.iter().flat_map(|p| p.columns.iter().map(|c| c.rpm)));
    for (p, label) in panels.iter_mut().zip(labels) {
        p.x_range = x.clone();
        p.title = label.to_string();
    }
    let title = format!(
        "{}: order plots, {} (left) and {} (right) ({}, motor/drum ratio {})",
        runs[0].channel,
        labels[0],
        labels[1],
        runs[0].quantity.noun(),
        fmt_order(opts.motor_ratio)
    );
    let subtitle = format!("{}; one colour scale", panels[0].subtitle);
    let opts = AnalysisOptions {
        plot_size: (
            2 * opts.plot_size.0 - COLOUR_BAR_AREA,
            opts.plot_size.1 + 40,
        ),
        ..opts.clone()
    };
    Ok(render_both!(
        base,
        opts,
        draw_heat_pair(&title, &subtitle, &panels[0], &panels[1])
    ))
}

/// Two runs' order tracks of one channel over speed in one chart: the tracks of `orders`
/// (those the analysis tracked), `runs[0]` solid, `runs[1]` dashed, one colour per order.
pub fn track_overlay_plot(
    runs: [&RunUp; 2],
    labels: [&str; 2],
    orders: &[f64],
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    Ok(render_both!(
        base,
        opts,
        draw_track_overlay(runs, labels, orders, opts)
    ))
}

fn draw_track_overlay<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    runs: [&RunUp; 2],
    labels: [&str; 2],
    orders: &[f64],
    opts: &AnalysisOptions,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(
        root,
        &format!(
            "{}: order tracks, {} solid, {} dashed",
            runs[0].channel, labels[0], labels[1]
        ),
        &format!(
            "order amplitudes (peak), angle domain, Hann over {} revolutions; gaps: not \
                 resolved or below the axis",
            opts.order_block_revs
        ),
    )?;
    let (w, _) = body.dim_in_pixel();
    let (plot, legend) = body.split_horizontally(w.saturating_sub(LEGEND_AREA));
    let x_range = rpm_range(runs.iter().flat_map(|r| r.order_blocks().map(|b| b.rpm)));
    fn picked<'r>(r: &'r RunUp, orders: &[f64]) -> Vec<&'r OrderTrack> {
        r.tracks
            .iter()
            .filter(|t| orders.iter().any(|o| (o - t.order).abs() < 1e-9))
            .collect()
    }
    let (ta, tb) = (picked(runs[0], orders), picked(runs[1], orders));
    // 12 % headroom so the largest track is not drawn on the frame.
    let max = ta
        .iter()
        .chain(&tb)
        .flat_map(|t| t.amplitude.iter().flatten())
        .fold(0.0, |m: f64, &a| m.max(a));
    let axis = AmplitudeAxis::new(opts.colour_scale, runs[0].quantity, max * 1.12);
    let sa = track_lines(ta.into_iter(), &runs[0].blocks, &axis);
    let sb = track_lines(tb.into_iter(), &runs[1].blocks, &axis);
    draw_track_chart(&plot, &x_range, &axis, &[(&sa, false), (&sb, true)])?;
    let items: Vec<(String, RGBColor)> = sa
        .iter()
        .enumerate()
        .map(|(i, (l, _))| (l.clone(), TRACK_COLOURS[i % TRACK_COLOURS.len()]))
        .collect();
    draw_legend(&legend, "drum orders:", &items, 30)?;
    // Which run is which line style.
    let style = font(TICK_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let top = 30 + 28 * (items.len() as i32 + 2);
    legend.draw(&Text::new("runs:".to_string(), (12, top), style.clone()))?;
    for (k, label) in labels.iter().enumerate() {
        let y = top + 30 + 28 * k as i32;
        let segs: &[(i32, i32)] = if k == 0 {
            &[(14, 44)]
        } else {
            &[(14, 24), (30, 40)]
        };
        for &(x0, x1) in segs {
            legend.draw(&PathElement::new([(x0, y), (x1, y)], BLACK.stroke_width(3)))?;
        }
        legend.draw(&Text::new(label.to_string(), (52, y), style.clone()))?;
    }
    Ok(())
}
