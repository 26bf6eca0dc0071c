//! Decks with closed-form answers, to check the FE chain (deck writer, ccx, import).

use crate::deck::Deck;
use crate::mesh::{Material, Mesh, Section};
use std::f64::consts::PI;

/// A cantilever of B32 beams along x, clamped at x = 0: length `l`, square section of side `a`,
/// steel (E 210 GPa, nu 0.3, rho 7850), `n` elements, `modes` eigenmodes. Euler-Bernoulli:
/// f_i = (beta_i l)^2 / (2 pi l^2) sqrt(E I / (rho A)), beta l = 1.8751, 4.6941, 7.8548.
pub fn cantilever(l: f64, a: f64, n: usize, modes: usize) -> Deck {
    let mut d = Deck::new(&format!("cantilever, {n} B32 elements"));
    let nodes: Vec<(usize, [f64; 3])> = (0..=2 * n)
        .map(|i| (i + 1, [l * i as f64 / (2 * n) as f64, 0.0, 0.0]))
        .collect();
    d.nodes(Some("NALL"), &nodes);
    let elems: Vec<(usize, Vec<usize>)> = (0..n)
        .map(|e| (e + 1, vec![2 * e + 1, 2 * e + 2, 2 * e + 3]))
        .collect();
    d.elements("B32", "EALL", &elems)
        .nset("CLAMP", &[1])
        .nset("TIP", &[2 * n + 1])
        .line("*BOUNDARY")
        .line("CLAMP, 1, 6")
        .material("STEEL", 210e9, 0.3, 7850.0)
        .line("*BEAM SECTION, ELSET=EALL, MATERIAL=STEEL, SECTION=RECT")
        .line(&format!("{a}, {a}"))
        .line("0, 0, 1")
        .frequency_step(modes);
    d
}

/// A simply supported rectangular plate of S8R shells in the x-y plane: `a` x `b`, thickness `h`,
/// steel, `nx` x `ny` elements, `modes` eigenmodes. All edge nodes are held in x, y and z (the
/// in-plane hold does not change the bending modes of a flat plate). Leissa (Vibration of Plates,
/// NASA SP-160, 1969): f_mn = pi / 2 (m^2 / a^2 + n^2 / b^2) sqrt(D / (rho h)),
/// D = E h^3 / (12 (1 - nu^2)).
pub fn plate_simply_supported(a: f64, b: f64, h: f64, nx: usize, ny: usize, modes: usize) -> Deck {
    let mut d = Deck::new(&format!("simply supported plate, {nx} x {ny} S8R elements"));
    let (gx, gy) = (2 * nx + 1, 2 * ny + 1);
    // Serendipity grid: no node at the centre of an element.
    let mut id = vec![vec![0usize; gx]; gy];
    let mut nodes = Vec::new();
    for (j, row) in id.iter_mut().enumerate() {
        for (i, slot) in row.iter_mut().enumerate() {
            if i % 2 == 1 && j % 2 == 1 {
                continue;
            }
            *slot = nodes.len() + 1;
            let p = [
                a * i as f64 / (gx - 1) as f64,
                b * j as f64 / (gy - 1) as f64,
                0.0,
            ];
            nodes.push((*slot, p));
        }
    }
    d.nodes(Some("NALL"), &nodes);
    let mut elems = Vec::new();
    for ej in 0..ny {
        for ei in 0..nx {
            let (i, j) = (2 * ei, 2 * ej);
            let c = vec![
                id[j][i],
                id[j][i + 2],
                id[j + 2][i + 2],
                id[j + 2][i],
                id[j][i + 1],
                id[j + 1][i + 2],
                id[j + 2][i + 1],
                id[j + 1][i],
            ];
            elems.push((elems.len() + 1, c));
        }
    }
    let edge: Vec<usize> = (0..gy)
        .flat_map(|j| (0..gx).map(move |i| (i, j)))
        .filter(|&(i, j)| i == 0 || j == 0 || i == gx - 1 || j == gy - 1)
        .map(|(i, j)| id[j][i])
        .collect();
    d.elements("S8R", "EALL", &elems)
        .nset("EDGE", &edge)
        .line("*BOUNDARY")
        .line("EDGE, 1, 3")
        .material("STEEL", 210e9, 0.3, 7850.0)
        .line("*SHELL SECTION, ELSET=EALL, MATERIAL=STEEL")
        .line(&format!("{h}"))
        .frequency_step(modes);
    d
}

/// A shallow sinusoidal arch of B32 beams in the x-y plane for the characteristic curves'
/// closed form: span `l`, rise y0 = `h` sin(pi x / l) (`h` = 0: a straight beam), rectangular
/// section `t` in the plane (bending) by `b` across it, steel, `n` elements. Pinned at both
/// ends on immovable supports (translations and the out-of-plane rotations held, the in-plane
/// rotation free); every node held out of the plane, so that only the in-plane problem of the
/// closed form is solved.
pub fn arch(l: f64, h: f64, t: f64, b: f64, n: usize) -> Mesh {
    let mut m = Mesh::new(&format!(
        "shallow arch, span {l} m, rise {h} m, {n} B32 elements"
    ));
    let ids: Vec<usize> = (0..=2 * n)
        .map(|i| {
            let x = l * i as f64 / (2 * n) as f64;
            m.node([x, h * (PI * x / l).sin(), 0.0])
        })
        .collect();
    let section = Section::Beam {
        width: b,
        height: t,
        normal: [0.0, 0.0, 1.0],
        material: Material {
            name: "STEEL".into(),
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        },
    };
    m.part("BEAM", section).elements = (0..n)
        .map(|e| vec![ids[2 * e], ids[2 * e + 1], ids[2 * e + 2]])
        .collect();
    m.add_to_set("ENDS", &[ids[0], ids[2 * n]]);
    m.add_to_set("MID", &[ids[n]]);
    m.fixed = vec![("ENDS".into(), 1, 5), ("NALL".into(), 3, 3)];
    m
}
