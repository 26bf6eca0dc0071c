//! `washdyn fe reference`: our own full-mesh reference. The linear machine
//! (`assembly::linear_machine`) solved twice at drum order 1: by CalculiX on the assembled full
//! meshes (`*STEADY STATE DYNAMICS`, `assembly/`) and by washdyn's Ritz model in the frequency
//! domain (`harmonic.rs`); every sensor channel compared per speed, ccx's convergence with its
//! mode count, and washdyn's with the tub's and the cabinet's modes, with and without static
//! correction modes. Writes full-mesh.md and full-mesh.json.

mod committed;
mod report;

pub use crate::error::fe::FullMeshError;
pub use committed::CcxReference;
pub use report::write;

use crate::analysis::metrics::median;
use crate::error::FileError;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::PathBuf;
use washdyn_fe::assembly::{self, LinearSpec, SCENE, Settings, Solution};
use washdyn_model::ir::{EffectSet, Model, SensorKind};
use washdyn_runtime::harmonic;
use washdyn_runtime::system::Interpreter;

/// ccx's mode counts of the study: the last is the reference (with 100, to 183 Hz, ccx's own
/// truncation shows: 7.8 % at 1400 rpm, docs/full-mesh.md).
pub const MODES: [usize; 2] = [100, 200];
/// ccx's answer for the reference mode count, committed (`CcxReference`), relative to the
/// workspace root.
pub const COMMITTED: &str = "models/fe/full-mesh.ccx.json";
/// The speeds between 300 and 1400 rpm.
pub const SPEEDS_RPM: [f64; 8] = [300.0, 400.0, 600.0, 800.0, 1000.0, 1130.0, 1200.0, 1400.0];
/// A channel is compared where its amplitude is at least this share of the largest amplitude
/// of its kind (accelerations, displacements) at that speed.
pub const COMPARED_SHARE: f64 = 0.1;

/// What to compute.
#[derive(Clone, Debug)]
pub struct Args {
    pub model: String,
    /// ccx's mode counts, ascending; the last one is the reference, the others show its
    /// convergence.
    pub modes: Vec<usize>,
    pub speeds_rpm: Vec<f64>,
    pub spec: LinearSpec,
    /// Scratch directory for the decks and ccx's files.
    pub work: PathBuf,
    /// Also wash the Ritz model through its mode counts (the convergence table).
    pub convergence: bool,
    /// ccx's answer for the reference (last) mode count read from this file instead of solved,
    /// refused unless it came from the deck the code writes now.
    pub committed: Option<PathBuf>,
}

/// One channel at one speed.
#[derive(Clone, Debug, Serialize)]
pub struct Channel {
    pub name: String,
    /// ccx's and washdyn's amplitude (m/s^2 or m) and phase (deg, against the drum angle).
    pub ccx: f64,
    pub ccx_phase: f64,
    pub washdyn: f64,
    pub washdyn_phase: f64,
    /// washdyn / ccx - 1 on the amplitude.
    pub amplitude: f64,
    /// |washdyn - ccx| / |ccx| on the complex amplitude.
    pub complex: f64,
    /// At least `COMPARED_SHARE` of its kind's largest amplitude at this speed.
    pub compared: bool,
}

/// One speed.
#[derive(Clone, Debug, Serialize)]
pub struct Speed {
    pub rpm: f64,
    pub channels: Vec<Channel>,
    /// Median and worst |amplitude difference| over the compared channels, and the worst one.
    pub median: f64,
    pub worst: f64,
    pub worst_channel: String,
    /// Worst |complex difference| over the compared channels.
    pub worst_complex: f64,
}

/// ccx's convergence: per mode count, per speed, the worst change of a compared channel
/// against the reference (the most modes), relative to the channel.
#[derive(Clone, Debug, Serialize)]
pub struct CcxRun {
    pub modes: usize,
    pub highest_hz: f64,
    pub wall_s: f64,
    pub worst_change: Vec<f64>,
}

/// One Ritz configuration: median and worst amplitude difference per speed.
#[derive(Clone, Debug, Serialize)]
pub struct Ritz {
    pub tub_modes: usize,
    pub cabinet_modes: usize,
    pub tub_correction: usize,
    pub cabinet_correction: usize,
    pub median: Vec<f64>,
    pub worst: Vec<f64>,
}

