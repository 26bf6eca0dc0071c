//! The energy balance along a run: the category powers of `equations::energy` integrated over
//! the integrator's dense output. Here, not beside the split, because it drives a back end and an
//! integrator (the model crate has neither).

use crate::system::Mechanical;
use washdyn_model::equations::{Category, EnergyWork};
use washdyn_ode::Stepper;

/// The category powers of a back end at (t, y = [q; q'; z]) in the order of
/// `Equations::energy_categories` (its resolved model's), the drive's with q'^T M1' q' / 2 (M1
/// depends on t only: a central difference over 1e-6 s). Their sum is dT/dt for
/// T = q'^T M q' / 2. False when the back end has no resolved model.
pub fn powers<S: Mechanical + ?Sized>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    w: &mut EnergyWork,
    out: &mut Vec<f64>,
) -> bool {
    let n = sys.layout().n();
    let (q, qd, z) = (&y[..n], &y[n..2 * n], &y[2 * n..]);
    let d = sys.speed().drive(t);
    let Some(eq) = sys.equations() else {
        return false;
    };
    eq.powers(&d, q, qd, z, w, out);
    let n1 = eq.layout.n1;
    let dt = 1e-6;
    sys.eval(t + dt, q, qd, &mut w.m1p, &mut w.hs);
    sys.eval(t - dt, q, qd, &mut w.m1m, &mut w.hs);
    let mut p = 0.0;
    for i in 0..n1 {
        for j in 0..n1 {
            p += 0.5 * qd[i] * (w.m1p[i * n1 + j] - w.m1m[i * n1 + j]) / (2.0 * dt) * qd[j];
        }
    }
    out[0] += p;
    true
}

/// The kinetic energy q'^T M q' / 2 of the vibration at (t, q'), M = diag(M1(t), M2).
pub fn kinetic<S: Mechanical + ?Sized>(
    sys: &mut S,
    t: f64,
    q: &[f64],
    qd: &[f64],
    w: &mut EnergyWork,
) -> f64 {
    let lay = sys.layout();
    let (n1, n2) = (lay.n1, lay.n2);
    sys.eval(t, q, qd, &mut w.m1p, &mut w.hs);
    let mut k = 0.0;
    for i in 0..n1 {
        for j in 0..n1 {
            k += 0.5 * qd[i] * w.m1p[i * n1 + j] * qd[j];
        }
    }
    let m2 = sys.m2();
    for i in 0..n2 {
        for j in 0..n2 {
            k += 0.5 * qd[n1 + i] * m2[i * n2 + j] * qd[n1 + j];
        }
    }
    k
}

/// Interval of the energy rows a run writes, s (100 rows per simulated second: a run-up's
/// balance in about 18 000 rows).
pub const ENERGY_ROW_S: f64 = 0.01;

/// The balance along a run: each category's work integrated along the integrator's dense
/// output (3-point Gauss-Legendre on each step, split at the row times), the kinetic energy at
/// the rows, and the closure |T - T0 - sum W| over the throughput (integral of |dT/dt|).
pub struct Balance {
    pub categories: Vec<Category>,
    /// Work of each category since the start, J.
    pub work: Vec<f64>,
    pub kinetic0: f64,
    pub throughput: f64,
    /// The closure at the last row (what `closure` gives there, without evaluating M again).
    pub row_closure: f64,
    w: EnergyWork,
    p: Vec<f64>,
    y: Vec<f64>,
    /// The next row's time is t0 + rows x ENERGY_ROW_S (no drift over a long run).
    t0: f64,
    rows: u64,
}

impl Balance {
    /// At the start (t0, y0 = [q; q']); `None` for a back end without a resolved model.
    pub fn new<S: Mechanical + ?Sized>(sys: &mut S, t0: f64, y0: &[f64]) -> Option<Balance> {
        let eq = sys.equations()?;
        let categories = eq.energy_categories();
        let mut w = EnergyWork::new(eq);
        let n = eq.layout.n();
        let kinetic0 = kinetic(sys, t0, &y0[..n], &y0[n..2 * n], &mut w);
        Some(Balance {
            work: vec![0.0; categories.len()],
            p: Vec::with_capacity(categories.len()),
            categories,
            kinetic0,
            throughput: 0.0,
            row_closure: 0.0,
            w,
            y: y0.to_vec(),
            t0,
            rows: 0,
        })
    }

    /// Integrate over the solver's last step; `row(t, rpm, kinetic, work)` at each row time in it
    /// (the first call also gives the start's row).
    pub fn step<S, V, E>(
        &mut self,
        sys: &mut S,
        solver: &V,
        mut row: impl FnMut(f64, f64, f64, &[f64]) -> Result<(), E>,
    ) -> Result<(), E>
    where
        S: Mechanical + ?Sized,
        V: Stepper + ?Sized,
    {
        let n = sys.layout().n();
        let g = 0.6f64.sqrt() / 2.0;
        let nodes = [
            (0.5 - g, 5.0 / 18.0),
            (0.5, 8.0 / 18.0),
            (0.5 + g, 5.0 / 18.0),
        ];
        let (mut a, end) = (solver.t_prev(), solver.t());
        if self.rows == 0 {
            let (kin, rpm) = (self.kinetic0, sys.speed().rpm(self.t0));
            row(self.t0, rpm, kin, &self.work)?;
            self.rows = 1;
        }
        while a < end {
            let next = self.t0 + self.rows as f64 * ENERGY_ROW_S;
            let b = if next > a && next <= end { next } else { end };
            for (x, wt) in nodes {
                let t = a + x * (b - a);
                solver.interpolate(t, &mut self.y);
                powers(sys, t, &self.y, &mut self.w, &mut self.p);
                let mut total = 0.0;
                for (wk, pc) in self.work.iter_mut().zip(&self.p) {
                    *wk += wt * (b - a) * pc;
                    total += pc;
                }
                self.throughput += wt * (b - a) * total.abs();
            }
            if b == next {
                solver.interpolate(b, &mut self.y);
                let (q, qd) = (&self.y[..n], &self.y[n..2 * n]);
                let kin = kinetic(sys, b, q, qd, &mut self.w);
                self.row_closure = self.residual(kin);
                row(b, sys.speed().rpm(b), kin, &self.work)?;
                self.rows += 1;
            }
            a = b;
        }
        Ok(())
    }

    /// |T(t) - T0 - sum W| / throughput at the solver's current state.
    pub fn closure<S: Mechanical + ?Sized>(&mut self, sys: &mut S, t: f64, y: &[f64]) -> f64 {
        let n = sys.layout().n();
        let kin = kinetic(sys, t, &y[..n], &y[n..2 * n], &mut self.w);
        self.residual(kin)
    }

    /// |kin - T0 - sum W| / throughput.
    fn residual(&self, kin: f64) -> f64 {
        let w: f64 = self.work.iter().sum();
        (kin - self.kinetic0 - w).abs() / self.throughput.max(f64::MIN_POSITIVE)
    }
}
