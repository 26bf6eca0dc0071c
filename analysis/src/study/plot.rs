//! The two pictures of a variant study, each as PNG and SVG like the run-up plots (same frame,
//! font and output): [`pareto`], the trade-off between two outputs with the non-dominated
//! variants named, and [`sobol_bars`], which parameters an output's variance comes from.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::pareto::{Sense, front};
use super::sobol::Indices;
use crate::error::AnalysisError;
use crate::options::AnalysisOptions;
use crate::plot::{
    DESC_SIZE, DynErr, NOTE_SIZE, PResult, TICK_SIZE, TRACK_COLOURS, fmt_number, font, framed,
    init_fonts, render_both, write_png,
};

/// Size and formats of the study plots.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotOptions {
    /// Pixel size of the PNG (the SVG uses the same layout).
    pub plot_size: (u32, u32),
    /// Also write an SVG (the PNG is always written).
    pub svg: bool,
}

impl Default for PlotOptions {
    /// The run-up plots' size and formats.
    fn default() -> Self {
        let a = AnalysisOptions::default();
        PlotOptions {
            plot_size: a.plot_size,
            svg: a.svg,
        }
    }
}

/// One output of every variant, as the Pareto plot shows it on an axis.
#[derive(Debug, Clone, Copy)]
pub struct Output<'a> {
    /// What it is (`tub displacement, peak`).
    pub name: &'a str,
    /// Its unit for the axis label (`mm`).
    pub unit: &'a str,
    /// Whether smaller or larger is better.
    pub sense: Sense,
    /// One value per variant (NaN: the variant failed).
    pub values: &'a [f64],
}

impl Output<'_> {
    fn label(&self) -> String {
        format!("{} [{}]", self.name, self.unit)
    }
}

/// Width right of the data for the legend.
const LEGEND_AREA: u32 = 250;
const GREY: RGBColor = RGBColor(160, 160, 160);

/// `lo..hi` of the finite values, padded by 6 % so no marker sits on the frame, and by another
/// 10 % on the side `better` of `sense`, where the front's ids are written.
fn padded(values: impl Iterator<Item = f64>, better: Sense) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let pad = 0.06 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
    let ids = pad * 10.0 / 6.0;
    match better {
        Sense::Minimise => (lo - pad - ids)..(hi + pad),
        Sense::Maximise => (lo - pad)..(hi + pad + ids),
    }
}

/// Draws a legend item's marker centred at a pixel of the legend area.
type Marker<'a, DB> = &'a dyn Fn(&DrawingArea<DB, Shift>, (i32, i32)) -> PResult;

/// A legend beside the data: a marker and a label per item.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[(&str, Marker<DB>)],
) -> PResult
where
    DB::ErrorType: 'static,
{
    let style = font(TICK_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, (label, mark)) in items.iter().enumerate() {
        let y = 40 + 30 * i as i32;
        mark(area, (28, y))?;
        area.draw(&Text::new(label.to_string(), (52, y), style.clone()))?;
    }
    Ok(())
}

/// The Pareto plot of outputs `x` and `y` over the variants `ids`: every variant as a grey dot,
/// the non-dominated ones ([`front`] of the two outputs with their senses) marked, labelled with
/// their ids and joined in order of `x`. Variants with a non-finite output are not drawn; the
/// subtitle counts them. Writes `<base>.png` (and `.svg`); returns the paths.
pub fn pareto(
    ids: &[&str],
    x: &Output,
    y: &Output,
    opts: &PlotOptions,
    base: &Path,
) -> Result<Vec<PathBuf>, AnalysisError> {
    if x.values.len() != ids.len() || y.values.len() != ids.len() {
        return Err(AnalysisError::InvalidStudy(format!(
            "Pareto plot: {} ids, {} values of {}, {} of {}",
            ids.len(),
            x.values.len(),
            x.name,
            y.values.len(),
            y.name
        )));
    }
    init_fonts();
    let points: Vec<[f64; 2]> = x
        .values
        .iter()
        .zip(y.values)
        .map(|(&a, &b)| [a, b])
        .collect();
    let on_front = front(&points, &[x.sense, y.sense]);
    Ok(render_both!(
        base,
        opts,
        draw_pareto(ids, x, y, &points, &on_front)
    ))
}

