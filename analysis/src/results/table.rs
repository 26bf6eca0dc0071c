//! The table writer: a schema (names, text or number, nullable, unit metadata), Parquet with
//! BYTE_STREAM_SPLIT floats or CSV, appended in row groups, and `Batched`, which buffers rows and
//! writes them when a group is full or a second has passed. Every result table goes through it.

use parquet::basic::{Compression, Encoding, LogicalType, Repetition, Type as Physical};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::Format;

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
    pub fn len(&self) -> usize {
        match self {
            Column::Text(v) => v.len(),
            Column::F64(v) => v.len(),
        }
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
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
pub(super) fn write_due(rows: usize, last: Instant, max_rows: usize, wait: Duration) -> bool {
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
