//! The drum against issue 19's targets, from CalculiX's own output (skipped locally without ccx,
//! required under CI=true): on rigid bearings its first rocking pair lies in 90-150 Hz; at
//! 1400 rpm with the reference unbalance (0.6 kg at (0.15, 0, 0.69)) plus its own centrifugal
//! load, its front edge moves 2-4 mm, the spider stays <= 100 MPa and the shaft <= 250 MPa
//! (von Mises).
//!
//! And the Campbell diagram (issue item 7): washdyn's whirl split against ccx's
//! `*COMPLEX FREQUENCY, CORIOLIS` on the knot-free brick variant of the drum.

use crate::common;
use common::have_ccx;

use std::collections::HashMap;
use std::f64::consts::PI;
use washdyn_fe::bodies::{self, drum::Drum};
use washdyn_fe::pipeline::BodySpec;
use washdyn_fe::stress::von_mises;

fn drum_spec() -> BodySpec {
    bodies::builtin()
        .into_iter()
        .find(|b| b.name == "drum")
        .expect("the built-in drum")
}

/// Distance from the drum axis.
fn radius(p: [f64; 3]) -> f64 {
    (p[1].powi(2) + (p[2] - bodies::DRUM_AXIS_POINT[2]).powi(2)).sqrt()
}

/// The shell's nodes on the front edge (x = x_front, r = radius).
fn front_edge(spec: &BodySpec, drum: &Drum) -> Vec<usize> {
    let m = &spec.mesh;
    (1..=m.nodes.len())
        .filter(|&id| {
            let p = m.nodes[id - 1];
            (p[0] - drum.x_front).abs() < 1e-7 && (radius(p) - drum.radius).abs() < 1e-7
        })
        .collect()
}

#[test]
fn first_rocking_pair_on_rigid_bearings_lies_in_90_to_150_hz() {
    if !have_ccx() {
        return;
    }
    let (spec, drum) = (drum_spec(), Drum::default());
    let dir = tempfile::tempdir().unwrap();
    let solved = washdyn_fe::modal::solve(&spec.mesh, dir.path(), "drum_modes", 8, false).unwrap();
    let edge = front_edge(&spec, &drum);
    // Rocking: the front edge moves sideways as a whole. Measure how much of the edge's motion
    // is its mean lateral (y, z) translation: ~1 for rocking, 0 for ovalling (n >= 2 waves),
    // torsion and the axial mode.
    let mut rocking = Vec::new();
    for m in &solved.frd.modes {
        let u: HashMap<usize, [f64; 3]> = m.disp.iter().copied().collect();
        let n = edge.len() as f64;
        let mean = [1, 2].map(|c| edge.iter().map(|id| u[id][c]).sum::<f64>() / n);
        let rms = (edge
            .iter()
            .map(|id| u[id].iter().map(|v| v * v).sum::<f64>())
            .sum::<f64>()
            / n)
            .sqrt();
        let share = mean[0].hypot(mean[1]) / rms;
        eprintln!(
            "{:8.2} Hz: lateral share of the front edge's motion {share:.3}",
            m.frequency_hz
        );
        if share > 0.5 {
            rocking.push(m.frequency_hz);
        }
    }
    // Measured: 107.46 Hz (a pair to 1e-9; share 0.88); then the axial mode (121.0 Hz, share
    // 0), two more laterally moving pairs (147.2 and 155.8 Hz) and the torsion (147.4 Hz).
    assert!(rocking.len() >= 2, "{rocking:?}");
    let (a, b) = (rocking[0], rocking[1]);
    assert!((a - b).abs() < 1e-4 * a, "not a pair: {rocking:?}");
    assert!((90.0..=150.0).contains(&a), "first rocking pair at {a} Hz");
}

