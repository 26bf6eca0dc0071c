//! The mechanical system as both back ends present it, and its first-order form for the
//! integrators. M1 is factorised (Cholesky) at every evaluation, M2 once.

use crate::mass::LowRankMass;
use washdyn_model::equations::{Equations, JacobianWork, Layout};
use washdyn_model::ir::{EffectSet, Model};
use washdyn_model::linalg::{cholesky_in_place, cholesky_solve};
use washdyn_model::speed::Speed;
use washdyn_ode::{OdeSystem, PortedJacobian};

/// M(q, t) q'' = h(q, q', t) with M = diag(M1(q, t), M2), as either back end evaluates it.
pub trait Mechanical {
    fn layout(&self) -> Layout;
    /// M1 (n1 x n1, row-major) and h (length n) at (t, q, q'), the element states at their
    /// assembly value (z = 0).
    fn eval(&mut self, t: f64, q: &[f64], qd: &[f64], m1: &mut [f64], h: &mut [f64]);
    /// As `eval` at element states `z` (`layout().nz`), and their rates into `zd`. A back end
    /// without element states needs only `eval`.
    #[allow(clippy::too_many_arguments)]
    fn eval_states(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        z: &[f64],
        m1: &mut [f64],
        h: &mut [f64],
        zd: &mut [f64],
    ) {
        assert!(
            z.is_empty() && zd.is_empty(),
            "a back end with element states evaluates them"
        );
        self.eval(t, q, qd, m1, h);
    }
    /// The constant M2 (n2 x n2, row-major).
    fn m2(&self) -> &[f64];
    /// h alone and the element states' rates (M1 not formed), for a solve of M1 through its
    /// structure. `false`: not provided (the caller takes `eval_states`).
    #[allow(clippy::too_many_arguments)]
    fn forces(
        &mut self,
        _t: f64,
        _q: &[f64],
        _qd: &[f64],
        _z: &[f64],
        _h: &mut [f64],
        _zd: &mut [f64],
    ) -> bool {
        false
    }
    /// Sensor channels (3 per sensor) from the state and its acceleration.
    fn sensors(&self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]);
    /// Channel names, in the order of `sensors`.
    fn channel_names(&self) -> Vec<String>;
    /// The prescribed drum speed.
    fn speed(&self) -> &Speed;
    /// q'' directly, for a back end that factorises M1 itself (the generated one: straight-line
    /// code). `false`: not provided, the caller factorises M1 from `eval`.
    fn accelerations(&mut self, _t: f64, _q: &[f64], _qd: &[f64], _qdd: &mut [f64]) -> bool {
        false
    }
    /// Analytic d q''/d q and d q''/d q' (row-major n x n each). `false`: not provided, the
    /// implicit integrators difference numerically.
    fn acceleration_jacobians(
        &mut self,
        _t: f64,
        _q: &[f64],
        _qd: &[f64],
        _dq: &mut [f64],
        _dqd: &mut [f64],
    ) -> bool {
        false
    }
    /// Whether `acceleration_jacobians` is provided (traced code: cheaper than forming the
    /// mass form from `force_jacobians`, which the implicit methods then leave alone).
    fn has_acceleration_jacobians(&self) -> bool {
        false
    }
    /// The resolved model behind the back end (the interpreter's, or the one generated code
    /// embeds): what a coordinate means, for the tolerances and the body layer's questions.
    fn equations(&self) -> Option<&Equations> {
        None
    }
    /// dh/dq and dh/dq' (row-major n x n each), exact: what the implicit methods iterate
    /// with (M depends on t only) and the static start's Newton uses (every back end gives
    /// the same, so both start from the same bits). Every back end has them (the
    /// interpreter's `Equations::force_jacobians`, generated code's through the model it
    /// embeds), so none has to be guessed by differences: no default.
    fn force_jacobians(&mut self, t: f64, q: &[f64], qd: &[f64], hq: &mut [f64], hqd: &mut [f64]);
}

/// The interpreter back end: the one derivation evaluated with f64 on the resolved model.
#[derive(Clone, Debug)]
pub struct Interpreter {
    pub eq: Equations,
    pub speed: Speed,
    m2: Vec<f64>,
    work: JacobianWork,
}

