//! The two heat plots of one channel: the order plot (drum speed against drum order, from the
//! angle-domain order spectra) and the cascade (drum speed against frequency, from the time
//! spectra, up to where the content ends). What they show is built here; the heat layer draws it.

use std::path::Path;

use plotters::prelude::*;

use super::axis::{fmt_number, nice_ceil, rpm_range};
use super::heat::{HeatColumn, HeatPlot, Overlay, draw_heat_plot};
use super::{DynErr, init_fonts, write_png};
use crate::error::AnalysisError;
use crate::options::{AnalysisOptions, fmt_order};
use crate::orders::RunUp;

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

pub(super) fn heat_plot_order<'a>(run: &'a RunUp, opts: &AnalysisOptions) -> HeatPlot<'a> {
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
