//! The heat-map layer of the order plot and the cascade: pixel values by max hold over blocks
//! and bins, the bitmap with its axes, the reference lines (orders or rays) with their boxed
//! labels, and the colour bar. Separate because both heat plots, and the two runs side by side
//! of `washdyn compare`, draw through it.

use std::ops::Range;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::element::BitMapElement;
use plotters::prelude::*;
use plotters::style::FontTransform;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{AmplitudeAxis, colour_map, fmt_number};
use super::{COLOUR_BAR_AREA, DESC_SIZE, NO_DATA, NOTE_SIZE, PResult, TICK_SIZE, font, framed};
use crate::options::ColourScale;
use crate::signals::Quantity;

/// Amplitude (SI, amplitude-corrected) per pixel of a `w` x `h` heat map, top row
/// first; NaN where there is no data. Each pixel column takes the blocks nearest in speed
/// (and all within half a column of them); each
/// pixel keeps the largest bin overlapping its frequency interval and the largest
/// over those blocks, so no peak disappears between pixels (max hold).
fn heat_values(
    cols: &[HeatColumn],
    x: &Range<f64>,
    yr: &Range<f64>,
    w: usize,
    h: usize,
) -> Vec<f64> {
    let mut out = vec![f64::NAN; w * h];
    if cols.is_empty() || w == 0 || h == 0 {
        return out;
    }
    // Each column of blocks covers the speeds nearer to it than to its neighbours (no empty
    // stripes where blocks are sparse in speed, as in a fast ramp); blocks at one speed (a hold)
    // share a pixel column, which shows their largest value.
    let dx = (x.end - x.start) / w as f64;
    let dy = (yr.end - yr.start) / h as f64;
    let speeds: Vec<f64> = cols.iter().map(|c| c.rpm).collect();
    // A block's pixel column, computed once: a block covers several columns.
    let mut cache: Vec<Option<Vec<f64>>> = vec![None; cols.len()];
    let column = |c: &HeatColumn| -> Vec<f64> {
        let amp = c.amp;
        let top = amp.len() as i64 - 1;
        // Nearest bin of an axis value >= 0 (bin k spans k +- 0.5).
        let bin = |y: f64| (y * c.bins_per_unit + 0.5) as i64;
        (0..h)
            .map(|j| {
                // Row j spans [y_lo, y_hi) in axis units.
                let y_hi = yr.end - j as f64 * dy;
                let y_lo = y_hi - dy;
                let k_lo = bin(y_lo.max(0.0));
                let k_hi = bin(y_hi).min(top);
                if k_lo > k_hi {
                    return f64::NAN;
                }
                amp[k_lo as usize..=k_hi as usize]
                    .iter()
                    .fold(f64::NAN, |m: f64, &v| if v.is_nan() { m } else { m.max(v) })
            })
            .collect()
    };
    for i in 0..w {
        let rc = x.start + (i as f64 + 0.5) * dx;
        let k = speeds.partition_point(|&r| r < rc);
        let nearest = match (k.checked_sub(1), speeds.get(k)) {
            (Some(a), Some(&b)) if rc - speeds[a] <= b - rc => speeds[a],
            (Some(a), None) => speeds[a],
            (_, Some(&b)) => b,
            (None, None) => continue,
        };
        // Within half a pixel of the nearest speed: every block there.
        let tol = 0.5 * dx;
        let a = speeds.partition_point(|&r| r < nearest.min(rc) - tol);
        let e = speeds.partition_point(|&r| r <= nearest.max(rc) + tol);
        for b in a..e {
            let col = cache[b].get_or_insert_with(|| column(&cols[b]));
            for (j, &v) in col.iter().enumerate() {
                let cell = &mut out[j * w + i];
                if cell.is_nan() || v > *cell {
                    *cell = v;
                }
            }
        }
    }
    out
}

/// One block's spectrum as a heat-map column: its drum speed, amplitudes (NaN: no data) and
/// bins per unit of the y axis.
pub(super) struct HeatColumn<'a> {
    pub(super) rpm: f64,
    pub(super) amp: &'a [f64],
    pub(super) bins_per_unit: f64,
}

/// Reference lines drawn over a heat map.
pub(super) enum Overlay {
    /// Horizontal lines at these orders (order plot).
    Orders(Vec<(f64, String)>),
    /// Rays `f = order * rpm / 60` (cascade).
    Rays(Vec<(f64, String)>),
}

/// Everything a heat-map plot needs apart from the backend.
pub(super) struct HeatPlot<'a> {
    pub(super) title: String,
    pub(super) subtitle: String,
    /// Sorted by speed.
    pub(super) columns: Vec<HeatColumn<'a>>,
    pub(super) x_range: Range<f64>,
    pub(super) y_range: Range<f64>,
    pub(super) y_desc: String,
    pub(super) scale: ColourScale,
    pub(super) quantity: Quantity,
    pub(super) overlay: Overlay,
}

