//! The runs compared: a run directory's signals and what the run cost (its summary.json), and
//! the check that two runs follow the same channels, sample rate and speed profile. Separate
//! because it is all input: it refuses before anything is analysed.

use crate::analysis::{Signals, read_signals};
use serde::{Deserialize, Serialize};
use std::path::Path;
use washdyn_ode::Rounded;

use super::{CompareArgs, CompareError, PROFILE_TOLERANCE};

/// What a run cost, from its summary.json (fields a summary lacks stay empty).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Cost {
    pub label: String,
    pub dir: String,
    pub model: Option<String>,
    pub scene: Option<String>,
    pub backend: Option<String>,
    pub method: Option<String>,
    pub rtol: Option<f64>,
    pub status: Option<String>,
    pub error: Option<String>,
    pub t_reached: Option<f64>,
    pub t_end: Option<f64>,
    pub steps: Option<u64>,
    pub rejected_steps: Option<u64>,
    pub rhs_evals: Option<u64>,
    pub wall_time_s: Option<f64>,
    pub energy_closure: Option<f64>,
}

impl Cost {
    /// The cost fields of a run's summary.json.
    pub fn read(dir: &Path, label: &str) -> Result<Cost, CompareError> {
        let path = dir.join("summary.json");
        let err = |message: String| CompareError::Summary {
            path: path.clone(),
            message,
        };
        let text = std::fs::read_to_string(&path).map_err(|e| err(e.to_string()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| err(format!("not JSON: {e}")))?;
        if !v.is_object() {
            return Err(err("not a run summary (expected a JSON object)".into()));
        }
        let s = |k: &str| v.get(k).and_then(|x| x.as_str()).map(str::to_string);
        let f = |k: &str| v.get(k).and_then(serde_json::Value::as_f64);
        let u = |k: &str| v.get(k).and_then(serde_json::Value::as_u64);
        Ok(Cost {
            label: label.to_string(),
            dir: dir.display().to_string(),
            model: s("model"),
            scene: s("scene"),
            backend: s("backend"),
            method: s("integrator"),
            rtol: f("rtol"),
            status: s("status"),
            error: s("error"),
            t_reached: f("t_reached"),
            t_end: f("t_end"),
            steps: u("steps"),
            rejected_steps: u("rejected_steps"),
            rhs_evals: u("rhs_evals"),
            wall_time_s: f("wall_time_s"),
            energy_closure: f("energy_closure"),
        })
    }
}

/// A run directory's signals (sensors.parquet, else sensors.csv) and its cost.
pub fn load(dir: &Path, label: &str) -> Result<(Signals, Cost), CompareError> {
    if !dir.is_dir() {
        return Err(CompareError::NoRun {
            dir: dir.to_path_buf(),
        });
    }
    let file = ["sensors.parquet", "sensors.csv"]
        .iter()
        .map(|f| dir.join(f))
        .find(|p| p.is_file())
        .ok_or_else(|| CompareError::NoSensors {
            dir: dir.to_path_buf(),
        })?;
    crate::run_dir::check_same_run(dir, &file)?;
    let cost = Cost::read(dir, label)?;
    Ok((read_signals(file)?, cost))
}

/// A measurement to compare a run with over speed, through the one door for measured data: a
/// mapping file (`measurement.toml`: UFF 58/58b, CSV or Parquet files, which channel is which
/// sensor, the speed from a tacho or an rpm channel; `crate::measured`), or a CSV or Parquet
/// file with `time_s`, `drum_rpm` and channels named like the run's sensors. Uncalibrated: the
/// comparison reports its own factor and applies it only when asked.
pub fn load_measured(path: &Path) -> Result<Signals, CompareError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("toml") => Ok(crate::measured::load(path)
            .map_err(|e| CompareError::Measured(Box::new(e)))?
            .signals),
        Some("uff" | "unv" | "58") => Err(CompareError::UffWithoutMapping {
            path: path.to_path_buf(),
        }),
        _ => Ok(read_signals(path)?),
    }
}

