//! Where sampled sensor signals go: streamed CSV on disk (an interrupted run keeps what it
//! computed), or memory for tests and in-process analysis.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Receives uniformly sampled rows: time, drum rpm, then the sensor channels.
pub trait SampleSink {
    fn header(&mut self, channels: &[String]) -> io::Result<()>;
    fn sample(&mut self, t: f64, rpm: f64, values: &[f64]) -> io::Result<()>;
    fn flush(&mut self) -> io::Result<()>;
    /// The state at each sample (drum angle phi, rad, and q), for sinks that keep it for field
    /// recovery after the run; ignored by default.
    fn state(&mut self, _t: f64, _phi: f64, _q: &[f64]) -> io::Result<()> {
        Ok(())
    }
    /// Whether the sink keeps the energy balance (the run then integrates it).
    fn wants_energy(&self) -> bool {
        false
    }
    /// The balance's categories, before the first energy row.
    fn energy_header(
        &mut self,
        _categories: &[washdyn_model::equations::Category],
    ) -> io::Result<()> {
        Ok(())
    }
    /// One row of the balance: kinetic energy and each category's work since the start, J.
    fn energy(&mut self, _t: f64, _rpm: f64, _kinetic: f64, _work: &[f64]) -> io::Result<()> {
        Ok(())
    }
}

/// `sensors.csv`: columns `time_s`, `drum_rpm`, then one per channel.
pub struct CsvSink {
    w: BufWriter<File>,
    line: String,
}

impl CsvSink {
    pub fn create(path: &Path) -> io::Result<CsvSink> {
        Ok(CsvSink {
            w: BufWriter::with_capacity(1 << 20, File::create(path)?),
            line: String::with_capacity(4096),
        })
    }
}

impl SampleSink for CsvSink {
    fn header(&mut self, channels: &[String]) -> io::Result<()> {
        write!(self.w, "time_s,drum_rpm")?;
        for c in channels {
            write!(self.w, ",{c}")?;
        }
        writeln!(self.w)
    }
    fn sample(&mut self, t: f64, rpm: f64, values: &[f64]) -> io::Result<()> {
        use std::fmt::Write as _;
        self.line.clear();
        // 9 significant digits: far below any sensor's noise, and 3x smaller files than {:e}.
        let _ = write!(self.line, "{t:.6},{rpm:.4}");
        for v in values {
            let _ = write!(self.line, ",{v:.9e}");
        }
        self.line.push('\n');
        self.w.write_all(self.line.as_bytes())
    }
    fn flush(&mut self) -> io::Result<()> {
        self.w.flush()
    }
}

/// Keeps every sample in memory.
#[derive(Default, Debug, Clone)]
pub struct MemorySink {
    pub channels: Vec<String>,
    pub time: Vec<f64>,
    pub rpm: Vec<f64>,
    /// Row-major: one row of channel values per sample.
    pub values: Vec<f64>,
}

impl MemorySink {
    /// Column `c` as a vector.
    pub fn column(&self, c: usize) -> Vec<f64> {
        let n = self.channels.len();
        self.values.iter().skip(c).step_by(n).copied().collect()
    }
    pub fn column_by_name(&self, name: &str) -> Option<Vec<f64>> {
        self.channels
            .iter()
            .position(|c| c == name)
            .map(|c| self.column(c))
    }
}

impl SampleSink for MemorySink {
    fn header(&mut self, channels: &[String]) -> io::Result<()> {
        self.channels = channels.to_vec();
        Ok(())
    }
    fn sample(&mut self, t: f64, rpm: f64, values: &[f64]) -> io::Result<()> {
        self.time.push(t);
        self.rpm.push(rpm);
        self.values.extend_from_slice(values);
        Ok(())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}
