//! The brick's shape functions and Gauss rules, the assembly on fields with a closed-form
//! integral, the rigid parts' term against the exact centrifugal potential; and, through ccx
//! (skipped without it, except under CI): our reading of ccx's bricks and Gauss points against
//! the stresses ccx prints there, and a spinning cantilever's Southwell coefficients.

use super::*;
use crate::mesh::Rigid;
use crate::modal::Shapes;

/// A brick with curved edges: the box a x b x c at `origin`, its mid-edge nodes pushed off the
/// chords and its corners moved a little.
fn distorted(origin: [f64; 3], size: [f64; 3]) -> [[f64; 3]; 20] {
    std::array::from_fn(|a| {
        let p = hex20::NODES[a];
        let mut x: [f64; 3] = std::array::from_fn(|i| origin[i] + 0.5 * size[i] * (p[i] + 1.0));
        let s = 0.04 * (a as f64 * 0.7).sin();
        x[0] += s * size[0] * p[1];
        x[1] += s * size[1] * p[2];
        x[2] += 0.03 * size[2] * (1.0 - p[0] * p[0]);
        x
    })
}

#[test]
fn shape_functions_interpolate_and_their_derivatives_are_the_finite_differences() {
    let mut worst = 0.0f64;
    for (b, pb) in hex20::NODES.iter().enumerate() {
        let n = hex20::shape(*pb);
        for (a, v) in n.iter().enumerate() {
            worst = worst.max((v - if a == b { 1.0 } else { 0.0 }).abs());
        }
    }
    eprintln!("N_a(x_b) - delta_ab: {worst:e}");
    // Measured 0 (the nodes' coordinates are exact in binary).
    assert!(worst == 0.0, "N_a(x_b) - delta_ab: {worst:e}");
    let p = [0.31, -0.57, 0.83];
    let sum: f64 = hex20::shape(p).iter().sum();
    assert!((sum - 1.0).abs() < 1e-15, "{sum}");
    let d = hex20::natural_gradient(p);
    let h = 1e-6;
    let mut worst = 0.0f64;
    for k in 0..3 {
        let (mut a, mut b) = (p, p);
        a[k] += h;
        b[k] -= h;
        let (na, nb) = (hex20::shape(a), hex20::shape(b));
        for i in 0..20 {
            worst = worst.max(((na[i] - nb[i]) / (2.0 * h) - d[i][k]).abs());
        }
    }
    eprintln!("dN/dxi against central differences: {worst:e}");
    // Central differences of cubic functions: error h^2 / 6 times the third derivative.
    // Measured 6.6e-11.
    assert!(worst < 5e-10, "{worst:e}");
}

#[test]
fn gradients_of_a_linear_field_and_the_volume_are_exact() {
    let x = distorted([0.1, -0.2, 0.3], [0.05, 0.02, 0.01]);
    let a = [[1.0, 2.0, -0.5], [0.3, -1.0, 4.0], [2.5, 0.7, 0.1]];
    let u: [[f64; 3]; 20] =
        std::array::from_fn(|n| std::array::from_fn(|i| (0..3).map(|j| a[i][j] * x[n][j]).sum()));
    let mut worst = 0.0f64;
    let mut vols = Vec::new();
    for n in [2, 3] {
        let mut vol = 0.0;
        for (p, w) in hex20::gauss(n).unwrap() {
            let (g, det) = hex20::spatial_gradient(&x, p).unwrap();
            vol += w * det;
            for i in 0..3 {
                for j in 0..3 {
                    let h: f64 = (0..20).map(|b| u[b][i] * g[b][j]).sum();
                    worst = worst.max((h - a[i][j]).abs());
                }
            }
        }
        vols.push(vol);
    }
    eprintln!("linear field's gradient: {worst:e}; volumes {vols:?}");
    // The 20-node brick holds linear fields exactly: measured 1.8e-13 (round-off of the
    // inverse Jacobian of a 1 cm brick times coordinates of 0.3 m).
    assert!(worst < 1e-12, "{worst:e}");
    // Both rules on the curved brick: the 2-point rule of C3D20R is not exact for its
    // Jacobian (measured 1.6e-5 relative to the 3-point rule's volume).
    let rel = (vols[0] - vols[1]).abs() / vols[1];
    assert!(rel < 1e-4, "{vols:?}");
    // A box: both exact.
    let size = [0.05, 0.02, 0.01];
    let b: [[f64; 3]; 20] = std::array::from_fn(|a| {
        std::array::from_fn(|i| 0.5 * size[i] * (hex20::NODES[a][i] + 1.0))
    });
    for n in [2, 3] {
        let v: f64 = hex20::gauss(n)
            .unwrap()
            .iter()
            .map(|(p, w)| w * hex20::spatial_gradient(&b, *p).unwrap().1)
            .sum();
        assert!((v / 1e-5 - 1.0).abs() < 1e-14, "{n} points: {v}");
    }
}

