//! The integrators must not allocate after construction: `init`, `step` and `interpolate` run
//! on preallocated work arrays (simulation loops call them millions of times). A counting
//! global allocator checks it; counts are per thread so parallel tests do not interfere.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use washdyn_ode::problems::{Hires, VanDerPol};
use washdyn_ode::{AnySolver, Method, OdeSystem, Options, Solver, Stepper};

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> u64 {
    ALLOCATIONS.with(|c| c.get())
}

/// Runs `solver` over [t0, t_end] with re-inits at the stops and dense output at 10 points per
/// step; returns the allocations counted during init/step/interpolate and the step count.
fn run<S: OdeSystem>(
    solver: &mut AnySolver,
    sys: &mut S,
    y0: &[f64],
    stops: &[f64],
    out: &mut [f64],
) -> (u64, u64) {
    let before = allocations();
    Solver::<S>::init(solver, sys, 0.0, y0).unwrap();
    for &stop in stops {
        while solver.t() < stop {
            Solver::<S>::step(solver, sys, stop).unwrap();
            let (a, b) = (solver.t_prev(), solver.t());
            for k in 0..=10 {
                solver.interpolate(a + (b - a) * k as f64 / 10.0, out);
            }
        }
        // As after a discontinuity at the stop: restart from the current state.
        out.copy_from_slice(solver.y());
        Solver::<S>::init(solver, sys, stop, out).unwrap();
    }
    (allocations() - before, solver.stats().steps)
}

#[test]
fn integrators_do_not_allocate_after_construction() {
    for m in Method::ALL {
        if m == Method::Imex {
            // A problem with a linear part (HIRES and VDPOL name none), refactorisations as
            // the step changes.
            let mut sys = washdyn_ode::problems::Coupled {
                omega: 1e4,
                zeta: 0.02,
            };
            let mut solver = AnySolver::new(m, 4, Options::default());
            let mut out = vec![0.0; 4];
            let y0 = [0.1, 0.0, 0.0, 0.0];
            let (allocs, steps) = run(&mut solver, &mut sys, &y0, &[0.5, 1.0], &mut out);
            assert!(steps > 10, "{m}: only {steps} steps");
            assert_eq!(allocs, 0, "{m} allocated {allocs} times");
            continue;
        }
        // HIRES, with the analytic and the finite-difference Jacobian (first order: not for
        // generalized-alpha, which refuses it).
        for analytic in [true, false] {
            if m == Method::GeneralizedAlpha {
                break;
            }
            let mut sys = Hires {
                analytic_jacobian: analytic,
            };
            let opts = Options {
                rtol: 1e-6,
                atol: 1e-9,
                h0: if m == Method::Rk4 { 1e-3 } else { 0.0 },
                ..Options::default()
            };
            let mut solver = AnySolver::new(m, 8, opts);
            let mut out = vec![0.0; 8];
            let (allocs, steps) = run(&mut solver, &mut sys, &Hires::Y0, &[1.0, 5.0], &mut out);
            assert!(steps > 10, "{m}: only {steps} steps");
            assert_eq!(
                allocs, 0,
                "{m} (analytic J {analytic}) allocated {allocs} times"
            );
        }
        // Stiff Van der Pol (rejections, Newton failures and Jacobian refreshes).
        if m.implicit() {
            let mut sys = VanDerPol { eps: 1e-6 };
            let mut solver = AnySolver::new(m, 2, Options::default());
            let mut out = vec![0.0; 2];
            let (allocs, steps) = run(&mut solver, &mut sys, &[2.0, 0.0], &[0.5, 1.0], &mut out);
            let st = solver.stats();
            assert!(steps > 100 && st.rejected_steps > 0, "{st:?}");
            assert_eq!(allocs, 0, "{m} on VDPOL allocated {allocs} times");
        }
    }
}

/// The failure paths build their errors from plain data, without allocating either.
#[test]
fn errors_do_not_allocate() {
    for m in [Method::Dopri5, Method::Sdirk4] {
        let mut sys = washdyn_ode::problems::Blowup;
        let mut solver = AnySolver::new(m, 1, Options::default());
        let before = allocations();
        Solver::<_>::init(&mut solver, &mut sys, 0.0, &[1.0]).unwrap();
        let mut err = None;
        while err.is_none() {
            err = Solver::<_>::step(&mut solver, &mut sys, 2.0).err();
        }
        assert_eq!(allocations() - before, 0, "{m}");
    }
}

/// The counter itself works (guards against a vacuous pass).
#[test]
fn the_counter_sees_allocations() {
    let before = allocations();
    let v = std::hint::black_box(vec![1u8; 100]);
    assert!(allocations() > before);
    drop(v);
}