impl Interpreter {
    /// For a checked model and a scene of it.
    pub fn new(model: &Model, scene: &EffectSet) -> Interpreter {
        let eq = Equations::new(model, scene);
        let n2 = eq.layout.n2;
        let mut m2 = vec![0.0; n2 * n2];
        for i in 0..n2 {
            m2[i * n2 + i] = 1.0;
        }
        Interpreter {
            work: JacobianWork::new(&eq),
            eq,
            speed: Speed::new(&model.speed.table),
            m2,
        }
    }
}

impl Mechanical for Interpreter {
    fn layout(&self) -> Layout {
        self.eq.layout
    }
    fn eval(&mut self, t: f64, q: &[f64], qd: &[f64], m1: &mut [f64], h: &mut [f64]) {
        let d = self.speed.drive(t);
        self.eq.eval(&d, q, qd, m1, h);
    }
    fn eval_states(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        z: &[f64],
        m1: &mut [f64],
        h: &mut [f64],
        zd: &mut [f64],
    ) {
        let d = self.speed.drive(t);
        self.eq.eval_states(&d, q, qd, z, m1, h);
        self.eq.state_rates(q, qd, z, zd);
    }
    fn forces(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        z: &[f64],
        h: &mut [f64],
        zd: &mut [f64],
    ) -> bool {
        let d = self.speed.drive(t);
        self.eq.forces(&d, q, qd, z, h);
        self.eq.state_rates(q, qd, z, zd);
        true
    }
    fn m2(&self) -> &[f64] {
        &self.m2
    }
    fn sensors(&self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        let d = self.speed.drive(t);
        for i in 0..self.eq.sensors.len() {
            let v = self.eq.sensor(i, &d, q, qd, qdd);
            out[3 * i..3 * i + 3].copy_from_slice(&v);
        }
    }
    fn channel_names(&self) -> Vec<String> {
        self.eq
            .sensors
            .iter()
            .flat_map(|s| s.channels.iter().cloned())
            .collect()
    }
    fn speed(&self) -> &Speed {
        &self.speed
    }
    fn equations(&self) -> Option<&Equations> {
        Some(&self.eq)
    }
    fn force_jacobians(&mut self, t: f64, q: &[f64], qd: &[f64], hq: &mut [f64], hqd: &mut [f64]) {
        let d = self.speed.drive(t);
        self.eq.force_jacobians(&d, q, qd, &mut self.work, hq, hqd);
    }
}

/// First-order form y = [q; q'; z] for the integrators (z: the element states, usually none),
/// with preallocated work arrays.
pub struct FirstOrder<S: Mechanical> {
    pub sys: S,
    layout: Layout,
    m1: Vec<f64>,
    l2: Vec<f64>,
    h: Vec<f64>,
    jq: Vec<f64>,
    jqd: Vec<f64>,
    col: Vec<f64>,
    /// M2 = I (modal coordinates of a mass-normalised body): no solve with it.
    m2_identity: bool,
    /// The absolute tolerance's scales over y (`Equations::atol_scales`), computed once: the
    /// integrators ask at every `init` (each speed breakpoint), which must not allocate.
    atol: Vec<f64>,
    /// The ported form's port count and work arrays (`Equations::ported_ports`), where it
    /// applies: the implicit methods then factorise n1 + r instead of n.
    ported: Option<(usize, JacobianWork)>,
    /// M1 through its low-rank structure (`mass.rs`), where the back end gives h alone.
    low_rank: Option<LowRankMass>,
}