/// A prestress of one brick with uniform stress `s`.
fn one_brick(x: [[f64; 3]; 20], s: [f64; 6], points: usize) -> Prestress {
    Prestress {
        centrifugal: Centrifugal::new(1.0, [0.0; 3], [1.0, 0.0, 0.0]),
        bricks: vec![Brick {
            number: 1,
            nodes: std::array::from_fn(|a| 100 + a),
            stress: vec![s; points],
            lame: (121e9, 81e9),
        }],
        coords: (0..20).map(|a| (100 + a, x[a])).collect(),
        u0: (0..20).map(|a| (100 + a, [0.0; 3])).collect(),
        loads: Vec::new(),
        solve_s: 0.0,
    }
}

#[test]
fn the_assembly_integrates_grad_u_sigma_grad_v_exactly_for_linear_fields() {
    // Linear fields u_k = A_k x on a brick under a uniform stress: K_kl = V tr(A_k sigma A_l^T).
    let x = distorted([0.0, 0.0, 0.0], [0.04, 0.03, 0.02]);
    let s = [3e6, -1e6, 0.5e6, 2e6, -0.7e6, 1.1e6];
    let sig = [[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]];
    let a: [[[f64; 3]; 3]; 2] = [
        [[1.0, 0.2, 0.0], [0.0, -0.5, 0.3], [0.1, 0.0, 2.0]],
        [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.4, 0.2, -0.3]],
    ];
    let shapes: Vec<Vec<(usize, [f64; 3])>> = a
        .iter()
        .map(|m| {
            (0..20)
                .map(|n| {
                    let v = std::array::from_fn(|i| (0..3).map(|j| m[i][j] * x[n][j]).sum());
                    (100 + n, v)
                })
                .collect()
        })
        .collect();
    let refs: Vec<&[(usize, [f64; 3])]> = shapes.iter().map(|v| &v[..]).collect();
    let vol: f64 = hex20::gauss(3)
        .unwrap()
        .iter()
        .map(|(p, w)| w * hex20::spatial_gradient(&x, *p).unwrap().1)
        .sum();
    let mut worst = 0.0f64;
    let (k, ku) = one_brick(x, s, 27).stiffness(&refs).unwrap();
    assert!(
        ku.iter().all(|v| *v == 0.0),
        "no static displacement, no K_u: {ku}"
    );
    for p in 0..2 {
        for q in 0..2 {
            let mut e = 0.0;
            for i in 0..3 {
                for j in 0..3 {
                    for m in 0..3 {
                        e += a[p][i][j] * sig[j][m] * a[q][i][m];
                    }
                }
            }
            e *= vol;
            worst = worst.max((k[(p, q)] - e).abs() / e.abs().max(1.0));
        }
    }
    eprintln!("K against V tr(A_k sigma A_l^T): {worst:e}");
    // Measured 5.9e-16 (round-off).
    assert!(worst < 6e-15, "{worst:e}: {k}");
    // A uniform static gradient G0 (u0 = G0 x): K_u,kl = V [e_k : C : sym(G0^T A_l) +
    // sym(G0^T A_k) : C : e_l], e = sym(A), C : e = lambda tr(e) E + 2 mu e.
    let g0 = [
        [2e-4, -1e-4, 3e-5],
        [5e-5, 1e-4, -2e-4],
        [1e-4, 3e-4, -5e-5],
    ];
    let mut pre = one_brick(x, s, 8);
    pre.u0 = (0..20)
        .map(|a| {
            let v = std::array::from_fn(|i| (0..3).map(|j| g0[i][j] * x[a][j]).sum());
            (100 + a, v)
        })
        .collect();
    let (_, ku) = pre.stiffness(&refs).unwrap();
    let (lam, mu) = pre.bricks[0].lame;
    let sym = |m: [[f64; 3]; 3]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (m[i][j] + m[j][i])))
    };
    let gt = |m: [[f64; 3]; 3]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|c| g0[c][i] * m[c][j]).sum()))
    };
    let ddot = |p: [[f64; 3]; 3], q: [[f64; 3]; 3]| -> f64 {
        let tr = (p[0][0] + p[1][1] + p[2][2]) * (q[0][0] + q[1][1] + q[2][2]);
        lam * tr
            + 2.0
                * mu
                * (0..3)
                    .flat_map(|i| (0..3).map(move |j| (i, j)))
                    .map(|(i, j)| p[i][j] * q[i][j])
                    .sum::<f64>()
    };
    let vol8: f64 = hex20::gauss(2)
        .unwrap()
        .iter()
        .map(|(p, w)| w * hex20::spatial_gradient(&x, *p).unwrap().1)
        .sum();
    let mut worst_u = 0.0f64;
    for p in 0..2 {
        for q in 0..2 {
            let e = vol8 * (ddot(sym(a[p]), sym(gt(a[q]))) + ddot(sym(gt(a[p])), sym(a[q])));
            worst_u = worst_u.max((ku[(p, q)] - e).abs() / e.abs().max(1.0));
        }
    }
    eprintln!("K_u against its closed form: {worst_u:e}");
    // Measured 1.4e-13 (round-off of terms that partly cancel).
    assert!(worst_u < 1e-12, "{worst_u:e}: {ku}");
    // A shape missing a node is refused.
    let short = &shapes[0][..19];
    assert!(one_brick(x, s, 27).stiffness(&[short]).is_err());
}

