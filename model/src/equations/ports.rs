//! The marker ports of the structured Jacobians (`jacobian.rs`, `states.rs`): the constant
//! linear maps between a marker's local 3-vectors (u, alpha, W q, Phi q and rates) and the
//! generalised coordinates, the local coordinates seeded along them over dual numbers, and
//! the chain rule through them (an input port's row, an output pair's rows).

use super::kinematics::{Load, Local, MarkerDef};
use crate::dual::Dual;
use crate::geom::V;
use crate::scalar::Scalar;

/// A constant linear map between a 3-vector at a marker and the generalised coordinates:
/// identity on three columns (the tub's u or alpha) or mode-shape rows (W or Phi, per mode).
#[derive(Clone, Copy)]
pub(super) enum Port<'a> {
    Rigid(usize),
    Modal(usize, &'a [[f64; 3]]),
}

impl Port<'_> {
    pub(super) fn cols(&self) -> (usize, usize) {
        match *self {
            Port::Rigid(c) => (c, c + 3),
            Port::Modal(s, r) => (s, s + r.len()),
        }
    }
}

/// Which local coordinate an input port seeds.
#[derive(Clone, Copy)]
pub(super) enum Field {
    U,
    Alpha,
    W,
    Phi,
}

/// A marker's input ports (at most four; `None` past the last).
pub(super) fn inputs(m: &MarkerDef) -> [Option<(Port<'_>, Field)>; 4] {
    let mut out = [None; 4];
    let mut i = 0;
    if let Some(c) = m.frame {
        out[0] = Some((Port::Rigid(c), Field::U));
        out[1] = Some((Port::Rigid(c + 3), Field::Alpha));
        i = 2;
    }
    if let Some(r) = &m.modal {
        out[i] = Some((Port::Modal(r.start, &r.w), Field::W));
        out[i + 1] = Some((Port::Modal(r.start, &r.phi), Field::Phi));
    }
    out
}

/// The local coordinates at one level (positions, or rates when `rate`) over `L`, seeded
/// along lanes `3 lane0 + ...` for each input port, the other level constant.
pub(super) fn seeded<const N: usize>(
    m: &MarkerDef,
    l: &Local<f64>,
    rate: bool,
    lane0: usize,
) -> (Local<Dual<N>>, usize) {
    let mut out = constant::<N>(l);
    let mut lane = lane0;
    for (_, field) in inputs(m).into_iter().flatten() {
        let v = match (field, rate) {
            (Field::U, false) => &mut out.u,
            (Field::Alpha, false) => &mut out.alpha,
            (Field::W, false) => &mut out.w,
            (Field::Phi, false) => &mut out.phi,
            (Field::U, true) => &mut out.ud,
            (Field::Alpha, true) => &mut out.alphad,
            (Field::W, true) => &mut out.wd,
            (Field::Phi, true) => &mut out.phid,
        };
        for a in 0..3 {
            v.0[a].d[3 * lane + a] = 1.0;
        }
        lane += 1;
    }
    (out, lane)
}

/// The local coordinates as constants over `Dual<N>`.
pub(super) fn constant<const N: usize>(l: &Local<f64>) -> Local<Dual<N>> {
    let c = |v: V<f64>| V(v.0.map(Dual::<N>::c));
    Local {
        u: c(l.u),
        alpha: c(l.alpha),
        w: c(l.w),
        phi: c(l.phi),
        ud: c(l.ud),
        alphad: c(l.alphad),
        wd: c(l.wd),
        phid: c(l.phid),
    }
}

/// A marker's output ports with the load's value there.
#[allow(clippy::type_complexity)]
pub(super) fn outputs<'a, const N: usize>(
    m: &'a MarkerDef,
    l: &Load<Dual<N>>,
) -> [Option<(Port<'a>, V<Dual<N>>)>; 4] {
    let mut out = [None; 4];
    let mut i = 0;
    if let Some(c) = m.frame {
        out[0] = Some((Port::Rigid(c), l.force));
        out[1] = Some((Port::Rigid(c + 3), l.moment));
        i = 2;
    }
    if let Some(r) = &m.modal {
        out[i] = Some((Port::Modal(r.start, &r.w), l.modal_force));
        out[i + 1] = Some((Port::Modal(r.start, &r.phi), l.modal_moment));
    }
    out
}

/// A marker's ports (W then Phi on its modes) as the identity on its six port columns from
/// `slot` (the ported form), or unchanged.
pub(super) fn ported<T: Copy>(
    mut ports: [Option<(Port<'_>, T)>; 4],
    slot: Option<usize>,
) -> [Option<(Port<'_>, T)>; 4] {
    if let Some(c) = slot {
        for (k, (p, _)) in ports.iter_mut().flatten().enumerate() {
            debug_assert!(matches!(p, Port::Modal(..)), "a port marker has no frame");
            *p = Port::Rigid(c + 3 * k);
        }
    }
    ports
}

/// row += d v / d(the element's local inputs) chained through the input ports' maps (lane k
/// of `v` is the k-th present port's, three lanes each).
pub(super) fn add_port_row<const N: usize>(
    ins: &[Option<(Port<'_>, Field)>; 8],
    v: &Dual<N>,
    row: &mut [f64],
) {
    for (lane, &(port, _)) in ins.iter().flatten().enumerate() {
        let k = [0, 1, 2].map(|b| v.d[3 * lane + b]);
        match port {
            Port::Rigid(c) => {
                for b in 0..3 {
                    row[c + b] += k[b];
                }
            }
            Port::Modal(s, rows) => {
                for (xj, r) in row[s..s + rows.len()].iter_mut().zip(rows) {
                    *xj += k[0] * r[0] + k[1] * r[1] + k[2] * r[2];
                }
            }
        }
    }
}

/// h[rows, c0..c1] += P^T x for a pair of output ports on the same rows (the tub's force and
/// moment rows, or a body's W and Phi rows), x holding six rows of length n (the first port's
/// three, then the second's).
pub(super) fn scatter_rows(
    pf: Port<'_>,
    pm: Port<'_>,
    x: &[f64],
    c0: usize,
    c1: usize,
    n: usize,
    h: &mut [f64],
) {
    let xr = |a: usize| &x[a * n + c0..a * n + c1];
    match (pf, pm) {
        (Port::Modal(s, wr), Port::Modal(_, pr)) => {
            let (x0, x1, x2, x3, x4, x5) = (xr(0), xr(1), xr(2), xr(3), xr(4), xr(5));
            for (k, (w, p)) in wr.iter().zip(pr).enumerate() {
                let row = &mut h[(s + k) * n + c0..(s + k) * n + c1];
                // Zipped slices: no bounds checks, so the loop vectorises.
                let xs = x0.iter().zip(x1).zip(x2).zip(x3).zip(x4).zip(x5);
                for (v, (((((a, b), c), d), e), f)) in row.iter_mut().zip(xs) {
                    *v += w[0] * a + w[1] * b + w[2] * c + p[0] * d + p[1] * e + p[2] * f;
                }
            }
        }
        _ => {
            for (a, r) in [pf, pm]
                .into_iter()
                .flat_map(|p| match p {
                    Port::Rigid(r) => [r, r + 1, r + 2],
                    Port::Modal(..) => unreachable!("ports pair rigid with rigid"),
                })
                .enumerate()
            {
                for (v, xj) in h[r * n + c0..r * n + c1].iter_mut().zip(xr(a)) {
                    *v += xj;
                }
            }
        }
    }
}
