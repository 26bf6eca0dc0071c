//! `washdyn fe reference`: our own full-mesh reference. The linear machine
//! (`assembly::linear_machine`) solved twice at drum order 1: by CalculiX on the assembled full
//! meshes (`*STEADY STATE DYNAMICS`, `assembly.rs`) and by washdyn's Ritz model in the frequency
//! domain (`harmonic.rs`); every sensor channel compared per speed, ccx's convergence with its
//! mode count, and washdyn's with the tub's and the cabinet's modes, with and without static
//! correction modes. Writes full-mesh.md and full-mesh.json.

use nalgebra::Complex;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use washdyn_fe::assembly::{self, LinearSpec, SCENE, Settings, Solution};
use washdyn_runtime::harmonic;
use washdyn_runtime::ir::files::content_hash;
use washdyn_runtime::ir::{Model, SensorKind};
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

/// ccx's answer for one assembled deck, as `washdyn fe reference` commits it: the 200-mode
/// solve takes 15 to 20 min on 2 cores, too long for every test run, and the deck's hash ties
/// the answer to what the code and the model write now (a changed mesh, model or deck writer
/// refuses it instead of comparing with a stale reference).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CcxReference {
    /// `ccx -v` of the solve.
    pub ccx_version: String,
    /// FNV-1a 64 of the deck's text (`ir::files::content_hash`).
    pub deck_fnv1a64: String,
    pub modes: usize,
    pub wall_s: f64,
    /// ccx's total mass (EMAS plus the point masses), kg.
    pub mass: Option<f64>,
    /// The assembled machine's eigenfrequencies, Hz.
    pub frequencies: Vec<f64>,
    pub rpm: Vec<f64>,
    /// Per speed, every channel's complex amplitude as [re, im] (`Solution::channels`).
    pub channels: Vec<Vec<[f64; 2]>>,
}

impl CcxReference {
    fn of(s: &Solution, deck: &str, modes: usize) -> CcxReference {
        CcxReference {
            ccx_version: washdyn_fe::ccx::version().unwrap_or_default(),
            deck_fnv1a64: content_hash(deck.as_bytes()),
            modes,
            wall_s: s.wall_s,
            mass: s.mass,
            frequencies: s.frequencies.clone(),
            rpm: s.rpm.clone(),
            channels: s
                .channels
                .iter()
                .map(|c| c.iter().map(|z| [z.re, z.im]).collect())
                .collect(),
        }
    }

