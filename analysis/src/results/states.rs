//! The states table (`states.parquet`, for `washdyn fields`): q at every sample, encoded and
//! written on a thread of its own so that keeping the states costs the run little.

use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::table::{TableWriter, write_due};
use super::{Format, GROUP_ROWS, GROUP_WAIT};

/// `states.parquet`: time_s, drum_angle_rad, then q (the scene's layout: tub rigid, tub
/// modes, drum modes, cabinet modes) at every sample, for recovery after the run. The run thread
/// only fills column buffers; a writer thread encodes and writes each full row group, so that
/// keeping the states costs the run little (Parquet encoding on the run thread took a third of
/// the `elastic` run-up's wall time).
pub struct StateRecorder {
    path: PathBuf,
    cols: Vec<Vec<f64>>,
    last_send: Instant,
    tx: Option<std::sync::mpsc::SyncSender<Vec<Vec<f64>>>>,
    writer: Option<std::thread::JoinHandle<io::Result<()>>>,
    /// The run's id, written into the file's metadata.
    pub run_id: Option<String>,
}

impl StateRecorder {
    pub fn new(dir: &Path) -> StateRecorder {
        StateRecorder {
            path: dir.join("states.parquet"),
            cols: Vec::new(),
            last_send: Instant::now(),
            tx: None,
            writer: None,
            run_id: None,
        }
    }

    fn start(&mut self, n_q: usize) -> io::Result<()> {
        let mut names = vec!["time_s".to_string(), "drum_angle_rad".to_string()];
        names.extend((0..n_q).map(|i| format!("q{i}")));
        let n = names.len();
        let mut metadata = vec![(
            "washdyn".to_string(),
            "states on the sample grid: q in the scene's layout (tub u m, alpha rad, then modal \
             coordinates)"
                .to_string(),
        )];
        metadata.extend(super::run_id_entry(&self.run_id));
        let mut w = TableWriter::create_f64(&self.path, Format::Parquet, &names, &metadata)?;
        // Two groups in flight at most: a slow disk holds the run back instead of the memory
        // growing without bound.
        let (tx, rx) = std::sync::mpsc::sync_channel::<Vec<Vec<f64>>>(2);
        self.writer = Some(std::thread::spawn(move || {
            for group in rx {
                let cols: Vec<&[f64]> = group.iter().map(Vec::as_slice).collect();
                w.append_slices(&cols)?;
            }
            w.finish()
        }));
        self.tx = Some(tx);
        self.cols = vec![Vec::with_capacity(GROUP_ROWS); n];
        Ok(())
    }

    /// Hand the buffered rows to the writer thread.
    pub(super) fn send(&mut self) -> io::Result<()> {
        if self.cols.first().is_none_or(Vec::is_empty) {
            return Ok(());
        }
        let group: Vec<Vec<f64>> = self
            .cols
            .iter_mut()
            .map(|c| std::mem::replace(c, Vec::with_capacity(GROUP_ROWS)))
            .collect();
        self.last_send = Instant::now();
        match &self.tx {
            Some(tx) if tx.send(group).is_ok() => Ok(()),
            // The writer stopped: its error comes out of `finish`.
            _ => self
                .finish()
                .and(Err(io::Error::other("the states writer stopped"))),
        }
    }

    pub(super) fn row(&mut self, t: f64, phi: f64, q: &[f64]) -> io::Result<()> {
        if self.tx.is_none() {
            self.start(q.len())?;
        }
        let row = [t, phi].into_iter().chain(q.iter().copied());
        for (c, v) in self.cols.iter_mut().zip(row) {
            c.push(v);
        }
        if write_due(self.cols[0].len(), self.last_send, GROUP_ROWS, GROUP_WAIT) {
            self.send()?;
        }
        Ok(())
    }

    /// Send what is buffered, close the file (Parquet footer) and wait for the writer.
    pub fn finish(&mut self) -> io::Result<()> {
        if self.tx.is_some() && self.cols.first().is_some_and(|c| !c.is_empty()) {
            let group = std::mem::take(&mut self.cols);
            if let Some(tx) = &self.tx {
                let _ = tx.send(group);
            }
        }
        self.tx = None;
        match self.writer.take() {
            Some(h) => h
                .join()
                .map_err(|_| io::Error::other("the states writer panicked"))?,
            None => Ok(()),
        }
    }
}