/// Both runs' signals, up to `--until` if given, and costs; refused where they cannot be
/// compared: a run that did not finish compared whole, an `--until` outside a run, other
/// channels, sample rates or drum speeds ([`check_comparable`]).
pub fn load_pair(args: &CompareArgs) -> Result<([Signals; 2], [Cost; 2]), CompareError> {
    let [da, db] = [args.runs[0].as_path(), args.runs[1].as_path()];
    let (mut sa, ca) = load(da, &args.labels[0])?;
    let (mut sb, cb) = load(db, &args.labels[1])?;
    // A run that did not finish is not another speed profile: say what became of it.
    if args.until.is_none() {
        for (s, c, d) in [(&sa, &ca, da), (&sb, &cb, db)] {
            if let Some(status) = c.status.as_ref().filter(|st| st.as_str() != "ok") {
                return Err(CompareError::Unfinished {
                    dir: d.to_path_buf(),
                    status: status.clone(),
                    error: c.error.clone(),
                    last: s.time[s.len() - 1],
                });
            }
        }
    }
    if let Some(t) = args.until {
        for (s, d) in [(&mut sa, da), (&mut sb, db)] {
            let span = [s.time[0], s.time[s.len() - 1]];
            if !s.truncate(t) {
                return Err(CompareError::Until {
                    dir: d.to_path_buf(),
                    until: t,
                    span,
                });
            }
        }
    }
    check_comparable([da, db], &sa, &sb)?;
    Ok(([sa, sb], [ca, cb]))
}

/// Refuse runs that cannot be compared sample by sample: other channels, sample rates or drum
/// speeds.
pub fn check_comparable(dirs: [&Path; 2], a: &Signals, b: &Signals) -> Result<(), CompareError> {
    let (da, db) = (dirs[0].to_path_buf(), dirs[1].to_path_buf());
    let names = |s: &Signals| -> std::collections::BTreeSet<String> {
        s.channels.iter().map(|c| c.name.clone()).collect()
    };
    let (na, nb) = (names(a), names(b));
    if na != nb {
        return Err(CompareError::Channels {
            a: da,
            b: db,
            only_a: na.difference(&nb).cloned().collect(),
            only_b: nb.difference(&na).cloned().collect(),
        });
    }
    if (a.sample_rate - b.sample_rate).abs() > PROFILE_TOLERANCE * a.sample_rate {
        return Err(CompareError::SampleRate {
            a: da,
            b: db,
            rate_a: a.sample_rate,
            rate_b: b.sample_rate,
        });
    }
    let profile = |detail: String| CompareError::Profile {
        a: da.clone(),
        b: db.clone(),
        detail,
    };
    let span = |s: &Signals| {
        format!(
            "{} samples, {} to {} s",
            s.len(),
            Rounded(s.time[0]),
            Rounded(s.time[s.len() - 1])
        )
    };
    let dt = 1.0 / a.sample_rate;
    if a.len() != b.len() || (a.time[0] - b.time[0]).abs() > PROFILE_TOLERANCE * dt {
        return Err(profile(format!(
            "the first has {}, the second {} (a run that stopped early cannot be compared)",
            span(a),
            span(b)
        )));
    }
    let top = a.drum_rpm.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    let (k, d) = a
        .drum_rpm
        .iter()
        .zip(&b.drum_rpm)
        .map(|(p, q)| (p - q).abs())
        .enumerate()
        .fold(
            (0, 0.0f64),
            |best, (k, d)| if d > best.1 { (k, d) } else { best },
        );
    if d > PROFILE_TOLERANCE * top.max(1.0) {
        return Err(profile(format!(
            "drum_rpm differs by {d:.6} rpm at t = {} s ({} against {} rpm)",
            Rounded(a.time[k]),
            a.drum_rpm[k],
            b.drum_rpm[k]
        )));
    }
    Ok(())
}
