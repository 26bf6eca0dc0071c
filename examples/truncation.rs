//! What modal truncation costs: the `elastic` scene with its eigenmodes cut at each frequency
//! (the dropped modes' static response to every element load kept, `ModalData::truncate`)
//! against all the modal data's modes, at constant drum speeds on the steady state (2 s from
//! rest under the mean loads, compared over the next second, sampled at 20 kHz so the tub's
//! modes to 6.6 kHz do not alias). Errors: the sensor accelerations in the 300 Hz analysis
//! band (`analysis::metrics::band_error`), and drum orders 1-6 (Hann window, within 40 dB of the
//! channel's strongest order). Regenerates docs/truncation.md:
//! `cargo run --release --example truncation -- [RPM...] > docs/truncation.md`.
//! With `--deep DIR` the reference is the model with each body's modal data from
//! `DIR/<body>.modal.toml` where it exists (fe's `modes_2k` example: the drum with `spin`),
//! every mode kept, and the rows are the committed data's cuts against it. `--cuts 210,700`
//! runs only those cuts; `--against DIR2` puts DIR2's data where the committed data was (and
//! leaves out the row of every mode, which would be DIR2's whole data);
//! `--method auto` integrates with another method than dopri5. The reference and the rows run
//! side by side on all cores (rayon), so their wall times are measured under the same load.

use std::time::Instant;
use washdyn::accuracy::TRUNCATION_CUTS_HZ;
use washdyn::analysis::metrics::{BAND_HZ, ORDER_FLOOR, band_error, is_accel};
use washdyn::analysis::spectrum::Window;
use washdyn_model::ir::EffectSet;
use washdyn_model::ir::modal::read_file;
use washdyn_ode::{AnySolver, Method, Options};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Guard, Labels, RunOptions, Start, run_guarded};
use washdyn_runtime::system::{FirstOrder, Interpreter};

const SAMPLE_RATE: f64 = 20_000.0;
const SETTLE: f64 = 2.0;
const WINDOW: f64 = 1.0;
const TOL: f64 = 1e-7;

/// A reference run as `--cache` keeps it: coordinates, steps, wall s, the compared window.
type Cached = (usize, u64, f64, Vec<(String, Vec<f64>)>);

struct Run {
    n: usize,
    wall: f64,
    steps: u64,
    mem: MemorySink,
}

/// Each body's modal data in words.
fn describe(m: &washdyn_model::ir::Model) -> Vec<String> {
    m.elastic
        .iter()
        .filter_map(|e| {
            let d = e.data.as_ref()?;
            Some(format!(
                "{}: {} eigenmodes to {:.0} Hz + {} correction",
                e.name,
                d.eigenmodes(),
                d.frequencies[d.eigenmodes() - 1],
                d.modes() - d.eigenmodes()
            ))
        })
        .collect()
}

/// The reference model with its modal data replaced by DIR's where DIR has a body's file.
fn deep(dir: &str) -> (washdyn_model::ir::Model, Vec<String>) {
    let mut m = washdyn_models::reference();
    for e in &mut m.elastic {
        let p = std::path::Path::new(dir).join(format!("{}.modal.toml", e.name));
        if p.exists() {
            e.data = Some(read_file(&p, &p.display().to_string()).expect("deep modal data"));
        }
    }
    let used = describe(&m);
    (m, used)
}

fn run(base: &washdyn_model::ir::Model, rpm: f64, cutoff: Option<f64>, method: Method) -> Run {
    let mut m = base.clone();
    m.speed.table = vec![[0.0, rpm], [1000.0, rpm]];
    let s = EffectSet {
        mode_cutoff: cutoff,
        ..m.scene(Some("elastic")).expect("scene")
    };
    let mut sys = FirstOrder::new(Interpreter::new(&m, &s));
    let n = sys.layout().n();
    let opts = Options {
        rtol: TOL,
        atol: TOL * 1e-3,
        ..Options::default()
    };
    let mut solver = AnySolver::new(method, 2 * n, opts);
    let mut mem = MemorySink::default();
    let ropts = RunOptions {
        t_start: 0.0,
        t_end: SETTLE + WINDOW,
        sample_rate: SAMPLE_RATE,
        start: Start::MeanLoad,
    };
    let labels = Labels {
        model: m.name.clone(),
        scene: s.name.clone(),
        backend: "interpreted".into(),
    };
    let t = Instant::now();
    let summary = run_guarded(
        &mut sys,
        &mut solver,
        &ropts,
        &labels,
        (TOL, TOL * 1e-3),
        &mut mem,
        &mut |_| {},
        // A study runs as long as it takes (a stiff reference beside other jobs projects
        // past the default's hour).
        &Guard {
            max_projected_s: f64::INFINITY,
            ..Guard::default()
        },
    )
    .unwrap_or_else(|(e, _)| panic!("{rpm} rpm, cut {cutoff:?}: {e}"));
    Run {
        n,
        wall: t.elapsed().as_secs_f64(),
        steps: summary.steps,
        mem,
    }
}