impl<S: Mechanical> FirstOrder<S> {
    pub fn new(sys: S) -> Self {
        let layout = sys.layout();
        let (n1, n2) = (layout.n1, layout.n2);
        let m2_identity = sys
            .m2()
            .iter()
            .enumerate()
            .all(|(k, &v)| v == if k % (n2 + 1) == 0 { 1.0 } else { 0.0 });
        let mut l2 = sys.m2().to_vec();
        assert!(
            cholesky_in_place(&mut l2, n2),
            "M2 is not positive definite"
        );
        let mut atol = vec![1.0; layout.dim()];
        if let Some(eq) = sys.equations() {
            eq.atol_scales(&mut atol);
        }
        let ported = sys
            .equations()
            .filter(|_| m2_identity && !sys.has_acceleration_jacobians())
            .and_then(|eq| Some((eq.ported_ports()?, JacobianWork::new(eq))));
        let low_rank = sys.equations().and_then(LowRankMass::new);
        FirstOrder {
            atol,
            ported,
            low_rank,
            sys,
            layout,
            m1: vec![0.0; n1 * n1],
            l2,
            h: vec![0.0; n1 + n2],
            jq: vec![0.0; (n1 + n2) * (n1 + n2)],
            jqd: vec![0.0; (n1 + n2) * (n1 + n2)],
            col: vec![0.0; n1 + n2],
            m2_identity,
        }
    }

    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// q'' at (t, q, q') into `qdd`, the element states at their assembly value (a system
    /// without states: all of it). A mass block that is not positive definite yields NaN, which
    /// the integrators report as a non-finite state with its time.
    pub fn accelerations(&mut self, t: f64, q: &[f64], qd: &[f64], qdd: &mut [f64]) {
        self.solve(t, q, qd, &[], qdd, &mut []);
    }

    /// q'' and the element states' rates at the whole state y = [q; q'; z] into `qdd`, `zd`.
    pub fn rates(&mut self, t: f64, y: &[f64], qdd: &mut [f64], zd: &mut [f64]) {
        let n = self.layout.n();
        let (q, rest) = y.split_at(n);
        let (qd, z) = rest.split_at(n);
        self.solve(t, q, qd, z, qdd, zd);
    }

    /// q'' and z' at element states `z` (empty: their assembly value, and no z'): M1 through
    /// its structure where the back end gives h alone, else the back end's own q'' (a system
    /// without states), else its M1 factorised here.
    fn solve(&mut self, t: f64, q: &[f64], qd: &[f64], z: &[f64], qdd: &mut [f64], zd: &mut [f64]) {
        if self.low_rank.is_some() && self.sys.forces(t, q, qd, z, &mut self.h, zd) {
            return self.solve_low_rank(t, qdd);
        }
        if !z.is_empty() {
            self.sys
                .eval_states(t, q, qd, z, &mut self.m1, &mut self.h, zd);
        } else if self.layout.nz == 0 && self.sys.accelerations(t, q, qd, qdd) {
            return;
        } else {
            self.sys.eval(t, q, qd, &mut self.m1, &mut self.h);
        }
        self.solve_mass(qdd);
    }

    /// q'' from the `h` just evaluated, M1 solved through its structure.
    fn solve_low_rank(&mut self, t: f64, qdd: &mut [f64]) {
        let (n1, n2) = (self.layout.n1, self.layout.n2);
        let phi = self.sys.speed().drive(t).phi;
        qdd.copy_from_slice(&self.h);
        let lr = self.low_rank.as_mut().expect("called with a low-rank form");
        if !lr.solve(phi, &mut qdd[..n1]) {
            qdd[..n1].fill(f64::NAN);
        }
        if !self.m2_identity {
            cholesky_solve(&self.l2, n2, &mut qdd[n1..]);
        }
    }

    /// q'' = M^-1 h from the `m1` and `h` just evaluated.
    fn solve_mass(&mut self, qdd: &mut [f64]) {
        let (n1, n2) = (self.layout.n1, self.layout.n2);
        qdd.copy_from_slice(&self.h);
        if cholesky_in_place(&mut self.m1, n1) {
            cholesky_solve(&self.m1, n1, &mut qdd[..n1]);
        } else {
            qdd[..n1].fill(f64::NAN);
        }
        // Mass-normalised modes (M2 = I, as the generator assumes): nothing to solve.
        if !self.m2_identity {
            cholesky_solve(&self.l2, n2, &mut qdd[n1..]);
        }
    }
}

