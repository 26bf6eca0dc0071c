//! Field recovery on the FE meshes (`washdyn fields`), through CalculiX and an independent VTK
//! reader: the tub's and the drum's modal data and field files are built with ccx, the
//! reference machine's elastic scene is put at its static rest position, and
//! - meshio (Python) reads the written grid: node count, cell types, and one node's
//!   displacement equal to u + alpha x (x - p0) + W q computed here from the stored shapes;
//! - the drum's bearing node, where the drum is clamped, moves with the tub's bearing patch.
//!
//! Without ccx or meshio the test skips, except under CI (`CI=true`), where it fails.

use crate::common;

use std::path::PathBuf;
use std::process::Command;
use washdyn::fields::{Recovery, States, write_fields};
use washdyn_model::equations::Equations;
use washdyn_model::ir::BodyRef;
use washdyn_model::ir::Model;
use washdyn_model::ir::modal::ModalData;
use washdyn_runtime::system::Interpreter;

fn tools() -> bool {
    let meshio = Command::new("python3")
        .args(["-c", "import meshio"])
        .output()
        .is_ok_and(|o| o.status.success());
    common::required_tool(
        washdyn_fe::ccx::available(),
        "CalculiX",
        "apt-get install calculix-ccx",
    ) && common::required_tool(meshio, "meshio", "python3 -m pip install meshio")
}

/// The tub's and the drum's modal data and field files from this machine's ccx
/// (`common::builtin`, shared with tests/fe_bodies.rs): the folder with `<body>.field.bin`, and
/// each body's modal data from the same solve.
fn built() -> (PathBuf, Vec<(&'static String, &'static ModalData)>) {
    let b = common::builtin::tub_and_drum();
    (
        common::builtin::dir(),
        b.iter().map(|x| (&x.spec.name, &x.data)).collect(),
    )
}

/// The reference machine on this solve's modal data for the bodies `built` made: the
/// formulas compared below then meet the field of their own solve (another machine's solve is
/// re-projected onto the committed modes: `fields_of_this_solve_align_with_the_committed_data`).
fn on_this_solve(model: &Model) -> Model {
    let mut m = model.clone();
    for e in &mut m.elastic {
        if let Some((_, d)) = built().1.iter().find(|(n, _)| **n == e.name) {
            e.data = Some((*d).clone());
        }
    }
    washdyn_model::ir::check::check(&m).unwrap_or_else(|e| panic!("{e:?}"));
    m
}

/// This machine's fresh solve against the committed modal data (another machine's solve, issue
/// 23): `Field::align` accepts each body's field, turning or flipping only within groups of
/// equal frequency, and `Recovery` builds on the committed reference's elastic scene.
#[test]
fn fields_of_this_solve_align_with_the_committed_data() {
    if !tools() {
        return;
    }
    let committed = washdyn_models::built_in("reference").unwrap().unwrap();
    for (name, _) in &built().1 {
        let path = built().0.join(format!("{name}.field.bin"));
        let field = washdyn_fe::field::Field::read(&path).unwrap();
        let e = committed.elastic.iter().find(|e| &e.name == *name).unwrap();
        let al = field
            .align(e.data.as_ref().unwrap())
            .unwrap_or_else(|e| panic!("{e}"));
        eprintln!(
            "{name}: largest deviation {:.2e}, groups re-projected {:?}",
            al.worst(),
            al.changed()
        );
        // Measured on this project's machine against the committed data: 1.8e-5 (the tub's
        // correction modes as one group), 1.4e-6 (the drum); nothing turned or flipped.
        assert!(al.worst() < 2e-4, "{name}: {:.2e}", al.worst());
    }
    let scene = committed.scene(Some("elastic")).unwrap();
    let eq = Equations::new(&committed, &scene);
    let rec = Recovery::new(&eq, &built().0).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(rec.bodies.len(), 2);
}

