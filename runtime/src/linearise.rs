//! The one linearisation of the machine about a rest point: M q'' + C q' + K q = f with
//! K = -dh/dq and C = -dh/dq' at (q0, q' = 0) for a given drive, what the rigid modes
//! (`washdyn modes`) and the frequency-domain steady state (`harmonic`) stand on. Set-up code:
//! it may allocate.
//!
//! K and C are the exact force Jacobians of the derivation (`Equations::force_jacobians`, the
//! ones the implicit methods and the static start iterate with): every force element law
//! (springs, linear and friction dampers, damper joints, gaskets, contacts) and the body terms
//! have them by structure, and both back ends present the same `Equations` (the interpreter
//! its own, generated code the model it embeds), so there is no step size to choose and no
//! difference fallback. The element states are held at their assembly value.

use crate::statics::static_equilibrium;
use crate::system::Mechanical;
use nalgebra::{DMatrix, DVector};
use washdyn_model::equations::{Drive, Equations, JacobianWork};

/// The machine linearised about q0 with q' = 0 (n x n matrices over q = [q1; q2]).
#[derive(Clone, Debug)]
pub struct Linearisation {
    /// The drive it was taken at (drum angle, speed, acceleration).
    pub drive: Drive<f64>,
    /// The rest point.
    pub q0: DVector<f64>,
    /// diag(M1(q0), M2).
    pub m: DMatrix<f64>,
    /// -dh/dq at (q0, 0).
    pub k: DMatrix<f64>,
    /// -dh/dq' at (q0, 0).
    pub c: DMatrix<f64>,
    /// h(q0, 0): the load left at q0 (zero at an equilibrium, up to its tolerance).
    pub h0: DVector<f64>,
}

impl Linearisation {
    /// The linearisation of `eq` with the constant M2 `m2` (n2 x n2, row-major) at drive `d`
    /// about q0 (velocities zero).
    pub fn new(eq: &Equations, m2: &[f64], d: &Drive<f64>, q0: &[f64]) -> Linearisation {
        let (n, n1, n2) = (eq.layout.n(), eq.layout.n1, eq.layout.n2);
        let zero = vec![0.0; n];
        let mut m1 = vec![0.0; n1 * n1];
        let mut h = vec![0.0; n];
        eq.eval(d, q0, &zero, &mut m1, &mut h);
        let (mut hq, mut hqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        let mut work = JacobianWork::new(eq);
        eq.force_jacobians(d, q0, &zero, &mut work, &mut hq, &mut hqd);
        let mut m = DMatrix::zeros(n, n);
        m.view_mut((0, 0), (n1, n1))
            .copy_from(&DMatrix::from_row_slice(n1, n1, &m1));
        m.view_mut((n1, n1), (n2, n2))
            .copy_from(&DMatrix::from_row_slice(n2, n2, m2));
        Linearisation {
            drive: *d,
            q0: DVector::from_column_slice(q0),
            m,
            k: -DMatrix::from_row_slice(n, n, &hq),
            c: -DMatrix::from_row_slice(n, n, &hqd),
            h0: DVector::from_vec(h),
        }
    }

    /// The linearisation of a back end at time t (its drive there) about q0.
    pub fn of<S: Mechanical + ?Sized>(
        sys: &S,
        t: f64,
        q0: &[f64],
    ) -> Result<Linearisation, String> {
        let eq = sys
            .equations()
            .ok_or("linearisation: the back end does not present its equations")?;
        Ok(Linearisation::new(eq, sys.m2(), &sys.speed().drive(t), q0))
    }

    /// The linearisation about the static equilibrium at time t (`statics::static_equilibrium`).
    pub fn at_rest<S: Mechanical>(sys: &mut S, t: f64) -> Result<Linearisation, String> {
        let q0 = static_equilibrium(sys, t)?;
        Linearisation::of(sys, t, &q0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::Interpreter;

    /// M1 and h at the rest come from the same evaluation the integrators take, and K, C
    /// are the back end's own force Jacobians (the ones `statics` and the implicit methods use):
    /// the same bits. The reference machine's first scene, about its static equilibrium.
    #[test]
    fn linearisation_is_the_back_ends_evaluation_and_jacobians() {
        let m = washdyn_model::ir::toml_file::load_str(
            include_str!("../../models/data/reference.toml"),
            "reference.toml",
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/data"),
        )
        .unwrap();
        let scene = m.scene(None).unwrap();
        let mut sys = Interpreter::new(&m, &scene);
        let lin = Linearisation::at_rest(&mut sys, 0.0).unwrap();
        let (n, n1) = (sys.layout().n(), sys.layout().n1);
        let zero = vec![0.0; n];
        let (mut m1, mut h) = (vec![0.0; n1 * n1], vec![0.0; n]);
        sys.eval(0.0, lin.q0.as_slice(), &zero, &mut m1, &mut h);
        let (mut hq, mut hqd) = (vec![0.0; n * n], vec![0.0; n * n]);
        sys.force_jacobians(0.0, lin.q0.as_slice(), &zero, &mut hq, &mut hqd);
        assert_eq!(lin.h0.as_slice(), &h[..]);
        for i in 0..n1 {
            for j in 0..n1 {
                assert_eq!(lin.m[(i, j)], m1[i * n1 + j]);
            }
        }
        for i in 0..n {
            for j in 0..n {
                assert_eq!(lin.k[(i, j)], -hq[i * n + j]);
                assert_eq!(lin.c[(i, j)], -hqd[i * n + j]);
            }
        }
        // At the rest: what is left of h is the equilibrium's tolerance (1e-10 N absolute).
        assert!(lin.h0.amax() < 1e-8, "{}", lin.h0.amax());
    }
}
