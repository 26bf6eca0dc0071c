//! Generated vs interpreted back end, per scene of the reference machine: one M1+h evaluation,
//! one q'' evaluation (M1 factorised), and a whole run-up; and what free parameters cost: the
//! reference (its suspension free) against the same machine with every number folded. Ratios
//! for the README come from one run of this bench (`cargo bench --bench backends`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::io;
use washdyn::spec::RunSpec;
use washdyn_model::equations::{Equations, JacobianWork};
use washdyn_ode::{AnySolver, Dopri5, Method, OdeSystem, Options, Solver, Stepper};
use washdyn_runtime::output::SampleSink;
use washdyn_runtime::run::{Labels, RunOptions, run};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

/// The reference machine with nothing free: every number a literal of its generated code.
mod folded {
    washdyn_macros::machine! {
        /// The reference, folded.
        reference_folded {
            base: "models/data/reference.toml",
            free: [],
        }
    }
}

/// A state in the middle of the run-up (0.5 mm, 1 mrad, 0.1 m/s).
fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
    let q = (0..n).map(|i| if i < 3 { 5e-4 } else { 1e-3 }).collect();
    let qd = (0..n).map(|i| 0.1 / (i + 1) as f64).collect();
    (q, qd)
}

fn evaluations(c: &mut Criterion) {
    let m = washdyn_models::reference();
    // The generated code's operation counts, to set the timings against (flops per evaluation).
    let (_, stats) = washdyn_model::codegen::generate_with_stats(&m).unwrap();
    for s in &stats {
        eprintln!(
            "scene {}: n1 {} n2 {}; M1 + h {} operations; q'' {} operations",
            s.scene, s.n1, s.n2, s.ops_mass_forces, s.ops_accelerations
        );
    }
    for scene in m.scene_names() {
        let eff = m.scene(Some(&scene)).unwrap();
        let mut interp = Interpreter::new(&m, &eff);
        let mut gen_ = washdyn_models::generated("reference", &scene).unwrap();
        let lay = interp.layout();
        let (n, n1) = (lay.n(), lay.n1);
        let (q, qd) = state(n);
        let (mut m1, mut h) = (vec![0.0; n1 * n1], vec![0.0; n]);
        let t = 120.0;
        let mut g = c.benchmark_group(format!("mass_and_forces/{scene}"));
        g.bench_function("interpreted", |b| {
            b.iter(|| interp.eval(black_box(t), black_box(&q), black_box(&qd), &mut m1, &mut h))
        });
        g.bench_function("generated", |b| {
            b.iter(|| gen_.eval(black_box(t), black_box(&q), black_box(&qd), &mut m1, &mut h))
        });
        g.finish();
        // The same evaluation with the suspension's numbers folded in.
        let mut fold = folded::reference_folded::system(&scene).unwrap();
        let mut g = c.benchmark_group(format!("free_parameters/mass_and_forces/{scene}"));
        g.bench_function("free", |b| {
            b.iter(|| gen_.eval(black_box(t), black_box(&q), black_box(&qd), &mut m1, &mut h))
        });
        g.bench_function("folded", |b| {
            b.iter(|| fold.eval(black_box(t), black_box(&q), black_box(&qd), &mut m1, &mut h))
        });
        g.finish();
        let mut fa = FirstOrder::new(Interpreter::new(&m, &eff));
        let mut qdd = vec![0.0; n];
        let mut g = c.benchmark_group(format!("accelerations/{scene}"));
        g.bench_function("interpreted", |b| {
            b.iter(|| fa.accelerations(black_box(t), black_box(&q), black_box(&qd), &mut qdd))
        });
        g.bench_function("generated", |b| {
            b.iter(|| gen_.accelerations(black_box(t), black_box(&q), black_box(&qd), &mut qdd))
        });
        g.finish();
        // dh/dq and dh/dq' exactly, by structure (elements' local Jacobians through their
        // markers' maps) and by the whole derivation over dual numbers, against what the
        // implicit methods did without them: forward differences of q'' over the 2n state columns (2n + 1
        // generated q'' evaluations).
        let (mut hq, mut hqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        let mut g = c.benchmark_group(format!("jacobians/{scene}"));
        g.bench_function("structured_interpreted", |b| {
            b.iter(|| interp.force_jacobians(black_box(t), &q, &qd, &mut hq, &mut hqd))
        });
        let eq = Equations::new(&m, &eff);
        let mut work = JacobianWork::new(&eq);
        let d = interp.speed().drive(t);
        g.bench_function("dual_whole_derivation", |b| {
            b.iter(|| eq.force_jacobians_dual(black_box(&d), &q, &qd, &mut work, &mut hq, &mut hqd))
        });
        let mut y = [q.clone(), qd.clone()].concat();
        let mut out = vec![0.0; n];
        g.bench_function("differences_generated", |b| {
            b.iter(|| {
                gen_.accelerations(t, &y[..n], &y[n..], &mut out);
                for j in 0..2 * n {
                    let yj = y[j];
                    y[j] = yj + 1e-7;
                    let (a, v) = y.split_at(n);
                    gen_.accelerations(t, a, v, &mut out);
                    y[j] = yj;
                }
                black_box(&out);
            })
        });
        g.finish();
    }
}

struct Null;
impl SampleSink for Null {
    fn header(&mut self, _: &[String]) -> io::Result<()> {
        Ok(())
    }
    fn sample(&mut self, _: f64, _: f64, v: &[f64]) -> io::Result<()> {
        black_box(v);
        Ok(())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

fn run_up<S: Mechanical>(sys: S) -> u64 {
    let mut sys = FirstOrder::new(sys);
    let n = 2 * sys.layout().n();
    // `washdyn run`'s options for dopri5 at its default tolerance (rtol 1e-6, atol 1e-9).
    let opts = RunSpec::default().options(Method::Dopri5, 1e-6);
    let mut solver = Dopri5::new(n, opts);
    let ro = RunOptions {
        t_end: sys.sys.speed().end(),
        sample_rate: 2000.0,
        ..RunOptions::default()
    };
    let s = run(
        &mut sys,
        &mut solver,
        &ro,
        &Labels::default(),
        (opts.rtol, opts.atol),
        &mut Null,
        &mut |_| {},
    )
    .map_err(|e| e.0.to_string())
    .unwrap();
    s.rhs_evals
}

fn run_ups(c: &mut Criterion) {
    let m = washdyn_models::reference();
    let mut g = c.benchmark_group("run_up_178s_dopri5");
    g.sample_size(10);
    // The rigid scenes; the elastic scene's run-up (minutes) is in benches/runup_report.sh.
    for scene in m.scene_names().into_iter().filter(|s| s != "elastic") {
        let eff = m.scene(Some(&scene)).unwrap();
        g.bench_with_input(BenchmarkId::new("interpreted", &scene), &scene, |b, _| {
            b.iter(|| run_up(Interpreter::new(&m, &eff)))
        });
        g.bench_with_input(BenchmarkId::new("generated", &scene), &scene, |b, s| {
            b.iter(|| run_up(washdyn_models::generated("reference", s).unwrap()))
        });
        g.bench_with_input(
            BenchmarkId::new("generated_folded", &scene),
            &scene,
            |b, s| b.iter(|| run_up(folded::reference_folded::system(s).unwrap())),
        );
    }
    g.finish();
}

/// The first-order form with its ported form withheld: the implicit methods factorise the
/// dense n x n mass form, as before `OdeSystem::ported_jacobians`.
struct Dense<S: Mechanical>(FirstOrder<S>);

impl<S: Mechanical> OdeSystem for Dense<S> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.0.rhs(t, y, dy)
    }
    fn mass_jacobians(
        &mut self,
        t: f64,
        y: &[f64],
        m: &mut [f64],
        hq: &mut [f64],
        hqd: &mut [f64],
    ) -> bool {
        self.0.mass_jacobians(t, y, m, hq, hqd)
    }
    fn second_order(&self) -> Option<usize> {
        self.0.second_order()
    }
    fn atol_scales(&self, s: &mut [f64]) {
        self.0.atol_scales(s)
    }
}

/// `STEPS` steps of an implicit method from rest at 60 s (the tub settling, the dampers
/// stuck: the run-up's stiff phase).
fn implicit_steps<S: OdeSystem>(sys: &mut S, solver: &mut AnySolver) -> f64 {
    const STEPS: usize = 20;
    let y0 = vec![0.0; sys.dim()];
    solver.init(sys, 60.0, &y0).unwrap();
    for _ in 0..STEPS {
        solver.step(sys, 61.0).unwrap();
    }
    solver.y()[0]
}

/// rodas4, sdirk4 and generalized-alpha on the elastic scenes (generated), factorising the ported n1 + r matrix
/// (`washdyn_ode::ported`) against the dense n x n mass form: 20 steps each. The elastic scenes'
/// dampers carry states: generalized-alpha's ported matrix holds them (n1 + r + nz), its
/// "dense" route differences the whole Jacobian, as sdirk4 and rodas4 do on both.
fn ported(c: &mut Criterion) {
    for scene in ["elastic", "elastic_rigid_tub"] {
        let gen_ = || FirstOrder::new(washdyn_models::generated("reference", scene).unwrap());
        let dim = gen_().dim();
        let opts = Options {
            rtol: 1e-6,
            atol: 1e-9,
            ..Options::default()
        };
        let mut g = c.benchmark_group(format!("implicit_20_steps/{scene}"));
        g.sample_size(10);
        for method in [Method::Rodas4, Method::Sdirk4, Method::GeneralizedAlpha] {
            let (mut p, mut d) = (gen_(), Dense(gen_()));
            let mut solver = AnySolver::new(method, dim, opts);
            g.bench_function(format!("{method}_ported"), |b| {
                b.iter(|| implicit_steps(&mut p, &mut solver))
            });
            eprintln!("{scene} {method} ported: {:?}", solver.stats());
            let mut solver = AnySolver::new(method, dim, opts);
            g.bench_function(format!("{method}_dense"), |b| {
                b.iter(|| implicit_steps(&mut d, &mut solver))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, evaluations, run_ups, ported);
criterion_main!(benches);
