//! Measured run-ups in (issue 51): a rig's files (UFF 58/58b, CSV, Parquet) and a mapping file
//! (`measurement.toml`, docs/validation.md) into the analysis' [`Signals`]: each measured
//! channel as the washdyn sensor channel it stands for (in SI, its sign flipped where the
//! rig's axis is opposite to washdyn's), the drum speed from a tacho or a speed channel, and
//! what was done to the data (unit conversions, calibration factors, tacho repairs) for the
//! user to see. Nothing is resampled: the channels must share one time base.
//!
//! Calibration factors are stored, never applied on loading: [`Measured::calibrated`] applies
//! them where a caller asks (the comparison's flag), so a number is never scaled unseen.
//! The measured speed becomes a run's speed table through [`speed_table`] and
//! [`write_speed_csv`] (the format of `sweep --profiles` and `washdyn run --speed`).
//! Files: `mapping.rs` (the TOML), `sources.rs` (files to channels), `table.rs`, `error.rs`.

mod error;
mod mapping;
mod report;
mod sources;
mod table;
#[cfg(test)]
mod tests;

pub use error::{ChannelAt, MappingAt, MeasuredError};
pub use mapping::{ChannelMap, Mapping, Seg, SpeedMap, Spots, TachoMap};
pub use table::{TABLE_STEP_S, TABLE_TOL_RPM, speed_table, write_speed_csv};

use sources::Raw;
use std::path::Path;
use washdyn_analysis::tacho::{self, Edge, TachoQuality, TachoSettings};
use washdyn_analysis::uff58::{SiUnit, UnitConversion};
use washdyn_analysis::{Channel, Quantity, Signals};

/// What was done to one measured channel on its way to a sensor channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelReport {
    /// The washdyn sensor channel.
    pub sensor: String,
    /// The measured channel.
    pub measured: ChannelAt,
    /// From the file's unit to SI: `si = factor * file value`.
    pub unit: UnitConversion,
    /// Whether the mapping's `unit` replaced the file's label.
    pub unit_overridden: bool,
    /// Whether the sign was flipped.
    pub flipped: bool,
    /// The calibration factor, not applied to `Measured::signals` ([`Measured::calibrated`]).
    pub calibration: Option<f64>,
}

/// Where the drum speed came from.
#[derive(Debug, Clone, PartialEq)]
pub enum SpeedFrom {
    /// A tacho channel, its settings and what was found and repaired.
    Tacho {
        channel: ChannelAt,
        settings: TachoSettings,
        quality: TachoQuality,
    },
    /// A speed channel (rpm).
    Rpm { channel: ChannelAt },
}

/// A loaded measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// The sensor channels in SI with the drum speed (uncalibrated); with a tacho, only the
    /// span where its speed is valid.
    pub signals: Signals,
    /// Per sensor channel, in `signals.channels`' order.
    pub channels: Vec<ChannelReport>,
    pub speed: SpeedFrom,
    /// What a user should read: unknown units, assumed units, channels of no known quantity.
    pub warnings: Vec<String>,
}

impl Measured {
    /// The tacho's pulse count and repairs, if the speed came from a tacho.
    pub fn tacho_quality(&self) -> Option<&TachoQuality> {
        match &self.speed {
            SpeedFrom::Tacho { quality, .. } => Some(quality),
            SpeedFrom::Rpm { .. } => None,
        }
    }

    /// The signals with every channel's calibration factor applied.
    pub fn calibrated(&self) -> Signals {
        let mut s = self.signals.clone();
        for (c, r) in s.channels.iter_mut().zip(&self.channels) {
            if let Some(f) = r.calibration {
                c.data.iter_mut().for_each(|v| *v *= f);
            }
        }
        s
    }
}

/// Load the measurement a mapping file describes.
pub fn load(mapping_path: impl AsRef<Path>) -> Result<Measured, MeasuredError> {
    let (m, spots) = mapping::read(mapping_path.as_ref())?;
    load_mapping(&m, &spots)
}