/// Three point masses on a rigid part whose REF node is off the spin axis, spinning about x
/// through (0, 0.1, 0).
fn rigid_disc() -> (Mesh, Centrifugal) {
    let mut m = Mesh::new("rigid disc");
    let pts = [[0.2, 0.35, 0.05], [0.25, -0.1, 0.2], [0.15, 0.0, -0.3]];
    let ids: Vec<usize> = pts.iter().map(|p| m.fresh_node(*p)).collect();
    m.part("M", Section::Mass { kg: 0.7 }).elements = ids.iter().map(|&i| vec![i]).collect();
    m.add_to_set("R", &ids);
    let ref_node = m.fresh_node([0.21, 0.12, 0.03]);
    let rot_node = m.fresh_node([0.21, 0.12, 0.03]);
    m.rigid.push(Rigid {
        nset: "R".into(),
        ref_node,
        rot_node,
    });
    (m, Centrifugal::new(90.0, [0.0, 0.1, 0.0], [1.0, 0.0, 0.0]))
}

#[test]
fn a_rigid_parts_stiffness_less_its_spin_softening_is_the_centrifugal_potentials_hessian() {
    // V(theta) = -1/2 Omega^2 sum m |P (x_ref + R(theta) rho - a)|^2 exactly (Rodrigues);
    // its Hessian at theta = 0 is what the part's K_G less its spin softening must be.
    let (m, c) = rigid_disc();
    let r = &m.rigid[0];
    let x0 = m.nodes[r.ref_node - 1];
    let masses: Vec<usize> = m.nsets["R"].clone();
    let modes: Vec<Shapes> = (0..3)
        .map(|k| {
            let mut th = [0.0; 3];
            th[k] = 1.0;
            Shapes {
                frequency_hz: 1.0,
                w: masses
                    .iter()
                    .map(|&id| {
                        let rho = sub(m.nodes[id - 1], x0);
                        (id, washdyn_model::geom::f::cross(th, rho))
                    })
                    .collect(),
                rot: [(r.rot_node, th)].into_iter().collect(),
            }
        })
        .collect();
    let loads = point_mass_loads(&m, &c);
    let w2 = c.omega * c.omega;
    let k = rigid_parts(&m, &loads, &modes).unwrap()
        - w2 * point_mass_softening(&m, &modes, c.axis).unwrap();
    let v = |th: [f64; 3]| -> f64 {
        let t = (th[0] * th[0] + th[1] * th[1] + th[2] * th[2]).sqrt();
        masses
            .iter()
            .map(|&id| {
                let rho = sub(m.nodes[id - 1], x0);
                let rot = if t == 0.0 {
                    rho
                } else {
                    let e = th.map(|x| x / t);
                    let ex = washdyn_model::geom::f::cross(e, rho);
                    let ed = dot(e, rho);
                    std::array::from_fn(|i| {
                        rho[i] * t.cos() + ex[i] * t.sin() + e[i] * ed * (1.0 - t.cos())
                    })
                };
                let x: [f64; 3] = std::array::from_fn(|i| x0[i] + rot[i]);
                let p = c.off_axis(x);
                -0.5 * w2 * 0.7 * dot(p, p)
            })
            .sum()
    };
    let h = 1e-4;
    let mut worst = 0.0f64;
    let scale = k.abs().max();
    for i in 0..3 {
        for j in 0..3 {
            let at = |si: f64, sj: f64| {
                let mut t = [0.0; 3];
                t[i] += si * h;
                t[j] += sj * h;
                v(t)
            };
            let hess =
                (at(1.0, 1.0) - at(1.0, -1.0) - at(-1.0, 1.0) + at(-1.0, -1.0)) / (4.0 * h * h);
            worst = worst.max((hess - k[(i, j)]).abs() / scale);
        }
    }
    eprintln!("rigid part's K_G - S against the potential's Hessian: {worst:e}");
    // Central differences, h = 1e-4: measured 2.2e-8 of the largest entry.
    assert!(worst < 2e-7, "{worst:e}\n{k}");
    // About the spin axis a rigid part on the axis turns freely: with the REF node on the axis
    // the (x, x) entry vanishes. Here it is off the axis, and the part's loads do not balance,
    // so it need not; the identity above holds regardless.
}