/// The top of a heat map's colour scale: the largest amplitude any of its pixels shows (every
/// column's bins that overlap the y axis; each column covers at least one pixel column).
fn heat_max(p: &HeatPlot) -> f64 {
    p.columns
        .iter()
        .filter_map(|c| {
            let top = c.amp.len().checked_sub(1)?;
            let bin = |y: f64| ((y * c.bins_per_unit + 0.5) as usize).min(top);
            let (lo, hi) = (bin(p.y_range.start.max(0.0)), bin(p.y_range.end));
            (lo <= hi).then(|| c.amp[lo..=hi].iter().copied().filter(|v| !v.is_nan()))
        })
        .flatten()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
}

/// A heat map with its axes and overlay in `area`, coloured on `axis` (the caller's colour
/// scale, so several panels can share one). Returns the right edge and the vertical range of
/// the plotting area in root pixels, where a colour bar goes.
fn draw_heat_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &HeatPlot,
    axis: &AmplitudeAxis,
) -> PResult<(i32, Range<i32>)>
where
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .margin_right(24)
        .x_label_area_size(62)
        .y_label_area_size(84)
        .build_cartesian_2d(p.x_range.clone(), p.y_range.clone())?;

    let (px, py) = chart.plotting_area().get_pixel_range();
    let (pw, ph) = ((px.end - px.start) as usize, (py.end - py.start) as usize);
    let values = heat_values(&p.columns, &p.x_range, &p.y_range, pw, ph);
    let mut rgb = Vec::with_capacity(pw * ph * 3);
    // A bin spans several pixels: reuse the colour of an equal neighbour (log10 per pixel was a
    // tenth of a run's time).
    let mut last = (f64::NAN, NO_DATA);
    for v in &values {
        let c = if v.is_nan() {
            NO_DATA
        } else if *v == last.0 {
            last.1
        } else {
            let c = colour_map(axis.fraction(*v));
            last = (*v, c);
            c
        };
        rgb.extend_from_slice(&[c.0, c.1, c.2]);
    }
    // The bitmap goes at the plotting area's root pixels, drawn on `area` (shifted by its base).
    let (bx, by) = area.get_base_pixel();
    let image = BitMapElement::with_owned_buffer(
        (px.start - bx, py.start - by),
        (pw as u32, ph as u32),
        rgb,
    )
    .ok_or("heat map buffer size mismatch")?;
    area.draw(&image)?;

    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("drum speed [rpm]")
        .y_desc(p.y_desc.as_str())
        .axis_desc_style(font(DESC_SIZE))
        .label_style(font(TICK_SIZE))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| fmt_number(*v))
        .x_labels(10)
        .y_labels(12)
        .draw()?;

    draw_overlay(&mut chart, &p.overlay, &p.x_range, &p.y_range)?;
    Ok((px.end, py))
}

pub(super) fn draw_heat_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: &HeatPlot,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(root, &p.title, &p.subtitle)?;
    let (w, _) = body.dim_in_pixel();
    let (main, _) = body.split_horizontally(w.saturating_sub(COLOUR_BAR_AREA));
    let axis = AmplitudeAxis::new(p.scale, p.quantity, heat_max(p));
    let bar = draw_heat_panel(&main, p, &axis)?;
    draw_colour_bar(root, &axis, bar)
}

/// Two heat maps side by side (`a` left, `b` right) on one colour scale and the same axes
/// (the caller gives both the same ranges), each titled by its own `title`, one colour bar.
pub(super) fn draw_heat_pair<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
    a: &HeatPlot,
    b: &HeatPlot,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(root, title, subtitle)?;
    let (w, _) = body.dim_in_pixel();
    let (main, _) = body.split_horizontally(w.saturating_sub(COLOUR_BAR_AREA));
    let (mw, _) = main.dim_in_pixel();
    let (left, right) = main.split_horizontally(mw / 2);
    let axis = AmplitudeAxis::new(a.scale, a.quantity, heat_max(a).max(heat_max(b)));
    draw_heat_panel(&left.titled(&a.title, font(DESC_SIZE))?, a, &axis)?;
    let bar = draw_heat_panel(&right.titled(&b.title, font(DESC_SIZE))?, b, &axis)?;
    draw_colour_bar(root, &axis, bar)
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw_overlay<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    overlay: &Overlay,
    x: &Range<f64>,
    y: &Range<f64>,
) -> PResult
where
    DB::ErrorType: 'static,
{
    // Thin, translucent dashes: the marked order stays visible between them.
    let line = ShapeStyle::from(&WHITE.mix(0.8)).stroke_width(1);
    let label_style = font(NOTE_SIZE);
    let (_, py) = chart.plotting_area().get_pixel_range();
    match overlay {
        Overlay::Orders(lines) => {
            for (o, label) in lines {
                if *o < y.start || *o > y.end {
                    continue;
                }
                let pts = [(x.start, *o), (x.end, *o)];
                chart.draw_series(DashedLineSeries::new(pts, 8, 8, line))?;
                let at = chart.backend_coord(&(x.end, *o));
                boxed_label(
                    chart.plotting_area(),
                    label,
                    (at.0 - 8, at.1 - 8),
                    Pos::new(HPos::Right, VPos::Bottom),
                    &label_style,
                )?;
            }
        }
        Overlay::Rays(rays) => {
            // Labels of rays that leave through the top are stacked, so they never overlap.
            let mut stacked = 0;
            let (px, _) = chart.plotting_area().get_pixel_range();
            for (o, label) in rays {
                // Clip f = o * rpm / 60 to the plot rectangle.
                let f = |r: f64| o * r / 60.0;
                let r0 = x.start;
                let r1 = x.end.min(if *o > 0.0 { y.end * 60.0 / o } else { x.end });
                if r1 <= r0 || f(r0) > y.end {
                    continue;
                }
                let pts = [(r0, f(r0).max(y.start)), (r1, f(r1))];
                chart.draw_series(DashedLineSeries::new(pts, 8, 8, line))?;
                let at = chart.backend_coord(&(r1, f(r1)));
                // Below the ray's end if there is room, else above it.
                let (_, th) = chart
                    .plotting_area()
                    .estimate_text_size(label, &label_style)?;
                let below = at.1 + 12 + th as i32 + 4 < py.end;
                let (dy, vpos) = if below {
                    let dy = 12 + stacked * (th as i32 + 8);
                    stacked += 1;
                    (dy, VPos::Top)
                } else {
                    (-12, VPos::Bottom)
                };
                // Right of the ray's end where it leaves in the left half, else left of it.
                let (dx, hpos) = if at.0 < (px.start + px.end) / 2 {
                    (12, HPos::Left)
                } else {
                    (-12, HPos::Right)
                };
                boxed_label(
                    chart.plotting_area(),
                    label,
                    (at.0 + dx, at.1 + dy),
                    Pos::new(hpos, vpos),
                    &label_style,
                )?;
            }
        }
    }
    Ok(())
}

