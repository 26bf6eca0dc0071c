//! The element states' share of the ported Jacobians (`Equations::force_jacobians_ported`): a
//! friction damper's deflection z enters h through its loads and has a rate z' of its own.
//! - dz'/dq and dz'/dq' (z's row) come from the element's two seeded passes, the same lanes as
//!   its loads, chained through its input ports (`add_port_row`);
//! - dh/dz and dz'/dz (z's column) from one pass seeded along z with the markers constant,
//!   scattered through its output ports. They go to the E_v matrix: an implicit method
//!   advances z with its velocity update (`washdyn_ode::ported`).
//!
//! No step size to choose; the tests hold the rows and columns to differences of the model's
//! own h and z'.

use super::kinematics::Local;
use super::ports::{constant, outputs, ported, scatter_rows};
use super::{Drive, Equations, Placed};
use crate::dual::Dual;
use crate::elements::Element;

impl Equations {
    /// Column `r` (the state s's) of `hv` (dimension n): dh/dz_s on the element's output
    /// ports and dz_s'/dz_s on the diagonal, over `Dual<N>` seeded along z_s (lane 0).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn state_column<E: Element, const N: usize>(
        &self,
        p: &Placed<E>,
        (la, lb): (&Local<f64>, &Local<f64>),
        slots: [Option<usize>; 2],
        (s, r): (usize, usize),
        d: &Drive<Dual<N>>,
        z: &mut [Dual<N>],
        x: &mut [f64],
        hv: &mut [f64],
        n: usize,
    ) {
        let (ma, mb) = p.e.markers();
        let (ca, cb) = (constant::<N>(la), constant::<N>(lb));
        z[s].d[0] = 1.0;
        let (ya, yb) = self.element_loads(p, &ca, &cb, d, z);
        let (a, b) = (ma.state_of(&ca), mb.state_of(&cb));
        let zd = p.e.state_rate(&a, &b, self.exact_geometry, z);
        z[s].d[0] = 0.0;
        for ((m, y), slot) in [(ma, &ya), (mb, &yb)].into_iter().zip(slots) {
            for pair in ported(outputs(m, y), slot).chunks(2) {
                let (Some((po, vf)), Some((pm, vm))) = (pair[0], pair[1]) else {
                    continue;
                };
                for a in 0..6 {
                    x[a * n + r] = if a < 3 {
                        vf.0[a].d[0]
                    } else {
                        vm.0[a - 3].d[0]
                    };
                }
                scatter_rows(po, pm, x, r, r + 1, n, hv);
            }
        }
        hv[r * n + r] += zd.d[0];
    }
}
