//! What loading did, as `washdyn analyse` prints it: the speed's source and the tacho's
//! quality, each channel's unit conversion, sign and calibration, and the warnings.

use super::{Measured, SpeedFrom};
use std::fmt;
use washdyn_analysis::tacho::Edge;
use washdyn_ode::Rounded;

impl fmt::Display for Measured {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.speed {
            SpeedFrom::Tacho {
                channel,
                settings,
                quality: q,
            } => {
                let side = match settings.ratio {
                    1.0 => "on the drum".to_string(),
                    r => format!("on the motor, {r} motor turns per drum turn"),
                };
                let edge = match settings.edge {
                    Edge::Rising => "rising",
                    Edge::Falling => "falling",
                };
                writeln!(
                    f,
                    "drum speed from the tacho {channel}: pulses per revolution {}, {side}, \
                     {edge} edges",
                    settings.pulses_per_rev
                )?;
                writeln!(
                    f,
                    "  {} pulses found, {} missing filled in, {} extra dropped; largest speed \
                     jump between pulse intervals {:.3} rpm; speed valid {}-{} s",
                    q.pulses,
                    q.missing.len(),
                    q.extra.len(),
                    q.max_speed_jump_rpm,
                    Rounded(q.span.0),
                    Rounded(q.span.1)
                )?;
                for (what, times) in [("missing", &q.missing), ("extra", &q.extra)] {
                    if !times.is_empty() {
                        let shown: Vec<String> =
                            times.iter().take(10).map(|t| format!("{t:.4}")).collect();
                        let more = if times.len() > 10 { ", ..." } else { "" };
                        writeln!(f, "  {what} pulses at {} s{more}", shown.join(", "))?;
                    }
                }
            }
            SpeedFrom::Rpm { channel } => writeln!(f, "drum speed from {channel} (rpm)")?,
        }
        for c in &self.channels {
            let u = &c.unit;
            let si = u.si.map_or("(unknown: as in the file)", |s| s.symbol());
            let from = if u.label.is_empty() {
                "(no unit)"
            } else {
                &u.label
            };
            let given = if c.unit_overridden {
                " (the mapping's unit)"
            } else {
                ""
            };
            write!(
                f,
                "{} <- {}: {from}{given} x {} -> {si}",
                c.sensor, c.measured, u.factor
            )?;
            if c.flipped {
                write!(f, ", sign flipped")?;
            }
            if let Some(k) = c.calibration {
                write!(f, ", calibration factor {k} (not applied)")?;
            }
            writeln!(f)?;
        }
        for w in &self.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}
