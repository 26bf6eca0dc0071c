//! Butcher tableaux as plain data. The methods read their coefficients from here, so a tableau
//! can be checked against the order conditions in one place (see the tests at the bottom).

/// An s-stage Runge-Kutta tableau with an optional embedded weight vector. `a` is the full
/// s x s matrix, row-major; explicit methods leave the diagonal and upper triangle zero,
/// diagonally implicit ones the upper triangle only.
#[derive(Clone, Copy, Debug)]
pub struct Tableau<const S: usize> {
    pub a: [[f64; S]; S],
    pub b: [f64; S],
    /// Embedded (lower order) weights, used only for the error estimate.
    pub b_hat: [f64; S],
    pub c: [f64; S],
    /// Order of `b` and of `b_hat`.
    pub order: u32,
    pub order_hat: u32,
}

/// Classic fourth-order Runge-Kutta (Kutta 1901). No embedded pair: `b_hat` repeats `b` and
/// `order_hat` is 0 to make that explicit.
pub const RK4: Tableau<4> = Tableau {
    a: [
        [0.0, 0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0, 0.0],
        [0.0, 0.5, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ],
    b: [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    b_hat: [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    c: [0.0, 0.5, 0.5, 1.0],
    order: 4,
    order_hat: 0,
};

/// Dormand & Prince (1980) 5(4) pair, as in Hairer, Norsett & Wanner, Solving ODEs I, Table
/// II.5.2. The seventh stage is evaluated at the new solution, so it is the first stage of the
/// next step (FSAL): b equals the last row of `a`.
pub const DOPRI5: Tableau<7> = Tableau {
    a: [
        [0.0; 7],
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
            0.0,
        ],
    ],
    b: [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    b_hat: [
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ],
    c: [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    order: 5,
    order_hat: 4,
};

/// Coefficients of Hairer's continuous extension of DOPRI5 (Solving ODEs I, Section II.6,
/// and the published `dopri5` code): the fifth term of the dense output polynomial is
/// h * sum(d_i k_i). Stage 2 does not enter.
pub const DOPRI5_DENSE_D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Five-stage L-stable SDIRK of order 4 with an embedded method of order 3, gamma = 1/4;
/// Hairer & Wanner, Solving ODEs II, Section IV.6, Table 6.5. Stiffly accurate: b is the last
/// row of `a`, so y1 is the last stage value and R(infinity) = 0.
pub const SDIRK4: Tableau<5> = Tableau {
    a: [
        [0.25, 0.0, 0.0, 0.0, 0.0],
        [0.5, 0.25, 0.0, 0.0, 0.0],
        [17.0 / 50.0, -1.0 / 25.0, 0.25, 0.0, 0.0],
        [371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.25, 0.0],
        [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.25],
    ],
    b: [25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.25],
    b_hat: [59.0 / 48.0, -17.0 / 96.0, 225.0 / 32.0, -85.0 / 12.0, 0.0],
    c: [0.25, 0.75, 11.0 / 20.0, 0.5, 1.0],
    order: 4,
    order_hat: 3,
};

/// The diagonal entry of [`SDIRK4`].
pub const SDIRK4_GAMMA: f64 = 0.25;

/// The additive pair ARK4(3)6L[2]SA of Kennedy & Carpenter (2003, Appl. Numer. Math. 44,
/// 139-181, Tables 3-6), as SUNDIALS ARKODE lists it (ARK436L2SA_ERK/DIRK_6_3_4): an explicit
/// tableau and an L-stable ESDIRK (gamma = 1/4) that share c, b and the embedded weights, so
/// that y' = f_E + f_I advances as one method of order 4 (embedded 3). Stiffly accurate in the
/// implicit part: b is the last row of `a`.
pub const ARK436_E: Tableau<6> = Tableau {
    a: [
        [0.0; 6],
        [0.5, 0.0, 0.0, 0.0, 0.0, 0.0],
        [13861.0 / 62500.0, 6889.0 / 62500.0, 0.0, 0.0, 0.0, 0.0],
        [
            -116923316275.0 / 2393684061468.0,
            -2731218467317.0 / 15368042101831.0,
            9408046702089.0 / 11113171139209.0,
            0.0,
            0.0,
            0.0,
        ],
        [
            -451086348788.0 / 2902428689909.0,
            -2682348792572.0 / 7519795681897.0,
            12662868775082.0 / 11960479115383.0,
            3355817975965.0 / 11060851509271.0,
            0.0,
            0.0,
        ],
        [
            647845179188.0 / 3216320057751.0,
            73281519250.0 / 8382639484533.0,
            552539513391.0 / 3454668386233.0,
            3354512671639.0 / 8306763924573.0,
            4040.0 / 17871.0,
            0.0,
        ],
    ],
    b: ARK436_B,
    b_hat: ARK436_B_HAT,
    c: ARK436_C,
    order: 4,
    order_hat: 3,
};

/// The implicit half of [`ARK436_E`]'s pair (ESDIRK: the first stage is explicit).
pub const ARK436_I: Tableau<6> = Tableau {
    a: [
        [0.0; 6],
        [0.25, 0.25, 0.0, 0.0, 0.0, 0.0],
        [8611.0 / 62500.0, -1743.0 / 31250.0, 0.25, 0.0, 0.0, 0.0],
        [
            5012029.0 / 34652500.0,
            -654441.0 / 2922500.0,
            174375.0 / 388108.0,
            0.25,
            0.0,
            0.0,
        ],
        [
            15267082809.0 / 155376265600.0,
            -71443401.0 / 120774400.0,
            730878875.0 / 902184768.0,
            2285395.0 / 8070912.0,
            0.25,
            0.0,
        ],
        ARK436_B,
    ],
    b: ARK436_B,
    b_hat: ARK436_B_HAT,
    c: ARK436_C,
    order: 4,
    order_hat: 3,
};

/// The diagonal of [`ARK436_I`] (stages 2 to 6).
pub const ARK436_GAMMA: f64 = 0.25;

const ARK436_B: [f64; 6] = [
    82889.0 / 524892.0,
    0.0,
    15625.0 / 83664.0,
    69875.0 / 102672.0,
    -2260.0 / 8211.0,
    0.25,
];
const ARK436_B_HAT: [f64; 6] = [
    4586570599.0 / 29645900160.0,
    0.0,
    178811875.0 / 945068544.0,
    814220225.0 / 1159782912.0,
    -3700637.0 / 11593932.0,
    61727.0 / 225920.0,
];
const ARK436_C: [f64; 6] = [0.0, 0.5, 83.0 / 250.0, 31.0 / 50.0, 17.0 / 20.0, 1.0];

/// A Rosenbrock method in Hairer's transformed variables u_i (Solving ODEs II, Section IV.7,
/// eq. 7.4'): with W = I / (h gamma) - J,
/// W u_i = f(t + c_i h, y + sum_j a_ij u_j) + sum_j (cm_ij / h) u_j + h d_i f_t,
/// y1 = y + sum_i b_i u_i, error estimate sum_i e_i u_i. Strictly lower triangular `a`, `cm`.
#[derive(Clone, Copy, Debug)]
pub struct Rosenbrock<const S: usize> {
    pub gamma: f64,
    pub a: [[f64; S]; S],
    pub cm: [[f64; S]; S],
    pub b: [f64; S],
    pub e: [f64; S],
    pub c: [f64; S],
    pub d: [f64; S],
    /// Order of `b` and of the embedded solution `b - e`.
    pub order: u32,
    pub order_hat: u32,
}

/// RODAS4: six stages, order 4 with an embedded order 3, L-stable and stiffly accurate
/// (Hairer & Wanner, Solving ODEs II, Section VI.4, Table 4.2; coefficients of their `rodas`
/// code, METH = 1). Stage 6 is evaluated at the stage-5 result, so b = row 6 of `a` with
/// b_6 = 1, and the last stage itself is the error estimate.
pub const RODAS4: Rosenbrock<6> = {
    let a51 = 1.221_224_509_226_641;
    let a52 = 6.019_134_481_288_629;
    let a53 = 12.537_083_329_320_87;
    let a54 = -0.687_886_036_105_895;
    Rosenbrock {
        gamma: 0.25,
        a: [
            [0.0; 6],
            [1.544, 0.0, 0.0, 0.0, 0.0, 0.0],
            [
                0.946_678_528_081_582_6,
                0.255_701_169_898_328_4,
                0.0,
                0.0,
                0.0,
                0.0,
            ],
            [
                3.314_825_187_068_521,
                2.896_124_015_972_201,
                0.998_641_913_997_781_7,
                0.0,
                0.0,
                0.0,
            ],
            [a51, a52, a53, a54, 0.0, 0.0],
            [a51, a52, a53, a54, 1.0, 0.0],
        ],
        cm: [
            [0.0; 6],
            [-5.6688, 0.0, 0.0, 0.0, 0.0, 0.0],
            [
                -2.430_093_356_833_875,
                -0.206_359_915_709_191_5,
                0.0,
                0.0,
                0.0,
                0.0,
            ],
            [
                -0.107_352_905_815_137_5,
                -9.594_562_251_023_355,
                -20.470_286_148_096_16,
                0.0,
                0.0,
                0.0,
            ],
            [
                7.496_443_313_967_647,
                -10.246_804_314_643_52,
                -33.999_903_528_199_05,
                11.708_908_932_061_6,
                0.0,
                0.0,
            ],
            [
                8.083_246_795_921_522,
                -7.981_132_988_064_893,
                -31.521_594_328_743_71,
                16.319_305_431_231_36,
                -6.058_818_238_834_054,
                0.0,
            ],
        ],
        b: [a51, a52, a53, a54, 1.0, 1.0],
        e: [0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        c: [0.0, 0.386, 0.21, 0.63, 1.0, 1.0],
        d: [0.25, -0.1043, 0.1035, -0.036_200_000_000_000_23, 0.0, 0.0],
        order: 4,
        order_hat: 3,
    }
};

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    fn dot<const S: usize>(u: &[f64; S], v: &[f64; S]) -> f64 {
        u.iter().zip(v).map(|(x, y)| x * y).sum()
    }
    fn mat_vec<const S: usize>(a: &[[f64; S]; S], v: &[f64; S]) -> [f64; S] {
        let mut out = [0.0; S];
        for i in 0..S {
            out[i] = dot(&a[i], v);
        }
        out
    }
    fn hadamard<const S: usize>(u: &[f64; S], v: &[f64; S]) -> [f64; S] {
        let mut out = [0.0; S];
        for i in 0..S {
            out[i] = u[i] * v[i];
        }
        out
    }

    /// Residuals of the order conditions sum b_i Phi_i(t) = 1/gamma(t) for all rooted trees t
    /// with at most 5 nodes (Butcher; Solving ODEs I, Table II.2.2), grouped by order.
    /// Returns the largest residual for each order 1..=5.
    pub(crate) fn order_residuals<const S: usize>(
        a: &[[f64; S]; S],
        b: &[f64; S],
        c: &[f64; S],
    ) -> [f64; 5] {
        let one = [1.0; S];
        let c2 = hadamard(c, c);
        let c3 = hadamard(&c2, c);
        let c4 = hadamard(&c3, c);
        let ac = mat_vec(a, c);
        let ac2 = mat_vec(a, &c2);
        let ac3 = mat_vec(a, &c3);
        let aac = mat_vec(a, &ac);
        let aac2 = mat_vec(a, &ac2);
        let aaac = mat_vec(a, &aac);
        let a_cac = mat_vec(a, &hadamard(c, &ac));
        let conds: [(usize, f64, f64); 17] = [
            (1, dot(b, &one), 1.0),
            (2, dot(b, c), 1.0 / 2.0),
            (3, dot(b, &c2), 1.0 / 3.0),
            (3, dot(b, &ac), 1.0 / 6.0),
            (4, dot(b, &c3), 1.0 / 4.0),
            (4, dot(b, &hadamard(c, &ac)), 1.0 / 8.0),
            (4, dot(b, &ac2), 1.0 / 12.0),
            (4, dot(b, &aac), 1.0 / 24.0),
            (5, dot(b, &c4), 1.0 / 5.0),
            (5, dot(b, &hadamard(&c2, &ac)), 1.0 / 10.0),
            (5, dot(b, &hadamard(c, &ac2)), 1.0 / 15.0),
            (5, dot(b, &hadamard(c, &aac)), 1.0 / 30.0),
            (5, dot(b, &hadamard(&ac, &ac)), 1.0 / 20.0),
            (5, dot(b, &ac3), 1.0 / 20.0),
            (5, dot(b, &a_cac), 1.0 / 40.0),
            (5, dot(b, &aac2), 1.0 / 60.0),
            (5, dot(b, &aaac), 1.0 / 120.0),
        ];
        let mut worst = [0.0f64; 5];
        for (order, value, expected) in conds {
            worst[order - 1] = worst[order - 1].max((value - expected).abs());
        }
        worst
    }

    /// Checks the row-sum condition c_i = sum_j a_ij, and that the order conditions hold up to
    /// `order` and (when order < 5) fail for order + 1, i.e. the order is exactly as claimed.
    fn check<const S: usize>(t: &Tableau<S>) {
        for i in 0..S {
            let row: f64 = t.a[i].iter().sum();
            assert!(
                (row - t.c[i]).abs() < 1e-14,
                "row {i}: {row} != c = {}",
                t.c[i]
            );
        }
        let check_order = |b: &[f64; S], p: u32| {
            let res = order_residuals(&t.a, b, &t.c);
            for (k, r) in res.iter().enumerate().take(p as usize) {
                assert!(*r < 1e-13, "order {} condition residual {r}", k + 1);
            }
            if (p as usize) < 5 {
                assert!(
                    res[p as usize] > 1e-6,
                    "claims order {p} but satisfies order {}",
                    p + 1
                );
            }
        };
        check_order(&t.b, t.order);
        if t.order_hat > 0 {
            check_order(&t.b_hat, t.order_hat);
        }
    }

    #[test]
    fn rk4_has_order_4() {
        check(&RK4);
    }

    #[test]
    fn dopri5_has_orders_5_and_4() {
        check(&DOPRI5);
        // FSAL: b is the last row of A and c_7 = 1.
        assert_eq!(DOPRI5.b, DOPRI5.a[6]);
    }

    #[test]
    fn sdirk4_has_orders_4_and_3_and_is_l_stable() {
        check(&SDIRK4);
        for i in 0..5 {
            assert_eq!(SDIRK4.a[i][i], SDIRK4_GAMMA);
        }
        // Stiffly accurate, hence R(inf) = 1 - b^T A^{-1} 1 = 0: the last stage is the solution.
        assert_eq!(SDIRK4.b, SDIRK4.a[4]);
        // R(z) at large |z| by solving (I - z A) k = z 1, R = 1 + b.k; tends to 0 like 1/z.
        for z in [-1e4, -1e8] {
            let mut k = [0.0; 5];
            for i in 0..5 {
                let s = 1.0 + dot(&SDIRK4.a[i], &k);
                k[i] = z * s / (1.0 - z * SDIRK4.a[i][i]);
            }
            let r = 1.0 + dot(&SDIRK4.b, &k);
            assert!(r.abs() < 50.0 / z.abs(), "R({z}) = {r}");
        }
    }

    /// Each half of ARK4(3)6L[2]SA is a Runge-Kutta method of order 4 (embedded 3) on its own;
    /// the pair's coupling conditions (one half's A inside the other's trees) hold to order 4;
    /// the implicit half is L-stable.
    #[test]
    fn ark436_halves_and_their_coupling_have_orders_4_and_3() {
        for t in [&ARK436_E, &ARK436_I] {
            check(t);
            for i in 0..6 {
                let row: f64 = t.a[i].iter().sum();
                assert!((row - t.c[i]).abs() < 1e-14, "row sum {i}");
            }
        }
        let (ae, ai) = (&ARK436_E.a, &ARK436_I.a);
        let (b, c) = (&ARK436_B, &ARK436_C);
        for (x, y) in [(ae, ai), (ai, ae)] {
            // The mixed trees (the others hold per half, c being shared): order 3,
            // b.(A_x A_y 1) = 1/6; order 4, b.(A_x A_y c) = 1/24.
            let r = dot(b, &mat_vec(x, &mat_vec(y, &[1.0; 6])));
            assert!((r - 1.0 / 6.0).abs() < 1e-12, "b A A 1 = {r}");
            let r = dot(b, &mat_vec(x, &mat_vec(y, c)));
            assert!((r - 1.0 / 24.0).abs() < 1e-10, "b A A c = {r}");
        }
        for i in 1..6 {
            assert_eq!(ai[i][i], ARK436_GAMMA);
        }
        assert_eq!(ARK436_I.a[5], ARK436_B);
        // L-stable: R(z) of the implicit half tends to 0 like 1/z.
        for z in [-1e4, -1e8] {
            let mut k = [0.0; 6];
            for i in 0..6 {
                let s = 1.0 + dot(&ai[i], &k);
                k[i] = z * s / (1.0 - z * ai[i][i]);
            }
            let r = 1.0 + dot(b, &k);
            assert!(r.abs() < 50.0 / z.abs(), "R({z}) = {r}");
        }
    }

    /// The dense output of DOPRI5 is y0 + h sum b_i(theta) k_i; its weights must satisfy the
    /// order conditions up to order 4 with right-hand sides theta^rho(t) / gamma(t) (Solving
    /// ODEs I, Section II.6). The weights follow from the Hermite-type formula used in
    /// `dopri5.rs`.
    #[test]
    fn dopri5_dense_output_has_order_4() {
        let b = DOPRI5.b;
        let d = DOPRI5_DENSE_D;
        for theta in [0.1, 0.3, 0.5, 0.77, 1.0] {
            let th1 = 1.0 - theta;
            // y(theta) - y0 = theta*(r2 + th1*(r3 + theta*(r4 + th1*r5))), with
            // r2 = h b.k, r3 = h k1 - r2, r4 = r2 - h k7 - r3, r5 = h d.k (per unit h).
            let mut w = [0.0; 7];
            for i in 0..7 {
                let e1 = if i == 0 { 1.0 } else { 0.0 };
                let e7 = if i == 6 { 1.0 } else { 0.0 };
                let r2 = b[i];
                let r3 = e1 - r2;
                let r4 = r2 - e7 - r3;
                let r5 = d[i];
                w[i] = theta * (r2 + th1 * (r3 + theta * (r4 + th1 * r5)));
            }
            let one = [1.0; 7];
            let c = DOPRI5.c;
            let c2 = hadamard(&c, &c);
            let ac = mat_vec(&DOPRI5.a, &c);
            let conds = [
                (dot(&w, &one), theta),
                (dot(&w, &c), theta.powi(2) / 2.0),
                (dot(&w, &c2), theta.powi(3) / 3.0),
                (dot(&w, &ac), theta.powi(3) / 6.0),
                (dot(&w, &hadamard(&c2, &c)), theta.powi(4) / 4.0),
                (dot(&w, &hadamard(&c, &ac)), theta.powi(4) / 8.0),
                (dot(&w, &mat_vec(&DOPRI5.a, &c2)), theta.powi(4) / 12.0),
                (dot(&w, &mat_vec(&DOPRI5.a, &ac)), theta.powi(4) / 24.0),
            ];
            for (k, (v, e)) in conds.iter().enumerate() {
                assert!(
                    (v - e).abs() < 1e-13,
                    "theta {theta}, condition {k}: {v} vs {e}"
                );
            }
        }
    }

    /// R(z) of a Rosenbrock tableau on y' = lambda y (J = lambda, z = h lambda): the stages
    /// solve (1/gamma - z) u_i = z (1 + sum a_ij u_j) + sum cm_ij u_j.
    fn rosenbrock_r<const S: usize>(m: &Rosenbrock<S>, z: f64) -> f64 {
        let mut u = [0.0; S];
        for i in 0..S {
            let rhs = z * (1.0 + dot(&m.a[i], &u)) + dot(&m.cm[i], &u);
            u[i] = rhs / (1.0 / m.gamma - z);
        }
        1.0 + dot(&m.b, &u)
    }

    /// RODAS4 on the test equation: R(z) - e^z = O(z^5) (order 4; halving z divides the
    /// defect by about 2^5), the embedded solution has order 3, and R(-inf) = 0 (L-stable).
    #[test]
    fn rodas4_stability_function_has_order_4_and_vanishes_at_infinity() {
        let m = &RODAS4;
        let defect = |z: f64| (rosenbrock_r(m, z) - z.exp()).abs();
        let ratio = defect(-0.02) / defect(-0.01);
        assert!(
            (ratio.log2() - 5.0).abs() < 0.2,
            "order 4 gives ratio 2^5: {ratio}"
        );
        let mut emb = *m;
        for i in 0..6 {
            emb.b[i] = m.b[i] - m.e[i];
        }
        let d_emb = |z: f64| (rosenbrock_r(&emb, z) - z.exp()).abs();
        let ratio = d_emb(-0.02) / d_emb(-0.01);
        assert!(
            (ratio.log2() - 4.0).abs() < 0.2,
            "embedded order 3: {ratio}"
        );
        for z in [-1e4, -1e8] {
            let r = rosenbrock_r(m, z);
            assert!(r.abs() < 50.0 / z.abs(), "R({z}) = {r}");
        }
        // A-stable along the imaginary axis.
        for w in [0.1, 1.0, 10.0, 1e3] {
            let mut u = [(0.0f64, 0.0f64); 6];
            let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
            let z = (0.0, w);
            for i in 0..6 {
                let mut acc = (1.0, 0.0);
                let mut cacc = (0.0, 0.0);
                for j in 0..i {
                    acc.0 += m.a[i][j] * u[j].0;
                    acc.1 += m.a[i][j] * u[j].1;
                    cacc.0 += m.cm[i][j] * u[j].0;
                    cacc.1 += m.cm[i][j] * u[j].1;
                }
                let num = mul(z, acc);
                let num = (num.0 + cacc.0, num.1 + cacc.1);
                let den = (1.0 / m.gamma, -w);
                let dd = den.0 * den.0 + den.1 * den.1;
                u[i] = mul(num, (den.0 / dd, -den.1 / dd));
            }
            let r = (
                1.0 + (0..6).map(|i| m.b[i] * u[i].0).sum::<f64>(),
                (0..6).map(|i| m.b[i] * u[i].1).sum::<f64>(),
            );
            assert!(r.0.hypot(r.1) <= 1.0 + 1e-12, "|R(i {w})| = {:?}", r);
        }
    }
}