fn draw_pareto<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    ids: &[&str],
    x: &Output,
    y: &Output,
    points: &[[f64; 2]],
    on_front: &[usize],
) -> PResult
where
    DB::ErrorType: 'static,
{
    let word = |s: Sense| match s {
        Sense::Minimise => "smaller",
        Sense::Maximise => "larger",
    };
    let shown: Vec<usize> = (0..points.len())
        .filter(|&k| points[k].iter().all(|v| v.is_finite()))
        .collect();
    let hidden = points.len() - shown.len();
    let body = framed(
        root,
        &format!("Pareto front: {} against {}", y.name, x.name),
        &format!(
            "{} variants, {} non-dominated; better: {} x, {} y{}",
            points.len(),
            on_front.len(),
            word(x.sense),
            word(y.sense),
            match hidden {
                0 => String::new(),
                h => format!("; {h} failed (or infinite), not shown"),
            }
        ),
    )?;
    let (w, _) = body.dim_in_pixel();
    let (plot, side) = body.split_horizontally(w.saturating_sub(LEGEND_AREA));
    let mut chart = ChartBuilder::on(&plot)
        .margin(12)
        .margin_right(20)
        .x_label_area_size(50)
        .y_label_area_size(100)
        .build_cartesian_2d(
            padded(shown.iter().map(|&k| points[k][0]), x.sense),
            padded(shown.iter().map(|&k| points[k][1]), y.sense),
        )?;
    chart
        .configure_mesh()
        .x_desc(x.label())
        .y_desc(y.label())
        .x_label_formatter(&|v| fmt_number(*v))
        .y_label_formatter(&|v| fmt_number(*v))
        .axis_desc_style(font(DESC_SIZE))
        .label_style(font(TICK_SIZE))
        .draw()?;
    chart.draw_series(
        shown
            .iter()
            .map(|&k| Circle::new((points[k][0], points[k][1]), 3, GREY.filled())),
    )?;
    let colour = TRACK_COLOURS[3];
    let mut line: Vec<(f64, f64)> = on_front
        .iter()
        .filter(|&&k| points[k].iter().all(|v| v.is_finite()))
        .map(|&k| (points[k][0], points[k][1]))
        .collect();
    line.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    chart.draw_series(LineSeries::new(line, colour.stroke_width(2)))?;
    // Ids on the front's better side, where no variant lies.
    let (dx, h) = match x.sense {
        Sense::Minimise => (-7, HPos::Right),
        Sense::Maximise => (7, HPos::Left),
    };
    let (dy, v) = match y.sense {
        Sense::Minimise => (5, VPos::Top),
        Sense::Maximise => (-5, VPos::Bottom),
    };
    let style = font(NOTE_SIZE).pos(Pos::new(h, v));
    chart.draw_series(
        on_front
            .iter()
            .filter(|&&k| points[k].iter().all(|v| v.is_finite()))
            .map(|&k| {
                EmptyElement::at((points[k][0], points[k][1]))
                    + Circle::new((0, 0), 6, colour.filled())
                    + Text::new(ids[k].to_string(), (dx, dy), style.clone())
            }),
    )?;
    let grey_dot = |a: &DrawingArea<DB, Shift>, p| -> PResult {
        Ok(a.draw(&Circle::new(p, 3, GREY.filled()))?)
    };
    let front_dot = |a: &DrawingArea<DB, Shift>, p: (i32, i32)| -> PResult {
        a.draw(&PathElement::new(
            [(p.0 - 16, p.1), (p.0 + 16, p.1)],
            colour.stroke_width(2),
        ))?;
        Ok(a.draw(&Circle::new(p, 6, colour.filled()))?)
    };
    legend(
        &side,
        &[("variant", &grey_dot), ("non-dominated (id)", &front_dot)],
    )
}

/// Colours of the first-order and total bars.
const S1_COLOUR: RGBColor = TRACK_COLOURS[0];
const ST_COLOUR: RGBColor = TRACK_COLOURS[1];

