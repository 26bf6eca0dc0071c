use super::*;

#[test]
fn folding_and_sharing() {
    let ((a, b, z, s), g) = trace(|| {
        let x = Sym::input();
        let y = Sym::input();
        let a = x * y + Sym::c(2.0) * Sym::c(3.0);
        let b = y * x + 6.0; // same node as a: commutative ordering + folding
        let z = x * 0.0 + y * 1.0 - y; // zero
        let s = (x - x).sqrt();
        (a, b, z, s)
    });
    assert_eq!(a, b);
    assert_eq!(g.constant(z.0), Some(0.0));
    assert_eq!(g.constant(s.0), Some(0.0));
    assert_eq!(g.eval(&[2.0, 5.0], &[a]), vec![16.0]);
}

/// y + A x recorded as one node: its value is the f64 loop's to the bit, zero columns
/// (a constant-0 x or an all-zero column) and rows left all zero are folded away, and a
/// MatVec consuming another's whole result is one chain.
#[test]
fn mat_vec_nodes_fold_and_evaluate_like_the_f64_loop() {
    // 3 rows x 4 columns, column-major; column 2 is all zero, row 1 is zero in the columns
    // that stay (x[3] is the constant 0).
    let a = [
        0.5, 0.0, -1.25, //
        2.0, 0.0, 3.0, //
        0.0, 0.0, 0.0, //
        7.0, 9.0, 1.0,
    ];
    let (out, g) = trace(|| {
        let x: Vec<Sym> = (0..3).map(|_| Sym::input()).chain([Sym::c(0.0)]).collect();
        let mut y = vec![Sym::input(), Sym::c(0.0), Sym::input()];
        Sym::mat_vec(&a, &x, &mut y);
        let first = y.clone();
        Sym::mat_vec(&a, &x, &mut y);
        (first, y)
    });
    let (first, second) = out;
    let mvs: Vec<Node> = g
        .nodes
        .iter()
        .copied()
        .filter(|n| matches!(n, Node::MatVec { .. }))
        .collect();
    assert_eq!(mvs.len(), 2, "{:?}", g.nodes);
    let Node::MatVec { table, x, y } = mvs[0] else {
        unreachable!()
    };
    // Columns 0 and 1 of rows 0 and 2 are left.
    assert_eq!(g.tables[table as usize], vec![0.5, -1.25, 2.0, 3.0]);
    assert_eq!(g.lists[x as usize].len(), 2);
    assert_eq!(g.lists[y as usize].len(), 2);
    assert_eq!(g.constant(first[1].0), Some(0.0), "row 1 stays y");
    let inputs = [0.3, -1.7, 2.9, 0.11, -4.0];
    let xs = [0.3, -1.7, 2.9, 0.0];
    let mut y = [0.11, 0.0, -4.0];
    f64::mat_vec(&a, &xs, &mut y);
    let v1 = g.eval(&inputs, &first);
    assert_eq!(v1, y.to_vec(), "bit for bit");
    f64::mat_vec(&a, &xs, &mut y);
    assert_eq!(g.eval(&inputs, &second), y.to_vec());
    // 2 x 2 x 2 operations per node.
    assert_eq!(g.op_count(&second), 16);
}

/// The picks differentiate row by row: d(y + A x)/dx_j is column j.
#[test]
fn picks_differentiate_to_the_table_columns() {
    let a = [1.5, -2.0, 0.25, 4.0];
    let (d, g) = trace(|| {
        let x = [Sym::input(), Sym::input()];
        let mut y = [x[0] * x[1], Sym::c(1.0)];
        Sym::mat_vec(&a, &x, &mut y);
        (derivative(&y, 0), derivative(&y, 1))
    });
    let v0 = g.eval(&[2.0, 3.0], &d.0);
    let v1 = g.eval(&[2.0, 3.0], &d.1);
    assert_eq!(v0, vec![3.0 + 1.5, -2.0], "dy/dx0 = [x1 + a00, a10]");
    assert_eq!(v1, vec![2.0 + 0.25, 4.0], "dy/dx1 = [x0 + a01, a11]");
}

/// The dependency pass sees through MatVec lists.
#[test]
fn dependencies_pass_through_mat_vec() {
    let a = [1.0, 2.0, 3.0, 4.0];
    let (y, g) = trace(|| {
        let q = Sym::input();
        let t = Sym::input();
        let mut y = [t.sin(), Sym::c(0.0)];
        Sym::mat_vec(&a, &[q, t], &mut y);
        let mut z = [t.cos(), Sym::c(2.0)];
        Sym::mat_vec(&a, &[t, t * t], &mut z);
        (y, z)
    });
    let dep = g.depends_on(0..1);
    assert!(y.0.iter().all(|s| dep[s.0 as usize]));
    assert!(y.1.iter().all(|s| !dep[s.0 as usize]));
}
