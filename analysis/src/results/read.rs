//! Reading a Parquet table back as f64 columns (nulls as NaN): what `analyse`, `fields` and the
//! tests read the run's files with. Separate from the writer: it shares no code with it.

use parquet::column::reader::ColumnReader;
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
