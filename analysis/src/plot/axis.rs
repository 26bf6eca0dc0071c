//! The amplitude axis (linear, log or dB, resolved against the data), the colour map and the
//! round tick numbers that every plot's axes use. Scale arithmetic only, no drawing: kept apart
//! so it reads (and is tested) on its own.

use std::ops::Range;

use plotters::prelude::RGBColor;

use crate::options::ColourScale;
use crate::signals::Quantity;

/// Perceptually ordered colour map (dark violet - blue - green - yellow), readable
/// in greyscale prints and for colour-blind readers, unlike a rainbow.
pub fn colour_map(t: f64) -> RGBColor {
    const ANCHORS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (ANCHORS.len() - 1) as f64;
    let i = (x.floor() as usize).min(ANCHORS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
    let mix = |p: u8, q: u8| (p as f64 + f * (q as f64 - p as f64)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Amplitude axis resolved against the data: maps SI amplitudes to the axis unit
/// (display unit or dB) and to a colour fraction, and provides ticks and caption.
#[derive(Debug, Clone, PartialEq)]
pub struct AmplitudeAxis {
    /// Scale kind.
    pub scale: ColourScale,
    /// Channel quantity (unit, dB reference).
    pub quantity: Quantity,
    /// Lower end in axis units (display unit, or dB).
    pub lo: f64,
    /// Upper end in axis units.
    pub hi: f64,
}

impl AmplitudeAxis {
    /// Axis covering amplitudes up to `max_si` (SI units).
    pub fn new(scale: ColourScale, quantity: Quantity, max_si: f64) -> AmplitudeAxis {
        // Displacements read in mm: the dB scale's range becomes a log axis in mm.
        let scale = match (scale, quantity) {
            (ColourScale::Decibel { range_db }, Quantity::Displacement) => {
                ColourScale::Log { range_db }
            }
            _ => scale,
        };
        let f = quantity.display_factor();
        let max = if max_si.is_finite() && max_si > 0.0 {
            max_si
        } else {
            1.0 / f
        };
        let (lo, hi) = match scale {
            ColourScale::Linear => (0.0, nice_ceil(max * f)),
            ColourScale::Log { range_db } => {
                let hi = max * f;
                (hi * 10f64.powf(-range_db / 20.0), hi)
            }
            ColourScale::Decibel { range_db } => {
                let hi = (20.0 * (max / quantity.db_reference()).log10() / 5.0).ceil() * 5.0;
                (hi - range_db, hi)
            }
        };
        AmplitudeAxis {
            scale,
            quantity,
            lo,
            hi,
        }
    }

    /// Value on the axis (display unit or dB) of an SI amplitude.
    pub fn axis_value(&self, v_si: f64) -> f64 {
        match self.scale {
            ColourScale::Linear | ColourScale::Log { .. } => v_si * self.quantity.display_factor(),
            ColourScale::Decibel { .. } => {
                20.0 * (v_si.max(1e-300) / self.quantity.db_reference()).log10()
            }
        }
    }

    /// Position of an SI amplitude along the axis, 0 (low) to 1 (high), clamped.
    pub fn fraction(&self, v_si: f64) -> f64 {
        let t = match self.scale {
            ColourScale::Log { .. } => {
                let v = self.axis_value(v_si);
                if v <= 0.0 {
                    0.0
                } else {
                    (v / self.lo).log10() / (self.hi / self.lo).log10()
                }
            }
            _ => (self.axis_value(v_si) - self.lo) / (self.hi - self.lo),
        };
        if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// Position of an axis value (not SI) along the axis.
    fn fraction_of_axis_value(&self, v: f64) -> f64 {
        match self.scale {
            ColourScale::Log { .. } => (v / self.lo).log10() / (self.hi / self.lo).log10(),
            _ => (v - self.lo) / (self.hi - self.lo),
        }
    }

    /// Tick positions (fraction) and labels.
    pub fn ticks(&self) -> Vec<(f64, String)> {
        let values: Vec<f64> = match self.scale {
            ColourScale::Linear => nice_ticks(self.lo, self.hi, 6),
            ColourScale::Decibel { range_db } => {
                let step = if range_db > 40.0 {
                    10.0
                } else if range_db > 15.0 {
                    5.0
                } else {
                    1.0
                };
                let first = (self.lo / step).ceil() as i64;
                let last = (self.hi / step).floor() as i64;
                (first..=last).map(|i| i as f64 * step).collect()
            }
            ColourScale::Log { .. } => {
                let decades = (self.hi / self.lo).log10();
                let mantissas: &[f64] = if decades < 2.5 {
                    &[1.0, 2.0, 5.0]
                } else {
                    &[1.0]
                };
                let (e0, e1) = (
                    self.lo.log10().floor() as i32,
                    self.hi.log10().ceil() as i32,
                );
                (e0..=e1)
                    .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
                    .filter(|v| *v >= self.lo * (1.0 - 1e-9) && *v <= self.hi * (1.0 + 1e-9))
                    .collect()
            }
        };
        values
            .into_iter()
            .map(|v| (self.fraction_of_axis_value(v), fmt_number(v)))
            .collect()
    }

    /// Axis caption with unit and convention (peak amplitude).
    pub fn caption(&self) -> String {
        let unit = self.quantity.display_unit();
        match self.scale {
            ColourScale::Linear => format!("amplitude (peak) [{unit}]"),
            ColourScale::Log { .. } => format!("amplitude (peak) [{unit}], log scale"),
            ColourScale::Decibel { .. } => {
                format!("level (peak) [{}]", self.quantity.db_reference_label())
            }
        }
    }
}

/// Smallest 1-2-2.5-5 number times a power of ten not below `v`.
pub(super) fn nice_ceil(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(v.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * p >= v * (1.0 - 1e-12) {
            return m * p;
        }
    }
    10.0 * p
}

/// About `n` round tick values in `[lo, hi]`.
fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = nice_ceil((hi - lo) / n.max(1) as f64);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// Short number for tick labels: plain decimals where readable, else scientific.
pub(crate) fn fmt_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.1e}");
        s.replace(".0e", "e")
    }
}

/// Speed axis range over the given blocks, padded to round 50 rpm.
pub(super) fn rpm_range<'a>(rpms: impl Iterator<Item = f64> + 'a) -> Range<f64> {
    let (lo, hi) = rpms.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| {
        (l.min(r), h.max(r))
    });
    if !lo.is_finite() {
        return 0.0..100.0;
    }
    let (mut lo, mut hi) = ((lo / 50.0).floor() * 50.0, (hi / 50.0).ceil() * 50.0);
    if hi - lo < 50.0 {
        lo -= 50.0;
        hi += 50.0;
    }
    lo.max(0.0)..hi
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_numbers() {
        assert_eq!(nice_ceil(0.73), 1.0);
        assert_eq!(nice_ceil(1.3), 2.0);
        assert_eq!(nice_ceil(2.2), 2.5);
        assert_eq!(nice_ceil(37.0), 50.0);
        assert_eq!(fmt_number(0.05), "0.05");
        assert_eq!(fmt_number(120.0), "120");
        assert_eq!(fmt_number(1e-5), "1e-5");
        let ticks: Vec<String> = nice_ticks(0.0, 1.0, 5)
            .into_iter()
            .map(fmt_number)
            .collect();
        assert_eq!(ticks, ["0", "0.2", "0.4", "0.6", "0.8", "1"]);
    }

    #[test]
    fn decibel_axis_rounds_up_to_5_db() {
        let a = AmplitudeAxis::new(
            ColourScale::Decibel { range_db: 60.0 },
            Quantity::Acceleration,
            1.0,
        );
        assert_eq!((a.lo, a.hi), (60.0, 120.0));
        assert!((a.fraction(1.0) - 1.0).abs() < 1e-12);
        assert!((a.fraction(1e-3) - 0.0).abs() < 1e-12);
        assert_eq!(a.ticks().len(), 7);
    }

    #[test]
    fn colour_map_ends() {
        assert_eq!(colour_map(0.0), RGBColor(68, 1, 84));
        assert_eq!(colour_map(1.0), RGBColor(253, 231, 37));
        assert_eq!(colour_map(f64::NAN), RGBColor(68, 1, 84));
    }
}
