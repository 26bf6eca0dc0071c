//! Forward-mode symbolic differentiation on the recorded graph: the analytic Jacobians the
//! generated code gives the implicit integrator. The derivative nodes join the same hash-consed
//! graph, so they share subexpressions with the function itself.

use super::{Node, Sym, with};
use crate::scalar::Scalar;

/// d outputs / d input `var` (an `Input` index), as new nodes of the current trace.
pub fn derivative(outputs: &[Sym], var: u32) -> Vec<Sym> {
    let hi = outputs.iter().map(|s| s.0 as usize + 1).max().unwrap_or(0);
    // None: the derivative is structurally zero.
    let mut d: Vec<Option<Sym>> = vec![None; hi];
    for i in 0..hi {
        let node = with(|g| g.nodes[i]);
        let get = |k: u32| d[k as usize];
        let s = |k: u32| Sym(k);
        let me = Sym(i as u32);
        d[i] = match node {
            Node::Const(_) | Node::Param(_) => None,
            Node::Input(k) => (k == var).then(|| Sym::c(1.0)),
            Node::Add(a, b) => match (get(a), get(b)) {
                (None, None) => None,
                (x, y) => Some(x.unwrap_or(Sym::c(0.0)) + y.unwrap_or(Sym::c(0.0))),
            },
            Node::Sub(a, b) => match (get(a), get(b)) {
                (None, None) => None,
                (x, y) => Some(x.unwrap_or(Sym::c(0.0)) - y.unwrap_or(Sym::c(0.0))),
            },
            Node::Mul(a, b) => match (get(a), get(b)) {
                (None, None) => None,
                (x, y) => {
                    let l = x.map_or(Sym::c(0.0), |x| x * s(b));
                    let r = y.map_or(Sym::c(0.0), |y| s(a) * y);
                    Some(l + r)
                }
            },
            // (a/b)' = (a' - (a/b) b') / b
            Node::Div(a, b) => match (get(a), get(b)) {
                (None, None) => None,
                (x, y) => {
                    let num = x.unwrap_or(Sym::c(0.0)) - y.map_or(Sym::c(0.0), |y| me * y);
                    Some(num / s(b))
                }
            },
            Node::Neg(a) => get(a).map(|x| -x),
            Node::Sqrt(a) => get(a).map(|x| x / (me * 2.0)),
            Node::Atan(a) => get(a).map(|x| x / (s(a) * s(a) + 1.0)),
            Node::Sin(a) => get(a).map(|x| s(a).cos() * x),
            Node::Cos(a) => get(a).map(|x| -(s(a).sin() * x)),
            // The larger operand's derivative: db + [a >= b] (da - db).
            Node::Max(a, b) => match (get(a), get(b)) {
                (None, None) => None,
                (x, y) => {
                    let (x, y) = (x.unwrap_or(Sym::c(0.0)), y.unwrap_or(Sym::c(0.0)));
                    let pick = Sym::mk(Node::Ge(a, b));
                    Some(y + pick * (x - y))
                }
            },
            // A step: zero derivative wherever it is defined.
            Node::Ge(..) => None,
            // (a^e)' = e a^(e-1) a' (the exponent is a constant).
            Node::Powf(a, e) => get(a).map(|x| {
                let e = Sym(e);
                Sym::mk(Node::Powf(a, (e - 1.0).0)) * e * x
            }),
            // The MatVec holds no scalar; each pick differentiates its row:
            // d(y_k + sum_j a_kj x_j) = dy_k + sum_j a_kj dx_j.
            Node::MatVec { .. } => None,
            Node::Pick(m, k) => {
                let (a, xs, ys) = with(|g| {
                    let Node::MatVec { table, x, y } = g.nodes[m as usize] else {
                        unreachable!("a pick reads a MatVec")
                    };
                    (
                        g.tables[table as usize].clone(),
                        g.lists[x as usize].clone(),
                        g.lists[y as usize].clone(),
                    )
                });
                let r = ys.len();
                let mut acc = get(ys[k as usize]);
                for (j, &xj) in xs.iter().enumerate() {
                    if let Some(dx) = get(xj) {
                        let t = dx * a[j * r + k as usize];
                        acc = Some(acc.map_or(t, |v| v + t));
                    }
                }
                acc
            }
        };
    }
    outputs
        .iter()
        .map(|o| d[o.0 as usize].unwrap_or(Sym::c(0.0)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::trace;
    use super::*;

    #[test]
    fn derivatives_match_closed_forms() {
        // f = atan(x y) + sqrt(x) / y + sin(x) cos(y); closed-form partials evaluated by hand.
        let ((dfdx, dfdy), g) = trace(|| {
            let x = Sym::input();
            let y = Sym::input();
            let f = (x * y).atan() + x.sqrt() / y + x.sin() * y.cos();
            let dx = derivative(&[f], 0)[0];
            let dy = derivative(&[f], 1)[0];
            (dx, dy)
        });
        let (x, y) = (0.7f64, 1.3f64);
        let ex = y / (1.0 + x * x * y * y) + 0.5 / (x.sqrt() * y) + x.cos() * y.cos();
        let ey = x / (1.0 + x * x * y * y) - x.sqrt() / (y * y) - x.sin() * y.sin();
        let v = g.eval(&[x, y], &[dfdx, dfdy]);
        assert!(
            (v[0] - ex).abs() < 1e-14 && (v[1] - ey).abs() < 1e-14,
            "{v:?}"
        );
    }

    /// max(x, y)^1.5 on both sides of the tie, against the closed form: the derivative is the
    /// larger operand's, 1.5 max^0.5.
    #[test]
    fn max_and_powf_differentiate_piecewise() {
        let ((f, dx, dy), g) = trace(|| {
            let x = Sym::input();
            let y = Sym::input();
            let f = x.max(y * 2.0).powf(1.5);
            (f, derivative(&[f], 0)[0], derivative(&[f], 1)[0])
        });
        for (x, y) in [(0.9f64, 0.3f64), (0.4, 0.5)] {
            let m = x.max(2.0 * y);
            let v = g.eval(&[x, y], &[f, dx, dy]);
            let (ex, ey) = if x >= 2.0 * y {
                (1.5 * m.sqrt(), 0.0)
            } else {
                (0.0, 3.0 * m.sqrt())
            };
            assert!((v[0] - m.powf(1.5)).abs() < 1e-15, "{v:?}");
            assert!(
                (v[1] - ex).abs() < 1e-14 && (v[2] - ey).abs() < 1e-14,
                "{v:?}"
            );
        }
    }
}