#[test]
fn recovered_fields_are_read_back_by_meshio_and_continuous_at_the_bearing() {
    if !tools() {
        return;
    }
    let built = &built().0;
    let dir = tempfile::tempdir().unwrap();
    let specs = washdyn_fe::bodies::builtin();
    let committed = washdyn_models::built_in("reference").unwrap().unwrap();
    let scene = committed.scene(Some("elastic")).unwrap();
    // The user's path: the committed modal data recovers this machine's fields (Recovery
    // checks they are the same model's, to another machine's round-off).
    Recovery::new(&Equations::new(&committed, &scene), built).unwrap_or_else(|e| panic!("{e}"));
    // The formulas: on this solve's data, where two paths must agree to round-off.
    let model = on_this_solve(&committed);
    let eq = Equations::new(&model, &scene);
    let rec = Recovery::new(&eq, built).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        rec.bodies
            .iter()
            .map(|b| b.name.as_str())
            .collect::<Vec<_>>(),
        ["tub", "drum"]
    );
    let mut sys = Interpreter::new(&model, &scene);
    let q = washdyn_runtime::statics::static_equilibrium(&mut sys, 0.0).unwrap();
    let states = States {
        t: vec![0.0, 1.0],
        phi: vec![0.0, 0.0],
        q: q.iter().map(|&x| vec![x, x]).collect(),
    };
    let out = dir.path().join("fields");
    let written = write_fields(&rec, &states, &[0.5], &out).unwrap();
    assert_eq!(
        written.files.len(),
        4,
        "two bodies, one grid and one .pvd each"
    );

    // By hand: a tub node on the measurement point MP_TUB1, u + alpha x (x - p0) + W q_file,
    // with the field's (file) modal coordinates q_file = T q_scene through the basis that the
    // scene's truncation stored in the modal data (row-major, file modes x scene modes; it
    // folds the dropped modes into the tub's correction modes, so scene mode k is not file
    // mode k).
    let tub = &rec.bodies[0];
    let h = &tub.field.header;
    let id = specs[0].mesh.nsets["MP_TUB1"][0];
    let i = h.ids.iter().position(|&x| x == id).unwrap();
    let x = h.nodes[i];
    let p0 = model.tub.cog;
    let r = [x[0] - p0[0], x[1] - p0[1], x[2] - p0[2]];
    let a = [q[3], q[4], q[5]];
    let mut want = [
        q[0] + a[1] * r[2] - a[2] * r[1],
        q[1] + a[2] * r[0] - a[0] * r[2],
        q[2] + a[0] * r[1] - a[1] * r[0],
    ];
    let tub_modes = eq.modes(BodyRef::Tub).unwrap();
    let qs = &q[tub_modes.start..tub_modes.start + tub_modes.n];
    let nf = tub.field.modes();
    let basis = tub_modes.data().basis.clone();
    let q_file: Vec<f64> = match &basis {
        Some(t) => {
            assert_eq!(t.len(), nf * tub_modes.n, "basis: file x scene modes");
            (0..nf)
                .map(|k| {
                    (0..tub_modes.n)
                        .map(|j| t[k * tub_modes.n + j] * qs[j])
                        .sum()
                })
                .collect()
        }
        None => qs.to_vec(),
    };
    for (k, qk) in q_file.iter().enumerate() {
        let s = tub.field.shape(k, i);
        for c in 0..3 {
            want[c] += s[c] * qk;
        }
    }
    let script = format!(
        "import meshio, json\n\
         m = meshio.read('{}')\n\
         print(json.dumps({{'points': len(m.points), 'types': sorted(c.type for c in m.cells), \
         'u': m.point_data['displacement_m'][{i}].tolist()}}))",
        out.join("tub_00000.vtu").display()
    );
    let o = Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    eprintln!("meshio: {read}; by hand {want:?}");
    assert_eq!(read["points"].as_u64().unwrap() as usize, h.nodes.len());
    let types: Vec<&str> = read["types"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    // The tub: S8R shells, C3D20 bricks (hub), B32 beams (stator truss).
    for t in ["hexahedron20", "line3", "quad8"] {
        assert!(types.contains(&t), "{types:?}");
    }
    let norm = (want[0].powi(2) + want[1].powi(2) + want[2].powi(2)).sqrt();
    assert!(norm > 1e-4, "the rest position moves the tub ({norm} m)");
    for c in 0..3 {
        let u = read["u"][c].as_f64().unwrap();
        // Written as Float32: equal to its rounding (6e-8 relative).
        assert!(
            (u - want[c]).abs() <= 1e-7 * norm,
            "{c}: {u} vs {}",
            want[c]
        );
    }

    // Continuity: the drum's clamped bearing node against the tub's BEARING node set, read as
    // the drum's mount reads it: the least-squares rigid motion of the set's recovered nodal
    // displacements, evaluated at the bearing point.
    let drum = &rec.bodies[1];
    let (_, du) = rec.displacement(drum, 0.0, &q);
    let bid = specs[1].mesh.nsets["BEARING"][0];
    let bi = drum
        .field
        .header
        .ids
        .iter()
        .position(|&x| x == bid)
        .unwrap();
    let b = drum.field.header.nodes[bi];
    let (_, tu) = rec.displacement(tub, 0.0, &q);
    let patch = &specs[0].mesh.nsets["BEARING"];
    let w: std::collections::HashMap<usize, [f64; 3]> = patch
        .iter()
        .map(|id| (*id, tu[h.ids.iter().position(|x| x == id).unwrap()]))
        .collect();
    let (uc, th, c) = washdyn_fe::modal::rigid_fit(&specs[0].mesh, patch, &w).unwrap();
    let rb = [b[0] - c[0], b[1] - c[1], b[2] - c[2]];
    let fit = [
        uc[0] + th[1] * rb[2] - th[2] * rb[1],
        uc[1] + th[2] * rb[0] - th[0] * rb[2],
        uc[2] + th[0] * rb[1] - th[1] * rb[0],
    ];
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let gap = dist(du[bi], fit);
    let size = dist(fit, [0.0; 3]);
    // How far the set's nodes themselves depart from that rigid motion (its own deformation).
    let spread = patch
        .iter()
        .map(|id| {
            let x = specs[0].mesh.nodes[id - 1];
            let r = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
            let rigid = [
                uc[0] + th[1] * r[2] - th[2] * r[1],
                uc[1] + th[2] * r[0] - th[0] * r[2],
                uc[2] + th[0] * r[1] - th[1] * r[0],
            ];
            dist(w[id], rigid)
        })
        .fold(0.0, f64::max);
    eprintln!(
        "bearing: drum {:?}, tub set's rigid fit {fit:?}: gap {gap:.2e} m; the set's nodes \
         depart from its rigid motion by up to {spread:.2e} m",
        du[bi]
    );
    assert!(size > 1e-4);
    // The same motion through two paths (modal rows at the point vs the fit of the recovered
    // nodes): equal to round-off.
    assert!(gap < 1e-9 * size, "gap {gap} m against {size} m");

    drum_rim_sensor_reads_the_recovered_field(&model, &rec, &specs[1].mesh);
}

