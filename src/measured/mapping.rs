//! The mapping file (`measurement.toml`): which files hold the measurement, which measured
//! channel is which washdyn sensor channel, and where the drum speed comes from. Parsed with
//! serde; every refusal names the file, the line and the field (docs/validation.md).

use super::error::{MappingAt, MeasuredError};
use serde::Deserialize;
use std::path::{Path as FsPath, PathBuf};
use washdyn_model::ir::check::Path;
use washdyn_model::ir::modal::from_toml;
use washdyn_model::ir::toml_file::{line_col, locate};

/// A whole mapping file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mapping {
    /// Measurement files (UFF 58/58b, CSV, Parquet), relative to the mapping file.
    pub files: Vec<PathBuf>,
    /// The measured channels to analyse, each as a washdyn sensor channel.
    #[serde(default, rename = "channel")]
    pub channels: Vec<ChannelMap>,
    /// Where the drum speed comes from.
    pub speed: SpeedMap,
}

/// One measured channel as a washdyn sensor channel.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ChannelMap {
    /// The channel's name in its file (UFF: `tub front [101+Z]`; CSV: the column).
    pub measured: Option<String>,
    /// Or its UFF response node and direction (`+Z`, `-X`, `Y`).
    pub node: Option<i64>,
    pub direction: Option<String>,
    /// The washdyn sensor channel it stands for (`tub_front_az`).
    pub sensor: String,
    /// The rig's axis points opposite to washdyn's (x along the drum axis to the door, z up).
    #[serde(default)]
    pub flip: bool,
    /// The unit of the file's values where its label is wrong or missing (`g`, `mm`).
    pub unit: Option<String>,
    /// A constant calibration factor (> 0): stored and reported, applied only where asked.
    pub calibration: Option<f64>,
}

/// The drum speed's source: a tacho pulse channel or a speed channel.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SpeedMap {
    pub tacho: Option<TachoMap>,
    /// A speed channel in rpm (a UFF rpm channel, a CSV/Parquet column such as `drum_rpm`).
    pub rpm: Option<String>,
}

/// A tacho channel and how to read it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TachoMap {
    pub channel: String,
    #[serde(default = "one")]
    pub pulses_per_rev: u32,
    /// `rising` or `falling`.
    #[serde(default = "rising")]
    pub edge: String,
    /// `drum` or `motor`.
    #[serde(default = "drum")]
    pub side: String,
    /// Motor turns per drum turn (a motor-side tacho's belt ratio).
    pub ratio: Option<f64>,
    pub threshold: Option<f64>,
    pub hysteresis: Option<f64>,
    pub smoothing_s: Option<f64>,
}

fn one() -> u32 {
    1
}
fn rising() -> String {
    "rising".into()
}
fn drum() -> String {
    "drum".into()
}

/// Where a mapping's fields are, for its refusals: a file's text, or the command line.
#[derive(Debug, Clone)]
pub struct Spots {
    pub file: String,
    /// The file's text; `None` for a mapping the command line built.
    src: Option<String>,
    /// The directory relative files are resolved in.
    pub dir: PathBuf,
}

impl Spots {
    /// A mapping given as options: its fields are named by `option(field)`.
    pub fn command_line(dir: PathBuf) -> Spots {
        Spots {
            file: "the command line".into(),
            src: None,
            dir,
        }
    }

    /// The place of the field at `path` (keys and indices), with its spelling.
    pub fn at(&self, path: &[Seg]) -> MappingAt {
        let mut p = Path::default();
        let mut shown = String::new();
        for s in path {
            match s {
                Seg::K(k) => {
                    p = p.key(k);
                    if !shown.is_empty() {
                        shown.push('.');
                    }
                    shown.push_str(k);
                }
                Seg::I(i) => {
                    p = p.idx(*i);
                    shown.push_str(&format!("[{i}]"));
                }
            }
        }
        let line = self
            .src
            .as_deref()
            .map_or(0, |src| locate(src, &p).0.max(1));
        if self.src.is_none() {
            shown = cli_option(&shown).unwrap_or(&shown).to_string();
        }
        MappingAt {
            file: self.file.clone(),
            line,
            field: shown,
        }
    }
}

/// `washdyn analyse`'s option that stands for a mapping field.
fn cli_option(field: &str) -> Option<&'static str> {
    Some(match field {
        "speed.tacho.channel" | "speed.tacho.edge" | "speed.tacho.side" => "--tacho",
        "speed.tacho.pulses_per_rev" => "--ppr",
        "speed.tacho.ratio" => "--motor-ratio",
        "speed.rpm" => "--rpm",
        "speed" => "--tacho or --rpm",
        _ => return None,
    })
}

/// A segment of a field's path.
#[derive(Debug, Clone, Copy)]
pub enum Seg<'a> {
    K(&'a str),
    I(usize),
}

/// Read and parse a mapping file.
pub fn read(path: &FsPath) -> Result<(Mapping, Spots), MeasuredError> {
    let text = std::fs::read_to_string(path).map_err(|source| MeasuredError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let shown = path.display().to_string();
    let mapping: Mapping = from_toml(&text).map_err(|(span, message)| {
        let line = span.map_or(1, |s| line_col(&text, s.start).0);
        MeasuredError::Mapping {
            at: MappingAt {
                file: shown.clone(),
                line,
                field: "mapping".into(),
            },
            message,
        }
    })?;
    let dir = path
        .parent()
        .map_or_else(|| PathBuf::from("."), FsPath::to_path_buf);
    let spots = Spots {
        file: shown,
        src: Some(text),
        dir,
    };
    if mapping.files.is_empty() {
        return Err(MeasuredError::at(
            &spots.at(&[Seg::K("files")]),
            "no measurement files",
        ));
    }
    Ok((mapping, spots))
}
