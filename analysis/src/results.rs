//! Result files: sensor signals and analysis tables as Parquet (default) or CSV.
//!
//! Parquet is the columnar format that pandas, polars, DuckDB, Spark and MATLAB (`parquetread`)
//! read with no custom code. A 178 s run-up at 2 kHz is 357k rows of 44 float64 columns: as
//! text 127 MB; here every float column uses BYTE_STREAM_SPLIT (bytes of equal significance
//! together) with snappy, and no dictionaries (floats rarely repeat). Only the low-level column
//! API of the `parquet` crate is used (no arrow stack, pure-Rust codec), so it adds little to
//! the cold build.
//!
//! Tables are written in row groups as the run goes (one at least every second of wall time),
//! so a long run's file grows on disk; the footer that makes a Parquet file readable is written
//! when the run ends, fails or is interrupted with Ctrl-C. A process killed outright leaves a
//! file without footer: use `--format csv` where that matters (CSV rows are flushed every second).

use parquet::basic::{Compression, Encoding, LogicalType, Repetition, Type as Physical};
use parquet::column::reader::ColumnReader;
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// File format of results.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Format {
    #[default]
    Parquet,
    Csv,
}

impl Format {
    pub fn extension(self) -> &'static str {
        match self {
            Format::Parquet => "parquet",
            Format::Csv => "csv",
        }
    }
    /// By extension; anything but `.parquet` is read as CSV.
    pub fn of_path(path: &Path) -> Format {
        if path.extension().is_some_and(|e| e == "parquet") {
            Format::Parquet
        } else {
            Format::Csv
        }
    }
}

impl std::str::FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "parquet" => Ok(Format::Parquet),
            "csv" => Ok(Format::Csv),
            _ => Err(format!("unknown format `{s}` (parquet, csv)")),
        }
    }
}

/// A column of a table.
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    /// Text (UTF-8), e.g. a channel name.
    Text(Vec<String>),
    /// Numbers; `NaN` is written as null in Parquet and as an empty field in CSV (a value that
    /// does not exist, such as an unresolved order).
    F64(Vec<f64>),
}

impl Column {
    fn len(&self) -> usize {
        match self {
            Column::Text(v) => v.len(),
            Column::F64(v) => v.len(),
        }
    }
    fn clear(&mut self) {
        match self {
            Column::Text(v) => v.clear(),
            Column::F64(v) => v.clear(),
        }
    }
}

/// A column borrowed for writing.
#[derive(Clone, Copy)]
enum ColRef<'a> {
    Text(&'a [String]),
    F64(&'a [f64]),
}

impl ColRef<'_> {
    fn len(&self) -> usize {
        match self {
            ColRef::Text(v) => v.len(),
            ColRef::F64(v) => v.len(),
        }
    }
}

/// A streaming table writer: columns of equal length appended in chunks.
pub struct TableWriter {
    inner: Inner,
    path: PathBuf,
}

enum Inner {
    Parquet {
        w: Option<SerializedFileWriter<BufWriter<File>>>,
        nullable: Vec<bool>,
    },
    Csv {
        w: BufWriter<File>,
        line: String,
    },
}

/// Schema of a table: column names, whether text, whether nullable (floats), and key-value
/// metadata (units).
pub struct Schema<'a> {
    pub names: &'a [String],
    pub text: &'a [bool],
    pub nullable: &'a [bool],
    pub metadata: &'a [(String, String)],
}

impl TableWriter {
    /// A table of non-null f64 columns (sensors, states, energy).
    pub fn create_f64(
        path: &Path,
        format: Format,
        names: &[String],
        metadata: &[(String, String)],
    ) -> io::Result<TableWriter> {
        let n = names.len();
        let schema = Schema {
            names,
            text: &vec![false; n],
            nullable: &vec![false; n],
            metadata,
        };
        TableWriter::create(path, format, &schema)
    }