/// A sensor on the drum's rim (its modal point DRUM_EDGE_0, a set of nodes) against the
/// recovered field of that set: the least-squares rigid motion of the set's recovered nodal
/// displacements at the set's point, with the drum turned (the field's points, B + R(x - B)).
/// Displacement at one state; acceleration against the second central difference of the
/// recovered displacement along q(t) = q0 + t q1 + t^2/2 q2, phi(t) = phi0 + w t + w' t^2/2
/// (the sensor's Coriolis and centripetal terms of the turning point and the drum's modes).
fn drum_rim_sensor_reads_the_recovered_field(
    model: &washdyn_model::ir::Model,
    rec: &Recovery,
    mesh: &washdyn_fe::mesh::Mesh,
) {
    use washdyn_model::equations::Drive;
    use washdyn_model::ir::{BodyRef, Sensor, SensorKind};
    let edge = "DRUM_EDGE_0";
    let scene = model.scene(Some("elastic")).unwrap();
    let eq0 = Equations::new(model, &scene);
    let point = eq0
        .elastic_drum()
        .unwrap()
        .modes
        .data()
        .points
        .iter()
        .find(|p| p.name == edge)
        .unwrap()
        .position;
    let mut m = model.clone();
    for kind in [SensorKind::Displacement, SensorKind::Acceleration] {
        m.sensors.push(Sensor {
            name: format!("rim_{kind:?}").to_lowercase(),
            body: BodyRef::Drum,
            point,
            kind,
        });
    }
    washdyn_model::ir::check::check(&m).unwrap_or_else(|e| panic!("{e:?}"));
    let eq = Equations::new(&m, &scene);
    let (du, ac) = (eq.sensors.len() - 2, eq.sensors.len() - 1);
    let spin = eq.sensors[du]
        .spin
        .as_ref()
        .expect("an off-axis drum sensor turns");
    let n = eq.layout.n();
    // A state with every kind of coordinate moving: tub translation and (small) rotation, the
    // tub's and the drum's modes.
    let wave = |scale: f64, k: f64| -> Vec<f64> {
        (0..n)
            .map(|i| {
                scale * ((i as f64 + 1.0) * k).sin() * if (3..6).contains(&i) { 1e-3 } else { 1.0 }
            })
            .collect()
    };
    let (q0, q1, q2) = (wave(1e-4, 0.7), wave(3e-3, 1.3), wave(0.4, 2.1));
    let (phi0, w, wd) = (1.234, 120.0, 35.0);
    let drum = &rec.bodies[1];
    let ids = &mesh.nsets[edge];
    let h = &drum.field.header;
    // The set's recovered motion at its point, fitted over the turned nodes.
    let fitted = |phi: f64, q: &[f64]| -> [f64; 3] {
        let (pts, disp) = rec.displacement(drum, phi, q);
        let mut turned = mesh.clone();
        let mut wmap = std::collections::HashMap::new();
        for id in ids {
            let i = h.ids.iter().position(|x| x == id).unwrap();
            turned.nodes[id - 1] = pts[i];
            wmap.insert(*id, disp[i]);
        }
        let (u, th, c) = washdyn_fe::modal::rigid_fit(&turned, ids, &wmap).unwrap();
        // The set's point turned like the nodes.
        let (b, e, ratio) = (spin.mount, spin.axis, spin.ratio);
        let th_d = phi * ratio;
        let r = [point[0] - b[0], point[1] - b[1], point[2] - b[2]];
        let (cs, sn) = (th_d.cos(), th_d.sin());
        let ed = e[0] * r[0] + e[1] * r[1] + e[2] * r[2];
        let exr = [
            e[1] * r[2] - e[2] * r[1],
            e[2] * r[0] - e[0] * r[2],
            e[0] * r[1] - e[1] * r[0],
        ];
        let p: Vec<f64> = (0..3)
            .map(|a| b[a] + r[a] * cs + exr[a] * sn + e[a] * ed * (1.0 - cs))
            .collect();
        let d = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        [
            u[0] + th[1] * d[2] - th[2] * d[1],
            u[1] + th[2] * d[0] - th[0] * d[2],
            u[2] + th[0] * d[1] - th[1] * d[0],
        ]
    };
    let drive = Drive {
        phi: phi0,
        omega: w,
        omega_dot: wd,
    };
    let zero = vec![0.0; n];
    // |want| and |got - want|.
    let compare = |got: [f64; 3], want: &[f64]| {
        let norm = |v: &dyn Fn(usize) -> f64| (0..3).map(|a| v(a).powi(2)).sum::<f64>().sqrt();
        (norm(&|a| want[a]), norm(&|a| got[a] - want[a]))
    };
    let sensed = eq.sensor(du, &drive, &q0, &zero, &zero);
    let want = fitted(phi0, &q0);
    let (size, diff) = compare(sensed, &want);
    // The second-order rotation terms (element_geometry) are the sensor's own: alpha ~ 1e-7
    // rad leaves them at 1e-14 of the motion.
    eprintln!(
        "drum rim displacement: sensor {sensed:?}, recovered {want:?}: {:.1e} of {size:.2e} m",
        diff / size
    );
    assert!(size > 1e-5, "the state moves the rim ({size} m)");
    // Measured 8.3e-12 relative: the sensor reads the modal data's rows, the recovery the
    // field of the same solve; the formulas agree to round-off.
    assert!(diff < 1e-10 * size);
    // Acceleration: central differences of the recovered motion along the path.
    let dt = 1e-5;
    let at = |t: f64| {
        let q: Vec<f64> = (0..n)
            .map(|i| q0[i] + t * q1[i] + 0.5 * t * t * q2[i])
            .collect();
        fitted(phi0 + w * t + 0.5 * wd * t * t, &q)
    };
    let (am, a0, ap) = (at(-dt), at(0.0), at(dt));
    let fd: Vec<f64> = (0..3)
        .map(|a| (ap[a] - 2.0 * a0[a] + am[a]) / (dt * dt))
        .collect();
    let sensed = eq.sensor(ac, &drive, &q0, &q1, &q2);
    let (size, diff) = compare(sensed, &fd);
    eprintln!(
        "drum rim acceleration: sensor {sensed:?}, differences {fd:?}: {:.1e} of {size:.2e} m/s^2",
        diff / size
    );
    assert!(size > 1e-2, "the path accelerates the rim ({size} m/s^2)");
    // Measured 1.7e-7 relative: the differences' truncation (w dt)^2 ~ 1e-6 of the turning
    // terms and round-off 1e-16 |x| / dt^2.
    assert!(diff < 2e-6 * size);
}

