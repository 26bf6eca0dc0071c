//! Sensor signals of a run-up and the readers for them (Parquet as `washdyn run` writes it, and
//! CSV through the `csv` crate, so quoted fields work).
//!
//! Format (written by the simulator, measured data looks the same): a header line
//! `time_s,drum_rpm,<channel>,...`, then one row per sample, uniformly sampled.
//! Lines starting with `#` and blank lines are skipped (so exported measurement files
//! with a comment preamble load as they are); line numbers in errors count every
//! physical line of the file, starting at 1.

use std::io::BufRead;
use std::path::{Path, PathBuf};

use super::error::AnalysisError;

/// Relative tolerance of each time step against the median step. A dropped sample
/// is a 100 % deviation; printing time with 6 significant digits at 2 kHz stays far below 1 %.
pub const TIME_STEP_TOLERANCE: f64 = 0.01;

/// Fewest samples [`read_signals`] accepts: enough to define a sample rate and see a trend.
pub const MIN_SAMPLES: usize = 8;

/// Physical quantity of a channel, derived from its name (`_a` + axis: acceleration,
/// `_u` + axis: displacement). It decides units on plots and the dB reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// m/s^2
    Acceleration,
    /// m
    Displacement,
    /// Unknown channel name: unit unknown, treated as a generic signal.
    Unknown,
}

impl Quantity {
    /// Classify a channel by the suffix of its name: `tub1_ax` is an acceleration,
    /// `drum_front_uz` a displacement, anything else unknown.
    pub fn from_channel_name(name: &str) -> Quantity {
        let suffix = match name.rsplit_once('_') {
            Some((_, s)) => s.to_ascii_lowercase(),
            None => return Quantity::Unknown,
        };
        let b = suffix.as_bytes();
        if b.len() != 2 || !matches!(b[1], b'x' | b'y' | b'z') {
            return Quantity::Unknown;
        }
        match b[0] {
            b'a' => Quantity::Acceleration,
            b'u' => Quantity::Displacement,
            _ => Quantity::Unknown,
        }
    }

    /// SI unit of the stored values (empty if unknown).
    pub fn si_unit(self) -> &'static str {
        match self {
            Quantity::Acceleration => "m/s²",
            Quantity::Displacement => "m",
            Quantity::Unknown => "",
        }
    }

    /// Unit shown on plots: displacements of a washing machine are millimetres, so
    /// plots show mm rather than ticks like 0.0012 m.
    pub fn display_unit(self) -> &'static str {
        match self {
            Quantity::Acceleration => "m/s²",
            Quantity::Displacement => "mm",
            Quantity::Unknown => "channel unit",
        }
    }

    /// Factor from SI value to the display unit.
    pub fn display_factor(self) -> f64 {
        match self {
            Quantity::Displacement => 1e3,
            _ => 1.0,
        }
    }

    /// dB reference value in SI units (ISO 1683: 1 µm/s², 1 pm), 1 for unknown units.
    pub fn db_reference(self) -> f64 {
        match self {
            Quantity::Acceleration => 1e-6,
            Quantity::Displacement => 1e-12,
            Quantity::Unknown => 1.0,
        }
    }

    /// Human-readable dB reference for axis labels.
    pub fn db_reference_label(self) -> &'static str {
        match self {
            Quantity::Acceleration => "dB re 1 µm/s²",
            Quantity::Displacement => "dB re 1 pm",
            Quantity::Unknown => "dB re 1 unit",
        }
    }

    /// Short noun for titles.
    pub fn noun(self) -> &'static str {
        match self {
            Quantity::Acceleration => "acceleration",
            Quantity::Displacement => "displacement",
            Quantity::Unknown => "signal",
        }
    }
}

/// One sensor channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// Column name from the header, e.g. `tub1_ax`.
    pub name: String,
    /// Quantity derived from the name.
    pub quantity: Quantity,
    /// Samples in SI units, same length as [`Signals::time`].
    pub data: Vec<f64>,
}

impl Channel {
    /// Channel with its quantity derived from the name.
    pub fn new(name: impl Into<String>, data: Vec<f64>) -> Channel {
        let name = name.into();
        Channel {
            quantity: Quantity::from_channel_name(&name),
            name,
            data,
        }
    }
}