/// The whole study.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    pub model: String,
    pub beta: f64,
    pub damper: f64,
    pub mesh_nodes: usize,
    pub mesh_elements: usize,
    /// The machine's mass: ccx's (EMAS of meshes and point masses) and the Ritz model's.
    pub mass_ccx: Option<f64>,
    pub mass_ritz: f64,
    pub ccx: Vec<CcxRun>,
    /// Eigenfrequencies (Hz) of the coupled machine up to 60 Hz: each of ccx's with washdyn's
    /// nearest (a mode the Ritz model lacks shows as a large difference).
    pub frequencies: Vec<(f64, f64)>,
    pub speeds: Vec<Speed>,
    pub ritz: Vec<Ritz>,
    pub washdyn_s: f64,
    /// ccx's answer for the reference mode count (full-mesh.ccx.json).
    #[serde(skip)]
    pub reference: Option<CcxReference>,
}

/// Which channels are compared: at least `COMPARED_SHARE` of the largest amplitude of their
/// kind (by the reference's amplitudes).
fn compared(model: &Model, amp: &[f64]) -> Vec<bool> {
    let kinds: Vec<SensorKind> = model.sensors.iter().flat_map(|s| [s.kind; 3]).collect();
    let top = |k: SensorKind| {
        kinds
            .iter()
            .zip(amp)
            .filter(|(kk, _)| **kk == k)
            .fold(0.0f64, |m, (_, a)| m.max(*a))
    };
    kinds
        .iter()
        .zip(amp)
        .map(|(k, a)| *a >= COMPARED_SHARE * top(*k) && *a > 0.0)
        .collect()
}

/// washdyn's order-1 channels of `model` (a linear machine) at each speed.
pub fn washdyn_channels(
    model: &Model,
    speeds_rpm: &[f64],
) -> Result<Vec<Vec<nalgebra::Complex<f64>>>, FullMeshError> {
    let scene = model.scene(Some(SCENE)).map_err(FullMeshError::Scene)?;
    let sys = Interpreter::new(model, &scene);
    speeds_rpm
        .iter()
        .map(|rpm| {
            harmonic::response(&sys, rpm * PI / 30.0, &[1.0])
                .map(|(_, h)| h[0].channels.clone())
                .map_err(FullMeshError::from)
        })
        .collect()
}

/// The Ritz model with the tub's and the cabinet's data cut to `nt` and `nc` eigenmodes, with
/// their correction modes (and the dropped modes' static share folded in) or without.
fn truncated(model: &Model, nt: usize, nc: usize, correction: bool) -> Model {
    let mut m = model.clone();
    for e in &mut m.elastic {
        let n = match e.name.as_str() {
            "tub" => nt,
            "cabinet" => nc,
            _ => continue,
        };
        if let Some(d) = &mut e.data {
            if !correction {
                *d = d.without_correction();
            }
            d.truncate(n, &[]);
        }
    }
    m
}

fn data_modes(model: &Model, name: &str) -> (usize, usize) {
    model
        .elastic
        .iter()
        .find(|e| e.name == name)
        .and_then(|e| e.data.as_ref())
        .map_or((0, 0), |d| (d.eigenmodes(), d.modes() - d.eigenmodes()))
}