/// Load the measurement of a mapping (read from a file, or built from options).
pub fn load_mapping(m: &Mapping, spots: &Spots) -> Result<Measured, MeasuredError> {
    let mut raws = Vec::new();
    for (k, f) in m.files.iter().enumerate() {
        let path = spots.dir.join(f);
        if !path.is_file() {
            let at = spots.at(&[Seg::K("files"), Seg::I(k)]);
            return Err(MeasuredError::at(
                &at,
                format!("no such file: {}", path.display()),
            ));
        }
        raws.extend(sources::read(&path)?);
    }
    if m.channels.is_empty() {
        return Err(MeasuredError::at(
            &spots.at(&[Seg::K("channel")]),
            "no [[channel]]: map at least one measured channel to a sensor channel",
        ));
    }
    let mut picked = Vec::new();
    for (i, c) in m.channels.iter().enumerate() {
        picked.push(find(&raws, c, |f| {
            spots.at(&[Seg::K("channel"), Seg::I(i), Seg::K(f)])
        })?);
    }
    let speed_at = |f: &str| spots.at(&[Seg::K("speed"), Seg::K("tacho"), Seg::K(f)]);
    let speed = match (&m.speed.tacho, &m.speed.rpm) {
        (Some(t), None) => find_named(&raws, &t.channel, &speed_at("channel"))?,
        (None, Some(r)) => find_named(&raws, r, &spots.at(&[Seg::K("speed"), Seg::K("rpm")]))?,
        _ => {
            return Err(MeasuredError::at(
                &spots.at(&[Seg::K("speed")]),
                "give the drum speed's source: either `tacho = { channel = .. }` or `rpm = ..`",
            ));
        }
    };
    let used: Vec<&Raw> = picked.iter().chain([&speed]).map(|&k| &raws[k]).collect();
    same_time_base(&used)?;
    let mut warnings = Vec::new();
    let mut channels = Vec::new();
    let mut reports: Vec<ChannelReport> = Vec::new();
    for (i, (c, &k)) in m.channels.iter().zip(&picked).enumerate() {
        let at = |f: &str| spots.at(&[Seg::K("channel"), Seg::I(i), Seg::K(f)]);
        if let Some(prev) = reports.iter().find(|r| r.sensor == c.sensor) {
            return Err(MeasuredError::at(
                &at("sensor"),
                format!(
                    "`{}` is mapped twice (also from {})",
                    c.sensor, prev.measured
                ),
            ));
        }
        let (ch, report) = channel(&raws[k], c, at, &mut warnings)?;
        channels.push(ch);
        reports.push(report);
    }
    let raw = &raws[speed];
    let (time, drum_rpm, speed) = speed_of(m, raw, &speed_at, &mut channels)?;
    let dt = raw.dt;
    let signals = Signals {
        time,
        drum_rpm,
        channels,
        sample_rate: 1.0 / dt,
    };
    signals.validate()?;
    Ok(Measured {
        signals,
        channels: reports,
        speed,
        warnings,
    })
}

/// The drum speed (rpm) and its times; with a tacho, the channels cut to the span where its
/// speed is valid.
fn speed_of(
    m: &Mapping,
    raw: &Raw,
    speed_at: &dyn Fn(&str) -> MappingAt,
    channels: &mut [Channel],
) -> Result<(Vec<f64>, Vec<f64>, SpeedFrom), MeasuredError> {
    let time: Vec<f64> = (0..raw.samples.len())
        .map(|i| raw.start + i as f64 * raw.dt)
        .collect();
    let Some(t) = &m.speed.tacho else {
        let from = SpeedFrom::Rpm {
            channel: raw.at.clone(),
        };
        return Ok((time, rpm_of(raw)?, from));
    };
    let settings = tacho_settings(t, speed_at)?;
    let s = tacho::speed_from_tacho(&time, &raw.samples, &settings).map_err(|source| {
        MeasuredError::Tacho {
            channel: Box::new(raw.at.clone()),
            source,
        }
    })?;
    let span = s.first..s.first + s.time.len();
    for c in channels.iter_mut() {
        c.data = c.data[span.clone()].to_vec();
    }
    let from = SpeedFrom::Tacho {
        channel: raw.at.clone(),
        settings,
        quality: s.quality,
    };
    Ok((s.time, s.rpm, from))
}