/// Whether ccx runs; under CI it must.
fn have_ccx() -> bool {
    let ok = crate::ccx::available();
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must install CalculiX (apt-get install calculix-ccx) for this test"
        );
        eprintln!("skipped: CalculiX not found");
    }
    ok
}

fn steel() -> crate::mesh::Material {
    crate::mesh::Material {
        name: "STEEL".into(),
        e: 210e9,
        nu: 0.3,
        rho: 7850.0,
    }
}

/// A C3D20 and a C3D20R brick side by side (curved edges), a curved strip of two S8R shells
/// (5 mm thick) beside them, and a point mass on a shell node; held at one end of each.
fn mixed() -> Mesh {
    let mut m = Mesh::new("bricks and shells");
    let mat = steel();
    for (k, section) in [
        Section::Solid {
            material: mat.clone(),
        },
        Section::ReducedSolid {
            material: mat.clone(),
        },
    ]
    .into_iter()
    .enumerate()
    {
        let x = distorted([0.1 + 0.06 * k as f64, 0.0, 0.0], [0.05, 0.03, 0.02]);
        let ids: Vec<usize> = x.iter().map(|p| m.node(*p)).collect();
        let name = if k == 0 { "FULL" } else { "REDUCED" };
        m.part(name, section).elements.push(ids.clone());
        let held: Vec<usize> = (0..20)
            .filter(|&a| hex20::NODES[a][0] == -1.0)
            .map(|a| ids[a])
            .collect();
        m.add_to_set("HELD", &held);
    }
    // The strip: x in [0, 0.1] at y = 0.1, curved in z; 5 x 3 nodes less the centres.
    let node = |m: &mut Mesh, i: usize, j: usize| {
        let x = 0.025 * i as f64;
        m.node([
            x,
            0.1 + 0.01 * j as f64 + 0.001 * (i * j) as f64,
            2.0 * x * x,
        ])
    };
    for e in 0..2 {
        let a = 2 * e;
        let n = vec![
            node(&mut m, a, 0),
            node(&mut m, a + 2, 0),
            node(&mut m, a + 2, 2),
            node(&mut m, a, 2),
            node(&mut m, a + 1, 0),
            node(&mut m, a + 2, 1),
            node(&mut m, a + 1, 2),
            node(&mut m, a, 1),
        ];
        m.part(
            "STRIP",
            Section::Shell {
                thickness: 0.005,
                material: mat.clone(),
            },
        )
        .elements
        .push(n);
    }
    let clamp: Vec<usize> = (0..3).map(|j| node(&mut m, 0, j)).collect();
    m.add_to_set("CLAMP", &clamp);
    let tip = node(&mut m, 4, 2);
    m.part("TIP", Section::Mass { kg: 0.05 })
        .elements
        .push(vec![tip]);
    m.fixed.push(("HELD".into(), 1, 3));
    m.fixed.push(("CLAMP".into(), 1, 6));
    m
}