/// ccx's integration-point stresses of `elset` (`*EL PRINT` / `S` in the `.dat`): the largest
/// von Mises stress.
fn max_ip_von_mises(dat: &str, elset: &str) -> f64 {
    let head = format!("for set {} and time", elset.to_ascii_uppercase());
    dat.lines()
        .skip_while(|l| !(l.contains("stresses (elem, integ.pnt.") && l.contains(&head)))
        .skip(1)
        .take_while(|l| !l.contains("for set") || l.trim().is_empty())
        .filter_map(|l| {
            let f: Vec<f64> = l
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            // elem, point, xx, yy, zz, xy, xz, yz.
            (f.len() == 8).then(|| von_mises(&[f[2], f[3], f[4], f[5], f[7], f[6]]))
        })
        .fold(0.0, f64::max)
}

#[test]
fn unbalance_at_1400_rpm_meets_the_deflection_and_stress_targets() {
    // The reference unbalance, 0.6 kg at (0.15, 0, 0.69), at 1400 rpm: 0.6 x 0.24 x
    // (1400 pi / 30)^2 = 3095 N radial (+z), as the consistent nodal load of the modal point
    // UNBALANCE_FRONT (the load the equations apply through its W), plus the drum's own
    // centrifugal load (*DLOAD CENTRIF on every element with density). One linear *STATIC
    // step on rigid bearings (both seats held).
    if !have_ccx() {
        return;
    }
    let (spec, drum) = (drum_spec(), Drum::default());
    let m = &spec.mesh;
    let omega = 1400.0 * PI / 30.0;
    let force = 0.6 * 0.24 * omega * omega;
    let point = [0.15, 0.0, 0.69];
    let mut d = m.model_deck();
    let loaded: Vec<&str> = m
        .parts
        .iter()
        .filter(|p| p.section.material().is_some())
        .map(|p| p.name.as_str())
        .collect();
    d.line("*ELSET, ELSET=SPIN");
    for c in loaded.chunks(8) {
        d.line(&c.join(", "));
    }
    d.line("*STEP").line("*STATIC").line("*CLOAD");
    for (id, r) in washdyn_fe::modal::point_reading(m, "UNBALANCE_FRONT", point).unwrap() {
        for (c, v) in r[2].iter().enumerate() {
            if *v != 0.0 {
                d.line(&format!("{id}, {}, {:.12e}", c + 1, force * v));
            }
        }
    }
    let a = bodies::DRUM_AXIS_POINT;
    d.line("*DLOAD").line(&format!(
        "SPIN, CENTRIF, {:e}, {}, {}, {}, 1, 0, 0",
        omega * omega,
        a[0],
        a[1],
        a[2]
    ));
    // Mid-surface output (the shell's edge nodes are original nodes), and the spider's
    // integration-point stresses: at its nodes shared with the back wall, ccx's nodal output
    // carries the expanded shell's values, not the bricks' (93 MPa there against 40 MPa at
    // the bricks' points, seen on a stiffer spider).
    d.line("*NODE FILE, OUTPUT=2D")
        .line("U")
        .line("*EL FILE, OUTPUT=2D")
        .line("S")
        .line("*EL PRINT, ELSET=DRUM_SPIDER")
        .line("S")
        .line("*END STEP");
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("unbalance.inp");
    std::fs::write(&deck, d.text()).unwrap();
    let run = washdyn_fe::ccx::run(&deck).unwrap_or_else(|e| panic!("{e}"));
    let frd = washdyn_fe::frd::parse(&std::fs::read_to_string(run.frd()).unwrap()).unwrap();
    let dat = std::fs::read_to_string(run.dat()).unwrap();
    let u: HashMap<usize, [f64; 3]> = frd.statics[0].iter().copied().collect();
    let s: HashMap<usize, [f64; 6]> = frd.static_stresses[0].iter().copied().collect();

    // Front edge: the largest displacement along the force (what closes the drum-tub gap).
    let edge = front_edge(&spec, &drum);
    let along = edge.iter().map(|id| u[id][2]).fold(f64::MIN, f64::max);
    let total = edge
        .iter()
        .map(|id| u[id].iter().map(|v| v * v).sum::<f64>().sqrt())
        .fold(0.0, f64::max);

    // Spider: ccx's integration-point stresses (no corner of the mesh is a boundary
    // singularity there; the arms' roots meet the disc at a re-entrant corner, which the
    // points stay inside of).
    let spider = max_ip_von_mises(&dat, "DRUM_SPIDER");

    // Shaft: ccx's nodal stresses. The seats are held rigidly, so where the shoulder meets the
    // front seat the stress is singular (a re-entrant corner on a rigid clamp): its peak grows
    // with refinement and means nothing alone. The section just outside the seat is the
    // shoulder's free length between the hub and the seat: its outer surface carries the
    // nominal bending stress, the number a shaft is designed to (times the fillet's notch
    // factor). Beam theory there: M = F (0.15 - x), sigma = 32 M / (pi d^3) with d 42 mm.
    let shaft = &m
        .parts
        .iter()
        .find(|p| p.name == "DRUM_SHAFT")
        .unwrap()
        .elements;
    let mut ids: Vec<usize> = shaft.iter().flatten().copied().collect();
    ids.sort_unstable();
    ids.dedup();
    let vm = |id: &usize| s.get(id).map_or(0.0, von_mises);
    let peak = ids
        .iter()
        .map(|id| (vm(id), *id))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
    let (seat, _) = drum.front_bearing.ends();
    let rs = 0.5 * drum.shoulder_diameter;
    let section = ids
        .iter()
        .filter(|id| {
            let p = m.nodes[**id - 1];
            (radius(p) - rs).abs() < 1e-7 && p[0] < drum.x_hub_back - 1e-7 && p[0] >= seat - 1e-7
        })
        .map(vm)
        .fold(0.0, f64::max);
    let beam = |x: f64| 32.0 * force * (point[0] - x) / (PI * drum.shoulder_diameter.powi(3));
    let pk = m.nodes[peak.1 - 1];
    eprintln!(
        "1400 rpm, 0.6 kg front: {force:.0} N; front edge {:.3} mm along the force ({:.3} mm \
         total); spider {:.1} MPa (integration points); shaft section outside the front seat \
         {:.1} MPa (beam theory {:.1} to {:.1}), shaft peak {:.1} MPa at x {:.4}, r {:.4}",
        along * 1e3,
        total * 1e3,
        spider * 1e-6,
        section * 1e-6,
        beam(drum.x_hub_back) * 1e-6,
        beam(seat) * 1e-6,
        peak.0 * 1e-6,
        pk[0],
        radius(pk)
    );
    // Measured (36 round): front edge 2.385 mm along the force (2.916 mm in all); spider
    // 58.5 MPa; shaft section 150.5 MPa (beam theory 140-145 MPa), shaft peak 212.8 MPa at the
    // shoulder's corner on the seat. Twice as fine round (72): 2.489 mm, 61.3 MPa, the shaft's
    // unchanged (its mesh along the axis is the same). The drum's first rocking pair then
    // drops from 107.5 to 104.6 Hz.
    assert!((2e-3..=4e-3).contains(&along), "front edge {along}");
    assert!(spider <= 100e6, "spider {spider}");
    assert!(section <= 250e6, "shaft section {section}");
}