impl<S: Mechanical> FirstOrder<S> {
    /// d q''/d q = M^-1 dh/dq and d q''/d q' = M^-1 dh/dq' (M depends on t only), from the
    /// back end's force Jacobians (NaN where M1 is not positive definite).
    fn acceleration_jacobians_from_forces(&mut self, t: f64, q: &[f64], qd: &[f64]) {
        let (n1, n2) = (self.layout.n1, self.layout.n2);
        let n = n1 + n2;
        self.sys
            .force_jacobians(t, q, qd, &mut self.jq, &mut self.jqd);
        self.sys.eval(t, q, qd, &mut self.m1, &mut self.h);
        if !cholesky_in_place(&mut self.m1, n1) {
            self.jq.fill(f64::NAN);
            return;
        }
        // Rows n1.. only when M2 is not the identity.
        let rows = if self.m2_identity { n1 } else { n };
        for mat in [&mut self.jq, &mut self.jqd] {
            for j in 0..n {
                for i in 0..rows {
                    self.col[i] = mat[i * n + j];
                }
                cholesky_solve(&self.m1, n1, &mut self.col[..n1]);
                if !self.m2_identity {
                    cholesky_solve(&self.l2, n2, &mut self.col[n1..]);
                }
                for i in 0..rows {
                    mat[i * n + j] = self.col[i];
                }
            }
        }
    }
}

impl<S: Mechanical> OdeSystem for FirstOrder<S> {
    fn dim(&self) -> usize {
        self.layout.dim()
    }
    fn second_order(&self) -> Option<usize> {
        Some(self.layout.n())
    }
    /// Per coordinate from the resolved model (`Equations::atol_scales`).
    fn atol_scales(&self, s: &mut [f64]) {
        s.copy_from_slice(&self.atol);
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.layout.n();
        let (dq, rest) = dy.split_at_mut(n);
        let (dqd, dz) = rest.split_at_mut(n);
        dq.copy_from_slice(&y[n..2 * n]);
        self.rates(t, y, dqd, dz);
    }
    /// M = diag(M1(t), M2) and the back end's force Jacobians, when it has them.
    fn mass_jacobians(
        &mut self,
        t: f64,
        y: &[f64],
        m: &mut [f64],
        hq: &mut [f64],
        hqd: &mut [f64],
    ) -> bool {
        let (n1, n2) = (self.layout.n1, self.layout.n2);
        let n = n1 + n2;
        let (q, qd) = (&y[..n], &y[n..2 * n]);
        // Element states: the implicit methods difference the whole Jacobian.
        if self.layout.nz > 0 || self.sys.has_acceleration_jacobians() {
            return false;
        }
        self.sys.force_jacobians(t, q, qd, hq, hqd);
        self.sys.eval(t, q, qd, &mut self.m1, &mut self.h);
        m.fill(0.0);
        for i in 0..n1 {
            m[i * n..i * n + n1].copy_from_slice(&self.m1[i * n1..(i + 1) * n1]);
        }
        let m2 = self.sys.m2();
        for i in 0..n2 {
            m[(n1 + i) * n + n1..(n1 + i + 1) * n].copy_from_slice(&m2[i * n2..(i + 1) * n2]);
        }
        true
    }
    /// (n1, r) where the ported form applies (`Equations::ported_ports`, M2 = I).
    fn ported_shape(&self) -> Option<(usize, usize)> {
        self.ported.as_ref().map(|(r, _)| (self.layout.n1, *r))
    }
    /// M1 and the model's ported force Jacobians (`Equations::force_jacobians_ported`), with
    /// the element states' rows and columns.
    fn ported_jacobians(&mut self, t: f64, y: &[f64], j: &mut PortedJacobian) -> bool {
        let n = self.layout.n();
        let (q, rest) = y.split_at(n);
        let (qd, z) = rest.split_at(n);
        let d = self.sys.speed().drive(t);
        let (Some(eq), Some((_, work))) = (self.sys.equations(), self.ported.as_mut()) else {
            return false;
        };
        let (eqm, ev) = (&mut j.eq, &mut j.ev);
        eq.force_jacobians_ported(
            &d,
            (q, qd, z),
            work,
            eqm,
            ev,
            &mut j.dq,
            &mut j.dv,
            &mut j.b2,
        );
        self.sys.eval(t, q, qd, &mut self.m1, &mut self.h);
        j.m1.copy_from_slice(&self.m1);
        true
    }
    /// M1 from the back end and the modal bodies' omega^2 and 2 zeta omega (every body with
    /// modes, both subsystems; zero on rigid coordinates). Only with M2 = I.
    fn linear_part(
        &mut self,
        t: f64,
        y: &[f64],
        m1: &mut [f64],
        k: &mut [f64],
        c: &mut [f64],
    ) -> Option<usize> {
        let (n1, n) = (self.layout.n1, self.layout.n());
        if !self.m2_identity {
            return None;
        }
        let eq = self.sys.equations()?;
        k.fill(0.0);
        c.fill(0.0);
        for m in eq.bodies.list.iter().filter_map(|b| b.modal()) {
            k[m.start..m.start + m.n].copy_from_slice(&m.omega2);
            c[m.start..m.start + m.n].copy_from_slice(&m.damping);
        }
        let (q, qd) = (&y[..n], &y[n..2 * n]);
        self.sys.eval(t, q, qd, &mut self.m1, &mut self.h);
        m1[..n1 * n1].copy_from_slice(&self.m1);
        Some(n1)
    }
    /// J = [[0, I], [dq''/dq, dq''/dq']]: the back end's traced d q'' or its force Jacobians
    /// (`false` with element states, which the implicit methods difference).
    fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) -> bool {
        let n = self.layout.n();
        let (q, qd) = y.split_at(n);
        if self.layout.nz > 0 {
            return false;
        }
        if !self
            .sys
            .acceleration_jacobians(t, q, qd, &mut self.jq, &mut self.jqd)
        {
            self.acceleration_jacobians_from_forces(t, q, qd);
        }
        let m = 2 * n;
        jac.fill(0.0);
        for i in 0..n {
            jac[i * m + n + i] = 1.0;
            jac[(n + i) * m..(n + i) * m + n].copy_from_slice(&self.jq[i * n..(i + 1) * n]);
            jac[(n + i) * m + n..(n + i + 1) * m].copy_from_slice(&self.jqd[i * n..(i + 1) * n]);
        }
        true
    }
}

