//! Unit labels as rigs write them (record 9 field 6), to SI.
//!
//! The label decides the factor. The units exponents of records 8-11 (fields 2-4: length,
//! force, temperature) state a dimension, not a scale: the format reads them only for data type
//! 1 (general), and the scale to SI lives in dataset 164 (units), which this reader skips;
//! pyuff writes them 0 whatever the data type. So they are used only where there is no label:
//! data type 1 with exponents (1, 0, 0) is a length, (0, 1, 0) a force, assumed in SI units
//! with a warning. Labels are matched case-sensitively: `g` is standard gravity, `G` is no SI
//! symbol for it (giga-, gauss) but some rigs write it so; it is read as `g` with a warning.

use std::fmt;

/// Standard gravity, m/s^2 (exact, 3rd CGPM 1901).
pub const STANDARD_GRAVITY: f64 = 9.80665;
/// The inch, m (exact, 1959).
const INCH: f64 = 0.0254;

/// The SI unit a channel's samples are stored in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiUnit {
    /// m/s^2
    MetrePerSecondSquared,
    /// m/s
    MetrePerSecond,
    /// m
    Metre,
    /// N
    Newton,
    /// Pa
    Pascal,
    /// V
    Volt,
    /// s
    Second,
    /// 1/s: frequency and rotational speed in revolutions per second (rpm / 60).
    PerSecond,
}

impl SiUnit {
    /// The unit's symbol.
    pub fn symbol(self) -> &'static str {
        match self {
            SiUnit::MetrePerSecondSquared => "m/s^2",
            SiUnit::MetrePerSecond => "m/s",
            SiUnit::Metre => "m",
            SiUnit::Newton => "N",
            SiUnit::Pascal => "Pa",
            SiUnit::Volt => "V",
            SiUnit::Second => "s",
            SiUnit::PerSecond => "1/s",
        }
    }

    /// The SI unit a specific data type (records 8-11, field 1) implies, if it implies one.
    pub fn of_data_type(code: i64) -> Option<SiUnit> {
        Some(match code {
            2 | 15 => SiUnit::Pascal,
            8 => SiUnit::Metre,
            9 | 13 => SiUnit::Newton,
            11 => SiUnit::MetrePerSecond,
            12 => SiUnit::MetrePerSecondSquared,
            17 => SiUnit::Second,
            18 | 19 => SiUnit::PerSecond,
            _ => return None,
        })
    }
}

impl fmt::Display for SiUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// How a channel's values were brought to SI: `si = factor * file value`.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitConversion {
    /// The label as the file writes it (trimmed; empty for `NONE` or blank).
    pub label: String,
    /// Factor from the file's unit to `si`; 1 where the unit is unknown.
    pub factor: f64,
    /// The SI unit of the stored samples; `None` for an unknown unit (kept as in the file).
    pub si: Option<SiUnit>,
}

/// What a reader should know about a channel it was given: nothing here refuses the file.
#[derive(Debug, Clone, PartialEq)]
pub enum UffWarning {
    /// A unit label this reader does not know: values kept as in the file (factor 1).
    UnknownUnit { label: String },
    /// No unit label: the SI unit the data type implies is assumed.
    NoUnitLabel { data_type: i64, assumed: SiUnit },
    /// Neither a label nor a data type that implies a unit: values kept as in the file.
    NoUnit { data_type: i64 },
    /// The label's unit is not the one the data type implies.
    UnitDisagrees {
        label: String,
        data_type: i64,
        implied: SiUnit,
    },
    /// `G` read as standard gravity.
    UpperCaseG,
}

impl fmt::Display for UffWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UffWarning::UnknownUnit { label } => {
                write!(f, "unknown unit `{label}`: values kept as in the file")
            }
            UffWarning::NoUnitLabel { data_type, assumed } => write!(
                f,
                "no unit label: {assumed} assumed from data type {data_type} ({})",
                super::header::data_type_name(*data_type)
            ),
            UffWarning::NoUnit { data_type } => write!(
                f,
                "no unit label and data type {data_type} ({}) implies none: values kept as in \
                 the file",
                super::header::data_type_name(*data_type)
            ),
            UffWarning::UnitDisagrees {
                label,
                data_type,
                implied,
            } => write!(
                f,
                "unit `{label}` disagrees with data type {data_type} ({}, {implied})",
                super::header::data_type_name(*data_type)
            ),
            UffWarning::UpperCaseG => f.write_str("unit `G` read as standard gravity g"),
        }
    }
}