/// Run the study.
pub fn study(args: &Args, log: &mut dyn FnMut(&str)) -> Result<Study, FullMeshError> {
    let (model, _) = crate::commands::resolve_model(&args.model)?;
    let lin = assembly::linear_machine(&model, &args.spec);
    let scene = lin.scene(Some(SCENE)).map_err(FullMeshError::Scene)?;
    let (runs, info, reference_answer) = solve_ccx(args, &lin, &scene, log)?;
    let (mesh_nodes, mesh_elements, mass_ritz) = info.ok_or(FullMeshError::NoModes)?;
    let reference = &runs.last().expect("at least one run").1;
    let ref_ch = &reference.channels;
    let t = std::time::Instant::now();
    let wd = washdyn_channels(&lin, &args.speeds_rpm)?;
    let washdyn_s = t.elapsed().as_secs_f64();
    let names: Vec<String> = lin.sensors.iter().flat_map(|s| s.channels()).collect();
    let mut speeds = Vec::new();
    let mut masks = Vec::new();
    for (k, (rpm, ccx)) in reference.rpm.iter().zip(ref_ch).enumerate() {
        let amp: Vec<f64> = ccx.iter().map(|c| c.norm()).collect();
        let mask = compared(&lin, &amp);
        let channels: Vec<Channel> = (0..names.len())
            .map(|c| {
                let (a, b) = (ccx[c], wd[k][c]);
                Channel {
                    name: names[c].clone(),
                    ccx: a.norm(),
                    ccx_phase: a.arg().to_degrees(),
                    washdyn: b.norm(),
                    washdyn_phase: b.arg().to_degrees(),
                    amplitude: b.norm() / a.norm() - 1.0,
                    complex: (b - a).norm() / a.norm(),
                    compared: mask[c],
                }
            })
            .collect();
        let used: Vec<&Channel> = channels.iter().filter(|c| c.compared).collect();
        let worst = used
            .iter()
            .max_by(|a, b| a.amplitude.abs().total_cmp(&b.amplitude.abs()))
            .expect("the largest channel is compared");
        speeds.push(Speed {
            rpm: *rpm,
            median: median(used.iter().map(|c| c.amplitude.abs()).collect()),
            worst: worst.amplitude.abs(),
            worst_channel: worst.name.clone(),
            worst_complex: used.iter().fold(0.0f64, |m, c| m.max(c.complex)),
            channels,
        });
        masks.push(mask);
    }
    // Worst change of a compared channel against the reference, per speed.
    let change = |x: &[Vec<nalgebra::Complex<f64>>]| -> Vec<f64> {
        x.iter()
            .zip(ref_ch)
            .zip(&masks)
            .map(|((a, r), mask)| {
                a.iter()
                    .zip(r)
                    .zip(mask)
                    .filter(|(_, m)| **m)
                    .fold(0.0f64, |m, ((a, r), _)| m.max((a - r).norm() / r.norm()))
            })
            .collect()
    };
    let ccx = runs
        .iter()
        .map(|(n, s)| CcxRun {
            modes: *n,
            highest_hz: s.frequencies.last().copied().unwrap_or(f64::NAN),
            wall_s: s.wall_s,
            worst_change: change(&s.channels),
        })
        .collect();
    // The coupled machine's eigenfrequencies up to 60 Hz.
    let sys = Interpreter::new(&lin, &scene);
    let wd_f = harmonic::linearise(&sys, args.speeds_rpm[0] * PI / 30.0)?.eigenfrequencies();
    let frequencies = reference
        .frequencies
        .iter()
        .take_while(|f| **f <= 60.0)
        .map(|a| {
            let near = wd_f
                .iter()
                .copied()
                .min_by(|x, y| (x - a).abs().total_cmp(&(y - a).abs()))
                .unwrap_or(f64::NAN);
            (*a, near)
        })
        .collect();
    // The Ritz model's convergence.
    let ritz = if args.convergence {
        ritz_convergence(args, &lin, ref_ch, &masks, &names, log)?
    } else {
        Vec::new()
    };
    Ok(Study {
        model: args.model.clone(),
        beta: args.spec.beta,
        damper: args.spec.damper,
        mesh_nodes,
        mesh_elements,
        mass_ccx: reference.mass,
        mass_ritz,
        ccx,
        frequencies,
        speeds,
        ritz,
        washdyn_s,
        reference: reference_answer,
    })
}

/// The solved machine's mesh nodes, elements and mass (the last mode count's).
type MeshInfo = (usize, usize, f64);

/// ccx on the assembled machine at each mode count (the last one's answer from
/// `args.committed` when given): the solutions, the mesh's size and mass, and the reference's
/// answer as the committed file keeps it.
#[allow(clippy::type_complexity)]
fn solve_ccx(
    args: &Args,
    lin: &Model,
    scene: &EffectSet,
    log: &mut dyn FnMut(&str),
) -> Result<
    (
        Vec<(usize, Solution)>,
        Option<MeshInfo>,
        Option<CcxReference>,
    ),
    FullMeshError,