/// The Sobol indices of one output as bars: per parameter its first-order index (left) and
/// total index (right), each with its confidence interval as an error bar. `output` names the
/// output with its unit (`tub displacement, peak [mm]`), `params` the parameters with theirs.
/// Writes `<base>.png` (and `.svg`); returns the paths.
pub fn sobol_bars(
    output: &str,
    params: &[&str],
    indices: &Indices,
    opts: &PlotOptions,
    base: &Path,
) -> Result<Vec<PathBuf>, AnalysisError> {
    if params.len() != indices.s1.len() {
        return Err(AnalysisError::InvalidStudy(format!(
            "Sobol bars: {} names for {} parameters",
            params.len(),
            indices.s1.len()
        )));
    }
    init_fonts();
    Ok(render_both!(
        base,
        opts,
        draw_sobol(output, params, indices)
    ))
}

fn draw_sobol<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    output: &str,
    params: &[&str],
    idx: &Indices,
) -> PResult
where
    DB::ErrorType: 'static,
{
    let body = framed(
        root,
        &format!("Sobol indices of {output}"),
        &format!(
            "share of its variance: alone (S1) and with interactions (ST); error bars {:.0} % \
             bootstrap, N = {}",
            100.0 * idx.conf_level,
            idx.base_rows
        ),
    )?;
    let (w, _) = body.dim_in_pixel();
    let (plot, side) = body.split_horizontally(w.saturating_sub(LEGEND_AREA));
    let d = params.len();
    // 0..1 at least, the scale of a variance share; wider where an interval reaches beyond.
    let ends = |s: &[f64], c: &[f64]| {
        s.iter()
            .zip(c)
            .flat_map(|(v, c)| [v - c, v + c])
            .collect::<Vec<_>>()
    };
    let all: Vec<f64> = [ends(&idx.s1, &idx.s1_conf), ends(&idx.st, &idx.st_conf)].concat();
    let lo = all
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::min);
    let hi = all
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(1.0, f64::max);
    let pad = 0.05 * (hi - lo);
    let y0 = if lo < 0.0 { lo - pad } else { 0.0 };
    let mut chart = ChartBuilder::on(&plot)
        .margin(12)
        .margin_right(20)
        .x_label_area_size(60)
        .y_label_area_size(90)
        .build_cartesian_2d(-0.5..(d as f64 - 0.5), y0..(hi + pad))?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(0)
        .x_desc("parameter")
        .y_desc("Sobol index [-]")
        .y_label_formatter(&|v| fmt_number(*v))
        .axis_desc_style(font(DESC_SIZE))
        .label_style(font(TICK_SIZE))
        .draw()?;
    chart.draw_series(LineSeries::new(
        [(-0.5, 0.0), (d as f64 - 0.5, 0.0)],
        BLACK.stroke_width(1),
    ))?;
    for (j, name) in params.iter().enumerate() {
        let c = j as f64;
        for (left, right, v, e, colour) in [
            (c - 0.36, c - 0.02, idx.s1[j], idx.s1_conf[j], S1_COLOUR),
            (c + 0.02, c + 0.36, idx.st[j], idx.st_conf[j], ST_COLOUR),
        ] {
            if !v.is_finite() {
                continue;
            }
            chart.draw_series(std::iter::once(Rectangle::new(
                [(left, 0.0), (right, v)],
                colour.filled(),
            )))?;
            if e > 0.0 && e.is_finite() {
                let (mid, cap) = ((left + right) / 2.0, (right - left) / 4.0);
                let bar = BLACK.stroke_width(2);
                for seg in [
                    [(mid, v - e), (mid, v + e)],
                    [(mid - cap, v - e), (mid + cap, v - e)],
                    [(mid - cap, v + e), (mid + cap, v + e)],
                ] {
                    chart.draw_series(LineSeries::new(seg, bar))?;
                }
            }
        }
        // Parameter names under their pair of bars, in the tick labels' place.
        let (px, py) = chart.backend_coord(&(c, y0));
        root.draw(&Text::new(
            name.to_string(),
            (px, py + 10),
            font(TICK_SIZE).pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
    }
    let bar = |colour: RGBColor| {
        move |a: &DrawingArea<DB, Shift>, p: (i32, i32)| -> PResult {
            Ok(a.draw(&Rectangle::new(
                [(p.0 - 14, p.1 - 9), (p.0 + 14, p.1 + 9)],
                colour.filled(),
            ))?)
        }
    };
    let (s1, st) = (bar(S1_COLOUR), bar(ST_COLOUR));
    legend(&side, &[("first order S1", &s1), ("total ST", &st)])
}
