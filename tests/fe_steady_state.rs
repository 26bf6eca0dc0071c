//! What the full-mesh reference (`assembly/`) relies on in CalculiX 2.20's
//! `*STEADY STATE DYNAMICS`, on a deck small enough to solve by hand: a chain of 40 point masses
//! along x (SPRINGA between them, one DASHPOTA inside the chain and one to a held node whose
//! constant depends on frequency), Rayleigh beta, loads in both load cases (on one node too).
//! Against nalgebra's solve in the same 8-mode subspace,
//! (Lambda - w^2 + i w (beta Lambda + Phi^T C(f) Phi)) q = Phi^T (F_1 + i F_2), x = Phi q:
//! (a) Rayleigh damping and dashpots combine; (b) a dashpot's frequency table is read in
//! cycles/time (Hz), linearly interpolated, constant beyond its ends; (d) `LOAD CASE=2` is the
//! imaginary part of the load, and the two printed blocks are Re x and Im x of
//! (K - w^2 M + i w C) x = F, i.e. f(t) = Re[F e^{i w t}], x(t) = Re[x e^{i w t}].
//! ARPACK in ccx takes ncv = 5 nev Lanczos vectors and fails (info = -3) when that exceeds the
//! dofs: 8 modes of 40 dofs work, 9 do not. Numbers in a deck need a decimal point: ccx reads
//! `*SPRING` data `4e3` as a degree of freedom (SPRING1) and refuses it.

use crate::common;
use common::have_ccx;
use nalgebra::{Complex, DMatrix, DVector};
use std::fmt::Write as _;

const N: usize = 40;
const NEV: usize = 8;
const BETA: f64 = 2e-3;
/// (c, f Hz) of the frequency-dependent dashpot between mass 5 and a held node.
const TABLE: [(f64, f64); 2] = [(30.0, 2.0), (20.0, 6.0)];

fn mass(i: usize) -> f64 {
    1.0 + i as f64 / (N - 1) as f64
}
fn stiffness(i: usize) -> f64 {
    4000.0 + 5000.0 * i as f64 / (N - 1) as f64
}

fn deck(freqs: &[f64], f1: &[(usize, f64)], f2: &[(usize, f64)]) -> String {
    let mut d = String::new();
    let w = &mut d;
    let _ = writeln!(w, "*NODE, NSET=NALL\n1, 0, 0, 0");
    for i in 0..N {
        let _ = writeln!(w, "{}, {}, 0, 0", i + 2, 0.1 * (i + 1) as f64);
    }
    let _ = writeln!(w, "{}, 0.5, 0, 0", N + 2);
    let mut e = 1;
    for i in 0..N {
        let _ = writeln!(
            w,
            "*ELEMENT, TYPE=MASS, ELSET=EM{i}\n{e}, {}\n*MASS, ELSET=EM{i}\n{:.12e},",
            i + 2,
            mass(i)
        );
        e += 1;
        let a = if i == 0 { 1 } else { i + 1 };
        let _ = writeln!(
            w,
            "*ELEMENT, TYPE=SPRINGA, ELSET=ES{i}\n{e}, {a}, {}\n*SPRING, ELSET=ES{i}\n\n{:.12e},",
            i + 2,
            stiffness(i)
        );
        e += 1;
    }
    let _ = writeln!(
        w,
        "*ELEMENT, TYPE=DASHPOTA, ELSET=ED\n{e}, 5, 9\n*DASHPOT, ELSET=ED\n\n12.,"
    );
    let _ = writeln!(
        w,
        "*ELEMENT, TYPE=DASHPOTA, ELSET=EF\n{}, {}, 7\n*DASHPOT, ELSET=EF\n",
        e + 1,
        N + 2
    );
    for (c, f) in TABLE {
        let _ = writeln!(w, "{c}, {f}");
    }
    let _ = writeln!(w, "*BOUNDARY\n1, 1, 3\n{}, 1, 3\nNALL, 2, 3", N + 2);
    let ids: Vec<String> = (2..N + 2).map(|i| i.to_string()).collect();
    let _ = writeln!(w, "*NSET, NSET=NOUT");
    for c in ids.chunks(16) {
        let _ = writeln!(w, "{}", c.join(", "));
    }
    let _ = writeln!(w, "*STEP\n*FREQUENCY, STORAGE=YES\n{NEV}\n*END STEP");
    for f in freqs {
        let _ = writeln!(
            w,
            "*STEP\n*STEADY STATE DYNAMICS\n{f}, {f}, 2\n*MODAL DAMPING, RAYLEIGH\n,,0.,{BETA}"
        );
        let _ = writeln!(w, "*CLOAD");
        for (n, v) in f1 {
            let _ = writeln!(w, "{}, 1, {v}", n + 2);
        }
        let _ = writeln!(w, "*CLOAD, LOAD CASE=2");
        for (n, v) in f2 {
            let _ = writeln!(w, "{}, 1, {v}", n + 2);
        }
        let _ = writeln!(w, "*NODE PRINT, NSET=NOUT\nU\n*END STEP");
    }
    d
}