/// Uniformly sampled signals of one run: time, drum speed and sensor channels.
#[derive(Debug, Clone, PartialEq)]
pub struct Signals {
    /// Sample times in s, strictly increasing and uniform.
    pub time: Vec<f64>,
    /// Drum speed in rpm at each sample.
    pub drum_rpm: Vec<f64>,
    /// Sensor channels.
    pub channels: Vec<Channel>,
    /// Sample rate in Hz (1 / mean time step).
    pub sample_rate: f64,
}

impl Signals {
    /// Signals for in-memory use (the simulator): time is generated as `t0 + i / sample_rate`.
    pub fn from_uniform(
        t0: f64,
        sample_rate: f64,
        drum_rpm: Vec<f64>,
        channels: Vec<Channel>,
    ) -> Result<Signals, AnalysisError> {
        if !(sample_rate.is_finite() && sample_rate > 0.0) {
            return Err(AnalysisError::InvalidSignals(format!(
                "sample rate must be positive, got {sample_rate}"
            )));
        }
        let time = (0..drum_rpm.len())
            .map(|i| t0 + i as f64 / sample_rate)
            .collect();
        let s = Signals {
            time,
            drum_rpm,
            channels,
            sample_rate,
        };
        s.validate()?;
        Ok(s)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True if there are no samples.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Keep the samples up to `t_end` (within half a sample), e.g. the common span of a run
    /// that stopped early and one that went on. False, and the signals left as they were, where
    /// `t_end` is not inside their span: not after the first sample, or past the last.
    pub fn truncate(&mut self, t_end: f64) -> bool {
        let half = 0.5 / self.sample_rate;
        let (Some(&first), Some(&last)) = (self.time.first(), self.time.last()) else {
            return false;
        };
        if !(t_end.is_finite() && t_end > first && t_end <= last + half) {
            return false;
        }
        let n = self.time.partition_point(|t| *t <= t_end + half);
        self.time.truncate(n);
        self.drum_rpm.truncate(n);
        for c in &mut self.channels {
            c.data.truncate(n);
        }
        true
    }

    /// Look up a channel by name.
    pub fn channel(&self, name: &str) -> Option<&Channel> {
        self.channels.iter().find(|c| c.name == name)
    }

    /// Consistency check for signals built in memory (the CSV reader checks per line).
    pub fn validate(&self) -> Result<(), AnalysisError> {
        let n = self.time.len();
        let bad = |m: String| Err(AnalysisError::InvalidSignals(m));
        if n < 2 {
            return Err(AnalysisError::TooFewSamples {
                context: "signals".into(),
                found: n,
                needed: 2,
            });
        }
        if self.drum_rpm.len() != n {
            return bad(format!(
                "drum_rpm has {} samples, time has {n}",
                self.drum_rpm.len()
            ));
        }
        if !(self.sample_rate.is_finite() && self.sample_rate > 0.0) {
            return bad(format!("sample rate {} is not positive", self.sample_rate));
        }
        if let Some(i) = self.drum_rpm.iter().position(|v| !v.is_finite()) {
            return bad(format!("drum_rpm sample {i} is not finite"));
        }
        let mut names = std::collections::HashSet::new();
        for c in &self.channels {
            if c.data.len() != n {
                return bad(format!(
                    "channel `{}` has {} samples, time has {n}",
                    c.name,
                    c.data.len()
                ));
            }
            if let Some(i) = c.data.iter().position(|v| !v.is_finite()) {
                return bad(format!("channel `{}` sample {i} is not finite", c.name));
            }
            if !names.insert(c.name.as_str()) {
                return bad(format!("duplicate channel name `{}`", c.name));
            }
        }
        Ok(())
    }
}

/// Read a run-up file: Parquet (`.parquet`, as `washdyn run` writes it) or CSV (see the module
/// docs for the format).
pub fn read_signals(path: impl AsRef<Path>) -> Result<Signals, AnalysisError> {
    let path = path.as_ref();
    if crate::results::Format::of_path(path) == crate::results::Format::Parquet {
        return read_parquet(path);
    }
    let file = std::fs::File::open(path).map_err(|source| AnalysisError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_signals(std::io::BufReader::new(file), path)
}

/// A Parquet signal file: float64 columns `time_s`, `drum_rpm`, then channels. Errors name
/// the row (1-based) instead of a line.
fn read_parquet(path: &Path) -> Result<Signals, AnalysisError> {
    let (names, mut cols) =
        crate::results::read_parquet_f64(path).map_err(|message| AnalysisError::Header {
            path: path.to_path_buf(),
            line: 0,
            message,
        })?;
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let names = parse_header(&refs, 0, path)?;
    let n = cols.first().map_or(0, Vec::len);
    for (c, name) in cols.iter().zip(&names) {
        if let Some(i) = c.iter().position(|v| !v.is_finite()) {
            return Err(AnalysisError::NotANumber {
                path: path.to_path_buf(),
                line: i + 1,
                column: name.clone(),
                value: c[i].to_string(),
            });
        }
    }
    let data = cols.split_off(2);
    let rpm = cols.pop().unwrap_or_default();
    let time = cols.pop().unwrap_or_default();
    finish(path, names, time, rpm, data, (1..=n).collect())
}

/// Parse run-up CSV text from any reader; `path` only names the source in errors.
pub fn parse_signals(reader: impl BufRead, path: &Path) -> Result<Signals, AnalysisError> {
    let p = || path.to_path_buf();
    let mut header: Option<Vec<String>> = None;
    let mut time: Vec<f64> = Vec::new();
    let mut rpm: Vec<f64> = Vec::new();
    let mut data: Vec<Vec<f64>> = Vec::new();
    // Line number of each sample, to point at the offending row in the uniformity check.
    let mut sample_lines: Vec<usize> = Vec::new();
    let lines = std::rc::Rc::new(std::cell::RefCell::new(Vec::new()));
    let mut csv = csv::ReaderBuilder::new()
        .has_headers(false)
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(LineIndex {
            inner: reader,
            offset: 0,
            blank: true,
            lines: lines.clone(),
        });
    // The csv crate's line counter skips blank lines; count physical lines from byte offsets.
    let line_of = |byte: u64| line_of(&lines.borrow(), byte);
    let mut record = csv::StringRecord::new();
    loop {
        match csv.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => {
                let line = e.position().map_or(0, |p| line_of(p.byte()));
                return Err(match e.into_kind() {
                    csv::ErrorKind::Io(source) => AnalysisError::Io { path: p(), source },
                    k => AnalysisError::Header {
                        path: p(),
                        line,
                        message: format!("{k:?}"),
                    },
                });
            }
        }
        let line_no = record.position().map_or(0, |p| line_of(p.byte()));
        // Comment lines (`#`, so a preamble of an exported file loads as it is) and blank lines.
        if record.iter().all(str::is_empty) || record.get(0).is_some_and(|f| f.starts_with('#')) {
            continue;
        }
        // A quote after blanks is not a CSV quote; take it off too (`a, "b"`).
        let fields: Vec<&str> = record.iter().map(unquote).collect();
        let Some(names) = &header else {
            let names = parse_header(&fields, line_no, path)?;
            data = vec![Vec::new(); names.len() - 2];
            header = Some(names);
            continue;
        };
        if fields.len() != names.len() {
            return Err(AnalysisError::RaggedRow {
                path: p(),
                line: line_no,
                expected: names.len(),
                found: fields.len(),
            });
        }
        let mut values = fields.iter().zip(names).map(|(cell, name)| {
            let v = cell.parse::<f64>().ok().filter(|v| v.is_finite());
            v.ok_or_else(|| AnalysisError::NotANumber {
                path: p(),
                line: line_no,
                column: name.clone(),
                value: (*cell).to_string(),
            })
        });
        let t = values.next().expect("header has >= 2 columns")?;
        if let Some(&prev) = time.last().filter(|&&prev| t <= prev) {
            return Err(AnalysisError::TimeNotIncreasing {
                path: p(),
                line: line_no,
                time: t,
                previous: prev,
            });
        }
        let r = values.next().expect("header has >= 2 columns")?;
        for (col, v) in data.iter_mut().zip(values) {
            col.push(v?);
        }
        time.push(t);
        rpm.push(r);
        sample_lines.push(line_no);
    }

    let Some(names) = header else {
        return Err(AnalysisError::EmptyFile { path: p() });
    };
    finish(path, names, time, rpm, data, sample_lines)
}

/// Checks shared by both formats (enough samples, uniform time), then the signals.
fn finish(
    path: &Path,
    names: Vec<String>,
    time: Vec<f64>,
    rpm: Vec<f64>,
    data: Vec<Vec<f64>>,
    sample_lines: Vec<usize>,
) -> Result<Signals, AnalysisError> {
    let p = || path.to_path_buf();
    let n = time.len();
    if n < MIN_SAMPLES {
        return Err(AnalysisError::TooFewSamples {
            context: path.display().to_string(),
            found: n,
            needed: MIN_SAMPLES,
        });
    }
    if let Some(i) = (1..n).find(|&i| time[i] <= time[i - 1]) {
        return Err(AnalysisError::TimeNotIncreasing {
            path: p(),
            line: sample_lines[i],
            time: time[i],
            previous: time[i - 1],
        });
    }
    // Judge steps against the median step: one dropped sample shifts the mean of a
    // short file enough to flag a good step, the median not.
    let mut steps: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let typical = steps[steps.len() / 2];
    for i in 1..n {
        let step = time[i] - time[i - 1];
        if (step - typical).abs() > TIME_STEP_TOLERANCE * typical {
            return Err(AnalysisError::TimeNotUniform {
                path: p(),
                line: sample_lines[i],
                step,
                typical_step: typical,
                tolerance_percent: TIME_STEP_TOLERANCE * 100.0,
            });
        }
    }
    let mean_step = (time[n - 1] - time[0]) / (n - 1) as f64;
    let channels = names
        .into_iter()
        .skip(2)
        .zip(data)
        .map(|(name, d)| Channel::new(name, d))
        .collect();
    Ok(Signals {
        time,
        drum_rpm: rpm,
        channels,
        sample_rate: 1.0 / mean_step,
    })
}

/// A reader that notes, for every line it passes on, the byte offset of its newline and whether
/// it was blank.
struct LineIndex<R> {
    inner: R,
    offset: u64,
    blank: bool,
    lines: std::rc::Rc<std::cell::RefCell<Vec<(u64, bool)>>>,
}

impl<R: std::io::Read> std::io::Read for LineIndex<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let mut lines = self.lines.borrow_mut();
        for (i, b) in buf[..n].iter().enumerate() {
            match b {
                b'\n' => {
                    lines.push((self.offset + i as u64, self.blank));
                    self.blank = true;
                }
                b' ' | b'\t' | b'\r' => {}
                _ => self.blank = false,
            }
        }
        self.offset += n as u64;
        Ok(n)
    }
}

