//! The consistent mass matrix against the element integrals and rigid motions, on a mixed
//! mesh (`mixed`, also used by the correction modes' tests).

use super::*;
use crate::lumping::{HEX20, consistent_mass_props};
use crate::mesh::{Material, Rigid, Section};
use crate::modal::Shapes;
use washdyn_model::geom::f::{add, cross, sub};

fn steel() -> Material {
    Material {
        name: "STEEL".into(),
        e: 210e9,
        nu: 0.3,
        rho: 7850.0,
    }
}

/// A curved S8R patch, a skewed C3D20, a B32 (`beam`) and point masses (one free, two on
/// a rigid part).
pub(crate) fn mixed(beam: bool) -> Mesh {
    let mut m = Mesh::new("mixed");
    let q: Vec<usize> = [
        [0.0, 0.0, 0.0],
        [0.2, 0.0, 0.01],
        [0.2, 0.1, 0.0],
        [0.0, 0.12, 0.0],
        [0.1, 0.0, 0.02],
        [0.2, 0.05, 0.01],
        [0.1, 0.11, 0.01],
        [0.0, 0.06, -0.01],
    ]
    .iter()
    .map(|p| m.node(*p))
    .collect();
    m.part(
        "S",
        Section::Shell {
            thickness: 0.002,
            material: steel(),
        },
    )
    .elements
    .push(q);
    let h: Vec<usize> = HEX20
        .iter()
        .map(|c| {
            m.node([
                0.3 + 0.05 * c[0] + 0.01 * c[1] * c[2],
                0.04 * c[1],
                0.03 * c[2] + 0.005 * c[0],
            ])
        })
        .collect();
    m.part("B", Section::Solid { material: steel() })
        .elements
        .push(h);
    if beam {
        let b: Vec<usize> = [[0.0, 0.0, 0.1], [0.1, 0.01, 0.1], [0.2, 0.0, 0.12]]
            .iter()
            .map(|p| m.node(*p))
            .collect();
        m.part(
            "L",
            Section::Beam {
                width: 0.01,
                height: 0.02,
                normal: [0.0, 0.0, 1.0],
                material: steel(),
            },
        )
        .elements
        .push(b);
    }
    let pm: Vec<usize> = [[0.5, 0.0, 0.0], [0.6, 0.1, 0.0], [0.55, -0.1, 0.05]]
        .iter()
        .map(|p| m.node(*p))
        .collect();
    m.part("P", Section::Mass { kg: 0.3 }).elements = pm.iter().map(|&i| vec![i]).collect();
    m.add_to_set("R", &pm[1..]);
    let r = m.fresh_node([0.58, 0.0, 0.02]);
    let rot = m.fresh_node([0.58, 0.0, 0.02]);
    m.rigid.push(Rigid {
        nset: "R".into(),
        ref_node: r,
        rot_node: rot,
    });
    m
}

#[test]
fn mass_props_equal_the_element_integrals_and_the_matrix_is_symmetric() {
    // Two paths: 1^T M 1, x^T M 1, x_a^T M x_b (the assembled matrix; sum N = 1 and
    // sum N x = x) against `consistent_mass_props`' direct integrals of rho, rho x,
    // rho x x^T at the same points.
    let m = mixed(true);
    let mm = consistent(&m);
    let (a, b) = (mm.mass_props(&m), consistent_mass_props(&m));
    assert!((a.mass - b.mass).abs() < 1e-14 * b.mass, "{a:?} {b:?}");
    for i in 0..3 {
        assert!((a.cog[i] - b.cog[i]).abs() < 1e-15, "{a:?} {b:?}");
        for j in 0..3 {
            assert!(
                (a.inertia[i][j] - b.inertia[i][j]).abs() < 1e-14 * b.inertia[i][i],
                "{a:?} {b:?}"
            );
        }
    }
    for i in 0..mm.ids.len() {
        for p in mm.start[i]..mm.start[i + 1] {
            let j = mm.cols[p];
            let back = (mm.start[j]..mm.start[j + 1])
                .find(|&q| mm.cols[q] == i)
                .expect("symmetric pattern");
            assert_eq!(mm.vals[p], mm.vals[back]);
        }
    }
}

#[test]
fn elementary_of_rigid_motions_are_the_mass_properties() {
    // Under a rigid translation e_a every sum collapses to a mass property: c = m e_a,
    // g_ab = m delta_ab; under a rotation about the CoG the modal mass is theta^T I theta
    // (shells' rotary inertia included; no beam: its torsion is not in the translations).
    let m = mixed(false);
    let mm = consistent(&m);
    let p = mm.mass_props(&m);
    let shapes: Vec<Shapes> = (0..6)
        .map(|k| {
            let (v, th) = if k < 3 {
                (
                    std::array::from_fn(|a| if a == k { 1.0 } else { 0.0 }),
                    [0.0; 3],
                )
            } else {
                (
                    [0.0; 3],
                    std::array::from_fn(|a| if a == k - 3 { 1.0 } else { 0.0 }),
                )
            };
            let w = (1..=m.nodes.len())
                .map(|id| (id, add(v, cross(th, sub(m.nodes[id - 1], p.cog)))))
                .collect();
            let rot = m.rigid.iter().map(|r| (r.rot_node, th)).collect();
            Shapes {
                frequency_hz: 0.0,
                w,
                rot,
            }
        })
        .collect();
    let el = mm.elementary(&m, &shapes).unwrap();
    let inner = mm.inner(&m, &shapes, &shapes).unwrap();
    for a in 0..3 {
        assert!((el.c[a][a] - p.mass).abs() < 1e-13 * p.mass);
        for k in 0..6 {
            let want = if k < 3 {
                if k == a { p.mass } else { 0.0 }
            } else {
                0.0
            };
            assert!((el.c[a][k] - want).abs() < 1e-13 * p.mass, "c[{a}][{k}]");
        }
    }
    for k in 0..6 {
        for l in 0..6 {
            let want = match (k < 3, l < 3) {
                (true, true) if k == l => p.mass,
                (false, false) => p.inertia[k - 3][l - 3],
                _ => 0.0,
            };
            let tr: f64 = (0..3).map(|a| el.g[a][a][k * 6 + l]).sum();
            assert!((tr - want).abs() < 1e-12, "g {k} {l}: {tr} vs {want}");
            assert!((inner[(k, l)] - want).abs() < 1e-12, "inner {k} {l}");
        }
    }
    // The inertial load of a rigid motion: its resultant is m a and its moment about the
    // CoG I alpha.
    let (v, om) = ([0.3, -0.2, 0.5], [1.0, 2.0, -0.5]);
    let f = mm.rigid_motion_load(&m, v, om, p.cog);
    let rot_nodes: Vec<usize> = m.rigid.iter().map(|r| r.rot_node).collect();
    let (mut force, mut moment) = ([0.0; 3], [0.0; 3]);
    for (id, x) in &f {
        if rot_nodes.contains(id) {
            moment = add(moment, *x);
        } else {
            force = add(force, *x);
            moment = add(moment, cross(sub(m.nodes[id - 1], p.cog), *x));
        }
    }
    for a in 0..3 {
        assert!((force[a] - p.mass * v[a]).abs() < 1e-12);
        let ia: f64 = (0..3).map(|b| p.inertia[a][b] * om[b]).sum();
        assert!((moment[a] - ia).abs() < 1e-12, "{moment:?}");
    }
}
