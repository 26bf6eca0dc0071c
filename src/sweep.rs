//! Parallel variant studies: unbalance position and mass, speed profile. Each variant is a copy
//! of the model's IR with those fields changed, checked by the one checker and run by the
//! interpreter (generated code bakes the base model's numbers in), on all cores.

use crate::commands::{integrator_options, write_summary};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use washdyn_runtime::ir::Model;
use washdyn_runtime::ir::check::check;
use washdyn_runtime::ir::toml_file::read_speed_csv;
use washdyn_runtime::ode::{AnySolver, Method};
use washdyn_runtime::output::CsvSink;
use washdyn_runtime::run::{Labels, RunOptions, Start, Summary, run};
use washdyn_runtime::system::{FirstOrder, Interpreter};

/// Axial unbalance positions in the drum (shared/reference-machine.md): front, middle, rear.
pub const POSITIONS: &[(&str, f64)] = &[("front", 0.15), ("middle", 0.0), ("rear", -0.12)];

/// One variant of a sweep.
#[derive(Clone, Debug)]
pub struct Variant {
    pub name: String,
    pub model: Model,
}

/// What to vary; an empty list keeps the model's own value.
#[derive(Clone, Debug, Default)]
pub struct SweepSpec {
    /// Names from `POSITIONS`.
    pub positions: Vec<String>,
    /// kg of the drum's first unbalance.
    pub masses: Vec<f64>,
    /// Speed profile CSV files (time_s, rpm).
    pub profiles: Vec<PathBuf>,
}

/// The cartesian product of the spec over the base model. Errors name the offending value.
pub fn variants(base: &Model, spec: &SweepSpec) -> Result<Vec<Variant>, String> {
    let ui = base
        .unbalances
        .iter()
        .position(|u| {
            base.rotors
                .iter()
                .any(|r| r.name == u.rotor && r.name == "drum")
        })
        .ok_or("the model has no unbalance on a rotor named `drum` to vary")?;
    let positions: Vec<Option<(&str, f64)>> = if spec.positions.is_empty() {
        vec![None]
    } else {
        spec.positions
            .iter()
            .map(|p| {
                POSITIONS
                    .iter()
                    .find(|(n, _)| n == p)
                    .map(|&(n, x)| Some((n, x)))
                    .ok_or_else(|| format!("unknown position `{p}` (front, middle, rear)"))
            })
            .collect::<Result<_, _>>()?
    };
    let masses: Vec<Option<f64>> = if spec.masses.is_empty() {
        vec![None]
    } else {
        spec.masses.iter().map(|&m| Some(m)).collect()
    };
    let profiles: Vec<Option<(String, Vec<[f64; 2]>)>> = if spec.profiles.is_empty() {
        vec![None]
    } else {
        spec.profiles
            .iter()
            .map(|p| {
                let stem = p
                    .file_stem()
                    .map_or("profile".into(), |s| s.to_string_lossy().to_string());
                read_speed_csv(p)
                    .map(|t| Some((stem, t)))
                    .map_err(|e| e.to_string())
            })
            .collect::<Result<_, _>>()?
    };
    let mut out = Vec::new();
    for pos in &positions {
        for mass in &masses {
            for prof in &profiles {
                let mut m = base.clone();
                let mut parts = Vec::new();
                if let Some((n, x)) = pos {
                    m.unbalances[ui].position[0] = *x;
                    parts.push(n.to_string());
                }
                if let Some(kg) = mass {
                    m.unbalances[ui].mass = *kg;
                    parts.push(format!("{kg}kg"));
                }
                if let Some((stem, table)) = prof {
                    m.speed.table = table.clone();
                    m.speed.csv = None;
                    parts.push(stem.clone());
                }
                let name = if parts.is_empty() {
                    "base".into()
                } else {
                    parts.join("_")
                };
                check(&m).map_err(|e| {
                    let msgs: Vec<String> = e.iter().map(|e| e.to_string()).collect();
                    format!("variant {name}: {}", msgs.join("; "))
                })?;
                out.push(Variant { name, model: m });
            }
        }
    }
    Ok(out)
}

/// A finished variant: its summary and the peak of each channel with the drum speed there.
#[derive(Clone, Debug)]
pub struct VariantResult {
    pub name: String,
    pub summary: Summary,
    pub peaks: Vec<(String, f64, f64)>,
}

/// Settings shared by every variant.
#[derive(Clone, Debug)]
pub struct SweepRun {
    pub out: PathBuf,
    pub t_end: Option<f64>,
    pub method: Method,
    pub tol: f64,
    pub scene: Option<String>,
    pub sample_rate: f64,
    pub jobs: usize,
}