/// The dashpot table's value at `x` (linear, constant beyond the ends).
fn table(x: f64) -> f64 {
    let (a, b) = (TABLE[0], TABLE[1]);
    if x <= a.1 {
        a.0
    } else if x >= b.1 {
        b.0
    } else {
        a.0 + (b.0 - a.0) * (x - a.1) / (b.1 - a.1)
    }
}

/// The solution in the lowest NEV modes' subspace, the table read at `table_x`.
fn modal(fhz: f64, table_x: f64, f: &DVector<Complex<f64>>) -> DVector<Complex<f64>> {
    let mut k = DMatrix::<f64>::zeros(N, N);
    let mut c = DMatrix::<f64>::zeros(N, N);
    for i in 0..N {
        k[(i, i)] += stiffness(i);
        if i > 0 {
            k[(i - 1, i - 1)] += stiffness(i);
            k[(i - 1, i)] -= stiffness(i);
            k[(i, i - 1)] -= stiffness(i);
        }
    }
    // Node ids 5 and 9 are masses 3 and 7; node 7 is mass 5.
    let (a, b) = (3, 7);
    c[(a, a)] += 12.0;
    c[(b, b)] += 12.0;
    c[(a, b)] -= 12.0;
    c[(b, a)] -= 12.0;
    c[(5, 5)] += table(table_x);
    // M^-1/2 K M^-1/2 = V L V^T, Phi = M^-1/2 V (mass-normalised).
    let s = DVector::from_fn(N, |i, _| 1.0 / mass(i).sqrt());
    let a = DMatrix::from_fn(N, N, |i, j| s[i] * k[(i, j)] * s[j]);
    let e = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..N).collect();
    order.sort_by(|x, y| e.eigenvalues[*x].total_cmp(&e.eigenvalues[*y]));
    let phi = DMatrix::from_fn(N, NEV, |i, m| s[i] * e.eigenvectors[(i, order[m])]);
    let lam: Vec<f64> = order[..NEV].iter().map(|&m| e.eigenvalues[m]).collect();
    let w = 2.0 * std::f64::consts::PI * fhz;
    let cc = phi.transpose() * &c * &phi;
    let sys = DMatrix::from_fn(NEV, NEV, |i, j| {
        let d = if i == j { lam[i] - w * w } else { 0.0 };
        let damp = if i == j { BETA * lam[i] } else { 0.0 } + cc[(i, j)];
        Complex::new(d, w * damp)
    });
    let phic = phi.map(|v| Complex::new(v, 0.0));
    let q = sys.lu().solve(&(phic.transpose() * f)).unwrap();
    phic * q
}

