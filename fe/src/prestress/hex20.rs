//! The 20-node serendipity brick as ccx numbers it (C3D20, C3D20R, and the C3D20R and C3D20
//! bricks ccx expands shells and beams into): corners 1-4 on the face zeta = -1 and 5-8 on
//! zeta = +1 (counter-clockwise about +zeta), mid-edges 9-12 of the bottom face (1-2, 2-3,
//! 3-4, 4-1), 13-16 of the top face, 17-20 of the edges 1-5, 2-6, 3-7, 4-8. And ccx's Gauss
//! rules with its point order (xi fastest, then eta, then zeta): 2 x 2 x 2 for C3D20R, 3 x 3 x 3
//! for C3D20. Both checked against ccx 2.20 (`prestress/tests.rs`): the stresses we form from
//! ccx's nodal displacements at these points are those it prints there.

/// Natural coordinates of the nodes, in ccx's order; with the shape functions and their
/// derivatives (`hex20`) and the Jacobian (`hex20_jacobian`), the lumping's own brick.
pub use crate::lumping::HEX20 as NODES;
use crate::lumping::{det3, hex20, hex20_jacobian};

/// ccx's `.frd` writes a 20-node brick's nodes 1-12, 17-20, 13-16: position `k` of the file's
/// list holds ccx's node `FRD_ORDER[k]` (0-based).
pub const FRD_ORDER: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15,
];

/// The shape functions at `p` (natural coordinates).
pub fn shape(p: [f64; 3]) -> [f64; 20] {
    hex20(p).0
}

/// The shape functions' derivatives by the natural coordinates at `p`: row a, column d.
pub fn natural_gradient(p: [f64; 3]) -> [[f64; 3]; 20] {
    hex20(p).1
}

/// One Gauss point: natural coordinates and weight.
pub type Point = ([f64; 3], f64);

/// ccx's rule with `n` points per direction (2 or 3), xi fastest: `n`^3 points.
pub fn gauss(n: usize) -> Option<Vec<Point>> {
    let (x, w): (&[f64], &[f64]) = match n {
        2 => (&[-1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt()], &[1.0, 1.0]),
        3 => (
            &[-(0.6f64.sqrt()), 0.0, 0.6f64.sqrt()],
            &[5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0],
        ),
        _ => return None,
    };
    let mut out = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                out.push(([x[i], x[j], x[k]], w[i] * w[j] * w[k]));
            }
        }
    }
    Some(out)
}

/// The rule of an element for which ccx prints `points` integration points: 8 (C3D20R) or 27
/// (C3D20).
pub fn rule_of(points: usize) -> Option<Vec<Point>> {
    match points {
        8 => gauss(2),
        27 => gauss(3),
        _ => None,
    }
}

/// At natural point `p` of the brick with nodes at `x`: the shape functions' gradients in
/// space (row a: dN_a/dx) and det J. None where the map folds (det J <= 0).
pub fn spatial_gradient(x: &[[f64; 3]; 20], p: [f64; 3]) -> Option<([[f64; 3]; 20], f64)> {
    let d = natural_gradient(p);
    // jt[k][i] = dx_i / dxi_k.
    let jt = hex20_jacobian(&d, |a| x[a]);
    let det = det3(jt);
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    // inv[k][i] = dxi_k / dx_i.
    let mut inv = [[0.0; 3]; 3];
    for k in 0..3 {
        for i in 0..3 {
            let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
            let (c0, c1) = ((k + 1) % 3, (k + 2) % 3);
            inv[k][i] = (jt[c0][r0] * jt[c1][r1] - jt[c1][r0] * jt[c0][r1]) / det;
        }
    }
    let g =
        std::array::from_fn(|a| std::array::from_fn(|i| (0..3).map(|k| d[a][k] * inv[k][i]).sum()));
    Some((g, det))
}
