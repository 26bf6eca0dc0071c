//! The line-plot layer of the speed plots, the two-run track overlay and the energy plot: track
//! colours, order tracks as polylines with gaps, raw signals as min/max bands over speed, and
//! the legend beside the data. Separate because those three plot kinds share it.

use std::ops::Range;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{AmplitudeAxis, fmt_number};
use super::{DESC_SIZE, PResult, TICK_SIZE, font};
use crate::options::ColourScale;
use crate::orders::{Block, OrderTrack};
use crate::signals::Channel;

/// Line colours for order tracks: distinct and print-safe.
pub(crate) const TRACK_COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// A track's legend label and its polyline segments (gaps where unresolved).
pub(super) type TrackLines = (String, Vec<Vec<(f64, f64)>>);

/// Width right of line plots for the legend, outside the data.
pub(super) const LEGEND_AREA: u32 = 270;

/// Min/max of `data` per speed bin, including the segment to the neighbouring
/// sample, so the band is what drawing every sample as a polyline would give at
/// this resolution (a 60 s run at 2 kHz has 120 000 samples).
fn envelope(rpm: &[f64], data: &[f64], x: &Range<f64>, bins: usize) -> Vec<(f64, f64, f64)> {
    let mut lo = vec![f64::INFINITY; bins];
    let mut hi = vec![f64::NEG_INFINITY; bins];
    let width = (x.end - x.start) / bins as f64;
    let bin = |r: f64| {
        let b = ((r - x.start) / width).floor();
        (b >= 0.0 && b < bins as f64).then_some(b as usize)
    };
    let mut put = |b: Option<usize>, v: f64| {
        if let Some(b) = b {
            lo[b] = lo[b].min(v);
            hi[b] = hi[b].max(v);
        }
    };
    let mut prev: Option<(Option<usize>, f64)> = None;
    for (&r, &v) in rpm.iter().zip(data) {
        let b = bin(r);
        put(b, v);
        if let Some((pb, pv)) = prev.filter(|(pb, _)| *pb != b) {
            put(b, pv);
            put(pb, v);
        }
        prev = Some((b, v));
    }
    (0..bins)
        .filter(|&b| lo[b] <= hi[b])
        .map(|b| (x.start + (b as f64 + 0.5) * width, lo[b], hi[b]))
        .collect()
}

/// Tick label formatter that prints round-off next to zero as `0`.
fn tick_formatter(span: f64) -> impl Fn(&f64) -> String {
    move |v: &f64| {
        if v.abs() < span.abs() * 1e-9 {
            "0".to_string()
        } else {
            fmt_number(*v)
        }
    }
}

/// Legend in its own area (outside the data): a coloured line and a label per item.
pub(super) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    items: &[(String, RGBColor)],
    top: i32,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let style = font(TICK_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    area.draw(&Text::new(title.to_string(), (12, top), style.clone()))?;
    for (i, (label, colour)) in items.iter().enumerate() {
        let y = top + 30 + 28 * i as i32;
        area.draw(&PathElement::new(
            [(14, y), (44, y)],
            colour.stroke_width(3),
        ))?;
        area.draw(&Text::new(label.clone(), (52, y), style.clone()))?;
    }
    Ok(())
}

/// Order tracks as polylines over speed on `axis`: runs of consecutive values, with gaps where
/// a track is not resolved or below the axis.
pub(super) fn track_lines<'a>(
    tracks: impl Iterator<Item = &'a OrderTrack>,
    blocks: &[Block],
    axis: &AmplitudeAxis,
) -> Vec<TrackLines> {
    tracks
        .map(|t| {
            // Split into runs of consecutive defined values so gaps stay gaps.
            let mut segs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for (a, b) in t.amplitude.iter().zip(blocks) {
                // Not resolved, or below the axis floor: a gap, not a line on the floor.
                let v = a
                    .map(|a| axis.axis_value(a))
                    .filter(|v| matches!(axis.scale, ColourScale::Linear) || *v >= axis.lo);
                match v {
                    Some(v) => segs.last_mut().expect("non-empty").push((b.rpm, v)),
                    None => segs.push(Vec::new()),
                }
            }
            segs.retain(|s| !s.is_empty());
            (t.label.clone(), segs)
        })
        .collect()
}