/// The raw channel a mapping entry names: by `measured`, or by `node` and `direction`.
fn find(
    raws: &[Raw],
    c: &ChannelMap,
    at: impl Fn(&str) -> MappingAt,
) -> Result<usize, MeasuredError> {
    match (&c.measured, c.node, &c.direction) {
        (Some(name), None, None) => find_named(raws, name, &at("measured")),
        (None, Some(node), Some(d)) => {
            let dir = sources::parse_direction(d).ok_or_else(|| {
                MeasuredError::at(
                    &at("direction"),
                    format!("`{d}` is no direction (+X, -Y, Z, +RZ)"),
                )
            })?;
            let hits: Vec<usize> = (0..raws.len())
                .filter(|&k| raws[k].dof == Some((node, dir)))
                .collect();
            one_of(raws, &hits, &at("node"), &format!("node {node} {dir}"))
        }
        _ => Err(MeasuredError::at(
            &at("measured"),
            "name the measured channel either by `measured = \"<name>\"` or by `node` and \
             `direction`",
        )),
    }
}

fn find_named(raws: &[Raw], name: &str, at: &MappingAt) -> Result<usize, MeasuredError> {
    let hits: Vec<usize> = (0..raws.len())
        .filter(|&k| raws[k].at.name == name)
        .collect();
    one_of(raws, &hits, at, &format!("`{name}`"))
}

/// The one hit; none or two refused with what the files hold.
fn one_of(
    raws: &[Raw],
    hits: &[usize],
    at: &MappingAt,
    what: &str,
) -> Result<usize, MeasuredError> {
    match hits {
        [k] => Ok(*k),
        [] => {
            let names: Vec<String> = raws
                .iter()
                .take(12)
                .map(|r| format!("`{}`", r.at.name))
                .collect();
            let more = if raws.len() > 12 { ", ..." } else { "" };
            Err(MeasuredError::at(
                at,
                format!(
                    "no measured channel {what}; the files hold {}{more}",
                    names.join(", ")
                ),
            ))
        }
        [a, b, ..] => Err(MeasuredError::at(
            at,
            format!("{what} is ambiguous: {} and {}", raws[*a].at, raws[*b].at),
        )),
    }
}

/// Every channel at the first's sample spacing, length and start (within half a sample).
fn same_time_base(used: &[&Raw]) -> Result<(), MeasuredError> {
    let Some(first) = used.first() else {
        return Ok(());
    };
    for r in &used[1..] {
        let refuse = |what, a: String, b: String| MeasuredError::TimeBase {
            what,
            first: Box::new(first.at.clone()),
            second: Box::new(r.at.clone()),
            a,
            b,
        };
        if (r.dt - first.dt).abs() > 1e-9 * first.dt {
            let hz = |dt: f64| format!("{} Hz", washdyn_ode::Rounded(1.0 / dt));
            return Err(refuse("sample rate", hz(first.dt), hz(r.dt)));
        }
        if r.samples.len() != first.samples.len() {
            let n = |r: &Raw| format!("{} samples", r.samples.len());
            return Err(refuse("length", n(first), n(r)));
        }
        if (r.start - first.start).abs() > 0.5 * first.dt {
            let s = |t: f64| format!("{t} s");
            return Err(refuse("start time", s(first.start), s(r.start)));
        }
    }
    Ok(())
}