    /// The committed answer in `path` for this deck (`channels` per speed), or why it does
    /// not fit.
    pub fn read(
        path: &Path,
        deck: &str,
        modes: usize,
        rpm: &[f64],
        channels: usize,
    ) -> Result<Solution, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let r: CcxReference =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let hash = content_hash(deck.as_bytes());
        let regenerate = format!(
            "regenerate it with `washdyn fe reference --modes {modes} --no-convergence` and \
             copy its full-mesh.ccx.json there"
        );
        if r.deck_fnv1a64 != hash {
            return Err(format!(
                "{}: ccx's answer is for the deck {}, the code writes {hash} now (mesh, model \
                 or deck writer changed): {regenerate}",
                path.display(),
                r.deck_fnv1a64
            ));
        }
        if r.modes != modes || r.rpm != rpm {
            return Err(format!(
                "{}: {} modes at {:?} rpm, asked for {modes} at {rpm:?}: {regenerate}",
                path.display(),
                r.modes,
                r.rpm
            ));
        }
        // The hash fixes the sensors, so this fails only for an edited file; the study indexes
        // every channel.
        if r.channels.len() != rpm.len() || r.channels.iter().any(|c| c.len() != channels) {
            return Err(format!(
                "{}: `channels` is not {} speeds of {channels} channels: {regenerate}",
                path.display(),
                rpm.len()
            ));
        }
        Ok(Solution {
            frequencies: r.frequencies,
            rpm: r.rpm,
            channels: r
                .channels
                .iter()
                .map(|c| c.iter().map(|z| Complex::new(z[0], z[1])).collect())
                .collect(),
            mass: r.mass,
            wall_s: r.wall_s,
        })
    }
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

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
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
) -> Result<Vec<Vec<nalgebra::Complex<f64>>>, String> {
    let scene = model.scene(Some(SCENE))?;
    let sys = Interpreter::new(model, &scene);
    speeds_rpm
        .iter()
        .map(|rpm| {
            harmonic::response(&sys, rpm * PI / 30.0, &[1.0])
                .map(|(_, h)| h[0].channels.clone())
                .map_err(|e| e.to_string())
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
pub fn study(args: &Args, log: &mut dyn FnMut(&str)) -> Result<Study, String> {
    let (model, _) = crate::commands::resolve_model(&args.model)?;
    let lin = assembly::linear_machine(&model, &args.spec);
    let scene = lin.scene(Some(SCENE))?;
    let bodies = washdyn_fe::bodies::builtin();
    let mesh = |name: &str| {
        bodies
            .iter()
            .find(|b| b.name == name)
            .map(|b| &b.mesh)
            .ok_or_else(|| format!("no built-in body {name}"))
    };
    std::fs::create_dir_all(&args.work).map_err(|e| format!("{}: {e}", args.work.display()))?;
    let mut runs: Vec<(usize, Solution)> = Vec::new();
    let mut info = None;
    let mut reference_answer = None;
    for &n in &args.modes {
        let settings = Settings {
            modes: n,
            speeds_rpm: args.speeds_rpm.clone(),
        };
        let a = assembly::assemble(&lin, &scene, mesh("tub")?, mesh("cabinet")?, &settings)?;
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
    let (mesh_nodes, mesh_elements, mass_ritz) = info.ok_or("no mode count given")?;
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
    let wd_f = harmonic::linearise(&sys, args.speeds_rpm[0] * PI / 30.0)
        .map_err(|e| e.to_string())?
        .eigenfrequencies();
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
    let mut ritz = Vec::new();
    if args.convergence {
        let (et, _) = data_modes(&lin, "tub");
        let (ec, _) = data_modes(&lin, "cabinet");
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
            let m = truncated(&lin, nt, nc, correction);
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
    }
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

/// What the reference relies on in CalculiX 2.20, measured on small decks (issue 19).
const CCX_NOTES: &str = "
## What the reference relies on in CalculiX 2.20

Checked on small decks (fe/tests/steady_state.rs: a chain of 40 point masses against a direct
complex solve in the same modal subspace; a curved 8 x 8 S8R plate for the equations; the
scalar dofs by a script during issue 19).

- Rayleigh damping and dashpots combine in `*STEADY STATE DYNAMICS`: ccx solves
  (Lambda - w^2 + i w (beta Lambda + Phi^T C Phi)) q = Phi^T F in the `*FREQUENCY` step's modes
  (agreement 1.3e-7, the .dat's 7 digits).
- A `*DASHPOT` table's frequency is in cycles/time (Hz), interpolated linearly, held constant
  beyond its ends: the hysteretic gasket (S K S / Omega_ref) is tabulated at the study's speeds.
- `*EQUATION` on S8R mid-surface nodes adds no stiffness (plate frequencies print identically),
  a load on the dependent auxiliary node equals the consistent nodal loads R_i^T F (identical
  displacements), the auxiliary node reads the rigid fit of the printed mid-surface
  displacements (4e-6, rotation 1e-5; 1.6e-6 in steady state), and a DASHPOTA or SPRING1 on a
  scalar auxiliary dof equals the element at the node (1.4e-6; dissipation equals input power
  to 2e-6).
- `*CLOAD` is the real part of F, `*CLOAD, LOAD CASE=2` its imaginary part (one node may carry
  both); the .dat prints Re x, then Im x of (K - w^2 M + i w C) x = F: f(t) = Re[F e^{i w t}],
  x(t) = Re[x e^{i w t}] (the conjugate convention is off by 100 %).
- A MASS element on a node that is dependent in an `*EQUATION` loses its couplings (ccx:
  \"add_sm_ei: coefficient should be 0\", 9.3 million times for the drum): the drum's point masses sit on independent nodes held by penalty springs (their
  mode at 1e5 Hz). On a `*RIGID BODY` (the motor) point masses are fine. Deck numbers need a
  decimal point (`*SPRING` data `4e3` reads as a degree of freedom) and at most 20 characters.
- `*FREQUENCY` runs ARPACK with ncv = 5 nev Lanczos vectors (info = -3 when that exceeds the
  dofs: 8 modes of 40 dofs work, 9 do not) and tolerance 1e-2. The eigen-solve dominates the
  cost and grows faster than the mode count.
- The mode-acceleration correction (the static response the kept modes miss, from `*STATIC`
  steps) fails on this machine: its softest modes (0.4 Hz: without preload the tub has no
  pendulum stiffness) dominate the static response, ccx's eigenvectors reproduce that only to
  ~1e-3 (a symmetric load shows a 0.7 % antisymmetric response in the modal sum), and
  (Omega / omega_1)^2 ~ 4e3 at 1400 rpm turns it into errors larger than the response. The
  reference converges by its mode count instead (table above).
";

fn pct(x: f64) -> String {
    format!("{:+.1} %", 100.0 * x)
}

/// full-mesh.md and full-mesh.json in `out`.
pub fn write(s: &Study, out: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut md = String::new();
    let w = &mut md;
    use std::fmt::Write as _;
    let _ = writeln!(
        w,
        "# Full-mesh reference: the linear machine in CalculiX against washdyn\n\n\
         Written by `washdyn fe reference` (src/full_mesh.rs); data in full-mesh.json.\n\n\
         The machine: `{}` made linear by `assembly::linear_machine` (no gravity or preload, \
         friction dampers as {:.0} N s/m linear dampers, no gyroscopic moments, the drum rigid, \
         its unbalance a prescribed rotating force, Rayleigh beta = {:.1e} s on the tub, the \
         cabinet, the springs and the gasket). CalculiX: the tub's and the cabinet's full meshes \
         ({} nodes, {} elements) assembled with the drum as rigid point masses, the springs as \
         SPRINGA, the dampers as DASHPOTA, the gasket's 6 x 6 K and D through scalar dofs, \
         solved with `*STEADY STATE DYNAMICS` at drum order 1 (fe/src/assembly.rs). washdyn: \
         the same machine's Ritz model (tub and cabinet modal data) in the frequency domain \
         (runtime/src/harmonic.rs). Mass: ccx {} kg, Ritz model {:.3} kg.\n",
        s.model,
        s.damper,
        s.beta,
        s.mesh_nodes,
        s.mesh_elements,
        s.mass_ccx.map_or("?".into(), |m| format!("{m:.3}")),
        s.mass_ritz
    );
    let _ = writeln!(
        w,
        "## Summary per speed\n\nAmplitude difference washdyn / ccx - 1 over the channels \
         above {:.0} % of the largest of their kind (accelerations, displacements) at that \
         speed; the complex difference |washdyn - ccx| / |ccx| includes the phase.\n\n\
         | rpm | Hz | channels | median | worst | worst channel | worst complex |\n\
         |---:|---:|---:|---:|---:|---|---:|",
        100.0 * COMPARED_SHARE
    );
    for sp in &s.speeds {
        let _ = writeln!(
            w,
            "| {:.0} | {:.2} | {} | {:.1} % | {:.1} % | {} | {:.1} % |",
            sp.rpm,
            sp.rpm / 60.0,
            sp.channels.iter().filter(|c| c.compared).count(),
            100.0 * sp.median,
            100.0 * sp.worst,
            sp.worst_channel,
            100.0 * sp.worst_complex
        );
    }
    let _ = writeln!(
        w,
        "\n## CalculiX's convergence with its mode count\n\nWorst change of a compared \
         channel against the {}-mode solution, per speed (|a_n - a_ref| / |a_ref|).\n",
        s.ccx.last().map_or(0, |c| c.modes)
    );
    let _ = write!(w, "| modes | up to Hz | ccx s |");
    for sp in &s.speeds {
        let _ = write!(w, " {:.0} rpm |", sp.rpm);
    }
    let _ = write!(w, "\n|---:|---:|---:|");
    for _ in &s.speeds {
        let _ = write!(w, "---:|");
    }
    let _ = writeln!(w);
    for c in &s.ccx {
        let _ = write!(w, "| {} | {:.0} | {:.0} |", c.modes, c.highest_hz, c.wall_s);
        for x in &c.worst_change {
            let _ = write!(w, " {x:.1e} |");
        }
        let _ = writeln!(w);
    }
    if !s.ritz.is_empty() {
        let _ = writeln!(
            w,
            "\n## washdyn's convergence with the Ritz basis\n\nMedian / worst amplitude \
             difference to the full mesh per speed, for the tub's and the cabinet's eigenmodes \
             kept and their static correction modes (\"+ n\": with the dropped eigenmodes' \
             static share folded in; 0: eigenmodes only).\n"
        );
        let _ = write!(w, "| tub | cabinet |");
        for sp in &s.speeds {
            let _ = write!(w, " {:.0} |", sp.rpm);
        }
        let _ = write!(w, "\n|---|---|");
        for _ in &s.speeds {
            let _ = write!(w, "---:|");
        }
        let _ = writeln!(w);
        for r in &s.ritz {
            let _ = write!(
                w,
                "| {} + {} | {} + {} |",
                r.tub_modes, r.tub_correction, r.cabinet_modes, r.cabinet_correction
            );
            for (m, x) in r.median.iter().zip(&r.worst) {
                let _ = write!(w, " {:.1} / {:.1} % |", 100.0 * m, 100.0 * x);
            }
            let _ = writeln!(w);
        }
    }
    let _ = writeln!(
        w,
        "\n## Eigenfrequencies of the coupled machine up to 60 Hz\n\nEach of ccx's with the \
         nearest of washdyn's: a mode the Ritz model lacks shows as a large difference.\n\n\
         | # | ccx Hz | washdyn Hz | difference |\n|---:|---:|---:|---:|"
    );
    for (i, (a, b)) in s.frequencies.iter().enumerate() {
        let _ = writeln!(w, "| {} | {a:.3} | {b:.3} | {} |", i + 1, pct(b / a - 1.0));
    }
    let _ = writeln!(
        w,
        "\n## Every channel\n\nAmplitude (m/s^2; m for displacements) and phase (deg, against \
         the drum angle); * marks a compared channel.\n\n| rpm | channel | ccx | washdyn | \
         amplitude | phase ccx / washdyn | complex |\n|---:|---|---:|---:|---:|---:|---:|"
    );
    for sp in &s.speeds {
        for c in &sp.channels {
            let _ = writeln!(
                w,
                "| {:.0} | {}{} | {:.4e} | {:.4e} | {} | {:.1} / {:.1} | {:.1} % |",
                sp.rpm,
                c.name,
                if c.compared { " *" } else { "" },
                c.ccx,
                c.washdyn,
                pct(c.amplitude),
                c.ccx_phase,
                c.washdyn_phase,
                100.0 * c.complex
            );
        }
    }
    md.push_str(CCX_NOTES);
    let md_path = out.join("full-mesh.md");
    std::fs::write(&md_path, md).map_err(|e| format!("{}: {e}", md_path.display()))?;
    let json_path = out.join("full-mesh.json");
    let json = serde_json::to_string_pretty(s).map_err(|e| e.to_string())?;
    std::fs::write(&json_path, json).map_err(|e| format!("{}: {e}", json_path.display()))?;
    let mut wrote = vec![md_path, json_path];
    if let Some(r) = &s.reference {
        let path = out.join("full-mesh.ccx.json");
        let json = serde_json::to_string_pretty(r).map_err(|e| e.to_string())?;
        std::fs::write(&path, json).map_err(|e| format!("{}: {e}", path.display()))?;
        wrote.push(path);
    }
    Ok(wrote)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed answer is refused for any other deck, mode count or speeds (the test
    /// suite's full-mesh comparison rests on this; the deck the code writes now is taken in
    /// tests/full_mesh.rs).
    #[test]
    fn committed_answer_is_refused_for_another_deck() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(COMMITTED);
        let r: CcxReference =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let nc = r.channels[0].len();
        let e = CcxReference::read(&path, "** another deck\n", r.modes, &r.rpm, nc).unwrap_err();
        assert!(
            e.contains(&r.deck_fnv1a64) && e.contains("regenerate"),
            "{e}"
        );
        // The right hash, other settings: a deck whose text hashes equal is what the file
        // records (FNV-1a of the text), so fake it by editing a copy of the file.
        let dir = tempfile::tempdir().unwrap();
        let copy = dir.path().join("ccx.json");
        let mut r2 = r.clone();
        r2.deck_fnv1a64 = content_hash(b"deck");
        std::fs::write(&copy, serde_json::to_string(&r2).unwrap()).unwrap();
        assert!(CcxReference::read(&copy, "deck", r.modes, &r.rpm, nc).is_ok());
        assert!(CcxReference::read(&copy, "deck", r.modes - 1, &r.rpm, nc).is_err());
        assert!(CcxReference::read(&copy, "deck", r.modes, &r.rpm[1..], nc).is_err());
        // An edited file with a channel short at one speed: refused, not indexed past its end.
        r2.channels[3].pop();
        std::fs::write(&copy, serde_json::to_string(&r2).unwrap()).unwrap();
        let e = CcxReference::read(&copy, "deck", r.modes, &r.rpm, nc).unwrap_err();
        assert!(e.contains("channels"), "{e}");
    }
}