/// The rotating-frame modes at `omega` (rad/s) of the reduced model (`rotating::campbell`'s
/// q'' + 2 Omega G q' + K q = 0): for each frequency f of `freqs`, the share of its
/// eigenvector in the rest modes `pair`. At w = 2 pi f the eigenvector is the null vector of
/// the Hermitian K - w^2 E + i 2 w Omega G (G skew), so no general eigensolver is needed.
fn pair_shares(
    freqs: &[f64],
    data: &washdyn_model::ir::modal::ModalData,
    omega: f64,
    pair: [usize; 2],
) -> Vec<f64> {
    use nalgebra::{Complex, DMatrix};
    let n = data.modes();
    let kg = data.geometric_stiffness.as_ref().expect("K_G");
    let e = kg.axis;
    let g = washdyn_fe::rotating::gyroscopic(&data.elementary, n, e);
    let k = DMatrix::<f64>::from_fn(n, n, |i, j| {
        // Spin softening: sum dm W^T (E - e e^T) W.
        let mut s = 0.0;
        for a in 0..3 {
            for b in 0..3 {
                let p = if a == b { 1.0 } else { 0.0 } - e[a] * e[b];
                s += p * data.elementary.g[a][b][i * n + j];
            }
        }
        let w0 = if i == j {
            (2.0 * PI * data.frequencies[i]).powi(2)
        } else {
            0.0
        };
        w0 + omega * omega * (kg.per_omega2[i * n + j] - s)
    });
    freqs
        .iter()
        .map(|f| {
            let w = 2.0 * PI * f;
            let h = DMatrix::<Complex<f64>>::from_fn(n, n, |i, j| {
                let d = if i == j { w * w } else { 0.0 };
                Complex::new(k[(i, j)] - d, 2.0 * w * omega * g[i * n + j])
            });
            let eig = h.symmetric_eigen();
            let c = (0..n)
                .min_by(|a, b| {
                    eig.eigenvalues[*a]
                        .abs()
                        .total_cmp(&eig.eigenvalues[*b].abs())
                })
                .expect("modes");
            let x = eig.eigenvectors.column(c);
            (x[pair[0]].norm_sqr() + x[pair[1]].norm_sqr()) / x.norm_squared()
        })
        .collect()
}