#[test]
fn rayleigh_dashpots_frequency_tables_and_load_cases() {
    if !have_ccx() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // 4 Hz lies inside the table (Hz) but beyond its end in rad/s (25 rad/s): the two readings
    // differ by 4 %; 7 and 11 Hz lie beyond it either way.
    let freqs = [4.0, 7.0, 11.0];
    let f1 = [(2, 1.5), (9, -0.7)];
    let f2 = [(2, 0.9), (32, 0.4)];
    let path = dir.path().join("chain.inp");
    std::fs::write(&path, deck(&freqs, &f1, &f2)).unwrap();
    let run = washdyn_fe::ccx::run(&path).unwrap();
    let dat = std::fs::read_to_string(run.dat()).unwrap();
    let prints = washdyn_fe::dat::node_prints(&dat, "NOUT").unwrap();
    assert_eq!(prints.len(), 2 * freqs.len());
    let mut f = DVector::<Complex<f64>>::zeros(N);
    for (n, v) in f1 {
        f[n] += Complex::new(v, 0.0);
    }
    for (n, v) in f2 {
        f[n] += Complex::new(0.0, v);
    }
    for (s, fhz) in freqs.iter().enumerate() {
        let x = DVector::from_fn(N, |i, _| {
            let node = i + 2;
            let get = |p: &[(usize, [f64; 3])]| p.iter().find(|(id, _)| *id == node).unwrap().1[0];
            Complex::new(get(&prints[2 * s]), get(&prints[2 * s + 1]))
        });
        let top = |v: &DVector<Complex<f64>>| v.iter().fold(0.0f64, |m, c| m.max(c.norm()));
        let err = |y: &DVector<Complex<f64>>| top(&(&x - y)) / top(y);
        let hz = modal(*fhz, *fhz, &f);
        let rad = modal(*fhz, 2.0 * std::f64::consts::PI * fhz, &f);
        let conj = hz.map(|v| v.conj());
        println!(
            "{fhz} Hz: ccx against the modal solve {:.1e} (table in rad/s: {:.1e}; conjugate \
             convention: {:.1e})",
            err(&hz),
            err(&rad),
            err(&conj)
        );
        // Measured 5.3e-8 .. 1.3e-7: the 7 digits ccx prints.
        assert!(err(&hz) < 1e-6, "{fhz} Hz: {:.2e}", err(&hz));
        assert!(err(&conj) > 0.5);
        if *fhz == 4.0 {
            // Measured 2.9e-2.
            assert!(err(&rad) > 1e-2);
        }
    }
}

