//! The Gauss point sums of the prestress stiffness (`Prestress::stiffness`), by batches of
//! points so that each batch is one matrix product.

use nalgebra::DMatrix;

/// Gauss points per batch of [`GaussSums`].
const BATCH: usize = 256;

/// The sums of `Prestress::stiffness` over the Gauss points, a batch of points at a time. Per
/// point the n x 9 gradients A9 (A9[k, 3i + j] = d u_k,i / d x_j) and B9 = A9 (E x sigma)
/// w det J: K_sigma += B9 A9^T; and sym(grad u_k) A6 (6: xx, yy, zz, xy, yz, zx) and
/// B6 = 2 w det J C : sym(G0^T grad u_k) (off-diagonals doubled): K_u += B6 A6^T, symmetrised
/// at the end.
pub(super) struct GaussSums {
    n: usize,
    a9: DMatrix<f64>,
    b9: DMatrix<f64>,
    a6: DMatrix<f64>,
    b6: DMatrix<f64>,
    ks: DMatrix<f64>,
    ku: DMatrix<f64>,
    /// Points in the batch.
    filled: usize,
}

impl GaussSums {
    pub(super) fn new(n: usize) -> GaussSums {
        GaussSums {
            n,
            a9: DMatrix::zeros(n, 9 * BATCH),
            b9: DMatrix::zeros(n, 9 * BATCH),
            a6: DMatrix::zeros(n, 6 * BATCH),
            b6: DMatrix::zeros(n, 6 * BATCH),
            ks: DMatrix::zeros(n, n),
            ku: DMatrix::zeros(n, n),
            filled: 0,
        }
    }

    /// One Gauss point: the shape functions' spatial gradients `g`, its weight times det J
    /// `wd`, ccx's stress `s` (xx, yy, zz, xy, yz, zx), the brick's static displacement `u0`
    /// and shapes `local` (node-major, as `shapes_at_nodes`' rows) and Lame's constants.
    pub(super) fn point(
        &mut self,
        g: &[[f64; 3]; 20],
        wd: f64,
        s: &[f64; 6],
        u0: &[[f64; 3]; 20],
        local: &[f64],
        (lam, mu): (f64, f64),
    ) {
        let stride = 3 * self.n;
        let sig = [[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]];
        let g0 = gradient(g, |node, i| u0[node][i]);
        let (c9, c6) = (9 * self.filled, 6 * self.filled);
        for m in 0..self.n {
            let h = gradient(g, |node, c| local[node * stride + 3 * m + c]);
            for c in 0..3 {
                for j in 0..3 {
                    self.a9[(m, c9 + 3 * c + j)] = h[c][j];
                    self.b9[(m, c9 + 3 * c + j)] =
                        wd * (h[c][0] * sig[0][j] + h[c][1] * sig[1][j] + h[c][2] * sig[2][j]);
                }
            }
            // (G0^T H)_ij = sum_c G0_ci H_cj.
            let gh: [[f64; 3]; 3] = std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..3).map(|c| g0[c][i] * h[c][j]).sum())
            });
            let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
            let tr = gh[0][0] + gh[1][1] + gh[2][2];
            for (v, &(i, j)) in pairs.iter().enumerate() {
                self.a6[(m, c6 + v)] = 0.5 * (h[i][j] + h[j][i]);
                let e = 0.5 * (gh[i][j] + gh[j][i]);
                let c = if i == j {
                    lam * tr + 2.0 * mu * e
                } else {
                    4.0 * mu * e
                };
                self.b6[(m, c6 + v)] = 2.0 * wd * c;
            }
        }
        self.filled += 1;
        if self.filled == BATCH {
            self.flush();
        }
    }

    /// K_sigma += B9 A9^T and K_u += B6 A6^T over the batch's points; the batch empties.
    fn flush(&mut self) {
        let add = |a: &DMatrix<f64>, b: &DMatrix<f64>, cols: usize, k: &mut DMatrix<f64>| {
            k.gemm(
                1.0,
                &b.columns(0, cols),
                &a.columns(0, cols).transpose(),
                1.0,
            );
        };
        add(&self.a9, &self.b9, 9 * self.filled, &mut self.ks);
        add(&self.a6, &self.b6, 6 * self.filled, &mut self.ku);
        self.filled = 0;
    }

    /// (K_sigma, K_u), symmetrised.
    pub(super) fn finish(mut self) -> (DMatrix<f64>, DMatrix<f64>) {
        if self.filled > 0 {
            self.flush();
        }
        let (ks, ku) = (&self.ks, &self.ku);
        (0.5 * (ks + ks.transpose()), 0.5 * (ku + ku.transpose()))
    }
}

/// The gradient of a field given at a brick's 20 nodes (`at(node, i)`: its component i there)
/// from the shape functions' spatial gradients `g`: [i][j] = d field_i / d x_j.
fn gradient(g: &[[f64; 3]; 20], at: impl Fn(usize, usize) -> f64) -> [[f64; 3]; 3] {
    let mut h = [[0.0; 3]; 3];
    for (node, gn) in g.iter().enumerate() {
        for i in 0..3 {
            let v = at(node, i);
            for j in 0..3 {
                h[i][j] += v * gn[j];
            }
        }
    }
    h
}
