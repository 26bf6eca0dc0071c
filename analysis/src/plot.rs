//! Plots of a run-up with plotters, each as PNG and SVG: order plot, cascade,
//! speed plot (order tracks and raw signal over speed) and a displacement overview.
//!
//! Text uses the pure-Rust ab_glyph route with DejaVu Sans compiled in, so no
//! system font lookup happens; [`init_fonts`] registers it (idempotent).
//! Heat maps are rendered as one bitmap of exactly the plot area's pixels (the
//! SVG embeds it as a PNG), so an SVG holds one image instead of ~10^5 rectangles.

use std::error::Error;
use std::ops::Range;
use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::element::BitMapElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, FontTransform, register_font};

use super::error::AnalysisError;
use super::options::{AnalysisOptions, ColourScale, fmt_order};
use super::orders::{Block, OrderTrack, RunUp};
use super::signals::{Channel, Quantity, Signals};

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Register the bundled font with plotters once per process. Every plotting entry
/// point calls it; call it yourself before using plotters elsewhere (e.g. benches),
/// because with the `ab_glyph` feature plotters has no other font source.
pub fn init_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if register_font(FAMILY, FontStyle::Normal, FONT).is_err() {
            panic!("bundled font assets/DejaVuSans.ttf is not a valid font");
        }
    });
}

type DynErr = Box<dyn Error + Send + Sync>;
type PResult<T = ()> = Result<T, DynErr>;

const TITLE_SIZE: u32 = 28;
const SUBTITLE_SIZE: u32 = 17;
const DESC_SIZE: u32 = 22;
const TICK_SIZE: u32 = 18;
const NOTE_SIZE: u32 = 17;
/// Width reserved right of a heat map for the colour bar, its ticks and caption.
const COLOUR_BAR_AREA: u32 = 200;
/// Colour of plot regions without data (above Nyquist, speed gaps).
const NO_DATA: RGBColor = RGBColor(225, 225, 225);

fn font(size: u32) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