#[test]
fn ccx_prints_at_our_gauss_points_the_stresses_of_its_own_nodal_displacements() {
    // Our reading of ccx's 3-D model (the .frd's brick order, the Gauss rules and their point
    // order, the .dat's component order, the shells' global axes) against ccx itself: the
    // stresses Hooke's law gives from ccx's displacements at the bricks' nodes, at our Gauss
    // points, are those ccx prints there. The centrifugal load (about z through the origin,
    // CENTRIF and the point mass's CLOAD) bends and stretches every element.
    if !have_ccx() {
        return;
    }
    let mesh = mixed();
    let dir = tempfile::tempdir().unwrap();
    let c = Centrifugal::new(2000.0, [0.0; 3], [0.0, 0.0, 1.0]);
    let (p, frd) = solve(&mesh, &c, dir.path(), "mixed").unwrap();
    assert_eq!(p.bricks.len(), 4);
    let points: Vec<usize> = p.bricks.iter().map(|b| b.stress.len()).collect();
    // C3D20: 27 points; C3D20R and the expanded S8R: 8.
    assert_eq!(points, [27, 8, 8, 8]);
    let u: HashMap<usize, [f64; 3]> = frd.statics[0].iter().copied().collect();
    let (e, nu) = (210e9, 0.3);
    let (lam, mu) = (
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        e / (2.0 * (1.0 + nu)),
    );
    let mut worst = [0.0f64; 2];
    for b in &p.bricks {
        let x: [[f64; 3]; 20] = std::array::from_fn(|a| p.coords[&b.nodes[a]]);
        let peak = b
            .stress
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for ((pt, _), s) in hex20::rule_of(b.stress.len())
            .unwrap()
            .iter()
            .zip(&b.stress)
        {
            let (g, _) = hex20::spatial_gradient(&x, *pt).unwrap();
            let h: [[f64; 3]; 3] = std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..20).map(|a| u[&b.nodes[a]][i] * g[a][j]).sum())
            });
            let eps = |i: usize, j: usize| 0.5 * (h[i][j] + h[j][i]);
            let tr = eps(0, 0) + eps(1, 1) + eps(2, 2);
            let ours = [
                lam * tr + 2.0 * mu * eps(0, 0),
                lam * tr + 2.0 * mu * eps(1, 1),
                lam * tr + 2.0 * mu * eps(2, 2),
                2.0 * mu * eps(0, 1),
                2.0 * mu * eps(1, 2),
                2.0 * mu * eps(2, 0),
            ];
            let k = usize::from(b.number > 2);
            for i in 0..6 {
                worst[k] = worst[k].max((ours[i] - s[i]).abs() / peak);
            }
        }
    }
    eprintln!(
        "stresses from ccx's displacements against its own: bricks {:.1e}, shells {:.1e} of the element's peak",
        worst[0], worst[1]
    );
    // The .frd's displacements have 6 digits: measured 2.1e-5 on the bricks; 8.6e-3 on the
    // shells, whose strain across the thickness is the difference of nearly equal
    // displacements. A wrong point order or node order is off by order 1, the shells' stresses
    // in their own axes (ccx's *EL PRINT without GLOBAL=YES) by 0.12 to 0.44.
    assert!(worst[0] < 2e-4 && worst[1] < 5e-2, "{worst:?}");
}

