//! The built-in FE models (tub, drum, cabinet) and their committed modal data.
//!
//! Without CalculiX: node sets, the mass balance against reference-machine.md, and the
//! committed files (they pass the checker; the drum's first elastic mode lies above what the
//! unbalance excites). With CalculiX (skipped locally without it, required under CI=true): the
//! tub's and the drum's decks solve; ccx's own mass totals (EMAS) against our element
//! integration; the modal data rebuilt from a fresh solve equals the committed files (the
//! cabinet's in an ignored test: its solve serves nothing else); the drum's stress-stiffened
//! frequencies at three speeds come back from the committed data.

use crate::common;
use common::have_ccx;

use std::path::PathBuf;
use washdyn_fe::bodies::{self, balance};
use washdyn_fe::lumping::{consistent_mass_props, continuum_mass_props, lump};
use washdyn_model::ir::modal::{self, ModalData};

fn committed(name: &str) -> ModalData {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("models/fe")
        .join(format!("{name}.modal.toml"));
    modal::read_file(&p, &p.display().to_string()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn committed_decks_are_what_the_code_writes() {
    // models/fe/*.inp are the decks behind the committed modal data (`washdyn fe write --out
    // models/fe`); they must not drift from the parametric models.
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models/fe");
    for (name, text) in bodies::decks() {
        let kept =
            std::fs::read_to_string(dir.join(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            kept == text,
            "models/fe/{name} differs from what the code writes"
        );
    }
}

#[test]
fn every_point_has_its_node_set() {
    for b in bodies::builtin() {
        for (set, _) in &b.points {
            let ids = b.mesh.nsets.get(set);
            assert!(ids.is_some_and(|v| !v.is_empty()), "{}: {set}", b.name);
        }
        // Every patch of a marker has at least 3 nodes (a rotation from the rigid fit).
        for (set, _) in b.points.iter().filter(|(s, _)| !s.starts_with("FOOT")) {
            assert!(b.mesh.nsets[set].len() >= 3, "{}: {set}", b.name);
        }
    }
}

#[test]
fn hrz_keeps_each_body_mass_exactly() {
    // HRZ scales each element's diagonal to the element's mass: the lumped total equals the
    // element integral (3 points a direction) to round-off: measured 8.9e-15 (cabinet).
    for b in bodies::builtin() {
        let l = lump(&b.mesh).mass_props(&b.mesh);
        let c = washdyn_fe::lumping::element_mass(&b.mesh);
        eprintln!(
            "{}: HRZ mass {:.1e} off the element integral",
            b.name,
            (l.mass / c - 1.0).abs()
        );
        assert!((l.mass - c).abs() < 1e-13 * c, "{}: {l:?} vs {c}", b.name);
    }
}

#[test]
fn tub_drum_and_rotor_make_the_suspended_body() {
    // The rigid model's suspended body (models/data/reference.toml: 55 kg, CoG (0, 0, 0.45),
    // its inertia tensor) and the FE models' tub + drum + rotor must be one machine: within
    // 1 % each (CoG per its height, 0.45 m; products per the diagonal). Measured 1.0e-3 at
    // worst.
    let model = washdyn_model::ir::toml_file::load_file(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models/data/reference.toml"),
    )
    .unwrap();
    let b = bodies::builtin();
    let drum = consistent_mass_props(&b[1].mesh);
    let tub = consistent_mass_props(&b[0].mesh);
    let total = tub.combine(&drum).combine(&balance::rotor());
    let rigid = &model.tub;
    eprintln!("FE suspended body {total:?}\nrigid model {rigid:?}");
    let mut worst = (total.mass / rigid.mass - 1.0).abs();
    for i in 0..3 {
        worst = worst.max((total.cog[i] - rigid.cog[i]).abs() / 0.45);
        for j in 0..3 {
            let scale = rigid.inertia[j][j].min(rigid.inertia[i][i]);
            worst = worst.max((total.inertia[i][j] - rigid.inertia[i][j]).abs() / scale);
        }
    }
    assert!((total.mass - rigid.mass).abs() < 0.01 * rigid.mass);
    for i in 0..3 {
        assert!(
            (total.cog[i] - rigid.cog[i]).abs() < 0.01 * 0.45,
            "{total:?}"
        );
        for j in 0..3 {
            let scale = rigid.inertia[j][j].min(rigid.inertia[i][i]);
            let dev = (total.inertia[i][j] - rigid.inertia[i][j]).abs() / scale;
            assert!(dev < 0.01, "I[{i}][{j}]: {dev:.3}: {total:?}");
        }
    }
    // The drum's polar inertia is the rigid model's drum rotor's.
    let polar = model
        .rotors
        .iter()
        .find(|r| r.name == "drum")
        .unwrap()
        .polar_inertia;
    worst = worst.max((drum.inertia[0][0] / polar - 1.0).abs());
    eprintln!("suspended body and drum polar inertia: worst deviation {worst:.2e}");
    assert!(
        (drum.inertia[0][0] - polar).abs() < 0.01 * polar,
        "{drum:?} vs {polar}"
    );
    // reference-machine.md's first estimate of the inertia, diag(2.6, 2.3, 2.3), is out of
    // reach of this geometry (30 % on Ixx); mass and CoG still hit it: within 1e-4 from the
    // balance search, within 5e-3 since issue 9 resized the bearing unit by hand (a 0.44 m
    // aluminium carrier plate: the CoG moved 0.9 mm along x, the mass by 1e-3).
    let d = balance::deviations(&total);
    assert!(d[..4].iter().all(|v| v.abs() < 5e-3), "{d:?}");
}

#[test]
fn committed_modal_data_passes_the_checker_and_the_drum_clears_the_unbalance() {
    for name in ["tub", "tub_bare", "drum", "cabinet"] {
        let d = committed(name);
        assert_eq!(modal::problems(&d), Vec::<String>::new(), "{name}");
        eprintln!(
            "{name}: {} modes, {:.2} to {:.2} Hz, lumping error {:.2e}",
            d.modes(),
            d.frequencies[0],
            d.frequencies[d.modes() - 1],
            d.mass_normalisation_error()
        );
    }
    // Seed paper: the first elastic drum mode must lie above what the unbalance excites; the
    // drum order 1 at 1400 rpm is 23.3 Hz, order 2 46.7 Hz is the nearest.
    let drum = committed("drum");
    assert!(
        drum.frequencies[0] > 1400.0 / 60.0 * 1.5,
        "{:?}",
        drum.frequencies
    );
    assert!(drum.geometric_stiffness.is_some());
}

#[test]
fn decks_solve_and_reproduce_the_committed_modal_data() {
    if !have_ccx() {
        return;
    }
    // The tub and the drum as tests/fields.rs recovers from them (`common::builtin`).
    for b in common::builtin::tub_and_drum() {
        compare(
            &b.spec,
            &b.data,
            &b.report,
            &common::builtin::dir().join(&b.spec.name),
        );
    }
}

/// The cabinet's solve (199 s of ccx plus 39 s for its correction modes, measured on a cold
/// CI-like run) is needed by no other test: it runs with the data's regeneration, not in CI's
/// budget. What the preload check adds is held in CI on other bodies: correction modes answer
/// a static load exactly (tests/fe_free_body.rs), and recovered stresses, the correction modes'
/// among them, match ccx's (tests/fields.rs, the drum).
#[test]
#[ignore = "ccx's cabinet solve, 240 s of one core: run with --ignored after regenerating the data"]
fn cabinet_deck_solves_to_the_committed_modal_data_and_its_preload_stresses() {
    if !have_ccx() {
        return;
    }
    let top = tempfile::tempdir().unwrap();
    let cabinet = bodies::builtin().remove(2);
    let dir = top.path().join(&cabinet.name);
    std::fs::create_dir_all(&dir).unwrap();
    let (data, report) = washdyn_fe::pipeline::build(&cabinet, &dir).unwrap();
    cabinet_preload_stresses_match_calculix(&cabinet, &data, &dir);
    compare(&cabinet, &data, &report, &dir);
}

/// One body of the two tests above, built in `dir`: ccx's
/// mass totals against ours, and the committed file against this solve.
fn compare(
    b: &washdyn_fe::pipeline::BodySpec,
    data: &ModalData,
    report: &washdyn_fe::pipeline::Report,
    dir: &std::path::Path,
) {
    // ccx's own mass totals against our element integration (point masses aside: EMAS
    // leaves MASS elements out). ccx prints 7 significant digits (5e-7 relative); its
    // curved shells, expanded to bricks about nodal normals, add a little: measured 1.2e-6
    // (tub), 1.4e-7 (drum), 3e-7 (cabinet); bound 5e-6.
    let dat = std::fs::read_to_string(dir.join(format!("{}.dat", b.name))).unwrap();
    let e = washdyn_fe::dat::emas(&dat, "EALL").expect("EMAS totals in the .dat");
    let c = continuum_mass_props(&b.mesh);
    eprintln!("{report}  ccx EMAS {:.6} kg, ours {:.6} kg", e.mass, c.mass);
    assert!(
        (e.mass - c.mass).abs() < 5e-6 * c.mass,
        "{}: {e:?} vs {c:?}",
        b.name
    );
    for i in 0..3 {
        assert!(
            (e.cog[i] - c.cog[i]).abs() < 1e-4,
            "{}: cog {e:?} vs {c:?}",
            b.name
        );
    }
    let ie = e.inertia();
    for i in 0..3 {
        // Shells and beams expanded to 3-D carry their through-section inertia, which
        // the mid-surface integral leaves out: t^2 / 12 and a^2 / 12 terms, < 0.5 %.
        assert!(
            (ie[i][i] - c.inertia[i][i]).abs() < 5e-3 * c.inertia[i][i],
            "{}: inertia {ie:?} vs {:?}",
            b.name,
            c.inertia
        );
    }
    // The committed file is what this code and ccx give now (frequencies to the .frd's
    // precision), every mode, the correction modes too.
    let old = committed(&b.name);
    assert_eq!(old.modes(), data.modes(), "{}", b.name);
    for (a, f) in old.frequencies.iter().zip(&data.frequencies) {
        assert!((a - f).abs() < 1e-6 * f, "{}: {a} vs {f}", b.name);
    }
    // Rigid modes: exactly six for the free-free tub, none for the others.
    let rigid = report.all_frequencies.iter().filter(|f| **f < 1.0).count();
    assert_eq!(rigid, if b.name == "tub" { 6 } else { 0 }, "{}", b.name);
}

/// The stresses the cabinet's field carries, superposed for the springs' preloads (147.15,
/// 147.15, 245.25 N down at the spring points, as consistent nodal loads) with the modes'
/// static response, against ccx's static solution of the cabinet under the same loads: per
/// node, the largest von Mises stress over its faces. The correction modes hold this static
/// load exactly, so their stresses (formed like their shapes) must close the gap the
/// eigenmodes leave.
fn cabinet_preload_stresses_match_calculix(
    spec: &washdyn_fe::pipeline::BodySpec,
    data: &ModalData,
    dir: &std::path::Path,
) {
    let field = washdyn_fe::field::Field::read(&dir.join("cabinet.field.bin")).unwrap();
    assert!(field.has_stresses());
    let loads = [
        ("SPRING_1", 147.15),
        ("SPRING_2", 147.15),
        ("SPRING_3", 245.25),
    ];
    let n = data.modes();
    let mut q = vec![0.0; n];
    let mut d = spec.mesh.model_deck();
    d.line("*STEP").line("*STATIC").line("*CLOAD");
    for (set, p) in loads {
        let pt = data.point(set).unwrap();
        for (k, qk) in q.iter_mut().enumerate() {
            *qk += pt.w[2][k] * (-p) / (2.0 * std::f64::consts::PI * data.frequencies[k]).powi(2);
        }
        for (id, r) in washdyn_fe::modal::point_reading(&spec.mesh, set, pt.position).unwrap() {
            for (c, row) in r[2].iter().enumerate() {
                if *row != 0.0 {
                    d.line(&format!("{id}, {}, {:.12e}", c + 1, -p * row));
                }
            }
        }
    }
    d.line("*NODE FILE")
        .line("U")
        .line("*EL FILE")
        .line("S")
        .line("*END STEP");
    let deck = dir.join("preload_stress.inp");
    std::fs::write(&deck, d.text()).unwrap();
    let run = washdyn_fe::ccx::run(&deck).unwrap_or_else(|e| panic!("{e}"));
    let frd = washdyn_fe::frd::parse(&std::fs::read_to_string(run.frd()).unwrap()).unwrap();
    let theirs: std::collections::HashMap<usize, [f64; 6]> =
        frd.static_stresses[0].iter().copied().collect();
    let points = washdyn_fe::stress::associate(&spec.mesh, &frd).unwrap();
    let h = &field.header;
    // Ours with all modes, and with the eigenmodes only.
    let ours = |modes: usize, i: usize| field.node_stress(i, &q[..modes]).0;
    let ccx: Vec<f64> = h
        .ids
        .iter()
        .map(|id| {
            points.get(id).map_or(0.0, |e| {
                e.iter()
                    .filter_map(|x| theirs.get(x))
                    .map(washdyn_fe::stress::von_mises)
                    .fold(0.0, f64::max)
            })
        })
        .collect();
    let peak = ccx.iter().copied().fold(0.0, f64::max);
    let worst = |modes: usize| {
        (0..h.nodes.len())
            .map(|i| (ours(modes, i) - ccx[i]).abs() / peak)
            .fold(0.0, f64::max)
    };
    let (all, eigen) = (worst(n), worst(data.eigenmodes()));
    eprintln!(
        "cabinet under the spring preloads: ccx peak von Mises {:.3} MPa; worst node error of \
         the peak: {all:.1e} with the correction modes, {eigen:.2} with the eigenmodes only",
        peak * 1e-6
    );
    // Measured: peak 72.4 MPa; 2.0e-6 of it with the correction modes (ccx's printed digits:
    // they answer this load exactly), 0.75 with the 60 eigenmodes (the rails' local bending
    // under the spring points is in none of them).
    assert!(all < 1e-3, "{all}");
    assert!(eigen > 10.0 * all, "{eigen} vs {all}");
}

#[test]
fn drum_stress_stiffened_frequencies_come_back_from_the_assembled_geometric_stiffness() {
    // The drum as `fe modal` builds it (`common::builtin`: its K_G assembled from ccx's static
    // centrifugal stresses at 1400 rpm, `washdyn_fe::prestress`) against ccx's own prestressed
    // body: the same static step (CENTRIF and the pulley masses' CLOADs), then a *FREQUENCY
    // perturbation step, at 400, 900 and 1400 rpm. ccx's step also holds the static
    // displacement's stiffness, and has neither the pulley's rigid-part stiffness nor the
    // point masses' spin softening (`PrestressReport::as_ccx` makes ours so; on this drum the
    // last two are below 3e-13 per (rad/s)^2: the pulley sits behind the rear bearing). And the committed data, whose K_G was fitted to ccx's
    // prestressed modes at 1400 rpm, for comparison.
    if !have_ccx() {
        return;
    }
    // The drum alone: this test does not wait for the tub's solve.
    let b = common::builtin::body("drum");
    let kg = b.data.geometric_stiffness.clone().unwrap();
    let as_ccx = b.report.prestress.as_ref().unwrap().as_ccx(&kg);
    let committed = committed("drum");
    let dir = tempfile::tempdir().unwrap();
    let f0 = &b.data.frequencies;
    let (mut worst, mut fitted) = (0.0f64, 0.0f64);
    for rpm in [400.0, 900.0, 1400.0] {
        let omega = rpm * std::f64::consts::PI / 30.0;
        let c = washdyn_fe::prestress::Centrifugal::new(omega, kg.axis_point, kg.axis);
        let (frd, _) = washdyn_fe::rotating::solve_prestressed(
            &b.spec.mesh,
            dir.path(),
            &format!("w{rpm}"),
            &c,
            10,
        )
        .unwrap();
        let ccx_f: Vec<f64> = frd.modes.iter().map(|m| m.frequency_hz).collect();
        let ours =
            washdyn_fe::rotating::reduced_frequencies(f0, &b.data.elementary, &as_ccx, omega);
        let old = washdyn_fe::rotating::reduced_frequencies(
            &committed.frequencies,
            &committed.elementary,
            committed.geometric_stiffness.as_ref().unwrap(),
            omega,
        );
        eprintln!("{rpm} rpm: ccx {ccx_f:?}\n  assembled {ours:?}\n  committed (fit) {old:?}");
        for (k, c) in ccx_f.iter().enumerate() {
            let rel = (ours[k] - c) / c;
            worst = worst.max(rel.abs());
            fitted = fitted.max(((old[k] - c) / c).abs());
            // A Rayleigh-Ritz projection on the 10 kept modes (from above), and the static
            // displacement's stiffness from the .frd's 6 digits (it splits the degenerate
            // pairs by up to 1.4e-4; 3.1e-5 below ccx at 400 rpm): measured 1.9e-3 (1400 rpm,
            // the torsion mode, 161.254 vs 160.956 Hz; 3.2e-3 with the stresses' K_G alone; the
            // committed data's fitted K_G 1.8e-3).
            assert!(
                rel.abs() < 5e-3,
                "mode {k} at {rpm} rpm: {} vs ccx {c}",
                ours[k]
            );
        }
    }
    eprintln!(
        "stress-stiffened frequencies against ccx: assembled K_G {worst:.1e}, the committed \
         (fitted) K_G {fitted:.1e}"
    );
}

// The drum's Campbell diagram against CalculiX: `tests/fe_drum.rs`, on the knot-free brick
// variant (ccx's Coriolis matrix is wrong on models with MPCs, as the production drum is).

/// The reference's counterweights (models/data/reference.toml, scene `counterweights`) are the
/// FE tub's concrete bricks: each sector's elements (top, bottom, collar by where they lie) by
/// the same consistent mass integration as the tub's, against the model's mass, CoG and
/// inertia about the CoG. Measured: 1.6e-5 at worst (bound 4e-4; the model's numbers integrate
/// the exact cylindrical sectors, docs/even-orders/counterweight_mass.py, the mesh its C3D20
/// with midside nodes on the circles, and are rounded), and the three together are the tub's
/// bricks.
#[test]
fn the_models_counterweights_are_the_fe_tubs_concrete_bricks() {
    let model = washdyn_model::ir::toml_file::load_file(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("models/data/reference.toml"),
    )
    .unwrap();
    let tub = bodies::tub::Tub::default().mesh();
    let bricks = tub
        .parts
        .iter()
        .find(|p| p.name == "TUB_COUNTERWEIGHT")
        .expect("the tub's counterweight bricks");
    // Which counterweight an element belongs to, by its centroid.
    let which = |e: &Vec<usize>| {
        let c: [f64; 3] = std::array::from_fn(|a| {
            e.iter().map(|&n| tub.nodes[n - 1][a]).sum::<f64>() / e.len() as f64
        });
        if c[0] > bodies::tub::Tub::default().x_front {
            "counterweight_collar"
        } else if c[2] > 0.45 {
            "counterweight_top"
        } else {
            "counterweight_bottom"
        }
    };
    let mut worst = 0.0f64;
    let mut total = 0.0;
    for w in &model.counterweights {
        let mut sub = tub.clone();
        sub.rigid.clear();
        sub.parts = vec![washdyn_fe::mesh::Part {
            elements: bricks
                .elements
                .iter()
                .filter(|e| which(e) == w.name)
                .cloned()
                .collect(),
            ..bricks.clone()
        }];
        let p = consistent_mass_props(&sub);
        total += p.mass;
        let scale = w.inertia[0][0].max(w.inertia[1][1]).max(w.inertia[2][2]);
        worst = worst.max((p.mass / w.mass - 1.0).abs());
        for a in 0..3 {
            worst = worst.max((p.cog[a] - w.cog[a]).abs() / 0.45);
            for b in 0..3 {
                worst = worst.max((p.inertia[a][b] - w.inertia[a][b]).abs() / scale);
            }
        }
        eprintln!("{}: FE {p:?}", w.name);
    }
    let all = {
        let mut sub = tub.clone();
        sub.rigid.clear();
        sub.parts = vec![bricks.clone()];
        consistent_mass_props(&sub).mass
    };
    eprintln!("counterweights against the FE bricks: {worst:.1e}; {total} of {all} kg");
    assert!(worst < 4e-4, "{worst:e}");
    assert!(
        (total - all).abs() < 1e-9 * all,
        "every brick in one counterweight"
    );
}
