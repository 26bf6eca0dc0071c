//! Nothing allocates in the step loop: a whole run allocates the same number of times whether
//! it simulates 1 s or 10 s, so every allocation is set-up (counting global allocator).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io;
use washdyn_ode::{AnySolver, Method, Options};
use washdyn_runtime::output::SampleSink;
use washdyn_runtime::run::{Labels, RunOptions, run};
use washdyn_runtime::system::{FirstOrder, Interpreter, Mechanical};

struct Counting;

thread_local! {
    /// Per thread, so tests running in parallel do not count each other's allocations.
    static ALLOCS: Cell<u64> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Counts samples, keeps nothing.
struct Null(u64);
impl SampleSink for Null {
    fn header(&mut self, _: &[String]) -> io::Result<()> {
        Ok(())
    }
    fn sample(&mut self, _: f64, _: f64, _: &[f64]) -> io::Result<()> {
        self.0 += 1;
        Ok(())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// Allocations of a whole run of `sys` over [0, t_end] with `method`, and the samples it wrote.
pub fn allocations<S: Mechanical>(
    sys: S,
    method: Method,
    t_end: f64,
    sample_rate: f64,
) -> (u64, u64) {
    let mut sys = FirstOrder::new(sys);
    let n = sys.layout().dim();
    let opts = Options {
        rtol: 1e-5,
        atol: 1e-8,
        h0: if method == Method::Rk4 { 2e-4 } else { 0.0 },
        ..Options::default()
    };
    let mut solver = AnySolver::new(method, n, opts);
    let mut sink = Null(0);
    let ro = RunOptions {
        t_end,
        sample_rate,
        ..RunOptions::default()
    };
    let before = ALLOCS.with(Cell::get);
    let r = run(
        &mut sys,
        &mut solver,
        &ro,
        &Labels::default(),
        (1e-5, 1e-8),
        &mut sink,
        &mut |_| {},
    );
    let after = ALLOCS.with(Cell::get);
    assert!(r.is_ok(), "{:?}", r.err().map(|e| e.0.to_string()));
    (after - before, sink.0)
}

/// A step loop that allocates shows in any ten-fold window: the allocations of a short run and
/// of a run ten times as long must be equal, and the long one must have sampled more than nine
/// times as often (20 samples in the short window, whatever its length).
fn same_allocations<S: Mechanical>(
    make: impl Fn() -> S,
    method: Method,
    (short, long): (f64, f64),
    what: &str,
) {
    let rate = 20.0 / short;
    let (a_short, ns) = allocations(make(), method, short, rate);
    let (a_long, nl) = allocations(make(), method, long, rate);
    assert!(
        nl > 9 * ns,
        "{what}/{method}: the long run sampled {nl}, the short {ns}"
    );
    assert_eq!(
        a_short, a_long,
        "{what}/{method}: allocations grow with the simulated time"
    );
}

/// The short and long runs: 0.5 and 5 s on the rigid scenes (the test took 96 s of CI with 1 and
/// 10 s). On the elastic cabinet's scene (arctan friction) dopri5 runs on its stability limit
/// while the friction dampers stick, so its windows are 50 and 500 ms (18 s with 0.5 and 5 s).
/// Every method takes 30 and 300 ms on the reference's `elastic` (its dampers as built: dopri5
/// turns stiff at 23 ms, inside both windows, so the warning's one allocation is in both).
fn window(method: Method, scene: Scene) -> (f64, f64) {
    match (scene, method) {
        (Scene::Rigid, _) => (0.5, 5.0),
        (Scene::ElasticCabinet, Method::Dopri5) => (0.05, 0.5),
        (Scene::ElasticCabinet, _) => (0.5, 5.0),
        (Scene::Elastic, _) => (0.03, 0.3),
    }
}

/// The scenes' kinds, by what their windows must be.
#[derive(Clone, Copy)]
enum Scene {
    Rigid,
    ElasticCabinet,
    Elastic,
}

/// The implicit methods and the composite one, with dopri5.
const ADAPTIVE: [Method; 5] = [
    Method::Dopri5,
    Method::Sdirk4,
    Method::Rodas4,
    Method::GeneralizedAlpha,
    Method::Auto,
];

#[test]
fn interpreted_run_allocates_only_at_set_up() {
    // The reference run-up's first seconds with every effect on, and the elastic cabinet's
    // scene, with every method.
    for (m, scene, kind) in [
        (washdyn_models::reference(), "full", Scene::Rigid),
        (
            washdyn_models::elastic_cabinet::model(),
            "elastic",
            Scene::ElasticCabinet,
        ),
    ] {
        let effects = m.scene(Some(scene)).unwrap();
        for method in Method::ALL {
            let make = || Interpreter::new(&m, &effects);
            same_allocations(make, method, window(method, kind), scene);
        }
    }
    // The reference's elastic scene (tub, drum and cabinet modes), the implicit methods with
    // its structured force Jacobians.
    let m = washdyn_models::reference();
    let effects = m.scene(Some("elastic")).unwrap();
    for method in ADAPTIVE {
        let make = || Interpreter::new(&m, &effects);
        same_allocations(make, method, window(method, Scene::Elastic), "elastic");
    }
}

#[test]
fn generated_run_allocates_only_at_set_up() {
    for (model, scene, kind) in [
        ("reference", "full", Scene::Rigid),
        ("reference", "rigid_low_speed", Scene::Rigid),
        // The dampers' moving parts (subsystem 2's rigid parts, their joints) and the contacts.
        ("reference", "damper_mass", Scene::Rigid),
        // The counterweights on their bolts: rigid parts of six coordinates, slider states.
        ("reference", "counterweights", Scene::Rigid),
        ("reference", "contact", Scene::Rigid),
        ("elastic_cabinet", "elastic", Scene::ElasticCabinet),
        // Above the traced size: the generated M1 and h, the force Jacobians over dual numbers.
        ("reference", "elastic", Scene::Elastic),
    ] {
        for method in ADAPTIVE {
            let make = || washdyn_models::generated(model, scene).unwrap();
            let what = format!("{model}/{scene}");
            same_allocations(make, method, window(method, kind), &what);
        }
    }
}
