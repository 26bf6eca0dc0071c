//! HIRES: "High Irradiance RESponse" of photomorphogenesis, 8 equations, mildly stiff. From the
//! Test Set for IVP Solvers (Mazzia & Magherini, Bari; problem `hires`, revision 2006), which
//! gives the reference solution at t = 321.8122 computed with RADAU5 in quadruple-like
//! precision (rtol = atol = 1.1e-18).

use crate::OdeSystem;

/// Whether the Jacobian is supplied (false exercises the finite-difference path).
#[derive(Clone, Copy, Debug)]
pub struct Hires {
    pub analytic_jacobian: bool,
}

impl Default for Hires {
    fn default() -> Self {
        Hires {
            analytic_jacobian: true,
        }
    }
}

impl Hires {
    pub const T_END: f64 = 321.8122;
    pub const Y0: [f64; 8] = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057];
    /// Reference solution at `T_END` (Test Set, `hires.f`, subroutine `solut`).
    pub const REFERENCE: [f64; 8] = [
        0.7371312573325668e-3,
        0.1442485726316185e-3,
        0.5888729740967575e-4,
        0.1175651343283149e-2,
        0.2386356198831331e-2,
        0.6238968252742796e-2,
        0.2849998395185769e-2,
        0.2850001604814231e-2,
    ];
}

impl OdeSystem for Hires {
    fn dim(&self) -> usize {
        8
    }
    fn rhs(&mut self, _t: f64, y: &[f64], f: &mut [f64]) {
        f[0] = -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007;
        f[1] = 1.71 * y[0] - 8.75 * y[1];
        f[2] = -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4];
        f[3] = 8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3];
        f[4] = -1.745 * y[4] + 0.43 * (y[5] + y[6]);
        f[5] = -280.0 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6];
        f[6] = 280.0 * y[5] * y[7] - 1.81 * y[6];
        f[7] = -f[6];
    }
    fn jacobian(&mut self, _t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        if !self.analytic_jacobian {
            return false;
        }
        jac.fill(0.0);
        let mut set = |i: usize, j: usize, v: f64| jac[i * 8 + j] = v;
        set(0, 0, -1.71);
        set(0, 1, 0.43);
        set(0, 2, 8.32);
        set(1, 0, 1.71);
        set(1, 1, -8.75);
        set(2, 2, -10.03);
        set(2, 3, 0.43);
        set(2, 4, 0.035);
        set(3, 1, 8.32);
        set(3, 2, 1.71);
        set(3, 3, -1.12);
        set(4, 4, -1.745);
        set(4, 5, 0.43);
        set(4, 6, 0.43);
        set(5, 3, 0.69);
        set(5, 4, 1.71);
        set(5, 5, -280.0 * y[7] - 0.43);
        set(5, 6, 0.69);
        set(5, 7, -280.0 * y[5]);
        set(6, 5, 280.0 * y[7]);
        set(6, 6, -1.81);
        set(6, 7, 280.0 * y[5]);
        set(7, 5, -280.0 * y[7]);
        set(7, 6, 1.81);
        set(7, 7, -280.0 * y[5]);
        true
    }
}
