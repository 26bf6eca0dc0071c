//! The states a run stored (`states.parquet`) and the instants `washdyn fields` is asked for
//! (`--times`, `--range`, `--revolution`): read, interpolated, and every instant checked before
//! any file is written.

use crate::Error;
use crate::error::fields::FieldsError;
use std::path::Path;

/// The times of `--times` (or `--revolution`) as numbers: finite and not negative. `option`
/// names the flag in the error, a refused setting. Checked before any file is read or written;
/// whether each lies inside the run is checked against its states (`States::instants`).
pub fn check_times(option: &'static str, times: &[f64]) -> Result<(), Error> {
    let bad: Vec<String> = times
        .iter()
        .filter(|t| !(t.is_finite() && **t >= 0.0))
        .map(|t| t.to_string())
        .collect();
    if bad.is_empty() {
        Ok(())
    } else {
        Err(Error::setting(
            option,
            format!(
                "{option}: {} is not a time in s (finite, >= 0)",
                bad.join(", ")
            ),
        ))
    }
}

/// Which instants to recover.
#[derive(Clone, Debug, PartialEq)]
pub enum Times {
    List(Vec<f64>),
    /// from, to, step (s).
    Range(f64, f64, f64),
    /// One drum revolution from this time, in `REVOLUTION_FRAMES` frames.
    Revolution(f64),
}

/// Frames of one revolution (every 10 degrees).
pub const REVOLUTION_FRAMES: usize = 36;

/// Most instants one `washdyn fields` call writes: each is a grid per body of 1-5 MB, so 1e4
/// frames are already tens of GB; a range with a tiny step is a typo.
pub const MAX_FRAMES: usize = 10_000;

/// The states a run wrote: time, drum angle and q per sample.
pub struct States {
    pub t: Vec<f64>,
    pub phi: Vec<f64>,
    pub q: Vec<Vec<f64>>,
}

impl States {
    pub fn read(path: &Path) -> Result<States, FieldsError> {
        let (names, cols) = crate::results::read_parquet_f64(path)
            .map_err(|message| FieldsError::StatesFile { message })?;
        if names.len() < 3 || names[0] != "time_s" || names[1] != "drum_angle_rad" {
            return Err(FieldsError::NotStates {
                path: path.to_path_buf(),
            });
        }
        let mut cols = cols.into_iter();
        let t = cols.next().expect("checked");
        let phi = cols.next().expect("checked");
        Ok(States {
            t,
            phi,
            q: cols.collect(),
        })
    }

    /// (phi, q) at time `t`, linear between samples; an error outside the run.
    pub fn at(&self, t: f64) -> Result<(f64, Vec<f64>), FieldsError> {
        let n = self.t.len();
        // Negated: a NaN time is outside too.
        if n == 0 || !(t >= self.t[0] - 1e-12 && t <= self.t[n - 1] + 1e-12) {
            return Err(FieldsError::Outside {
                t,
                first: *self.t.first().unwrap_or(&0.0),
                last: *self.t.last().unwrap_or(&0.0),
            });
        }
        let i = self.t.partition_point(|&x| x <= t).clamp(1, n.max(2) - 1);
        let (t0, t1) = (self.t[i - 1], self.t[i.min(n - 1)]);
        let f = if t1 > t0 {
            ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let lerp = |v: &[f64]| v[i - 1] + f * (v[i.min(n - 1)] - v[i - 1]);
        Ok((lerp(&self.phi), self.q.iter().map(|c| lerp(c)).collect()))
    }

    /// The instants `times` asks for, every one inside the stored states (all checked before
    /// the first file is written).
    pub fn instants(&self, times: &Times) -> Result<Vec<f64>, FieldsError> {
        let (option, list) = self.requested(times)?;
        if list.len() > MAX_FRAMES {
            return Err(FieldsError::TooMany {
                option,
                count: list.len(),
                max: MAX_FRAMES,
            });
        }
        let outside: Vec<FieldsError> = list.iter().filter_map(|&t| self.at(t).err()).collect();
        if !outside.is_empty() {
            return Err(FieldsError::Instants { option, outside });
        }
        Ok(list)
    }

    /// The option's name and the instants it lists.
    fn requested(&self, times: &Times) -> Result<(&'static str, Vec<f64>), FieldsError> {
        Ok(match times {
            Times::List(v) => ("--times", v.clone()),
            Times::Range(a, b, dt) => {
                let (from, to, step) = (*a, *b, *dt);
                if !(step > 0.0 && to >= from && from.is_finite() && to.is_finite()) {
                    return Err(FieldsError::Range { from, to, step });
                }
                let n = ((b - a) / dt + 1e-9).floor();
                if n >= MAX_FRAMES as f64 {
                    return Err(FieldsError::RangeTooLong {
                        from,
                        to,
                        step,
                        count: n,
                        max: MAX_FRAMES,
                    });
                }
                let n = n as usize;
                ("--range", (0..=n).map(|k| a + k as f64 * dt).collect())
            }
            Times::Revolution(t0) => {
                // Frames at equal drum angles over one turn.
                let (phi0, _) = self.at(*t0)?;
                let mut out = vec![*t0];
                let step = 2.0 * std::f64::consts::PI / REVOLUTION_FRAMES as f64;
                for k in 1..REVOLUTION_FRAMES {
                    let target = phi0 + k as f64 * step;
                    let i = self.phi.partition_point(|&p| p < target);
                    if i == 0 || i >= self.t.len() {
                        return Err(FieldsError::Revolution { t: *t0 });
                    }
                    let f = (target - self.phi[i - 1]) / (self.phi[i] - self.phi[i - 1]);
                    out.push(self.t[i - 1] + f * (self.t[i] - self.t[i - 1]));
                }
                ("--revolution", out)
            }
        })
    }
}