    pub fn create(path: &Path, format: Format, schema: &Schema) -> io::Result<TableWriter> {
        let file = BufWriter::with_capacity(1 << 16, File::create(path)?);
        let inner = match format {
            Format::Parquet => {
                let fields = schema
                    .names
                    .iter()
                    .zip(schema.text)
                    .zip(schema.nullable)
                    .map(|((n, &text), &nullable)| {
                        let rep = if nullable {
                            Repetition::OPTIONAL
                        } else {
                            Repetition::REQUIRED
                        };
                        let t = if text {
                            Type::primitive_type_builder(n, Physical::BYTE_ARRAY)
                                .with_logical_type(Some(LogicalType::String))
                        } else {
                            Type::primitive_type_builder(n, Physical::DOUBLE)
                        };
                        t.with_repetition(rep).build().map(Arc::new)
                    })
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(io::Error::other)?;
                let root = Type::group_type_builder("washdyn")
                    .with_fields(fields)
                    .build()
                    .map_err(io::Error::other)?;
                let kv = schema
                    .metadata
                    .iter()
                    .map(|(k, v)| KeyValue::new(k.clone(), v.clone()))
                    .collect();
                let mut props = WriterProperties::builder()
                    .set_compression(Compression::SNAPPY)
                    .set_dictionary_enabled(false)
                    .set_key_value_metadata(Some(kv));
                for (n, &text) in schema.names.iter().zip(schema.text) {
                    let path = parquet::schema::types::ColumnPath::from(n.as_str());
                    props = if text {
                        props.set_column_dictionary_enabled(path, true)
                    } else {
                        props.set_column_encoding(path, Encoding::BYTE_STREAM_SPLIT)
                    };
                }
                let w = SerializedFileWriter::new(file, Arc::new(root), Arc::new(props.build()))
                    .map_err(io::Error::other)?;
                Inner::Parquet {
                    w: Some(w),
                    nullable: schema.nullable.to_vec(),
                }
            }
            Format::Csv => {
                let mut w = file;
                let header: Vec<String> = schema.names.iter().map(|n| csv_field(n)).collect();
                writeln!(w, "{}", header.join(","))?;
                Inner::Csv {
                    w,
                    line: String::new(),
                }
            }
        };
        Ok(TableWriter {
            inner,
            path: path.to_path_buf(),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Append rows given as columns of equal length (a Parquet row group). The CSV file is
    /// flushed too, so what was appended is on disk.
    pub fn append(&mut self, columns: &[Column]) -> io::Result<()> {
        let refs: Vec<ColRef> = columns
            .iter()
            .map(|c| match c {
                Column::Text(v) => ColRef::Text(v),
                Column::F64(v) => ColRef::F64(v),
            })
            .collect();
        self.append_refs(&refs)
    }

    /// [`TableWriter::append`] for number columns held elsewhere (no copy).
    pub fn append_slices(&mut self, columns: &[&[f64]]) -> io::Result<()> {
        let refs: Vec<ColRef> = columns.iter().map(|c| ColRef::F64(c)).collect();
        self.append_refs(&refs)
    }

    fn append_refs(&mut self, columns: &[ColRef]) -> io::Result<()> {
        let rows = columns.first().map_or(0, ColRef::len);
        if rows == 0 {
            return Ok(());
        }
        debug_assert!(columns.iter().all(|c| c.len() == rows));
        match &mut self.inner {
            Inner::Parquet { w, nullable } => {
                let w = w.as_mut().ok_or_else(|| io::Error::other("table closed"))?;
                let mut rg = w.next_row_group().map_err(io::Error::other)?;
                let mut i = 0;
                while let Some(mut col) = rg.next_column().map_err(io::Error::other)? {
                    match columns[i] {
                        ColRef::F64(v) if nullable[i] => {
                            let def: Vec<i16> = v.iter().map(|x| i16::from(!x.is_nan())).collect();
                            let vals: Vec<f64> =
                                v.iter().copied().filter(|x| !x.is_nan()).collect();
                            col.typed::<DoubleType>()
                                .write_batch(&vals, Some(&def), None)
                                .map_err(io::Error::other)?;
                        }
                        ColRef::F64(v) => {
                            col.typed::<DoubleType>()
                                .write_batch(v, None, None)
                                .map_err(io::Error::other)?;
                        }
                        ColRef::Text(v) => {
                            let vals: Vec<ByteArray> =
                                v.iter().map(|s| ByteArray::from(s.as_str())).collect();
                            col.typed::<ByteArrayType>()
                                .write_batch(&vals, None, None)
                                .map_err(io::Error::other)?;
                        }
                    }
                    col.close().map_err(io::Error::other)?;
                    i += 1;
                }
                rg.close().map_err(io::Error::other)?;
                w.flush()
            }
            Inner::Csv { w, line } => {
                use std::fmt::Write as _;
                for r in 0..rows {
                    line.clear();
                    for (k, c) in columns.iter().enumerate() {
                        if k > 0 {
                            line.push(',');
                        }
                        match c {
                            ColRef::Text(v) => line.push_str(&csv_field(&v[r])),
                            // Shortest representation that reads back to the same f64.
                            ColRef::F64(v) if !v[r].is_nan() => {
                                let _ = write!(line, "{:?}", v[r]);
                            }
                            ColRef::F64(_) => {}
                        }
                    }
                    line.push('\n');
                    w.write_all(line.as_bytes())?;
                }
                w.flush()
            }
        }
    }

    /// Write the footer (Parquet) and flush. Idempotent.
    pub fn finish(&mut self) -> io::Result<()> {
        match &mut self.inner {
            Inner::Parquet { w, .. } => match w.take() {
                Some(w) => w.close().map(|_| ()).map_err(io::Error::other),
                None => Ok(()),
            },
            Inner::Csv { w, .. } => w.flush(),
        }
    }
}

impl Drop for TableWriter {
    fn drop(&mut self) {
        let _ = self.finish();
    }
}

/// A CSV field, quoted where it must be.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Whether `rows` buffered rows are due on disk: a full row group, or `wait` passed since the
/// last write (the clock is read every 256 rows only).
fn write_due(rows: usize, last: Instant, max_rows: usize, wait: Duration) -> bool {
    rows >= max_rows || (rows.is_multiple_of(256) && last.elapsed() >= wait)
}

/// Buffers rows into row groups: written when `max_rows` are held or `max_wait` has passed since
/// the last write, so a slow run's file grows at least every `max_wait`.
pub struct Batched {
    pub writer: TableWriter,
    cols: Vec<Column>,
    max_rows: usize,
    max_wait: Duration,
    last: Instant,
}

impl Batched {
    pub fn new(writer: TableWriter, cols: Vec<Column>, max_rows: usize) -> Batched {
        Batched {
            writer,
            cols,
            max_rows,
            max_wait: Duration::from_secs(1),
            last: Instant::now(),
        }
    }
    /// Write at least this often (default 1 s of wall time).
    pub fn with_max_wait(mut self, wait: Duration) -> Batched {
        self.max_wait = wait;
        self
    }
    pub fn columns_mut(&mut self) -> &mut [Column] {
        &mut self.cols
    }
    /// Call after each row.
    pub fn row_done(&mut self) -> io::Result<()> {
        let rows = self.cols.first().map_or(0, Column::len);
        if write_due(rows, self.last, self.max_rows, self.max_wait) {
            self.flush()?;
        }
        Ok(())
    }
    pub fn flush(&mut self) -> io::Result<()> {
        self.writer.append(&self.cols)?;
        self.cols.iter_mut().for_each(Column::clear);
        self.last = Instant::now();
        Ok(())
    }
    pub fn finish(&mut self) -> io::Result<()> {
        self.flush()?;
        self.writer.finish()
    }
}

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

/// All columns of a Parquet file as f64 (text columns are an error), with their names.
pub fn read_parquet_f64(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
    let file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let reader = SerializedFileReader::new(file)
        .map_err(|e| format!("{}: not a Parquet file: {e}", path.display()))?;
    let schema = reader.metadata().file_metadata().schema_descr_ptr();
    let names: Vec<String> = schema
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for g in 0..reader.num_row_groups() {
        let rg = reader
            .get_row_group(g)
            .map_err(|e| format!("{}: row group {g}: {e}", path.display()))?;
        let rows = rg.metadata().num_rows() as usize;
        for (i, col) in cols.iter_mut().enumerate() {
            let ColumnReader::DoubleColumnReader(mut r) = rg
                .get_column_reader(i)
                .map_err(|e| format!("{}: column `{}`: {e}", path.display(), names[i]))?
            else {
                return Err(format!(
                    "{}: column `{}` is not float64",
                    path.display(),
                    names[i]
                ));
            };
            let mut vals = Vec::with_capacity(rows);
            let mut def = Vec::with_capacity(rows);
            let optional = schema.column(i).max_def_level() > 0;
            let (recs, _, _) = r
                .read_records(rows, optional.then_some(&mut def), None, &mut vals)
                .map_err(|e| format!("{}: column `{}`: {e}", path.display(), names[i]))?;
            if optional {
                // Nulls become NaN.
                let mut it = vals.into_iter();
                col.extend(def.iter().map(|&d| {
                    if d > 0 {
                        it.next().unwrap_or(f64::NAN)
                    } else {
                        f64::NAN
                    }
                }));
            } else {
                col.extend(vals);
            }
            if recs != rows {
                return Err(format!(
                    "{}: column `{}` has {recs} of {rows} rows in row group {g}",
                    path.display(),
                    names[i]
                ));
            }
        }
    }
    Ok((names, cols))
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
    last_write: Instant,
    pub names: Vec<String>,
    /// The states, when the run keeps them.
    pub states: Option<StateRecorder>,
    /// The energy balance, when the run keeps it (`run --energy`).
    pub energy: Option<EnergyRecorder>,
}

/// `energy.parquet` (or .csv): the balance by category every `ENERGY_ROW_S` of simulated
/// time: time_s, drum_rpm, kinetic_J, then each category's work since the start (J; drive and
/// gravity as done on the vibration, a stored or dissipated category's work is minus its
/// stored energy or the energy it took), and the residual T - T0 - sum W. A few thousand rows
/// a run-up: kept in memory, written at the end (also when the run fails).
pub struct EnergyRecorder {
    path: PathBuf,
    format: Format,
    pub categories: Vec<washdyn_runtime::equations::Category>,
    /// time_s, drum_rpm, kinetic_J, the categories' work, residual_J.
    pub cols: Vec<Vec<f64>>,
}

impl EnergyRecorder {
    pub fn new(dir: &Path, format: Format) -> EnergyRecorder {
        EnergyRecorder {
            path: dir.join(format!("energy.{}", format.extension())),
            format,
            categories: Vec::new(),
            cols: Vec::new(),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The lines the energy plot shows, from the rows: the drive's work, the kinetic energy,
    /// the energy stored (springs and bearings with the gasket's stiffness; modal strain;
    /// gravity), dissipated by each dissipative element and by modal damping (each as a
    /// positive amount since the start), and the residual T - T0 - sum W.
    pub fn lines(&self) -> (Vec<f64>, Vec<crate::plot::EnergyLine>) {
        use crate::plot::EnergyLine;
        use washdyn_runtime::equations::Kind;
        let t = self.cols.first().cloned().unwrap_or_default();
        let rows = t.len();
        let col = |i: usize| &self.cols[3 + i];
        let sum = |pick: &dyn Fn(&washdyn_runtime::equations::Category) -> bool, sign: f64| {
            let mut v = vec![0.0; rows];
            for (i, c) in self.categories.iter().enumerate() {
                if pick(c) {
                    for (x, w) in v.iter_mut().zip(col(i)) {
                        *x += sign * w;
                    }
                }
            }
            v
        };
        let k0 = self
            .cols
            .get(2)
            .and_then(|c| c.first())
            .copied()
            .unwrap_or(0.0);
        let mut lines = vec![
            EnergyLine {
                name: "drive work".into(),
                values: sum(&|c| c.kind == Kind::Drive, 1.0),
            },
            EnergyLine {
                name: "kinetic (T - T0)".into(),
                values: self.cols[2].iter().map(|k| k - k0).collect(),
            },
            EnergyLine {
                name: "stored: elements".into(),
                values: sum(
                    &|c| c.kind == Kind::Stored && !c.name.ends_with("strain"),
                    -1.0,
                ),
            },
            EnergyLine {
                name: "stored: modal strain".into(),
                values: sum(&|c| c.name.ends_with("modal strain"), -1.0),
            },
            EnergyLine {
                name: "gravity (potential)".into(),
                values: sum(&|c| c.kind == Kind::Gravity, -1.0),
            },
            EnergyLine {
                name: "dissipated: modal damping".into(),
                values: sum(&|c| c.name.ends_with("modal damping"), -1.0),
            },
        ];
        for (i, c) in self.categories.iter().enumerate() {
            if c.kind == Kind::Dissipated && !c.name.ends_with("modal damping") {
                lines.push(EnergyLine {
                    name: c.name.clone(),
                    values: col(i).iter().map(|w| -w).collect(),
                });
            }
        }
        lines.push(EnergyLine {
            name: "residual".into(),
            values: self.cols.last().cloned().unwrap_or_default(),
        });
        // Lines that stay zero (a rigid scene's modal strain) say nothing.
        lines.retain(|l| l.values.iter().any(|v| *v != 0.0));
        (t, lines)
    }

    /// Column names: time_s, drum_rpm, kinetic_J, `<category>_J` (spaces as underscores),
    /// residual_J.
    pub fn names(&self) -> Vec<String> {
        let mut names = vec!["time_s".into(), "drum_rpm".into(), "kinetic_J".into()];
        names.extend(
            self.categories
                .iter()
                .map(|c| format!("{}_J", c.name.replace(' ', "_"))),
        );
        names.push("residual_J".into());
        names
    }

    fn row(&mut self, t: f64, rpm: f64, kinetic: f64, work: &[f64]) {
        let k0 = self
            .cols
            .get(2)
            .and_then(|c| c.first())
            .copied()
            .unwrap_or(kinetic);
        let residual = kinetic - k0 - work.iter().sum::<f64>();
        let row = [t, rpm, kinetic]
            .into_iter()
            .chain(work.iter().copied())
            .chain([residual]);
        for (c, v) in self.cols.iter_mut().zip(row) {
            c.push(v);
        }
    }

    fn finish(&mut self) -> io::Result<()> {
        if self.cols.is_empty() {
            return Ok(());
        }
        let names = self.names();
        let mut metadata: Vec<(String, String)> = names
            .iter()
            .map(|c| {
                let unit = match c.as_str() {
                    "time_s" => "s",
                    "drum_rpm" => "rpm",
                    _ => "J",
                };
                (format!("unit:{c}"), unit.to_string())
            })
            .collect();
        for c in &self.categories {
            metadata.push((
                format!("kind:{}_J", c.name.replace(' ', "_")),
                serde_json::to_string(&c.kind).expect("serialises"),
            ));
        }
        metadata.push((
            "washdyn".into(),
            "energy balance by category (model/src/equations/energy.rs): kinetic energy of the \
             vibration and each category's work since the start; residual = T - T0 - sum of the \
             work"
                .into(),
        ));
        let mut w = TableWriter::create_f64(&self.path, self.format, &names, &metadata)?;
        let cols: Vec<&[f64]> = self.cols.iter().map(Vec::as_slice).collect();
        w.append_slices(&cols)?;
        w.finish()
    }
}

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
}

impl StateRecorder {
    pub fn new(dir: &Path) -> StateRecorder {
        StateRecorder {
            path: dir.join("states.parquet"),
            cols: Vec::new(),
            last_send: Instant::now(),
            tx: None,
            writer: None,
        }
    }

    fn start(&mut self, n_q: usize) -> io::Result<()> {
        let mut names = vec!["time_s".to_string(), "drum_angle_rad".to_string()];
        names.extend((0..n_q).map(|i| format!("q{i}")));
        let n = names.len();
        let mut w = TableWriter::create_f64(
            &self.path,
            Format::Parquet,
            &names,
            &[(
                "washdyn".into(),
                "states on the sample grid: q in the scene's layout (tub u m, alpha rad, \
                 then modal coordinates)"
                    .into(),
            )],
        )?;
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
    fn send(&mut self) -> io::Result<()> {
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

    fn row(&mut self, t: f64, phi: f64, q: &[f64]) -> io::Result<()> {
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

/// Rows a row group holds at most, and the longest wait between writes.
const GROUP_ROWS: usize = 1 << 16;
const GROUP_WAIT: Duration = Duration::from_secs(1);

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
            last_write: Instant::now(),
            names: Vec::new(),
            states: None,
            energy: None,
        }
    }
    pub fn path(&self) -> &Path {
        &self.path
    }
    /// Write the rows of `memory` not yet written.
    fn write_kept(&mut self) -> io::Result<()> {
        let Some(t) = &mut self.table else {
            return Ok(());
        };
        let from = self.written;
        let cols: Vec<&[f64]> = self.memory.iter().map(|c| &c[from..]).collect();
        t.writer.append_slices(&cols)?;
        self.written = self.memory.first().map_or(0, Vec::len);
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
            if write_due(rows, self.last_write, GROUP_ROWS, GROUP_WAIT) {
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
        categories: &[washdyn_runtime::equations::Category],
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
            return self.write_kept();
        }
        match &mut self.table {
            Some(t) => t.flush(),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slow run's file must grow as it goes (issue 7: CSV stayed at 0 bytes for minutes
    /// behind a 1 MiB buffer): rows reach the disk once the wait has passed, both formats.
    #[test]
    fn rows_reach_the_disk_while_the_run_goes() {
        let dir = tempfile::tempdir().unwrap();
        for format in [Format::Csv, Format::Parquet] {
            let path = dir.path().join(format!("s.{}", format.extension()));
            let names = vec!["time_s".to_string(), "a_ax".to_string()];
            let schema = Schema {
                names: &names,
                text: &[false, false],
                nullable: &[false, false],
                metadata: &[],
            };
            let w = TableWriter::create(&path, format, &schema).unwrap();
            let empty = std::fs::metadata(&path).unwrap().len();
            let mut b = Batched::new(w, vec![Column::F64(Vec::new()); 2], 1 << 20)
                .with_max_wait(Duration::ZERO);
            for i in 0..256 {
                for c in b.columns_mut() {
                    if let Column::F64(v) = c {
                        v.push(i as f64);
                    }
                }
                b.row_done().unwrap();
            }
            let grown = std::fs::metadata(&path).unwrap().len();
            assert!(grown > empty + 500, "{format:?}: {empty} -> {grown} bytes");
            b.finish().unwrap();
        }
    }
}