/// One sensor channel: the unit (the mapping's where given), calibration checked, the sign.
fn channel(
    raw: &Raw,
    c: &ChannelMap,
    at: impl Fn(&str) -> MappingAt,
    warnings: &mut Vec<String>,
) -> Result<(Channel, ChannelReport), MeasuredError> {
    if c.sensor.trim().is_empty() {
        return Err(MeasuredError::at(
            &at("sensor"),
            "empty sensor channel name",
        ));
    }
    let (unit, mut data) = match &c.unit {
        Some(label) => {
            let u = sources::unit_of(label).ok_or_else(|| {
                MeasuredError::at(
                    &at("unit"),
                    format!("unknown unit `{label}` (g, m/s^2, mm/s^2, m, mm, um, V, rpm, ...)"),
                )
            })?;
            let data = raw.file_values().iter().map(|v| v * u.factor).collect();
            (u, data)
        }
        None => (raw.unit.clone(), raw.samples.clone()),
    };
    if let Some(f) = c.calibration.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(MeasuredError::at(
            &at("calibration"),
            format!(
                "{f} is no calibration factor: it must be a finite number > 0 (an axis opposite \
                 to washdyn's is `flip = true`)"
            ),
        ));
    }
    if c.flip {
        data.iter_mut().for_each(|v| *v = -*v);
    }
    let quantity = match unit.si {
        Some(SiUnit::MetrePerSecondSquared) => Quantity::Acceleration,
        Some(SiUnit::Metre) => Quantity::Displacement,
        _ => Quantity::Unknown,
    };
    let named = Quantity::from_channel_name(&c.sensor);
    if named != Quantity::Unknown && quantity != named {
        return Err(MeasuredError::at(
            &at("sensor"),
            format!(
                "`{}` is {} {} channel, but {} is in `{}`{}",
                c.sensor,
                if named == Quantity::Acceleration {
                    "an"
                } else {
                    "a"
                },
                named.noun(),
                raw.at,
                unit.label,
                if c.unit.is_none() {
                    " (set its `unit`)"
                } else {
                    ""
                }
            ),
        ));
    }
    warnings.extend(raw.warnings.iter().map(|w| format!("{}: {w}", raw.at)));
    if quantity == Quantity::Unknown {
        warnings.push(format!(
            "{}: unit `{}` is no acceleration or displacement: `{}` is analysed as a signal of \
             unknown unit",
            raw.at, unit.label, c.sensor
        ));
    }
    let report = ChannelReport {
        sensor: c.sensor.clone(),
        measured: raw.at.clone(),
        unit,
        unit_overridden: c.unit.is_some(),
        flipped: c.flip,
        calibration: c.calibration,
    };
    let ch = Channel {
        name: c.sensor.clone(),
        quantity,
        data,
    };
    Ok((ch, report))
}

/// A speed channel's values in rpm.
fn rpm_of(raw: &Raw) -> Result<Vec<f64>, MeasuredError> {
    if raw.unit.si != Some(SiUnit::PerSecond) {
        return Err(MeasuredError::NotASpeed {
            channel: Box::new(raw.at.clone()),
            unit: raw.unit.label.clone(),
        });
    }
    Ok(raw.samples.iter().map(|v| v * 60.0).collect())
}

/// The tacho's settings from the mapping, each refused at its field.
fn tacho_settings(
    t: &TachoMap,
    at: &dyn Fn(&str) -> MappingAt,
) -> Result<TachoSettings, MeasuredError> {
    let edge = match t.edge.as_str() {
        "rising" => Edge::Rising,
        "falling" => Edge::Falling,
        e => {
            return Err(MeasuredError::at(
                &at("edge"),
                format!("`{e}` is no edge (rising, falling)"),
            ));
        }
    };
    let ratio = match (t.side.as_str(), t.ratio) {
        ("drum", None) => 1.0,
        ("drum", Some(r)) => {
            return Err(MeasuredError::at(
                &at("ratio"),
                format!(
                    "a drum-side tacho turns with the drum: no ratio (got {r}); a tacho on the \
                     motor is `side = \"motor\"`"
                ),
            ));
        }
        ("motor", Some(r)) => r,
        ("motor", None) => {
            return Err(MeasuredError::at(
                &at("ratio"),
                "a motor-side tacho needs the belt ratio (motor turns per drum turn, e.g. 11.25)",
            ));
        }
        (s, _) => {
            return Err(MeasuredError::at(
                &at("side"),
                format!("`{s}` is no side (drum, motor)"),
            ));
        }
    };
    let settings = TachoSettings {
        pulses_per_rev: t.pulses_per_rev,
        edge,
        threshold: t.threshold,
        hysteresis: t.hysteresis,
        ratio,
        smoothing_s: t.smoothing_s.unwrap_or(tacho::DEFAULT_SMOOTHING_S),
    };
    settings.validate().map_err(|e| match &e {
        tacho::TachoError::InvalidSetting { field, .. } => {
            MeasuredError::at(&at(field), e.to_string())
        }
        _ => MeasuredError::at(&at("channel"), e.to_string()),
    })?;
    Ok(settings)
}