/// The paper's route as the reference for stresses: the drum's nodal displacements recovered
/// from a combination of its modes, imposed on its CalculiX model (`*BOUNDARY` on every
/// structural node, `*STATIC`); ccx's von Mises stress at the faces against the modal
/// superposition of the stored modal stresses, node by node.
#[test]
fn drum_stresses_by_modal_superposition_match_calculix_under_the_same_displacements() {
    if !tools() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let spec = washdyn_fe::bodies::builtin().remove(1);
    // The drum alone: this test does not wait for the tub's solve.
    common::builtin::body("drum");
    let field =
        washdyn_fe::field::Field::read(&common::builtin::dir().join("drum.field.bin")).unwrap();
    assert!(field.has_stresses());
    let h = &field.header;
    // Every mode takes part, with alternating signs (m kg^0.5).
    let q: Vec<f64> = (0..field.modes())
        .map(|k| 2e-3 * if k % 2 == 0 { 1.0 } else { -0.7 } / (k + 1) as f64)
        .collect();
    let disp = |i: usize| field.displacement(i, &q);
    // Ours (the recovery's own superposition): per node, the largest von Mises over its faces.
    let ours: Vec<f64> = (0..h.nodes.len())
        .map(|i| field.node_stress(i, &q).0)
        .collect();

    // ccx: the same displacements imposed on every structural node outside the rigid pulley
    // (its nodes follow their *RIGID BODY) and the clamped bearing.
    let mesh = &spec.mesh;
    let mut skip: std::collections::HashSet<usize> = mesh.printed_nodes().into_iter().collect();
    skip.extend(&mesh.nsets["BEARING"]);
    let mut d = mesh.model_deck();
    d.line("*STEP").line("*STATIC").line("*BOUNDARY");
    for (i, id) in h.ids.iter().enumerate() {
        if skip.contains(id) {
            continue;
        }
        for (c, u) in disp(i).iter().enumerate() {
            d.line(&format!("{id}, {}, {}, {u:.12e}", c + 1, c + 1));
        }
    }
    d.line("*NODE FILE")
        .line("U")
        .line("*EL FILE")
        .line("S")
        .line("*END STEP");
    let deck = dir.path().join("imposed.inp");
    std::fs::write(&deck, d.text()).unwrap();
    let run = washdyn_fe::ccx::run(&deck).unwrap_or_else(|e| panic!("{e}"));
    let frd = washdyn_fe::frd::parse(&std::fs::read_to_string(run.frd()).unwrap()).unwrap();
    let stress: std::collections::HashMap<usize, [f64; 6]> =
        frd.static_stresses[0].iter().copied().collect();
    let points = washdyn_fe::stress::associate(mesh, &frd).unwrap();
    let peak = ours.iter().copied().fold(0.0, f64::max);
    let (mut worst, mut at, mut compared) = (0.0f64, 0, 0);
    let mut errs = Vec::new();
    let mut ccx_peak = 0.0f64;
    for (i, id) in h.ids.iter().enumerate() {
        let Some(exp) = points.get(id) else { continue };
        if skip.contains(id) {
            continue;
        }
        let theirs = exp
            .iter()
            .filter_map(|e| stress.get(e))
            .map(washdyn_fe::stress::von_mises)
            .fold(0.0, f64::max);
        ccx_peak = ccx_peak.max(theirs);
        let err = (theirs - ours[i]).abs() / peak;
        errs.push((err, *id));
        compared += 1;
        if err > worst {
            (worst, at) = (err, *id);
        }
    }
    eprintln!(
        "{compared} nodes; peak von Mises: ours {:.4} MPa, ccx {:.4} MPa; worst node {at}: {worst:.2e} of the peak",
        peak * 1e-6,
        ccx_peak * 1e-6
    );
    errs.sort_by(|a, b| b.0.total_cmp(&a.0));
    let part = |id: usize| {
        mesh.parts
            .iter()
            .find(|p| p.elements.iter().any(|e| e.contains(&id)))
            .map_or("?".to_string(), |p| p.name.clone())
    };
    for (e, id) in errs.iter().take(12) {
        eprintln!(
            "  node {id} ({}): {e:.2e} at {:?}",
            part(*id),
            mesh.nodes[id - 1]
        );
    }
    let pct = |q: f64| errs[((1.0 - q) * errs.len() as f64) as usize].0;
    eprintln!(
        "  node error (of the peak): median {:.1e}, 90 % {:.1e}, 99 % {:.1e}",
        pct(0.5),
        pct(0.9),
        pct(0.99)
    );
    // Measured: the peak (181.6 MPa) to 1.5e-4; 90 % of the nodes within 1.6e-2 of the peak.
    // The worst nodes (17 %) lie on the 0.5 mm back wall near r = 0.19 m, where the spider's
    // brick arms join it: with only translations imposed, the shell's rotations there settle
    // to static equilibrium rather than to the modes' own (the stiff bricks against the thin
    // wall make them sensitive), so the bound there is loose.
    assert!(compared > 5000);
    assert!(
        (ccx_peak - peak).abs() < 1e-3 * peak,
        "{ccx_peak} vs {peak}"
    );
    assert!(pct(0.9) < 3e-2, "{}", pct(0.9));
    assert!(worst < 0.25, "{worst} at node {at}");
}