/// Run every variant on `jobs` threads; `done` is called as each finishes. Writes
/// `<out>/<variant>/{sensors.csv, summary.json}` and `<out>/sweep.csv`.
pub fn run_sweep(
    vars: Vec<Variant>,
    cfg: &SweepRun,
    done: &(dyn Fn(&VariantResult) + Sync),
) -> Result<Vec<VariantResult>, String> {
    fs::create_dir_all(&cfg.out).map_err(|e| format!("{}: {e}", cfg.out.display()))?;
    let queue = Mutex::new(vars.into_iter().enumerate());
    let results = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..cfg.jobs.max(1) {
            s.spawn(|| {
                loop {
                    let next = queue.lock().expect("queue").next();
                    let Some((i, v)) = next else { break };
                    let r = run_one(&v, cfg);
                    if let Ok(r) = &r {
                        done(r);
                    }
                    results.lock().expect("results").push((i, r));
                }
            });
        }
    });
    let mut results = results.into_inner().expect("results");
    results.sort_by_key(|(i, _)| *i);
    let results: Vec<VariantResult> = results
        .into_iter()
        .map(|(_, r)| r)
        .collect::<Result<_, _>>()?;
    write_table(&cfg.out.join("sweep.csv"), &results)?;
    Ok(results)
}

fn run_one(v: &Variant, cfg: &SweepRun) -> Result<VariantResult, String> {
    let scene = v.model.scene(cfg.scene.as_deref())?;
    let dir = cfg.out.join(&v.name);
    fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let interp = Interpreter::new(&v.model, &scene);
    let t_end = cfg.t_end.unwrap_or_else(|| interp.speed.end());
    let mut sys = FirstOrder::new(interp);
    let opts = integrator_options(cfg.method, cfg.tol, None, None);
    let mut solver = AnySolver::new(cfg.method, 2 * sys.layout().n(), opts);
    let csv = dir.join("sensors.csv");
    let mut sink = CsvSink::create(&csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    let ro = RunOptions {
        t_start: 0.0,
        t_end,
        sample_rate: cfg.sample_rate,
        start: Start::Static,
    };
    let labels = Labels {
        model: format!("{}/{}", v.model.name, v.name),
        scene: scene.name.clone(),
        backend: "interpreted".into(),
    };
    let summary = match run(
        &mut sys,
        &mut solver,
        &ro,
        &labels,
        (opts.rtol, opts.atol),
        &mut sink,
        &mut |_| {},
    ) {
        Ok(s) => s,
        Err((_, s)) => s,
    };
    write_summary(&dir, &summary)?;
    let peaks = peaks(&csv)?;
    Ok(VariantResult {
        name: v.name.clone(),
        summary,
        peaks,
    })
}

/// Largest |value| of each channel and the drum rpm where it occurs, read back from the CSV.
fn peaks(csv: &Path) -> Result<Vec<(String, f64, f64)>, String> {
    let text = fs::read_to_string(csv).map_err(|e| e.to_string())?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .ok_or("empty sensors.csv")?
        .split(',')
        .map(str::to_string)
        .collect();
    let mut best: Vec<(f64, f64)> = vec![(0.0, 0.0); header.len()];
    for l in lines {
        let v: Vec<f64> = l.split(',').filter_map(|c| c.parse().ok()).collect();
        if v.len() != header.len() {
            continue;
        }
        for c in 2..v.len() {
            if v[c].abs() > best[c].0 {
                best[c] = (v[c].abs(), v[1]);
            }
        }
    }
    Ok((2..header.len())
        .map(|c| (header[c].clone(), best[c].0, best[c].1))
        .collect())
}

fn write_table(path: &Path, results: &[VariantResult]) -> Result<(), String> {
    let mut s = String::from("variant,status,t_reached_s,steps,rhs_evals,wall_time_s");
    if let Some(r) = results.first() {
        for (c, _, _) in &r.peaks {
            s.push_str(&format!(",{c}_peak,{c}_peak_rpm"));
        }
    }
    s.push('\n');
    for r in results {
        let m = &r.summary;
        s.push_str(&format!(
            "{},{},{},{},{},{:.3}",
            r.name, m.status, m.t_reached, m.steps, m.rhs_evals, m.wall_time_s
        ));
        for (_, p, rpm) in &r.peaks {
            s.push_str(&format!(",{p:.6e},{rpm:.1}"));
        }
        s.push('\n');
    }
    fs::write(path, s).map_err(|e| format!("{}: {e}", path.display()))
}