/// Issue item 7. washdyn's Campbell diagram (the reduced drum: Coriolis from the elementary
/// sums over the consistent mass, spin softening, and stress stiffening assembled from ccx's
/// static centrifugal stresses and displacement) against ccx's `*COMPLEX FREQUENCY, CORIOLIS`, on the knot-free brick
/// variant of the drum (`Drum::brick_mesh`: sheets as single-layer C3D20R bricks sharing
/// faces, pulley as point masses on the shaft end, no *RIGID BODY, so ccx builds no MPC;
/// coarser than the production drum, 24 elements round and 6 along). The rocking pair's
/// whirl split agrees to 1e-3 at 400 and 1400 rpm.
///
/// Finding (ccx 2.20): on a model with MPCs, ccx's Coriolis matrix is wrong. On the production
/// drum (S8R sheets meeting at folds, i.e. shell knots; shells sharing nodes with bricks; the
/// pulley a *RIGID BODY; 12 modes, K_G from 36 prestressed ones) at 400 rpm ccx puts the
/// rocking pair at 102.79 / 112.17 Hz, a split of 9.38 Hz, where washdyn's reduced model of
/// the same eigenvectors gives 103.81 / 111.15 Hz, 7.34 Hz: ccx's split is 28 % larger (the
/// modes Coriolis hardly couples agree: 121.199 against 121.199 Hz). On this variant, with
/// no MPC, the two splits agree to 1.9e-5 (400 rpm: 5.42589 against 5.42600 Hz) and 4.1e-4
/// (1400 rpm: 20.1509 against 20.1592 Hz); bound 1e-3. So the reference for our split is the
/// brick variant (or the Coriolis integral of ccx's eigenvectors), not ccx's complex
/// frequency step on a model with knots or rigid bodies.
#[test]
fn campbell_whirl_split_matches_calculix_coriolis_on_the_knot_free_drum() {
    use washdyn_fe::modal::Keep;
    use washdyn_fe::pipeline::Spin;
    use washdyn_model::ir::modal::{ElasticBodyKind, Support};
    if !have_ccx() {
        return;
    }
    let drum = Drum {
        n_circ: 24,
        n_axial: 6,
        ..Drum::default()
    };
    let mesh = drum.brick_mesh();
    let (n, axis) = (8, [1.0, 0.0, 0.0]);
    let spec = BodySpec {
        name: "brick_drum".into(),
        kind: ElasticBodyKind::Drum,
        support: Support::Clamped,
        mesh: mesh.clone(),
        solve_modes: n,
        keep: Keep {
            rigid_below_hz: 0.0,
            max_hz: f64::INFINITY,
            max_modes: n,
        },
        points: Vec::new(),
        spin: Some(Spin {
            axis_point: bodies::DRUM_AXIS_POINT,
            axis,
            reference_speed: bodies::DRUM_REFERENCE_SPEED,
        }),
        correction: Vec::new(),
        correction_order: 1,
        recovery: false,
    };
    let dir = tempfile::tempdir().unwrap();
    let (data, report) = washdyn_fe::pipeline::build(&spec, dir.path()).unwrap();
    // ccx's complex frequencies stand on its prestressed stiffness, which holds the static
    // displacement's stiffness beside the stresses' (`PrestressReport::as_ccx`): without it
    // the split is 3.4e-3 off at 1400 rpm (20.2277 Hz), 3.7e-4 at 400 rpm.
    let kg = report
        .prestress
        .unwrap()
        .as_ccx(data.geometric_stiffness.as_ref().unwrap());
    let f0 = &data.frequencies;
    // The rocking pair at rest: the first degenerate pair.
    let p = (0..n - 1)
        .find(|&k| (f0[k + 1] - f0[k]).abs() < 1e-6 * f0[k])
        .expect("a degenerate pair");
    for rpm in [400.0, 1400.0] {
        let omega = rpm * PI / 30.0;
        let ours = washdyn_fe::rotating::campbell(f0, &data.elementary, &kg, omega);
        // The whirl pair: the two rotating modes made of the rocking pair at rest (above the
        // crossing near 1000 rpm the upper whirl passes the axial mode, so order alone won't do).
        let shares = pair_shares(&ours, &data, omega, [p, p + 1]);
        let mut by_share: Vec<usize> = (0..ours.len()).collect();
        by_share.sort_by(|a, b| shares[*b].total_cmp(&shares[*a]));
        let (lo, hi) = (
            ours[by_share[0].min(by_share[1])],
            ours[by_share[0].max(by_share[1])],
        );
        let ccx = washdyn_fe::rotating::coriolis_reference(
            &mesh,
            dir.path(),
            &format!("coriolis_{rpm}"),
            &washdyn_fe::prestress::Centrifugal::new(omega, bodies::DRUM_AXIS_POINT, axis),
            n,
        )
        .unwrap();
        let nearest = |f: f64| {
            let c = ccx
                .iter()
                .map(|c| c.0)
                .min_by(|a, b| (a - f).abs().total_cmp(&(b - f).abs()))
                .unwrap();
            assert!(
                (c - f).abs() < 1e-3 * f,
                "{rpm} rpm: ours {f} Hz, ccx nearest {c}"
            );
            c
        };
        let (split, reference) = (hi - lo, nearest(hi) - nearest(lo));
        let rel = (split - reference) / reference;
        eprintln!(
            "{rpm} rpm: rocking pair {lo:.4} / {hi:.4} Hz (pair shares {:.3}, {:.3}), split \
             {split:.5} Hz; ccx {reference:.5} Hz; relative {rel:.1e}\n  ours {ours:.4?}\n  ccx \
             {ccx:?}",
            shares[by_share[0]], shares[by_share[1]]
        );
        assert!(shares[by_share[1]] > 0.9, "{shares:?}");
        // Measured 1.9e-5 at 400 rpm (5.42589 vs 5.42600 Hz), 4.1e-4 at 1400 rpm (20.1509 vs
        // 20.1592 Hz; 9.6e-5 with the K_G fitted to ccx's prestressed modes).
        assert!(
            rel.abs() < 1e-3,
            "{rpm} rpm: split {split} vs ccx {reference}"
        );
    }
}
