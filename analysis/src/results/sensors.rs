//! The run's sensor table (`sensors.parquet` or `.csv`) and the runtime's sample sink: it streams
//! the samples in row groups, keeps them in memory for the analysis where asked, and hands the
//! states and the energy rows on to their recorders.

use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::energy::EnergyRecorder;
use super::states::StateRecorder;
use super::table::{Batched, Column, TableWriter, write_due};
use super::{Format, GROUP_ROWS, GROUP_WAIT, run_id_entry};

/// Unit of a sensor-file column, from its name (`time_s`, `drum_rpm`, `*_a?`, `*_u?`).
pub fn unit_of_column(name: &str) -> &'static str {
    let tail = name.rsplit('_').next().unwrap_or("");
    match (name, tail.chars().next()) {
        ("time_s", _) => "s",
        ("drum_rpm", _) => "rpm",
        (_, Some('a')) if tail.len() == 2 => "m/s^2",
        (_, Some('u')) if tail.len() == 2 => "m",
        _ => "",
    }
}

/// The run's sensor output: `sensors.parquet` (or `.csv`) streamed in row groups, and, for the
/// analysis, the same samples kept in memory as columns (no second pass through a file). When
/// kept, the row groups are written from the memory columns themselves (no second copy).
pub struct SensorRecorder {
    path: PathBuf,
    format: Format,
    table: Option<Batched>,
    /// time_s, drum_rpm, then the channels; empty unless kept.
    pub memory: Vec<Vec<f64>>,
    keep: bool,
    /// Rows of `memory` already written.
    written: usize,
    /// Write row groups as the run goes; without, all at `finish` ([`SensorRecorder::deferred`]).
    stream: bool,
    last_write: Instant,
    pub names: Vec<String>,
    /// The states, when the run keeps them.
    pub states: Option<StateRecorder>,
    /// The energy balance, when the run keeps it (`run --energy`).
    pub energy: Option<EnergyRecorder>,
    /// The run's id, written into the file's metadata (`RUN_ID_KEY`).
    pub run_id: Option<String>,
}

impl SensorRecorder {
    /// `keep`: hold the samples in memory for the analysis.
    pub fn new(dir: &Path, format: Format, keep: bool) -> SensorRecorder {
        SensorRecorder {
            path: dir.join(format!("sensors.{}", format.extension())),
            format,
            table: None,
            memory: Vec::new(),
            keep,
            written: 0,
            stream: true,
            last_write: Instant::now(),
            names: Vec::new(),
            states: None,
            energy: None,
            run_id: None,
        }
    }
    /// The samples kept in memory, written only at [`SensorRecorder::finish`], in row groups
    /// of a fixed size: the same samples give the same file, byte for byte (a study's dataset),
    /// where streaming cuts its row groups by wall time. A killed process leaves an empty file.
    pub fn deferred(dir: &Path, format: Format) -> SensorRecorder {
        SensorRecorder {
            stream: false,
            ..SensorRecorder::new(dir, format, true)
        }
    }
    pub fn path(&self) -> &Path {
        &self.path
    }
    /// Write the rows of `memory` not yet written, at most a row group's worth per group.
    fn write_kept(&mut self) -> io::Result<()> {
        let Some(t) = &mut self.table else {
            return Ok(());
        };
        let end = self.memory.first().map_or(0, Vec::len);
        while self.written < end {
            let (from, to) = (self.written, end.min(self.written + GROUP_ROWS));
            let cols: Vec<&[f64]> = self.memory.iter().map(|c| &c[from..to]).collect();
            t.writer.append_slices(&cols)?;
            self.written = to;
        }
        self.last_write = Instant::now();
        Ok(())
    }
    /// Write the footer (Parquet) and flush.
    pub fn finish(&mut self) -> io::Result<()> {
        if let Some(s) = self.states.as_mut() {
            s.finish()?;
        }
        if let Some(e) = self.energy.as_mut() {
            e.finish()?;
        }
        if self.keep {
            self.write_kept()?;
        }
        match &mut self.table {
            Some(t) => t.finish(),
            None => Ok(()),
        }
    }
}

impl washdyn_runtime::output::SampleSink for SensorRecorder {
    fn header(&mut self, channels: &[String]) -> io::Result<()> {
        let mut names = vec!["time_s".to_string(), "drum_rpm".to_string()];
        names.extend(channels.iter().cloned());
        let n = names.len();
        let mut metadata: Vec<(String, String)> = names
            .iter()
            .map(|c| (format!("unit:{c}"), unit_of_column(c).to_string()))
            .collect();
        metadata.push((
            "washdyn".into(),
            "sensor signals on a uniform time grid; accelerations m/s^2, displacements m, \
             global axes (x along the drum axis towards the door, z up)"
                .into(),
        ));
        metadata.extend(run_id_entry(&self.run_id));
        let w = TableWriter::create_f64(&self.path, self.format, &names, &metadata)?;
        // Kept samples are written from `memory`; the batch buffers stay empty then.
        let buffers = if self.keep { 0 } else { n };
        self.table = Some(
            Batched::new(w, vec![Column::F64(Vec::new()); buffers], GROUP_ROWS)
                .with_max_wait(GROUP_WAIT),
        );
        if self.keep {
            self.memory = vec![Vec::new(); n];
        }
        self.names = names;
        Ok(())
    }
    fn sample(&mut self, t: f64, rpm: f64, values: &[f64]) -> io::Result<()> {
        let row = [t, rpm].into_iter().chain(values.iter().copied());
        if self.keep {
            for (c, v) in self.memory.iter_mut().zip(row) {
                c.push(v);
            }
            let rows = self.memory[0].len() - self.written;
            if self.stream && write_due(rows, self.last_write, GROUP_ROWS, GROUP_WAIT) {
                self.write_kept()?;
            }
            return Ok(());
        }
        let table = self.table.as_mut().expect("header written first");
        for (c, v) in table.columns_mut().iter_mut().zip(row) {
            if let Column::F64(c) = c {
                c.push(v);
            }
        }
        table.row_done()
    }
    fn state(&mut self, t: f64, phi: f64, q: &[f64]) -> io::Result<()> {
        match &mut self.states {
            Some(s) => s.row(t, phi, q),
            None => Ok(()),
        }
    }
    fn wants_energy(&self) -> bool {
        self.energy.is_some()
    }
    fn energy_header(
        &mut self,
        categories: &[washdyn_model::equations::Category],
    ) -> io::Result<()> {
        if let Some(e) = self.energy.as_mut() {
            e.categories = categories.to_vec();
            e.cols = vec![Vec::new(); categories.len() + 4];
        }
        Ok(())
    }
    fn energy(&mut self, t: f64, rpm: f64, kinetic: f64, work: &[f64]) -> io::Result<()> {
        if let Some(e) = self.energy.as_mut() {
            e.row(t, rpm, kinetic, work);
        }
        Ok(())
    }
    fn flush(&mut self) -> io::Result<()> {
        if let Some(s) = self.states.as_mut() {
            s.send()?;
        }
        if self.keep {
            return if self.stream {
                self.write_kept()
            } else {
                Ok(())
            };
        }
        match &mut self.table {
            Some(t) => t.flush(),
            None => Ok(()),
        }
    }
}
