//! The measured files as one list of channels, whatever their format: UFF 58/58b datasets
//! (SI by their unit labels) and CSV/Parquet columns (SI already, `drum_rpm` in rpm).

use super::error::{ChannelAt, MeasuredError};
use std::path::Path;
use washdyn_analysis::read_signals;
use washdyn_analysis::uff58::{self, Direction, SiUnit, UnitConversion};

/// One measured channel before mapping.
#[derive(Debug, Clone)]
pub struct Raw {
    pub at: ChannelAt,
    /// UFF response node and direction; `None` for a column.
    pub dof: Option<(i64, Direction)>,
    /// Sample spacing and first sample's time, s.
    pub dt: f64,
    pub start: f64,
    /// Values in `unit.si` (as in the file where the unit is unknown).
    pub samples: Vec<f64>,
    pub unit: UnitConversion,
    /// What the reader warned about (unknown unit, assumed unit).
    pub warnings: Vec<String>,
}

impl Raw {
    /// The values as the file wrote them (before the unit's factor).
    pub fn file_values(&self) -> Vec<f64> {
        let f = self.unit.factor;
        self.samples.iter().map(|v| v / f).collect()
    }
}

/// Every channel of `file`: CSV/Parquet by extension, else UFF.
pub fn read(file: &Path) -> Result<Vec<Raw>, MeasuredError> {
    let ext = file
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if matches!(ext.as_str(), "csv" | "parquet" | "txt") {
        return columns(file);
    }
    let uff = uff58::read(file)?;
    let raws = uff
        .into_iter()
        .map(|c| Raw {
            at: ChannelAt {
                file: file.to_path_buf(),
                place: format!("dataset {} ({})", c.dataset, dataset_number(&c)),
                name: c.name.clone(),
            },
            dof: Some((c.response.node, c.response.direction)),
            dt: c.dt,
            start: c.start_time,
            warnings: c.warnings.iter().map(|w| w.to_string()).collect(),
            samples: c.samples,
            unit: c.unit,
        })
        .collect();
    Ok(raws)
}

fn dataset_number(c: &uff58::Uff58Channel) -> &'static str {
    match c.encoding {
        uff58::Encoding::Ascii => "58",
        _ => "58b",
    }
}

/// A CSV/Parquet signal file's columns: `drum_rpm` as a speed in rpm, the others in SI (the
/// format's convention), their quantity from their names.
fn columns(file: &Path) -> Result<Vec<Raw>, MeasuredError> {
    let s = read_signals(file)?;
    let dt = 1.0 / s.sample_rate;
    let start = s.time.first().copied().unwrap_or(0.0);
    let raw = |k: usize, name: &str, samples: Vec<f64>, unit: UnitConversion| Raw {
        at: ChannelAt {
            file: file.to_path_buf(),
            place: format!("column {}", k + 1),
            name: name.to_string(),
        },
        dof: None,
        dt,
        start,
        samples,
        unit,
        warnings: Vec::new(),
    };
    let rpm = UnitConversion {
        label: "rpm".into(),
        factor: 1.0 / 60.0,
        si: Some(SiUnit::PerSecond),
    };
    let mut out = vec![raw(
        1,
        "drum_rpm",
        s.drum_rpm.iter().map(|r| r / 60.0).collect(),
        rpm,
    )];
    for (k, c) in s.channels.into_iter().enumerate() {
        let si = match c.quantity {
            washdyn_analysis::Quantity::Acceleration => Some(SiUnit::MetrePerSecondSquared),
            washdyn_analysis::Quantity::Displacement => Some(SiUnit::Metre),
            washdyn_analysis::Quantity::Unknown => None,
        };
        let unit = UnitConversion {
            label: si.map_or(String::new(), |u| u.symbol().to_string()),
            factor: 1.0,
            si,
        };
        out.push(raw(k + 2, &c.name, c.data, unit));
    }
    Ok(out)
}

/// A direction as a mapping writes it: `+Z`, `-X`, `Z`, `+RY`.
pub fn parse_direction(s: &str) -> Option<Direction> {
    let s = s.trim().to_ascii_uppercase();
    let (sign, rest) = match s.as_bytes().first() {
        Some(b'-') => (-1, &s[1..]),
        Some(b'+') => (1, &s[1..]),
        _ => (1, s.as_str()),
    };
    let code = match rest {
        "X" => 1,
        "Y" => 2,
        "Z" => 3,
        "RX" => 4,
        "RY" => 5,
        "RZ" => 6,
        _ => return None,
    };
    Direction::new(sign * code)
}

/// A unit label's conversion to SI, if the label is known.
pub fn unit_of(label: &str) -> Option<UnitConversion> {
    let (c, _) = uff58::units::conversion(label, 0, [0, 0, 0]);
    c.si.is_some().then_some(c)
}
