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
//!
//! One file per concept: the table writer (`table.rs`: schema, Parquet or CSV, row groups as
//! the run goes), the reader (`read.rs`), and the run's three recorders, each a table of its own:
//! sensors (`sensors.rs`, also the runtime's sample sink), states (`states.rs`, written on a
//! thread of its own) and the energy balance (`energy.rs`, kept in memory and written at the
//! end). This file holds the format and the row-group limits the recorders share.

use std::path::Path;
use std::time::Duration;

mod energy;
mod read;
mod sensors;
mod states;
mod table;

pub use energy::EnergyRecorder;
pub use read::{Table, read_metadata, read_parquet_f64, read_table};
pub use sensors::{SensorRecorder, unit_of_column};
pub use states::StateRecorder;
pub use table::{Batched, Column, Schema, TableWriter};

/// The key of a run's id in its Parquet files' key-value metadata: the commands that read a
/// run refuse files whose id and summary.json's disagree (`washdyn::run_dir`).
pub const RUN_ID_KEY: &str = "washdyn.run_id";

/// The metadata entry of a run id, if any.
fn run_id_entry(id: &Option<String>) -> Option<(String, String)> {
    id.as_ref().map(|id| (RUN_ID_KEY.to_string(), id.clone()))
}

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

/// Rows a row group holds at most, and the longest wait between writes.
const GROUP_ROWS: usize = 1 << 16;
const GROUP_WAIT: Duration = Duration::from_secs(1);