/// A chart of order tracks over speed in `area` on `axis` (log axis where the scale is log);
/// each set's i-th track in colour i, solid or dashed.
pub(super) fn draw_track_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x_range: &Range<f64>,
    axis: &AmplitudeAxis,
    sets: &[(&[TrackLines], bool)],
) -> PResult
where
    DB::ErrorType: 'static,
{
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(12)
        .margin_right(20)
        .x_label_area_size(50)
        .y_label_area_size(100);
    let y_desc = axis.caption();
    let fmt_y = tick_formatter(axis.hi - axis.lo);
    match axis.scale {
        ColourScale::Log { .. } => {
            let mut chart =
                builder.build_cartesian_2d(x_range.clone(), (axis.lo..axis.hi).log_scale())?;
            chart
                .configure_mesh()
                .x_desc("drum speed [rpm]")
                .y_desc(y_desc.as_str())
                .axis_desc_style(font(DESC_SIZE))
                .label_style(font(TICK_SIZE))
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&fmt_y)
                .light_line_style(RGBColor(235, 235, 235))
                .draw()?;
            for (series, dashed) in sets {
                draw_track_series(&mut chart, series, *dashed)?;
            }
        }
        _ => {
            let mut chart = builder.build_cartesian_2d(x_range.clone(), axis.lo..axis.hi)?;
            chart
                .configure_mesh()
                .x_desc("drum speed [rpm]")
                .y_desc(y_desc.as_str())
                .axis_desc_style(font(DESC_SIZE))
                .label_style(font(TICK_SIZE))
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&fmt_y)
                .light_line_style(RGBColor(235, 235, 235))
                .draw()?;
            for (series, dashed) in sets {
                draw_track_series(&mut chart, series, *dashed)?;
            }
        }
    }
    Ok(())
}

fn draw_track_series<'a, DB: DrawingBackend + 'a, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, Y>>,
    series: &[TrackLines],
    dashed: bool,
) -> PResult
where
    DB::ErrorType: 'static,
    Y: Ranged<ValueType = f64>,
{
    for (i, (_, segs)) in series.iter().enumerate() {
        let style = TRACK_COLOURS[i % TRACK_COLOURS.len()].stroke_width(2);
        for seg in segs {
            if dashed {
                chart.draw_series(DashedLineSeries::new(seg.iter().copied(), 10, 6, style))?;
            } else {
                chart.draw_series(LineSeries::new(seg.iter().copied(), style))?;
            }
        }
    }
    Ok(())
}

/// Raw signals over speed as filled bands (see [`envelope`]); translucent so
/// several channels can share the panel.
pub(super) fn draw_raw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: &Range<f64>,
    channels: &[(&Channel, RGBColor)],
    rpm: &[f64],
    y_desc: &str,
    factor: f64,
) -> PResult
where
    DB::ErrorType: 'static,
{
    // Speed bins of about one pixel column.
    let bins = (area.dim_in_pixel().0 as usize).saturating_sub(140).max(50);
    let envs: Vec<Vec<(f64, f64, f64)>> = channels
        .iter()
        .map(|(c, _)| {
            envelope(rpm, &c.data, x, bins)
                .into_iter()
                .map(|(r, lo, hi)| (r, lo * factor, hi * factor))
                .collect()
        })
        .collect();
    let (mut lo, mut hi) = envs
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), e| {
            (l.min(e.1), h.max(e.2))
        });
    if !lo.is_finite() {
        (lo, hi) = (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05)
        .max(hi.abs().max(lo.abs()) * 1e-3)
        .max(1e-300);
    let fmt_y = tick_formatter(hi - lo + 2.0 * pad);
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .margin_right(20)
        .x_label_area_size(62)
        .y_label_area_size(100)
        .build_cartesian_2d(x.clone(), (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .x_desc("drum speed [rpm]")
        .y_desc(y_desc)
        .axis_desc_style(font(DESC_SIZE))
        .label_style(font(TICK_SIZE))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&fmt_y)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    let alpha = if channels.len() > 1 { 0.45 } else { 1.0 };
    for ((_, colour), env) in channels.iter().zip(envs) {
        let band: Vec<(f64, f64)> = env
            .iter()
            .map(|e| (e.0, e.2))
            .chain(env.iter().rev().map(|e| (e.0, e.1)))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            band,
            colour.mix(alpha).filled(),
        )))?;
    }
    Ok(())
}