/// A system chosen at run time (a generated scene picked by name).
impl<M: Mechanical + ?Sized> Mechanical for Box<M> {
    fn layout(&self) -> Layout {
        (**self).layout()
    }
    fn eval(&mut self, t: f64, q: &[f64], qd: &[f64], m1: &mut [f64], h: &mut [f64]) {
        (**self).eval(t, q, qd, m1, h)
    }
    fn eval_states(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        z: &[f64],
        m1: &mut [f64],
        h: &mut [f64],
        zd: &mut [f64],
    ) {
        (**self).eval_states(t, q, qd, z, m1, h, zd)
    }
    fn m2(&self) -> &[f64] {
        (**self).m2()
    }
    fn forces(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        z: &[f64],
        h: &mut [f64],
        zd: &mut [f64],
    ) -> bool {
        (**self).forces(t, q, qd, z, h, zd)
    }
    fn sensors(&self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        (**self).sensors(t, q, qd, qdd, out)
    }
    fn channel_names(&self) -> Vec<String> {
        (**self).channel_names()
    }
    fn speed(&self) -> &Speed {
        (**self).speed()
    }
    fn accelerations(&mut self, t: f64, q: &[f64], qd: &[f64], qdd: &mut [f64]) -> bool {
        (**self).accelerations(t, q, qd, qdd)
    }
    fn has_acceleration_jacobians(&self) -> bool {
        (**self).has_acceleration_jacobians()
    }
    fn equations(&self) -> Option<&Equations> {
        (**self).equations()
    }
    fn acceleration_jacobians(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        dq: &mut [f64],
        dqd: &mut [f64],
    ) -> bool {
        (**self).acceleration_jacobians(t, q, qd, dq, dqd)
    }
    fn force_jacobians(&mut self, t: f64, q: &[f64], qd: &[f64], hq: &mut [f64], hqd: &mut [f64]) {
        (**self).force_jacobians(t, q, qd, hq, hqd)
    }
}