/// The acceleration channels over the compared window.
fn window(m: &MemorySink) -> Vec<(String, Vec<f64>)> {
    let skip = (SETTLE * SAMPLE_RATE).round() as usize;
    (0..m.channels.len())
        .filter(|&c| is_accel(&m.channels[c]))
        .map(|c| (m.channels[c].clone(), m.column(c)[skip..].to_vec()))
        .collect()
}

/// Amplitude of the component at `f` (Hz): Hann-windowed DFT at `f`, amplitude-corrected.
fn amplitude(x: &[f64], f: f64) -> f64 {
    let hann = Window::hann(x.len());
    let (mut re, mut im) = (0.0, 0.0);
    for (k, (v, w)) in x.iter().zip(hann.coeffs()).enumerate() {
        let p = 2.0 * std::f64::consts::PI * f * k as f64 / SAMPLE_RATE;
        re += v * w * p.cos();
        im += v * w * p.sin();
    }
    2.0 * (re * re + im * im).sqrt() / x.len() as f64 * hann.amplitude_correction()
}

/// Remove `flag` and the value after it from `args`; the value, if the flag is there.
fn take(args: &mut Vec<String>, flag: &str) -> Option<String> {
    let i = args.iter().position(|a| a == flag)?;
    let v = args
        .get(i + 1)
        .unwrap_or_else(|| panic!("{flag} needs a value"))
        .clone();
    args.drain(i..i + 2);
    Some(v)
}

/// The command line, flags taken out; `rest` holds the speeds.
struct Args {
    deep_dir: Option<String>,
    cut_list: Vec<f64>,
    against: Option<String>,
    cache: Option<String>,
    method: Method,
    rest: Vec<String>,
}

fn parse_args() -> Args {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let deep_dir = take(&mut args, "--deep");
    // `--cuts 210,700`: only these cuts (Hz) instead of the study's list.
    let cut_list: Vec<f64> = take(&mut args, "--cuts").map_or_else(
        || TRUNCATION_CUTS_HZ.to_vec(),
        |v| {
            v.split(',')
                .map(|c| c.parse().expect("cut in Hz"))
                .collect()
        },
    );
    // `--against DIR2`: the rows are the model with DIR2's data instead of the committed data
    // (two deep references against each other).
    let against = take(&mut args, "--against");
    // `--cache DIR`: the reference's compared window is read from DIR if a run left it there,
    // else run and left there (the deep reference costs minutes).
    let cache = take(&mut args, "--cache");
    let method: Method = take(&mut args, "--method")
        .map_or(Method::Dopri5, |v| v.parse().expect("an integrator's name"));
    Args {
        deep_dir,
        cut_list,
        against,
        cache,
        method,
        rest: args,
    }
}

/// The report's title, what it compares and the table's head.
fn header(a: &Args, committed: &washdyn_model::ir::Model, used: &[String]) {
    println!("# Modal truncation of the elastic machine\n");
    println!(
        "`cargo run --release --example truncation -- {}` (interpreted, {} rtol {TOL:e}). \
         Each row: the `elastic` scene with the eigenmodes up to the cut, the dropped \
         eigenmodes and the correction modes folded into their static response to every \
         element load (a body uncut keeps its correction modes), against the reference below, at constant speed: 2 s from rest under the mean \
         loads, compared over the next 1 s sampled at 20 kHz. accel: worst relative error of \
         the sensor accelerations in the {BAND_HZ} Hz band; orders: worst |dB| of drum orders \
         1-6 within 40 dB of the channel's strongest (and within 20 dB: the weak even orders \
         of the cabinet's channels, 25-38 dB down, set the first). Wall times on a shared \
         2-core machine. The committed modal data: {}.\n",
        std::env::args().skip(1).collect::<Vec<_>>().join(" "),
        a.method.name(),
        describe(committed).join("; ")
    );
    if let Some(d) = &a.deep_dir {
        println!(
            "Reference (`--deep {d}`): every mode of the committed data, with DIR's where it \
             has a body's: {}.\n",
            used.join("; ")
        );
    } else {
        println!("Reference: every mode of the committed data.\n");
    }
    println!(
        "| rpm | modes up to Hz | coordinates | steps | wall s | accel | orders dB | orders \
         within 20 dB, dB |"
    );
    println!("|---|---|---|---|---|---|---|---|");
}