/// `washdyn fields` on a run whose scene keeps every body with a field file rigid and fixed (the
/// reference's `full`: the cabinet) names the files it found, why they serve nothing and the
/// scenes that would (issue 50), before reading them or the states; a folder without any says
/// so as before. No CalculiX needed: the file is never read.
#[test]
fn field_files_of_bodies_the_scene_keeps_rigid_are_named_with_the_remedy() {
    use washdyn::fields::{FieldsError, Request, Times, fields_command};
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    let fe = dir.path().join("fe");
    std::fs::create_dir_all(&run).unwrap();
    std::fs::create_dir_all(&fe).unwrap();
    std::fs::write(
        run.join("summary.json"),
        r#"{"model": "reference", "scene": "full"}"#,
    )
    .unwrap();
    let req = Request::Fields(Times::List(vec![0.0]));
    let e = fields_command(&run, None, &req, &fe, None).err().unwrap();
    assert!(matches!(e, FieldsError::NoFieldFiles { .. }), "{e}");
    std::fs::write(fe.join("cabinet.field.bin"), b"never read").unwrap();
    let e = fields_command(&run, None, &req, &fe, None).err().unwrap();
    match &e {
        FieldsError::NoMovingBody {
            scene,
            files,
            elastic_scenes,
            ..
        } => {
            assert_eq!(scene, "full");
            assert_eq!(files, &["cabinet.field.bin"]);
            assert_eq!(
                elastic_scenes,
                &[
                    "elastic",
                    "elastic_fine",
                    "elastic_rigid_tub",
                    "panel_curves",
                    "cabinet_counterweights"
                ]
            );
        }
        e => panic!("{e}"),
    }
    let out = common::washdyn_in(&["fields", "run", "--times", "0", "--fe", "fe"], dir.path());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    for part in [
        "fe holds cabinet.field.bin, but in the run's scene `full` none of these bodies is elastic",
        "run a scene that keeps them elastic (elastic, elastic_fine, elastic_rigid_tub, \
         panel_curves, cabinet_counterweights) with --states",
    ] {
        assert!(err.contains(part), "`{part}` in: {err}");
    }
    assert!(!run.join("fields").exists());
}
