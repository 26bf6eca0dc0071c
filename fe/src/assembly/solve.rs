//! Running the assembled deck: write it, run ccx on every core, read the eigenfrequencies, ccx's
//! mass and the sensors' complex amplitudes back (`solve`, `Solution`). Separate from the deck
//! (`deck.rs`) as the one part that needs CalculiX.

use super::{Assembly, AssemblyError};
use crate::error::{Error, Within};
use nalgebra::Complex;
use std::f64::consts::PI;
use std::path::Path;
use washdyn_model::ir::SensorKind;

/// ccx's answer: the assembled machine's eigenfrequencies and, per speed, every channel's
/// complex amplitude (drum order 1, channel(t) = Re[a e^{i phi}], phi the drum angle).
#[derive(Clone, Debug)]
pub struct Solution {
    pub frequencies: Vec<f64>,
    /// Drum speeds, rpm.
    pub rpm: Vec<f64>,
    /// Per speed, the channels in the model's sensor order (3 per sensor), accelerations as
    /// -w^2 u.
    pub channels: Vec<Vec<Complex<f64>>>,
    /// ccx's total mass (`EMAS` of the elements plus the point masses), kg.
    pub mass: Option<f64>,
    pub wall_s: f64,
}

/// Write the deck as `<dir>/<job>.inp`, run ccx, read the eigenfrequencies and the sensors'
/// amplitudes back.
pub fn solve(a: &Assembly, dir: &Path, job: &str) -> Result<Solution, Error> {
    let path = dir.join(format!("{job}.inp"));
    std::fs::write(&path, a.deck.text()).map_err(Error::io(&path))?;
    // Every core: the assembled machine's eigen-solve is most of the reference's time.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let run = crate::ccx::run_threads(&path, threads)?;
    let dat = std::fs::read_to_string(run.dat()).within(|| format!("{job}.dat"))?;
    let prints = crate::dat::node_prints(&dat, "WD_SENSORS").within(|| format!("{job}.dat"))?;
    // The real and imaginary parts per speed, the last 2 n prints (ccx prints nothing else
    // for the set: the request is made in the steady-state steps).
    let n = a.settings.speeds_rpm.len();
    if prints.len() != 2 * n {
        return Err(AssemblyError::SensorPrints {
            job: job.to_string(),
            prints: prints.len(),
            speeds: n,
        }
        .into());
    }
    let get = |p: &[(usize, [f64; 3])], node: usize| {
        p.iter()
            .find(|(id, _)| *id == node)
            .map(|(_, v)| *v)
            .ok_or_else(|| AssemblyError::NotPrinted {
                job: job.to_string(),
                node,
            })
    };
    let mut channels = Vec::new();
    for (s, rpm) in a.settings.speeds_rpm.iter().enumerate() {
        let w = rpm * PI / 30.0;
        let mut ch = Vec::new();
        for sn in &a.sensors {
            let (r, i) = (
                get(&prints[2 * s], sn.node)?,
                get(&prints[2 * s + 1], sn.node)?,
            );
            let f = match sn.kind {
                SensorKind::Displacement => 1.0,
                SensorKind::Acceleration => -w * w,
            };
            for k in 0..3 {
                ch.push(Complex::new(f * r[k], f * i[k]));
            }
        }
        channels.push(ch);
    }
    Ok(Solution {
        frequencies: crate::ccx::frequencies(&dat),
        rpm: a.settings.speeds_rpm.clone(),
        channels,
        mass: crate::dat::emas(&dat, "EALL").map(|e| e.mass + a.point_mass),
        wall_s: run.wall_s,
    })
}