/// Drum orders 1-6 of `x` at the drum frequency `f0`, Hz.
fn orders(x: &[f64], f0: f64) -> Vec<f64> {
    (1..=6)
        .map(|o| amplitude(x, o as f64 * f0))
        .collect::<Vec<_>>()
}

/// A row's errors against the reference's window `rw` and its orders `ro`: the worst
/// acceleration error in the band, the worst |dB| of the orders within 40 dB and within 20 dB
/// of the channel's strongest.
fn errors(
    cw: &[(String, Vec<f64>)],
    rw: &[(String, Vec<f64>)],
    ro: &[Vec<f64>],
    f0: f64,
) -> (f64, f64, f64) {
    let (mut accel, mut db, mut db20) = (0.0f64, 0.0f64, 0.0f64);
    for ((name, x), ((rn, y), yo)) in cw.iter().zip(rw.iter().zip(ro)) {
        assert_eq!(name, rn);
        accel = accel.max(band_error(x, y, SAMPLE_RATE, BAND_HZ).unwrap_or(0.0));
        let peak = yo.iter().fold(0.0f64, |a, b| a.max(*b));
        for (a, b) in orders(x, f0).iter().zip(yo) {
            let e = (20.0 * (a / b).log10()).abs();
            if *b >= ORDER_FLOOR * peak {
                db = db.max(e);
            }
            if *b >= 0.1 * peak {
                db20 = db20.max(e);
            }
        }
    }
    (accel, db, db20)
}

/// The rows of one speed: each cut against the reference (run, or read from `--cache`), side
/// by side on all cores, then the reference's own row.
fn speed_rows(
    a: &Args,
    reference: &washdyn_model::ir::Model,
    committed: &washdyn_model::ir::Model,
    rpm: f64,
) {
    let f0 = rpm / 60.0;
    // Against a deep reference, the committed data with every mode is a row of its own.
    let cuts: Vec<Option<f64>> = a
        .cut_list
        .iter()
        .map(|c| Some(*c))
        .chain(
            a.deep_dir
                .as_ref()
                .filter(|_| a.against.is_none())
                .map(|_| None),
        )
        .collect();
    let cached = a
        .cache
        .as_ref()
        .map(|d| std::path::Path::new(d).join(format!("reference_{rpm}.json")));
    let stored: Option<Cached> = cached
        .as_ref()
        .filter(|p| p.exists())
        .map(|p| serde_json::from_slice(&std::fs::read(p).expect("cache")).expect("cache"));
    let method = a.method;
    let mut runs: Vec<Option<Run>> = {
        use rayon::prelude::*;
        std::iter::once((reference, None, stored.is_none()))
            .chain(cuts.iter().map(|c| (committed, *c, true)))
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|(m, cut, go)| go.then(|| run(m, rpm, cut, method)))
            .collect()
    };
    let (rn, rsteps, rwall, rw) = match (runs.remove(0), stored) {
        (Some(r), _) => (r.n, r.steps, r.wall, window(&r.mem)),
        (None, Some(s)) => s,
        (None, None) => unreachable!(),
    };
    if let Some(p) = &cached {
        let s = (rn, rsteps, rwall, &rw);
        std::fs::write(p, serde_json::to_vec(&s).expect("json")).expect("cache");
    }
    let runs: Vec<Run> = runs.into_iter().flatten().collect();
    let ro: Vec<Vec<f64>> = rw.iter().map(|(_, x)| orders(x, f0)).collect();
    for (cut, c) in cuts.into_iter().zip(runs) {
        let (accel, db, db20) = errors(&window(&c.mem), &rw, &ro, f0);
        let cut = cut.map_or("all committed".into(), |c| format!("{c}"));
        println!(
            "| {rpm} | {cut} | {} | {} | {:.1} | {accel:.1e} | {db:.3} | {db20:.3} |",
            c.n, c.steps, c.wall
        );
    }
    println!("| {rpm} | all | {rn} | {rsteps} | {rwall:.1} | 0 | 0 | 0 |");
}

fn main() {
    let a = parse_args();
    let committed = match &a.against {
        Some(d) => deep(d).0,
        None => washdyn_models::reference(),
    };
    let (reference, used) = match &a.deep_dir {
        Some(d) => deep(d),
        None => (committed.clone(), Vec::new()),
    };
    let rpms: Vec<f64> = a.rest.iter().map(|r| r.parse().expect("rpm")).collect();
    let rpms = if rpms.is_empty() { vec![1400.0] } else { rpms };
    header(&a, &committed, &used);
    for rpm in rpms {
        speed_rows(&a, &reference, &committed, rpm);
    }
}