/// Perceptually ordered colour map (dark violet - blue - green - yellow), readable
/// in greyscale prints and for colour-blind readers, unlike a rainbow.
pub fn colour_map(t: f64) -> RGBColor {
    const ANCHORS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (ANCHORS.len() - 1) as f64;
    let i = (x.floor() as usize).min(ANCHORS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
    let mix = |p: u8, q: u8| (p as f64 + f * (q as f64 - p as f64)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Amplitude axis resolved against the data: maps SI amplitudes to the axis unit
/// (display unit or dB) and to a colour fraction, and provides ticks and caption.
#[derive(Debug, Clone, PartialEq)]
pub struct AmplitudeAxis {
    /// Scale kind.
    pub scale: ColourScale,
    /// Channel quantity (unit, dB reference).
    pub quantity: Quantity,
    /// Lower end in axis units (display unit, or dB).
    pub lo: f64,
    /// Upper end in axis units.
    pub hi: f64,
}

impl AmplitudeAxis {
    /// Axis covering amplitudes up to `max_si` (SI units).
    pub fn new(scale: ColourScale, quantity: Quantity, max_si: f64) -> AmplitudeAxis {
        // Displacements read in mm: the dB scale's range becomes a log axis in mm.
        let scale = match (scale, quantity) {
            (ColourScale::Decibel { range_db }, Quantity::Displacement) => {
                ColourScale::Log { range_db }
            }
            _ => scale,
        };
        let f = quantity.display_factor();
        let max = if max_si.is_finite() && max_si > 0.0 {
            max_si
        } else {
            1.0 / f
        };
        let (lo, hi) = match scale {
            ColourScale::Linear => (0.0, nice_ceil(max * f)),
            ColourScale::Log { range_db } => {
                let hi = max * f;
                (hi * 10f64.powf(-range_db / 20.0), hi)
            }
            ColourScale::Decibel { range_db } => {
                let hi = (20.0 * (max / quantity.db_reference()).log10() / 5.0).ceil() * 5.0;
                (hi - range_db, hi)
            }
        };
        AmplitudeAxis {
            scale,
            quantity,
            lo,
            hi,
        }
    }

    /// Value on the axis (display unit or dB) of an SI amplitude.
    pub fn axis_value(&self, v_si: f64) -> f64 {
        match self.scale {
            ColourScale::Linear | ColourScale::Log { .. } => v_si * self.quantity.display_factor(),
            ColourScale::Decibel { .. } => {
                20.0 * (v_si.max(1e-300) / self.quantity.db_reference()).log10()
            }
        }
    }

    /// Position of an SI amplitude along the axis, 0 (low) to 1 (high), clamped.
    pub fn fraction(&self, v_si: f64) -> f64 {
        let t = match self.scale {
            ColourScale::Log { .. } => {
                let v = self.axis_value(v_si);
                if v <= 0.0 {
                    0.0
                } else {
                    (v / self.lo).log10() / (self.hi / self.lo).log10()
                }
            }
            _ => (self.axis_value(v_si) - self.lo) / (self.hi - self.lo),
        };
        if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// Position of an axis value (not SI) along the axis.
    fn fraction_of_axis_value(&self, v: f64) -> f64 {
        match self.scale {
            ColourScale::Log { .. } => (v / self.lo).log10() / (self.hi / self.lo).log10(),
            _ => (v - self.lo) / (self.hi - self.lo),
        }
    }

    /// Tick positions (fraction) and labels.
    pub fn ticks(&self) -> Vec<(f64, String)> {
        let values: Vec<f64> = match self.scale {
            ColourScale::Linear => nice_ticks(self.lo, self.hi, 6),
            ColourScale::Decibel { range_db } => {
                let step = if range_db > 40.0 {
                    10.0
                } else if range_db > 15.0 {
                    5.0
                } else {
                    1.0
                };
                let first = (self.lo / step).ceil() as i64;
                let last = (self.hi / step).floor() as i64;
                (first..=last).map(|i| i as f64 * step).collect()
            }
            ColourScale::Log { .. } => {
                let decades = (self.hi / self.lo).log10();
                let mantissas: &[f64] = if decades < 2.5 {
                    &[1.0, 2.0, 5.0]
                } else {
                    &[1.0]
                };
                let (e0, e1) = (
                    self.lo.log10().floor() as i32,
                    self.hi.log10().ceil() as i32,
                );
                (e0..=e1)
                    .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
                    .filter(|v| *v >= self.lo * (1.0 - 1e-9) && *v <= self.hi * (1.0 + 1e-9))
                    .collect()
            }
        };
        values
            .into_iter()
            .map(|v| (self.fraction_of_axis_value(v), fmt_number(v)))
            .collect()
    }

    /// Axis caption with unit and convention (peak amplitude).
    pub fn caption(&self) -> String {
        let unit = self.quantity.display_unit();
        match self.scale {
            ColourScale::Linear => format!("amplitude (peak) [{unit}]"),
            ColourScale::Log { .. } => format!("amplitude (peak) [{unit}], log scale"),
            ColourScale::Decibel { .. } => {
                format!("level (peak) [{}]", self.quantity.db_reference_label())
            }
        }
    }
}

/// Smallest 1-2-2.5-5 number times a power of ten not below `v`.
fn nice_ceil(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(v.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * p >= v * (1.0 - 1e-12) {
            return m * p;
        }
    }
    10.0 * p
}

/// About `n` round tick values in `[lo, hi]`.
fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = nice_ceil((hi - lo) / n.max(1) as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// Short number for tick labels: plain decimals where readable, else scientific.
fn fmt_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.1e}");
        s.replace(".0e", "e")
    }
}

/// Speed axis range over the given blocks, padded to round 50 rpm.
fn rpm_range<'a>(rpms: impl Iterator<Item = f64> + 'a) -> Range<f64> {
    let (lo, hi) = rpms.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
        (l.min(r), h.max(r))
    });
    if !lo.is_finite() {
        return 0.0..100.0;
    }
    let (mut lo, mut hi) = ((lo / 50.0).floor() * 50.0, (hi / 50.0).ceil() * 50.0);
    if hi - lo < 50.0 {
        lo -= 50.0;
        hi += 50.0;
    }
    lo.max(0.0)..hi
}

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
struct HeatColumn<'a> {
    rpm: f64,
    amp: &'a [f64],
    bins_per_unit: f64,
}

/// Reference lines drawn over a heat map.
enum Overlay {
    /// Horizontal lines at these orders (order plot).
    Orders(Vec<(f64, String)>),
    /// Rays `f = order * rpm / 60` (cascade).
    Rays(Vec<(f64, String)>),
}

/// Everything a heat-map plot needs apart from the backend.
struct HeatPlot<'a> {
    title: String,
    subtitle: String,
    /// Sorted by speed.
    columns: Vec<HeatColumn<'a>>,
    x_range: Range<f64>,
    y_range: Range<f64>,
    y_desc: String,
    scale: ColourScale,
    quantity: Quantity,
    overlay: Overlay,
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

/// A white plot with its title and grey subtitle: the area below them.
fn framed<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
) -> PResult<DrawingArea<DB, Shift>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    Ok(root
        .titled(title, font(TITLE_SIZE))?
        .titled(subtitle, font(SUBTITLE_SIZE).color(&RGBColor(70, 70, 70)))?)
}

