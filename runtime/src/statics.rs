//! Static equilibrium h(q, 0, t0) = 0 by Newton's method with a finite-difference Jacobian: the
//! start of a run, so the tub does not drop under the unbalance's extra weight. Set-up code: it
//! may allocate.

use crate::system::Mechanical;
use nalgebra::{DMatrix, DVector};

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
        let mut k = DMatrix::zeros(n, n);
        for j in 0..n {
            let mut qp = q.clone();
            qp[j] += eps;
            sys.eval(t0, &qp, &zero, &mut m1, &mut hp);
            for i in 0..n {
                k[(i, j)] = (hp[i] - h[i]) / eps;
            }
        }
        let dq = k
            .lu()
            .solve(&(-DVector::from_column_slice(&h)))
            .ok_or("static equilibrium: singular stiffness (a free rigid-body motion?)")?;
        for i in 0..n {
            q[i] += dq[i];
        }
    }
    Err("static equilibrium: Newton did not converge in 50 iterations".into())
}