/// A steel cantilever (B32, 40 elements, 1 m along x from the origin, 20 mm wide along y,
/// 10 mm deep along z) clamped at the origin; TIP is its last three nodes. Returns it and its
/// line's nodes.
fn cantilever() -> (Mesh, Vec<usize>) {
    let mut m = Mesh::new("spinning cantilever");
    let beam = Section::Beam {
        width: 0.02,
        height: 0.01,
        normal: [0.0, 1.0, 0.0],
        material: steel(),
    };
    let ids =
        crate::bodies::geometry::beam_line(&mut m, "BEAM", &beam, [0.0; 3], [1.0, 0.0, 0.0], 40);
    m.add_to_set("ROOT", &ids[..1]);
    m.add_to_set("TIP", &ids[ids.len() - 3..]);
    m.fixed.push(("ROOT".into(), 1, 6));
    (m, ids)
}

/// `mesh` as a drum spinning about z through the origin (prestress at 30 rad/s), `modes`
/// eigenmodes kept, correction modes for `correction` (at the point TIP).
fn spinning(
    mesh: Mesh,
    modes: usize,
    correction: Vec<washdyn_model::ir::modal::LoadCase>,
) -> crate::pipeline::BodySpec {
    crate::pipeline::BodySpec {
        name: "cantilever".into(),
        kind: washdyn_model::ir::modal::ElasticBodyKind::Drum,
        support: washdyn_model::ir::modal::Support::Clamped,
        mesh,
        solve_modes: modes,
        keep: crate::modal::Keep {
            rigid_below_hz: 0.0,
            max_hz: f64::INFINITY,
            max_modes: modes,
        },
        points: vec![("TIP".into(), [1.0, 0.0, 0.0])],
        spin: Some(crate::pipeline::Spin {
            axis_point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            reference_speed: 30.0,
        }),
        correction,
        correction_order: 1,
        recovery: false,
    }
}