fn draw_heat_plot<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, p: &HeatPlot) -> PResult
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
fn draw_heat_pair<DB: DrawingBackend>(
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

/// Second title line: how the spectra were made.
fn method_note(run: &RunUp, opts: &AnalysisOptions, spectrum: &str) -> String {
    format!(
        "Hann, {:.3} s blocks (Δf = {:.3} Hz), {:.0} % overlap, {spectrum}; grey: no data",
        run.layout.len as f64 / run.layout.sample_rate,
        run.layout.df(),
        opts.overlap * 100.0,
    )
}

fn motor_labels(opts: &AnalysisOptions) -> Vec<(f64, String)> {
    opts.motor_drum_orders()
        .into_iter()
        .map(|(n, o)| (o, format!("motor order {n} (drum order {})", fmt_order(o))))
        .collect()
}

fn heat_plot_order<'a>(run: &'a RunUp, opts: &AnalysisOptions) -> HeatPlot<'a> {
    // Order spectra in the angle domain: every order on its bin at every speed (no smear, and
    // no scalloping beads along a ridge as it crosses the bins of a time spectrum).
    let mut columns: Vec<HeatColumn> = run
        .order_blocks()
        .zip(&run.order_spectra)
        .filter_map(|(b, s)| {
            s.as_ref().map(|s| HeatColumn {
                rpm: b.rpm,
                amp: s,
                bins_per_unit: run.order_bins_per_order,
            })
        })
        .collect();
    columns.sort_by(|a, b| a.rpm.total_cmp(&b.rpm));
    HeatPlot {
        title: format!(
            "{}: order plot ({}, motor/drum ratio {})",
            run.channel,
            run.quantity.noun(),
            fmt_order(opts.motor_ratio)
        ),
        subtitle: format!(
            "angle domain: Hann over {} revolutions ({} samples/rev), amplitude-corrected peak \
             spectrum; grey: no data",
            opts.order_block_revs, opts.samples_per_rev
        ),
        x_range: rpm_range(columns.iter().map(|c| c.rpm)),
        columns,
        y_range: 0.0..opts.max_order,
        y_desc: "drum order [-]".into(),
        scale: opts.colour_scale,
        quantity: run.quantity,
        overlay: Overlay::Orders(motor_labels(opts)),
    }
}

/// Upper frequency of a cascade: where the content ends. The frequency below which 99.9 % of
/// the spectral energy of all blocks lies, with 20 % headroom, rounded up to a nice number,
/// between 10 Hz and `limit`.
fn content_frequency(run: &RunUp, limit: f64) -> f64 {
    let Some(first) = run.blocks.first() else {
        return limit;
    };
    let n = first.spectrum.amplitude.len();
    let mut energy = vec![0.0; n];
    for b in &run.blocks {
        for (e, a) in energy.iter_mut().zip(&b.spectrum.amplitude).skip(1) {
            *e += a * a;
        }
    }
    let total: f64 = energy.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return limit;
    }
    let mut acc = 0.0;
    let k = energy
        .iter()
        .position(|e| {
            acc += e;
            acc >= 0.999 * total
        })
        .unwrap_or(n - 1);
    nice_ceil(1.2 * first.spectrum.frequency(k)).clamp(10.0, limit)
}

fn heat_plot_cascade<'a>(run: &'a RunUp, opts: &AnalysisOptions) -> HeatPlot<'a> {
    let mut columns: Vec<HeatColumn> = run
        .blocks
        .iter()
        .map(|b| HeatColumn {
            rpm: b.rpm,
            amp: &b.spectrum.amplitude,
            bins_per_unit: 1.0 / b.spectrum.df,
        })
        .collect();
    columns.sort_by(|a, b| a.rpm.total_cmp(&b.rpm));
    let nyquist = run.layout.sample_rate / 2.0;
    let limit = opts.max_frequency_hz.unwrap_or(nyquist).min(nyquist);
    let fmax = content_frequency(run, limit);
    // Only motor orders: a labelled drum-order-1 ray would sit among the low drum
    // harmonics, where a label cannot be told apart from its neighbours.
    let rays = motor_labels(opts);
    HeatPlot {
        title: format!("{}: cascade ({})", run.channel, run.quantity.noun()),
        subtitle: format!(
            "{}; 0-{} Hz holds 99.9 % of the energy",
            method_note(run, opts, "amplitude-corrected peak spectrum"),
            fmt_number(fmax)
        ),
        x_range: rpm_range(columns.iter().map(|c| c.rpm)),
        columns,
        y_range: 0.0..fmax,
        y_desc: "frequency [Hz]".into(),
        scale: opts.colour_scale,
        quantity: run.quantity,
        overlay: Overlay::Rays(rays),
    }
}

