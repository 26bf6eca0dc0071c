//! What one right-hand side of a generated scene costs, and its parts: the back end's M1 and h
//! (`eval_states`), the dense Cholesky of M1 it replaces, and `FirstOrder::rhs` as the
//! integrators call it (M1 through its low-rank structure where it applies).
//! `cargo run --release --example rhs_probe -- [SCENE]` (default `elastic`; docs/performance.md
//! quotes its output). With `ONLY_RHS=1` it times the right-hand side alone (for a profiler).

use std::time::Instant;
use washdyn_ode::OdeSystem;
use washdyn_runtime::system::{FirstOrder, Mechanical};

fn per_call(k: usize, f: impl FnMut(usize)) -> f64 {
    let t0 = Instant::now();
    (0..k).for_each(f);
    t0.elapsed().as_secs_f64() / k.max(1) as f64 * 1e6
}

fn main() {
    let scene = std::env::args().nth(1).unwrap_or_else(|| "elastic".into());
    let only_rhs = std::env::var("ONLY_RHS").is_ok();
    let mut g = washdyn_models::generated("reference", &scene).expect("a built-in scene");
    let lay = g.layout();
    let (n1, n, nz) = (lay.n1, lay.n(), lay.nz);
    let q: Vec<f64> = (0..n).map(|i| 1e-5 * (i as f64).sin()).collect();
    let qd: Vec<f64> = (0..n).map(|i| 1e-4 * (i as f64).cos()).collect();
    let z = vec![1e-5; nz];
    let (mut m1, mut h, mut zd) = (vec![0.0; n1 * n1], vec![0.0; n], vec![0.0; nz]);
    let t = |i: usize| 10.0 + i as f64 * 1e-4;
    if !only_rhs {
        let us = per_call(2000, |i| {
            g.eval_states(t(i), &q, &qd, &z, &mut m1, &mut h, &mut zd)
        });
        println!("M1 and h: {us:.1} us");
        let mut l = m1.clone();
        let us = per_call(2000, |_| {
            l.copy_from_slice(&m1);
            washdyn_model::linalg::cholesky_in_place(&mut l, n1);
        });
        println!("dense Cholesky of M1 (n1 = {n1}): {us:.1} us");
    }
    let mut fo = FirstOrder::new(g);
    let mut y = vec![0.0; fo.dim()];
    y[..n].copy_from_slice(&q);
    y[n..2 * n].copy_from_slice(&qd);
    let mut dy = vec![0.0; fo.dim()];
    let k = if only_rhs { 40_000 } else { 2000 };
    let us = per_call(k, |i| fo.rhs(t(i), &y, &mut dy));
    println!("right-hand side: {us:.1} us");
}