#[test]
fn a_spinning_cantilevers_stiffening_is_southwells() {
    // A slender steel cantilever (B32, 1 m, 10 mm deep along the spin axis z, 20 mm wide),
    // clamped on the axis and spinning about it: to first order in Omega^2 a mode's
    // omega^2 rises by K Omega^2, K = int T w'^2 / int m w^2 with T the centrifugal tension
    // (the Southwell coefficient; hub radius 0). Its flap mode (along the axis) has K = 1.1933
    // (Euler-Bernoulli cantilever mode, quadrature: 1.193336), its lead-lag mode (in the plane
    // of rotation) 1.1933 - 1 (spin softening). Both are diagonal entries of the modal data:
    // K_G for the flap mode, K_G - S_perp for the lead-lag mode.
    if !have_ccx() {
        return;
    }
    let (m, ids) = cantilever();
    let spec = spinning(m, 16, Vec::new());
    let dir = tempfile::tempdir().unwrap();
    let (data, report) = crate::pipeline::build(&spec, dir.path()).unwrap();
    let kg = data.geometric_stiffness.as_ref().unwrap();
    let n = data.frequencies.len();
    let sp = crate::rotating::s_perp(&data.elementary, n, kg.axis);
    // Modes: flap (8.38 Hz), lead-lag (16.7 Hz), second flap, ...
    let flap = kg.per_omega2[0];
    let lag = kg.per_omega2[n + 1] - sp[n + 1];
    eprintln!(
        "frequencies {:?}; flap K {flap}, lead-lag K {lag}; prestress {:.1} s",
        data.frequencies,
        report.prestress.as_ref().unwrap().solve_s
    );
    // The same integral on ccx's own mode shapes (the beam line's nodes, quadratic between
    // them, T = rho A Omega^2 (L^2 - x^2) / 2): what our assembly must give on them.
    let modes = {
        let s = crate::modal::solve(&spec.mesh, dir.path(), "shapes", 6, false).unwrap();
        crate::modal::select(&spec.mesh, &s.frd, &s.prints, spec.keep).unwrap()
    };
    let line = |k: usize, c: usize| -> f64 {
        let q = 0.6f64.sqrt();
        let rule = [(-q, 5.0 / 9.0), (0.0, 8.0 / 9.0), (q, 5.0 / 9.0)];
        let (mut num, mut den) = (0.0, 0.0);
        for e in 0..40 {
            let x: [f64; 3] = std::array::from_fn(|i| spec.mesh.nodes[ids[2 * e + i] - 1][0]);
            let w: [f64; 3] = std::array::from_fn(|i| modes[k].w[&ids[2 * e + i]][c]);
            let h = x[2] - x[0];
            for (s, wt) in rule {
                let n = [0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0)];
                let dn = [(2.0 * s - 1.0) / h, -4.0 * s / h, (2.0 * s + 1.0) / h];
                let at = |f: [f64; 3], g: [f64; 3]| f[0] * g[0] + f[1] * g[1] + f[2] * g[2];
                let (xx, ww, dw) = (at(n, x), at(n, w), at(dn, w));
                num += wt * 0.5 * h * 0.5 * (1.0 - xx * xx) * dw * dw;
                den += wt * 0.5 * h * ww * ww;
            }
        }
        num / den
    };
    let (flap_line, lag_line) = (line(0, 2), line(1, 1) - 1.0);
    eprintln!("on ccx's shapes: flap {flap_line}, lead-lag {lag_line}");
    // Measured 7.6e-5 (flap) and 2.3e-4 (lead-lag, whose S_perp also holds the beam's axial
    // motion) apart.
    assert!((flap - flap_line).abs() < 6e-4, "{flap} vs {flap_line}");
    assert!((lag - lag_line).abs() < 2e-3, "{lag} vs {lag_line}");
    // Against the closed form: ccx's expanded beam (one C3D20 across the 10 x 20 mm section)
    // is no Euler-Bernoulli beam (its flap frequency is 0.29 % above the beam formula's), and
    // its shapes give Southwell's integral 1.9e-3 above 1.193336: measured flap 1.19559,
    // lead-lag 0.19449.
    let k1 = 1.193336;
    assert!((flap - k1).abs() < 1e-2 * k1, "{flap}");
    assert!((lag - (k1 - 1.0)).abs() < 1e-2, "{lag}");
    // And ccx's own prestressed frequencies (a static step with the same load, then a
    // *FREQUENCY perturbation step) at 3 x the flap frequency, where the flap mode's
    // frequency has more than tripled, against the reduced model's (its four lowest).
    let c = Centrifugal::new(
        3.0 * 2.0 * std::f64::consts::PI * data.frequencies[0],
        [0.0; 3],
        [0.0, 0.0, 1.0],
    );
    let (frd, _) =
        crate::rotating::solve_prestressed(&spec.mesh, dir.path(), "ccx", &c, 4).unwrap();
    let ours =
        crate::rotating::reduced_frequencies(&data.frequencies, &data.elementary, kg, c.omega);
    let mut worst = 0.0f64;
    for (k, m) in frd.modes.iter().enumerate() {
        worst = worst.max((ours[k] - m.frequency_hz).abs() / m.frequency_hz);
    }
    eprintln!(
        "at {:.1} rad/s: ccx {:?}, ours {:?}",
        c.omega,
        frd.modes.iter().map(|m| m.frequency_hz).collect::<Vec<_>>(),
        &ours[..4]
    );
    eprintln!("worst {worst:e}");
    // Measured 8.3e-5 with 16 kept modes (the Ritz truncation: 4.2e-3 with 6).
    assert!(worst < 8e-4, "{worst:e}");
}

