//! Spectra and order tracks of all channels, one table each (`spectra.parquet`,
//! `orders.parquet`, or `.csv`), in long format: one row per channel, block and bin (or order),
//! because the order of a bin differs from block to block (`f / (rpm/60)`); a pivot (rows
//! `drum_rpm`, columns `order` or `frequency_hz`) gives the map.
//!
//! `spectra`: `channel, time_s, drum_rpm, frequency_hz, order, amplitude, amplitude_energy`
//! * `time_s`: block centre (s); `drum_rpm`: mean drum speed of the block;
//! * `order`: drum order of the bin (null below the minimum speed);
//! * `amplitude`: amplitude-corrected peak amplitude (read peaks of sines here);
//! * `amplitude_energy`: energy-corrected peak amplitude (sum `amplitude_energy^2 / 2` over a
//!   band for its mean square);
//! * amplitudes in the channel's SI unit (m/s^2 for `*_a?`, m for `*_u?`).
//!
//! `orders`: `channel, order, time_s, drum_rpm, amplitude`: the order tracks (peak amplitude,
//! SI unit); null where the order is not resolved in that block.

use std::path::{Path, PathBuf};

use super::error::AnalysisError;
use super::orders::RunUp;
use crate::results::{Column, Format, Schema, TableWriter};

fn table(
    path: &Path,
    format: Format,
    names: &[&str],
    text: &[bool],
    nullable: &[bool],
    what: &str,
) -> Result<TableWriter, AnalysisError> {
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let metadata = vec![(
        "washdyn".to_string(),
        format!(
            "{what}; amplitudes in SI units of the channel (m/s^2 for *_a?, m for *_u?), time in s, speed in rpm"
        ),
    )];
    TableWriter::create(
        path,
        format,
        &Schema {
            names: &names,
            text,
            nullable,
            metadata: &metadata,
        },
    )
    .map_err(|source| AnalysisError::Write {
        path: path.to_path_buf(),
        source,
    })
}

fn write_err(path: &Path) -> impl Fn(std::io::Error) -> AnalysisError + '_ {
    move |source| AnalysisError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// One channel's rows (one row group): the channel name, then the number columns.
fn append_channel(
    w: &mut TableWriter,
    path: &Path,
    channel: &str,
    cols: Vec<Vec<f64>>,
) -> Result<(), AnalysisError> {
    let n = cols.first().map_or(0, Vec::len);
    let mut all = vec![Column::Text(vec![channel.to_string(); n])];
    all.extend(cols.into_iter().map(Column::F64));
    w.append(&all).map_err(write_err(path))
}

/// Write the spectra of all channels, bins up to `max_frequency_hz`; one row group per channel.
pub fn write_spectra(
    runs: &[RunUp],
    max_frequency_hz: f64,
    dir: &Path,
    format: Format,
) -> Result<PathBuf, AnalysisError> {
    let path = dir.join(format!("spectra.{}", format.extension()));
    let mut w = table(
        &path,
        format,
        &[
            "channel",
            "time_s",
            "drum_rpm",
            "frequency_hz",
            "order",
            "amplitude",
            "amplitude_energy",
        ],
        &[true, false, false, false, false, false, false],
        &[false, false, false, false, true, false, false],
        "block spectra (Hann window) of every channel",
    )?;
    for run in runs {
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 6];
        for b in &run.blocks {
            let with_order = b.rpm >= run.min_rpm;
            for k in 0..b.spectrum.amplitude.len() {
                let f = b.spectrum.frequency(k);
                if f > max_frequency_hz + 1e-9 {
                    break;
                }
                cols[0].push(b.time_s);
                cols[1].push(b.rpm);
                cols[2].push(f);
                cols[3].push(if with_order {
                    b.order_of_bin(k)
                } else {
                    f64::NAN
                });
                cols[4].push(b.spectrum.amplitude[k]);
                cols[5].push(b.spectrum.energy[k]);
            }
        }
        append_channel(&mut w, &path, &run.channel, cols)?;
    }
    w.finish().map_err(write_err(&path))?;
    Ok(path)
}

/// Write the order tracks of all channels.
pub fn write_orders(runs: &[RunUp], dir: &Path, format: Format) -> Result<PathBuf, AnalysisError> {
    let path = dir.join(format!("orders.{}", format.extension()));
    let mut w = table(
        &path,
        format,
        &["channel", "order", "time_s", "drum_rpm", "amplitude"],
        &[true, false, false, false, false],
        &[false, false, false, false, true],
        "order tracks of every channel (peak amplitude; null where unresolved)",
    )?;
    for run in runs {
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 4];
        for t in &run.tracks {
            for (b, a) in run.blocks.iter().zip(&t.amplitude) {
                cols[0].push(t.order);
                cols[1].push(b.time_s);
                cols[2].push(b.rpm);
                cols[3].push(a.unwrap_or(f64::NAN));
            }
        }
        append_channel(&mut w, &path, &run.channel, cols)?;
    }
    w.finish().map_err(write_err(&path))?;
    Ok(path)
}