/// 1-based line of the first non-blank line at or after byte `byte` (a csv record's position
/// can be the start of blank lines before it).
fn line_of(lines: &[(u64, bool)], byte: u64) -> usize {
    let mut i = lines.partition_point(|&(end, _)| end < byte);
    while i < lines.len() && lines[i].1 {
        i += 1;
    }
    i + 1
}

fn unquote(s: &str) -> &str {
    s.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(s)
}

fn parse_header(fields: &[&str], line: usize, path: &Path) -> Result<Vec<String>, AnalysisError> {
    let err = |message: String| AnalysisError::Header {
        path: PathBuf::from(path),
        line,
        message,
    };
    let names: Vec<String> = fields.iter().map(|f| f.to_string()).collect();
    let expect = |i: usize, want: &str, what: &str| -> Result<(), AnalysisError> {
        match names.get(i) {
            Some(n) if n.eq_ignore_ascii_case(want) => Ok(()),
            Some(n) if n.parse::<f64>().is_ok() => Err(err(format!(
                "found a number (`{n}`) where the header should be; the first line must name the \
                 columns: `time_s,drum_rpm,<channels>`"
            ))),
            Some(n) => Err(err(format!(
                "column {} must be `{want}` ({what}), found `{n}`",
                i + 1
            ))),
            None => Err(err(format!(
                "missing column {} `{want}` ({what}); header must start with `time_s,drum_rpm`",
                i + 1
            ))),
        }
    };
    expect(0, "time_s", "time in s")?;
    expect(1, "drum_rpm", "drum speed in rpm")?;
    let mut seen = std::collections::HashSet::new();
    for (i, n) in names.iter().enumerate().skip(2) {
        if n.is_empty() {
            return Err(err(format!("column {} has an empty name", i + 1)));
        }
        if !seen.insert(n.as_str()) {
            return Err(err(format!("duplicate column name `{n}`")));
        }
    }
    Ok(names)
}