> {
    let bodies = washdyn_fe::bodies::builtin();
    let mesh = |name: &str| {
        bodies
            .iter()
            .find(|b| b.name == name)
            .map(|b| &b.mesh)
            .ok_or_else(|| FullMeshError::NoBody(name.to_string()))
    };
    std::fs::create_dir_all(&args.work).map_err(FileError::at::<FullMeshError>(&args.work))?;
    let mut runs: Vec<(usize, Solution)> = Vec::new();
    let mut info = None;
    let mut reference_answer = None;
    for &n in &args.modes {
        let settings = Settings {
            modes: n,
            speeds_rpm: args.speeds_rpm.clone(),
        };
        let a = assembly::assemble(lin, scene, mesh("tub")?, mesh("cabinet")?, &settings)?;
        log(&format!(
            "ccx: the assembled machine ({} mesh nodes, {} auxiliary), {n} modes, {} speeds ...",
            a.mesh_nodes,
            a.aux_nodes,
            args.speeds_rpm.len()
        ));
        let last = n == *args.modes.last().expect("a mode count");
        let s = match &args.committed {
            Some(path) if last => {
                let s = CcxReference::read(
                    path,
                    a.deck.text(),
                    n,
                    &args.speeds_rpm,
                    3 * a.sensors.len(),
                )?;
                log(&format!(
                    "  ccx's answer from {} (solved in {:.1} s, {} modes up to {:.1} Hz)",
                    path.display(),
                    s.wall_s,
                    s.frequencies.len(),
                    s.frequencies.last().copied().unwrap_or(f64::NAN)
                ));
                s
            }
            _ => {
                let s = assembly::solve(&a, &args.work, &format!("full_mesh_{n}"))?;
                log(&format!(
                    "  {:.1} s; {} modes up to {:.1} Hz",
                    s.wall_s,
                    s.frequencies.len(),
                    s.frequencies.last().copied().unwrap_or(f64::NAN)
                ));
                s
            }
        };
        if last {
            reference_answer = Some(CcxReference::of(&s, a.deck.text(), n));
        }
        info = Some((a.mesh_nodes, a.mesh_elements, a.mass));
        runs.push((n, s));
    }
    Ok((runs, info, reference_answer))
}

/// The Ritz model's convergence with its mode counts, with and without correction modes,
/// against ccx's reference on the compared channels.
fn ritz_convergence(
    args: &Args,
    lin: &Model,
    ref_ch: &[Vec<nalgebra::Complex<f64>>],
    masks: &[Vec<bool>],
    names: &[String],
    log: &mut dyn FnMut(&str),
) -> Result<Vec<Ritz>, FullMeshError> {
    let mut ritz = Vec::new();
    let (et, _) = data_modes(lin, "tub");
    let (ec, _) = data_modes(lin, "cabinet");
    let counts = |e: usize| -> Vec<usize> {
        let mut v: Vec<usize> = [5, 10, 20, 40, 80, 160]
            .into_iter()
            .filter(|n| *n < e)
            .collect();
        v.push(e);
        v
    };
    let mut configs = Vec::new();
    for correction in [true, false] {
        for &nt in &counts(et) {
            configs.push((nt, ec, correction));
        }
        for &nc in &counts(ec) {
            if nc != ec {
                configs.push((et, nc, correction));
            }
        }
    }
    for (nt, nc, correction) in configs {
        let m = truncated(lin, nt, nc, correction);
        let (_, tc) = data_modes(&m, "tub");
        let (_, ccn) = data_modes(&m, "cabinet");
        let w = washdyn_channels(&m, &args.speeds_rpm)?;
        let (mut med, mut worst) = (Vec::new(), Vec::new());
        for (k, ccx) in ref_ch.iter().enumerate() {
            let d: Vec<f64> = (0..names.len())
                .filter(|c| masks[k][*c])
                .map(|c| (w[k][c].norm() / ccx[c].norm() - 1.0).abs())
                .collect();
            worst.push(d.iter().copied().fold(0.0, f64::max));
            med.push(median(d));
        }
        log(&format!(
            "  Ritz: tub {nt} (+{tc}), cabinet {nc} (+{ccn}) modes: worst {:.1} %",
            100.0 * worst.iter().copied().fold(0.0, f64::max)
        ));
        ritz.push(Ritz {
            tub_modes: nt,
            cabinet_modes: nc,
            tub_correction: if correction { tc } else { 0 },
            cabinet_correction: if correction { ccn } else { 0 },
            median: med,
            worst,
        });
    }
    Ok(ritz)
}