/// Text on a white, slightly transparent box so it stays readable over the heat map.
fn boxed_label<DB: DrawingBackend, CT: CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    text: &str,
    at: (i32, i32),
    pos: Pos,
    style: &TextStyle,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let (tw, th) = area.estimate_text_size(text, style)?;
    let (tw, th) = (tw as i32, th as i32);
    let x0 = match pos.h_pos {
        HPos::Left => at.0,
        HPos::Center => at.0 - tw / 2,
        HPos::Right => at.0 - tw,
    };
    let y0 = match pos.v_pos {
        VPos::Top => at.1,
        VPos::Center => at.1 - th / 2,
        VPos::Bottom => at.1 - th,
    };
    let (bx, by) = area.get_base_pixel();
    let abs = area.strip_coord_spec();
    let rect = [
        (x0 - 4 - bx, y0 - 3 - by),
        (x0 + tw + 4 - bx, y0 + th + 3 - by),
    ];
    abs.draw(&Rectangle::new(rect, WHITE.mix(0.85).filled()))?;
    abs.draw(&Text::new(
        text.to_string(),
        (x0 - bx, y0 - by),
        style.pos(Pos::new(HPos::Left, VPos::Top)),
    ))?;
    Ok(())
}

/// Colour bar right of the plot area, `x_left` its left edge in root pixels and `y`
/// the plot area's vertical pixel range, so bar and map share their height.
fn draw_colour_bar<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    axis: &AmplitudeAxis,
    (x_left, y): (i32, Range<i32>),
) -> PResult
where
    DB::ErrorType: 'static,
{
    let bar_x = x_left + 36;
    let bar_w = 26u32;
    let h = (y.end - y.start).max(1) as u32;
    let mut rgb = Vec::with_capacity((bar_w * h * 3) as usize);
    for j in 0..h {
        let c = colour_map(1.0 - (j as f64 + 0.5) / h as f64);
        for _ in 0..bar_w {
            rgb.extend_from_slice(&[c.0, c.1, c.2]);
        }
    }
    let img = BitMapElement::with_owned_buffer((bar_x, y.start), (bar_w, h), rgb)
        .ok_or("colour bar buffer size mismatch")?;
    root.draw(&img)?;
    root.draw(&Rectangle::new(
        [(bar_x, y.start), (bar_x + bar_w as i32, y.end)],
        BLACK.stroke_width(1),
    ))?;
    let tick_style = font(TICK_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let mut widest = 0;
    for (t, label) in axis.ticks() {
        let py = y.end - (t * (y.end - y.start) as f64).round() as i32;
        let x1 = bar_x + bar_w as i32;
        root.draw(&PathElement::new([(x1, py), (x1 + 6, py)], BLACK))?;
        root.draw(&Text::new(label.clone(), (x1 + 9, py), tick_style.clone()))?;
        widest = widest.max(root.estimate_text_size(&label, &tick_style)?.0 as i32);
    }
    let caption = axis.caption();
    let cap_style = font(DESC_SIZE)
        .transform(FontTransform::Rotate90)
        .pos(Pos::new(HPos::Center, VPos::Top));
    let cx = bar_x + bar_w as i32 + 9 + widest + 12;
    let cy = (y.start + y.end) / 2;
    root.draw(&Text::new(caption, (cx + DESC_SIZE as i32, cy), cap_style))?;
    Ok(())
}