/// `*EQUATION` on S8R mid-surface nodes, as the assembly ties its auxiliary nodes: a curved
/// 8 x 8 S8R plate held on two edges, an auxiliary node 60 mm off the surface tied to the rigid
/// fit of a patch (`point_reading_full`, translation and rotation rows). The equations add no
/// stiffness, a load on the dependent node is the consistent nodal load R_i^T F, and the node
/// reads the rigid fit of the printed mid-surface displacements.
#[test]
fn equations_on_shell_nodes_read_the_rigid_fit() {
    use washdyn_fe::bodies::geometry::{near, shell_grid};
    use washdyn_fe::mesh::{Material, Mesh, Section};
    use washdyn_fe::modal::point_reading_full;
    if !have_ccx() {
        return;
    }
    let steel = Material {
        name: "STEEL".into(),
        e: 2.1e11,
        nu: 0.3,
        rho: 7850.0,
    };
    let mut m = Mesh::new("plate");
    let section = Section::Shell {
        thickness: 0.0012,
        material: steel,
    };
    shell_grid(&mut m, "PLATE", &section, 8, 8, false, |u, v| {
        let (x, y) = (0.4 * u, 0.4 * v);
        [x, y, 0.05 * (x - 0.2) * (x - 0.2)]
    });
    let all: Vec<usize> = (1..=m.nodes.len()).collect();
    let edges: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&id| m.nodes[id - 1][0].abs() < 1e-9 || m.nodes[id - 1][1].abs() < 1e-9)
        .collect();
    m.add_to_set("EDGES", &edges);
    m.fixed.push(("EDGES".into(), 1, 3));
    let centre = [0.3, 0.2, 0.005];
    let patch = near(&m, all, centre, 0.07);
    m.add_to_set("PATCH", &patch);
    let p = [0.3, 0.2, 0.06];
    let reading = point_reading_full(&m, "PATCH", p).unwrap();
    let plain = m.clone();
    let (aux, rot) = (m.fresh_node(p), m.fresh_node(p));
    m.add_to_set("AUX", &[aux, rot]);
    let mut eqs = String::from("*EQUATION\n");
    for (node, rotation) in [(aux, false), (rot, true)] {
        for a in 0..3 {
            let mut terms = vec![format!("{node},{},1.", a + 1)];
            for (id, r, t) in &reading {
                let rows = if rotation { t } else { r };
                for (d, c) in rows[a].iter().enumerate() {
                    if *c != 0.0 {
                        terms.push(format!("{id},{},{:.12e}", d + 1, -c));
                    }
                }
            }
            eqs.push_str(&format!("{}\n", terms.len()));
            for (i, c) in terms.chunks(4).enumerate() {
                let more = (i + 1) * 4 < terms.len();
                eqs.push_str(&format!("{}{}\n", c.join(","), if more { "," } else { "" }));
            }
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let solve = |name: &str, text: String| {
        let path = dir.path().join(format!("{name}.inp"));
        std::fs::write(&path, text).unwrap();
        let run = washdyn_fe::ccx::run(&path).unwrap();
        std::fs::read_to_string(run.dat()).unwrap()
    };
    // Frequencies without and with the (massless, unloaded) auxiliary nodes.
    let freq = "*STEP\n*FREQUENCY\n10\n*END STEP\n";
    let f0 = washdyn_fe::ccx::frequencies(&solve(
        "plain",
        format!("{}{freq}", plain.model_deck().text()),
    ));
    let with_eq = format!("{}{eqs}", m.model_deck().text());
    let f1 = washdyn_fe::ccx::frequencies(&solve("tied", format!("{with_eq}{freq}")));
    let df = f0
        .iter()
        .zip(&f1)
        .fold(0.0f64, |w, (a, b)| w.max((b / a - 1.0).abs()));
    // A load at the auxiliary node and the same as nodal loads R_i^T F.
    let force = [3.0, 10.0, 5.0];
    let statics = |loads: Vec<(usize, usize, f64)>| {
        let mut s = format!("{with_eq}*STEP\n*STATIC\n*CLOAD\n");
        for (n, d, v) in loads {
            s.push_str(&format!("{n}, {d}, {v:.12e}\n"));
        }
        s.push_str("*NODE PRINT, NSET=PATCH\nU\n*NODE PRINT, NSET=AUX\nU\n*END STEP\n");
        s
    };
    let at_aux = solve(
        "at_aux",
        statics((0..3).map(|a| (aux, a + 1, force[a])).collect()),
    );
    let nodal: Vec<(usize, usize, f64)> = reading
        .iter()
        .flat_map(|(id, r, _)| {
            (0..3).map(move |d| (*id, d + 1, (0..3).map(|a| r[a][d] * force[a]).sum()))
        })
        .collect();
    let at_nodes = solve("at_nodes", statics(nodal));
    let patch_u = |dat: &str| washdyn_fe::dat::node_prints(dat, "PATCH").unwrap()[0].clone();
    let (ua, un) = (patch_u(&at_aux), patch_u(&at_nodes));
    let top = un.iter().fold(0.0f64, |w, (_, v)| {
        w.max(v[0].abs().max(v[1].abs()).max(v[2].abs()))
    });
    let dload = ua.iter().zip(&un).fold(0.0f64, |w, ((_, a), (_, b))| {
        (0..3).fold(w, |w, k| w.max((a[k] - b[k]).abs()))
    }) / top;
    // The auxiliary nodes against the rigid fit of the printed patch displacements.
    let printed = washdyn_fe::dat::node_prints(&at_aux, "AUX").unwrap()[0].clone();
    let fit = |rotation: bool| -> [f64; 3] {
        std::array::from_fn(|a| {
            reading
                .iter()
                .map(|(id, r, t)| {
                    let rows = if rotation { t } else { r };
                    let u = ua.iter().find(|(n, _)| n == id).unwrap().1;
                    (0..3).map(|d| rows[a][d] * u[d]).sum::<f64>()
                })
                .sum()
        })
    };
    let rel = |node: usize, f: [f64; 3]| {
        let v = printed.iter().find(|(n, _)| *n == node).unwrap().1;
        let s = f.iter().fold(0.0f64, |w, x| w.max(x.abs()));
        (0..3).fold(0.0f64, |w, k| w.max((v[k] - f[k]).abs())) / s
    };
    let (dt, dr) = (rel(aux, fit(false)), rel(rot, fit(true)));
    println!(
        "S8R plate: frequencies change {df:.1e} with the equations; load at the node vs nodal \
         loads {dload:.1e}; the node vs the rigid fit {dt:.1e} (translation), {dr:.1e} (rotation)"
    );
    // Measured: 0 (identical prints of 7 digits), 0, 3.8e-6 and 1.0e-5 (beyond the prints'
    // rounding, far below what the comparison resolves).
    assert!(df < 1e-6, "{df:.2e}");
    assert!(dload < 1e-9, "{dload:.2e}");
    assert!(dt < 4e-5 && dr < 1e-4, "{dt:.2e} {dr:.2e}");
}
