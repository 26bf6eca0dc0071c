//! Reading a Parquet table back as f64 columns (nulls as NaN): what `analyse`, `fields` and the
//! tests read the run's files with; and any table the writer wrote, text columns too, with its
//! schema and metadata (a study's summaries, collected into one table). Separate from the
//! writer: it shares no code with it.

use super::table::Column;
use parquet::column::reader::ColumnReader;
use parquet::data_type::ByteArray;
use parquet::file::reader::{FileReader, SerializedFileReader};
use std::fs::File;
use std::path::Path;

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

/// A table as the writer takes it: names, columns, which number columns are nullable, and the
/// key-value metadata (units).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub columns: Vec<Column>,
    pub nullable: Vec<bool>,
    pub metadata: Vec<(String, String)>,
}

impl Table {
    /// Rows (0 without columns).
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Column::len)
    }
    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| &self.columns[i])
    }
}

/// A Parquet file's key-value metadata, from its footer alone (the data is not read).
pub fn read_metadata(path: &Path) -> Result<Vec<(String, String)>, String> {
    let at = |m: String| format!("{}: {m}", path.display());
    let file = File::open(path).map_err(|e| at(e.to_string()))?;
    let reader =
        SerializedFileReader::new(file).map_err(|e| at(format!("not a Parquet file: {e}")))?;
    Ok(key_values(reader.metadata().file_metadata()))
}

fn key_values(meta: &parquet::file::metadata::FileMetaData) -> Vec<(String, String)> {
    meta.key_value_metadata()
        .map(|kv| {
            kv.iter()
                .map(|k| (k.key.clone(), k.value.clone().unwrap_or_default()))
                .collect()
        })
        .unwrap_or_default()
}

/// A Parquet table of text (UTF-8) and float64 columns, as [`super::TableWriter`] writes them;
/// nulls of a number column read as NaN. Other column types are an error naming the column.
pub fn read_table(path: &Path) -> Result<Table, String> {
    let at = |m: String| format!("{}: {m}", path.display());
    let file = File::open(path).map_err(|e| at(e.to_string()))?;
    let reader =
        SerializedFileReader::new(file).map_err(|e| at(format!("not a Parquet file: {e}")))?;
    let meta = reader.metadata().file_metadata();
    let schema = meta.schema_descr_ptr();
    let names: Vec<String> = schema
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let nullable: Vec<bool> = (0..names.len())
        .map(|i| schema.column(i).max_def_level() > 0)
        .collect();
    let metadata = key_values(meta);
    let mut columns = Vec::with_capacity(names.len());
    for (i, name) in names.iter().enumerate() {
        columns.push(match schema.column(i).physical_type() {
            parquet::basic::Type::DOUBLE => Column::F64(Vec::new()),
            parquet::basic::Type::BYTE_ARRAY if !nullable[i] => Column::Text(Vec::new()),
            t => {
                return Err(at(format!(
                    "column `{name}` is {t:?}{}, neither float64 nor required text",
                    if nullable[i] { " (nullable)" } else { "" }
                )));
            }
        });
    }
    for g in 0..reader.num_row_groups() {
        let rg = reader
            .get_row_group(g)
            .map_err(|e| at(format!("row group {g}: {e}")))?;
        let rows = rg.metadata().num_rows() as usize;
        for (i, col) in columns.iter_mut().enumerate() {
            let name = &names[i];
            let bad = |m: String| at(format!("column `{name}`: {m}"));
            let reader = rg.get_column_reader(i).map_err(|e| bad(e.to_string()))?;
            let recs = match (reader, col) {
                (ColumnReader::DoubleColumnReader(mut r), Column::F64(out)) => {
                    let mut vals = Vec::with_capacity(rows);
                    let mut def = Vec::with_capacity(rows);
                    let (recs, _, _) = r
                        .read_records(rows, nullable[i].then_some(&mut def), None, &mut vals)
                        .map_err(|e| bad(e.to_string()))?;
                    if nullable[i] {
                        // Nulls become NaN.
                        let mut it = vals.into_iter();
                        out.extend(def.iter().map(|&d| {
                            if d > 0 {
                                it.next().unwrap_or(f64::NAN)
                            } else {
                                f64::NAN
                            }
                        }));
                    } else {
                        out.extend(vals);
                    }
                    recs
                }
                (ColumnReader::ByteArrayColumnReader(mut r), Column::Text(out)) => {
                    let mut vals: Vec<ByteArray> = Vec::with_capacity(rows);
                    let (recs, _, _) = r
                        .read_records(rows, None, None, &mut vals)
                        .map_err(|e| bad(e.to_string()))?;
                    for b in &vals {
                        let t = b
                            .as_utf8()
                            .map_err(|e| bad(format!("not UTF-8 text: {e}")))?;
                        out.push(t.to_string());
                    }
                    recs
                }
                _ => return Err(bad(format!("another type in row group {g}"))),
            };
            if recs != rows {
                return Err(bad(format!("{recs} of {rows} rows in row group {g}")));
            }
        }
    }
    Ok(Table {
        names,
        columns,
        nullable,
        metadata,
    })
}
