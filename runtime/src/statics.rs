//! Static equilibrium h(q, 0, t0) = 0 by Newton's method with a finite-difference Jacobian: the
//! start of a run, so the tub does not drop under the unbalance's extra weight. Set-up code: it
//! may allocate.

use crate::ode::lu::{lu_factor, lu_solve};
use crate::system::Mechanical;

/// Solve for the rest position at time t0 (velocities zero). Returns q.
pub fn static_equilibrium<S: Mechanical>(sys: &mut S, t0: f64) -> Result<Vec<f64>, String> {
    let lay = sys.layout();
    let (n, n1) = (lay.n(), lay.n1);
    let mut m1 = vec![0.0; n1 * n1];
    let zero = vec![0.0; n];
    let mut q = vec![0.0; n];
    let mut h = vec![0.0; n];
    let mut hp = vec![0.0; n];
    let eps = 1e-7;
    for _ in 0..50 {
        sys.eval(t0, &q, &zero, &mut m1, &mut h);
        let res = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if res < 1e-10 {
            return Ok(q);
        }
        // Row-major dh/dq by forward differences.
        let mut k = vec![0.0; n * n];
        for j in 0..n {
            let mut qp = q.clone();
            qp[j] += eps;
            sys.eval(t0, &qp, &zero, &mut m1, &mut hp);
            for i in 0..n {
                k[i * n + j] = (hp[i] - h[i]) / eps;
            }
        }
        let mut piv = vec![0; n];
        lu_factor(&mut k, n, &mut piv)
            .map_err(|_| "static equilibrium: singular stiffness (a free rigid-body motion?)")?;
        let mut dq: Vec<f64> = h.iter().map(|v| -v).collect();
        lu_solve(&k, n, &piv, &mut dq);
        for i in 0..n {
            q[i] += dq[i];
        }
    }
    Err("static equilibrium: Newton did not converge in 50 iterations".into())
}