/// Factor and SI unit of a known label.
fn known(label: &str) -> Option<(f64, SiUnit)> {
    use SiUnit::*;
    Some(match label {
        "g" | "G" => (STANDARD_GRAVITY, MetrePerSecondSquared),
        "m/s^2" | "m/s2" | "m/s²" | "m/s/s" | "m s^-2" => (1.0, MetrePerSecondSquared),
        "mm/s^2" | "mm/s2" | "mm/s²" => (1e-3, MetrePerSecondSquared),
        "in/s^2" | "in/s2" | "in/s²" => (INCH, MetrePerSecondSquared),
        "m/s" => (1.0, MetrePerSecond),
        "mm/s" => (1e-3, MetrePerSecond),
        "um/s" | "µm/s" | "μm/s" => (1e-6, MetrePerSecond),
        "in/s" => (INCH, MetrePerSecond),
        "m" => (1.0, Metre),
        "mm" => (1e-3, Metre),
        "um" | "µm" | "μm" => (1e-6, Metre),
        "in" => (INCH, Metre),
        "N" => (1.0, Newton),
        "kN" => (1e3, Newton),
        "Pa" => (1.0, Pascal),
        "kPa" => (1e3, Pascal),
        "V" => (1.0, Volt),
        "mV" => (1e-3, Volt),
        "s" => (1.0, Second),
        "ms" => (1e-3, Second),
        "Hz" | "1/s" => (1.0, PerSecond),
        "rpm" | "RPM" | "1/min" | "rev/min" => (1.0 / 60.0, PerSecond),
        _ => return None,
    })
}

/// The label without `NONE`, blanks or one pair of brackets (`[m/s^2]`).
pub fn clean_label(label: &str) -> &str {
    let l = label.trim();
    let l = l
        .strip_prefix('[')
        .and_then(|l| l.strip_suffix(']'))
        .unwrap_or(l)
        .trim();
    if l == "NONE" { "" } else { l }
}

/// The conversion of a channel with unit `label` and specific data type `data_type`, and the
/// warnings a user should see; `exponents` (length, force, temperature) serve only data type 1
/// without a label.
pub fn conversion(
    label: &str,
    data_type: i64,
    exponents: [i64; 3],
) -> (UnitConversion, Vec<UffWarning>) {
    let label = clean_label(label).to_string();
    let implied = SiUnit::of_data_type(data_type).or(match (data_type, exponents) {
        (1, [1, 0, 0]) => Some(SiUnit::Metre),
        (1, [0, 1, 0]) => Some(SiUnit::Newton),
        _ => None,
    });
    let mut warnings = Vec::new();
    let (factor, si) = if label.is_empty() {
        match implied {
            Some(assumed) => {
                warnings.push(UffWarning::NoUnitLabel { data_type, assumed });
                (1.0, Some(assumed))
            }
            None => {
                warnings.push(UffWarning::NoUnit { data_type });
                (1.0, None)
            }
        }
    } else if let Some((factor, si)) = known(&label) {
        if label == "G" {
            warnings.push(UffWarning::UpperCaseG);
        }
        // Data types 18 and 19 (frequency, rpm) share 1/s; 0 and 1 imply nothing to disagree with.
        if let Some(implied) = implied.filter(|&i| i != si) {
            warnings.push(UffWarning::UnitDisagrees {
                label: label.clone(),
                data_type,
                implied,
            });
        }
        (factor, Some(si))
    } else {
        warnings.push(UffWarning::UnknownUnit {
            label: label.clone(),
        });
        (1.0, None)
    };
    (UnitConversion { label, factor, si }, warnings)
}
