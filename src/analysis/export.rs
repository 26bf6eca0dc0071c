//! Spectra and order tracks as CSV.
//!
//! `<channel>_spectra.csv` is in long format, one row per block and bin, because
//! the order of a bin differs from block to block (it is `f / (rpm/60)`): a wide
//! table would need interpolation onto a common order grid. A spreadsheet loads it
//! as it is and a pivot table (rows `drum_rpm`, columns `order` or `frequency_hz`)
//! gives the map. Columns:
//!
//! `block,time_s,drum_rpm,order,frequency_hz,amplitude,amplitude_energy`
//!
//! * `time_s`: block centre; `drum_rpm`: mean drum speed of the block;
//! * `order`: drum order of the bin (empty below the minimum speed);
//! * `amplitude`: amplitude-corrected peak amplitude (read peaks of sines here);
//! * `amplitude_energy`: energy-corrected peak amplitude (sum `amplitude_energy²/2`
//!   over a band for its mean square);
//! * amplitudes in the channel's SI unit (m/s², m; as in the input).
//!
//! Bins run from 0 Hz to the cascade's upper frequency (default Nyquist).
//!
//! `<channel>_orders.csv` is wide: one row per block, one column per tracked order
//! (`order_1`, `order_11.25`, ...), the energy-based order amplitudes of the speed plot.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::error::AnalysisError;
use super::options::fmt_order;
use super::orders::RunUp;

fn create(path: &Path) -> Result<BufWriter<std::fs::File>, AnalysisError> {
    std::fs::File::create(path)
        .map(BufWriter::new)
        .map_err(|source| AnalysisError::Write {
            path: path.to_path_buf(),
            source,
        })
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> AnalysisError + '_ {
    move |source| AnalysisError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Write the long-format spectra CSV of one channel, bins up to `max_frequency_hz`.
pub fn write_spectra_csv(
    run: &RunUp,
    max_frequency_hz: f64,
    path: &Path,
) -> Result<(), AnalysisError> {
    let mut w = create(path)?;
    let e = io_err(path);
    writeln!(
        w,
        "block,time_s,drum_rpm,order,frequency_hz,amplitude,amplitude_energy"
    )
    .map_err(&e)?;
    for (i, b) in run.blocks.iter().enumerate() {
        let with_order = b.rpm >= run.min_rpm;
        for k in 0..b.spectrum.amplitude.len() {
            let f = b.spectrum.frequency(k);
            if f > max_frequency_hz + 1e-9 {
                break;
            }
            let order = if with_order {
                format!("{:.5}", b.order_of_bin(k))
            } else {
                String::new()
            };
            writeln!(
                w,
                "{i},{:.4},{:.3},{order},{f:.4},{:.6e},{:.6e}",
                b.time_s, b.rpm, b.spectrum.amplitude[k], b.spectrum.energy[k]
            )
            .map_err(&e)?;
        }
    }
    w.flush().map_err(&e)
}

/// Write the wide order-track CSV of one channel.
pub fn write_orders_csv(run: &RunUp, path: &Path) -> Result<(), AnalysisError> {
    let mut w = create(path)?;
    let e = io_err(path);
    let mut header = String::from("block,time_s,drum_rpm");
    for t in &run.tracks {
        header.push_str(&format!(",order_{}", fmt_order(t.order)));
    }
    writeln!(w, "{header}").map_err(&e)?;
    for (i, b) in run.blocks.iter().enumerate() {
        write!(w, "{i},{:.4},{:.3}", b.time_s, b.rpm).map_err(&e)?;
        for t in &run.tracks {
            match t.amplitude[i] {
                Some(a) => write!(w, ",{a:.6e}"),
                None => write!(w, ","),
            }
            .map_err(&e)?;
        }
        writeln!(w).map_err(&e)?;
    }
    w.flush().map_err(&e)
}
