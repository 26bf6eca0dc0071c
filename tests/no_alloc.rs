//! Nothing allocates in the step loop: a whole run allocates the same number of times whether
//! it simulates 1 s or 10 s, so every allocation is set-up (counting global allocator).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io;
use washdyn_runtime::ode::{AnySolver, Method, Options};
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

/// Allocations of a whole run of `sys` over [0, t_end] with `method`.
pub fn allocations<S: Mechanical>(sys: S, method: Method, t_end: f64) -> (u64, u64) {
    let mut sys = FirstOrder::new(sys);
    let n = 2 * sys.layout().n();
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
        sample_rate: 500.0,
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

/// The short and long runs on the reference's elastic scene. dopri5 runs on its stability
/// limit there while the friction dampers stick (the slope on the brackets' correction modes:
/// 310 k steps for the first second), so its runs are shorter (still ten samples and more).
fn window(method: Method) -> (f64, f64) {
    if method == Method::Dopri5 {
        (0.02, 0.2)
    } else {
        (0.03, 0.3)
    }
}

/// The short and long runs on the rigid scenes: 251 and 2501 samples at 500 Hz (the test took
/// 96 s of CI with 1 s and 10 s; a step loop that allocates shows in any ten-fold window).
const RIGID: (f64, f64) = (0.5, 5.0);

#[test]
fn interpreted_run_allocates_only_at_set_up() {
    // The reference run-up's first seconds with every effect on.
    // And the elastic cabinet's scene.
    for (m, scene) in [
        (washdyn_models::reference(), "full"),
        (washdyn_models::elastic_cabinet::model(), "elastic"),
    ] {
        let scene = m.scene(Some(scene)).unwrap();
        for method in Method::ALL {
            let (short, ns) = allocations(Interpreter::new(&m, &scene), method, RIGID.0);
            let (long, nl) = allocations(Interpreter::new(&m, &scene), method, RIGID.1);
            assert!(
                nl > 9 * ns,
                "{method}: the long run sampled {nl}, the short {ns}"
            );
            assert_eq!(
                short, long,
                "{method}: allocations grow with the simulated time"
            );
        }
    }
    // The reference's elastic scene (tub, drum and cabinet modes): shorter runs (`window`);
    // the implicit methods with its structured force Jacobians.
    let m = washdyn_models::reference();
    let scene = m.scene(Some("elastic")).unwrap();
    for method in [
        Method::Dopri5,
        Method::Sdirk4,
        Method::Rodas4,
        Method::GeneralizedAlpha,
        Method::Auto,
    ] {
        let (t_short, t_long) = window(method);
        let (short, ns) = allocations(Interpreter::new(&m, &scene), method, t_short);
        let (long, nl) = allocations(Interpreter::new(&m, &scene), method, t_long);
        assert!(nl > 9 * ns, "{method}: {nl} vs {ns}");
        assert_eq!(
            short, long,
            "elastic/{method}: allocations grow with the simulated time"
        );
    }
}

#[test]
fn generated_run_allocates_only_at_set_up() {
    for (model, scene) in [
        ("reference", "full"),
        ("reference", "rigid_low_speed"),
        // The dampers' moving parts (subsystem 2's rigid parts, their joints) and the contacts.
        ("reference", "damper_mass"),
        ("reference", "contact"),
        ("elastic_cabinet", "elastic"),
    ] {
        for method in [
            Method::Dopri5,
            Method::Sdirk4,
            Method::Rodas4,
            Method::GeneralizedAlpha,
            Method::Auto,
        ] {
            let sys = || washdyn_models::generated(model, scene).unwrap();
            let (short, ns) = allocations(sys(), method, RIGID.0);
            let (long, nl) = allocations(sys(), method, RIGID.1);
            assert!(nl > 9 * ns);
            assert_eq!(
                short, long,
                "{model}/{scene}/{method}: allocations grow with the simulated time"
            );
        }
    }
    // Above the traced size: the generated M1 and h, the force Jacobians over dual numbers.
    for method in [
        Method::Dopri5,
        Method::Sdirk4,
        Method::Rodas4,
        Method::GeneralizedAlpha,
        Method::Auto,
    ] {
        let sys = || washdyn_models::generated("reference", "elastic").unwrap();
        let (t_short, t_long) = window(method);
        let (short, ns) = allocations(sys(), method, t_short);
        let (long, nl) = allocations(sys(), method, t_long);
        assert!(nl > 9 * ns);
        assert_eq!(short, long, "reference/elastic/{method}: allocations grow");
    }
}