/// Line colours for order tracks: distinct and print-safe.
const TRACK_COLOURS: [RGBColor; 8] = [
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
type TrackLines = (String, Vec<Vec<(f64, f64)>>);

/// Width right of line plots for the legend, outside the data.
const LEGEND_AREA: u32 = 270;

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
fn draw_legend<DB: DrawingBackend>(
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

/// Order tracks as polylines over speed on `axis`: runs of consecutive values, with gaps where
/// a track is not resolved or below the axis.
fn track_lines<'a>(
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
fn draw_track_chart<DB: DrawingBackend>(
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
fn draw_raw_panel<DB: DrawingBackend>(
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

/// Encode an RGB buffer as PNG with the fast deflate level: 2-3x quicker than the default
/// level for plots, for files about a third larger.
fn write_png(path: &Path, size: (u32, u32), rgb: &[u8]) -> Result<(), AnalysisError> {
    let err = |e: String| AnalysisError::Plot {
        path: path.to_path_buf(),
        message: e,
    };
    let file = std::fs::File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), size.0, size.1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut w = enc.write_header().map_err(|e| err(e.to_string()))?;
    w.write_image_data(rgb).map_err(|e| err(e.to_string()))
}

/// Render `<base>.png`, and `<base>.svg` where `opts.svg`. Returns the paths.
macro_rules! render_both {
    ($base:expr, $opts:expr, $draw:ident ( $($arg:expr),* )) => {{
        let size = $opts.plot_size;
        let png = $base.with_extension("png");
        let svg = $base.with_extension("svg");
        {
            let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
                $draw(&root, $($arg),*)
                    .and_then(|_| root.present().map_err(DynErr::from))
                    .map_err(|e| AnalysisError::Plot { path: png.clone(), message: e.to_string() })?;
            }
            write_png(&png, size, &buf)?;
        }
        if $opts.svg {
            {
                let root = SVGBackend::new(&svg, size).into_drawing_area();
                $draw(&root, $($arg),*)
                    .and_then(|_| root.present().map_err(DynErr::from))
                    .map_err(|e| AnalysisError::Plot { path: svg.clone(), message: e.to_string() })?;
            }
            vec![png, svg]
        } else {
            vec![png]
        }
    }};
}

/// Order plot: drum speed vs order, colour = amplitude, motor orders marked.
/// Writes `<base>.png` and `<base>.svg` (`base` without extension).
pub fn order_plot(
    run: &RunUp,
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    let p = heat_plot_order(run, opts);
    Ok(render_both!(base, opts, draw_heat_plot(&p)))
}

/// Two runs' order plots of one channel side by side: `runs[0]` left, `runs[1]` right, each
/// titled with its label, on one colour scale and the same axes (the same drawing as
/// [`order_plot`], panel by panel). Writes `<base>.png` (and `.svg` where `opts.svg`), twice
/// as wide as a single order plot less one colour bar.
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

/// Cascade: drum speed vs frequency, colour = amplitude, order rays marked.
pub fn cascade_plot(
    run: &RunUp,
    opts: &AnalysisOptions,
    base: &Path,
) -> Result<Vec<std::path::PathBuf>, AnalysisError> {
    init_fonts();
    let p = heat_plot_cascade(run, opts);
    Ok(render_both!(base, opts, draw_heat_plot(&p)))
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_numbers() {
        assert_eq!(nice_ceil(0.73), 1.0);
        assert_eq!(nice_ceil(1.3), 2.0);
        assert_eq!(nice_ceil(2.2), 2.5);
        assert_eq!(nice_ceil(37.0), 50.0);
        assert_eq!(fmt_number(0.05), "0.05");
        assert_eq!(fmt_number(120.0), "120");
        assert_eq!(fmt_number(1e-5), "1e-5");
        let ticks: Vec<String> = nice_ticks(0.0, 1.0, 5)
            .into_iter()
            .map(fmt_number)
            .collect();
        assert_eq!(ticks, ["0", "0.2", "0.4", "0.6", "0.8", "1"]);
    }

    #[test]
    fn decibel_axis_rounds_up_to_5_db() {
        let a = AmplitudeAxis::new(
            ColourScale::Decibel { range_db: 60.0 },
            Quantity::Acceleration,
            1.0,
        );
        assert_eq!((a.lo, a.hi), (60.0, 120.0));
        assert!((a.fraction(1.0) - 1.0).abs() < 1e-12);
        assert!((a.fraction(1e-3) - 0.0).abs() < 1e-12);
        assert_eq!(a.ticks().len(), 7);
    }

    #[test]
    fn colour_map_ends() {
        assert_eq!(colour_map(0.0), RGBColor(68, 1, 84));
        assert_eq!(colour_map(1.0), RGBColor(253, 231, 37));
        assert_eq!(colour_map(f64::NAN), RGBColor(68, 1, 84));
    }
}