#[test]
fn a_spinning_bodys_correction_modes_stiffen_through_the_same_assembly() {
    // The cantilever with 3 eigenmodes (flap, lead-lag, second flap), then with a static
    // correction mode for a flap force (along the spin axis) at the tip beside them: its K_G comes from the static
    // solution's 3-D shape through the same bricks. More Ritz vectors, so the reduced
    // prestressed frequencies come closer to ccx's own, from above.
    if !have_ccx() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (m, _) = cantilever();
    let z = [0.0, 0.0, 1.0];
    let plain = spinning(m.clone(), 3, Vec::new());
    let with = spinning(
        m,
        3,
        vec![washdyn_model::ir::modal::LoadCase::force("TIP", z)],
    );
    let (a, _) = crate::pipeline::build(&plain, &dir.path().join("a").tap_mkdir()).unwrap();
    let (b, _) = crate::pipeline::build(&with, &dir.path().join("b").tap_mkdir()).unwrap();
    assert_eq!((a.modes(), b.modes()), (3, 4));
    let omega = 3.0 * 2.0 * std::f64::consts::PI * a.frequencies[0];
    let c = Centrifugal::new(omega, [0.0; 3], z);
    let (frd, _) =
        crate::rotating::solve_prestressed(&plain.mesh, dir.path(), "ccx", &c, 3).unwrap();
    let err = |d: &washdyn_model::ir::modal::ModalData| -> Vec<f64> {
        let f = crate::rotating::reduced_frequencies(
            &d.frequencies,
            &d.elementary,
            d.geometric_stiffness.as_ref().unwrap(),
            omega,
        );
        frd.modes
            .iter()
            .enumerate()
            .map(|(k, m)| f[k] / m.frequency_hz - 1.0)
            .collect()
    };
    let (ea, eb) = (err(&a), err(&b));
    eprintln!(
        "against ccx at {omega:.1} rad/s: eigenmodes {ea:?}, with the correction mode {eb:?}"
    );
    // At this speed the lead-lag mode is the lowest (the flap mode has stiffened past it).
    // Measured: the flap mode (second) 6.7e-3 high on the 3 eigenmodes, 4.3e-3 with the
    // correction mode; the second flap mode 3.2e-3 and 2.6e-3; the lead-lag mode (2.1e-2, no
    // motion along the force) unchanged.
    assert!(eb[1] > -1e-6 && eb[1] < 0.8 * ea[1], "{ea:?} {eb:?}");
    assert!(
        eb.iter()
            .zip(&ea)
            .all(|(b, a)| *b > -1e-6 && *b <= a + 1e-12),
        "{ea:?} {eb:?}"
    );
}

trait Mkdir {
    fn tap_mkdir(self) -> Self;
}

impl Mkdir for std::path::PathBuf {
    fn tap_mkdir(self) -> Self {
        std::fs::create_dir_all(&self).unwrap();
        self
    }
}
