//! What the validity monitor watches beside the tub's rigid motion (runtime/src/clearance.rs),
//! against the geometry computed here: the door ring's displacement (rigid u + alpha x s, plus
//! the tub's modal rows where its data has the point) and the drum-tub gap's closure (the drum's
//! front-edge deflection turned with the drum, plus the tub's deformation at the bearing moved
//! to the edge, minus the tub ring's, along the edge point's outward radius). And the checker's
//! drum-mass rule: a rigid drum on an elastic tub runs.

use nalgebra::{Matrix3, Vector3};
use washdyn_model::equations::Equations;
use washdyn_model::ir::modal::ModalPoint;
use washdyn_model::ir::toml_file::{load_file, load_str};
use washdyn_model::ir::{BodyRef, Model};
use washdyn_ode::{Dopri5, Options};
use washdyn_runtime::clearance::{DoorRing, DrumGap, Watch};
use washdyn_runtime::output::MemorySink;
use washdyn_runtime::run::{Guard, Labels, RunOptions, Start, run_guarded};
use washdyn_runtime::system::{FirstOrder, Interpreter};

fn data_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data")
}

fn reference() -> Model {
    load_file(&data_dir().join("reference.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn v(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// Rotation by `th` about +x (the drum's axis; the drum turns with positive angle).
fn rot_x(th: f64) -> Matrix3<f64> {
    let (c, s) = (th.cos(), th.sin());
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

/// A ring point `k` of 8 at x, radius r about the axis (., 0, 0.45), 45 degrees apart from +z
/// towards +y.
fn ring_point(x: f64, r: f64, k: usize) -> [f64; 3] {
    let th = std::f64::consts::PI * k as f64 / 4.0;
    [x, r * th.sin(), 0.45 + r * th.cos()]
}

#[test]
fn door_ring_is_the_rigid_motion_on_the_rigid_tub_and_adds_the_modes_where_the_data_has_them() {
    let m = reference();
    let rigid = m.scene(Some("full")).unwrap();
    let eq = Equations::new(&m, &rigid);
    let ring = DoorRing::new(&m, &eq).unwrap();
    assert_eq!(ring.points.len(), 8);
    let q = [1e-3, -2e-3, 0.5e-3, 0.01, 0.02, -0.015];
    let (u, a) = (v([q[0], q[1], q[2]]), v([q[3], q[4], q[5]]));
    let expect = (0..8)
        .map(|k| (u + a.cross(&(v(ring_point(0.30, 0.25, k)) - v([0.0, 0.0, 0.45])))).norm())
        .fold(0.0, f64::max);
    let (got, _) = ring.excursion(&q);
    // The same arithmetic in another order: measured 0.
    assert!((got - expect).abs() < 1e-17, "{got} vs {expect}");

    // The elastic tub: its data has points at ring points 0 (MP_TUB1, (0.3, 0, 0.7)) and 2
    // (MP_TUB2, (0.3, 0.25, 0.45)); one mode moves point 0 by that point's row.
    let elastic = m.scene(Some("elastic")).unwrap();
    let eq = Equations::new(&m, &elastic);
    let ring = DoorRing::new(&m, &eq).unwrap();
    assert!(
        ring.note.contains("MP_TUB1") && ring.note.contains("MP_TUB2"),
        "{}",
        ring.note
    );
    let with_rows = ring.points.iter().filter(|p| p.at.modal.is_some()).count();
    assert_eq!(with_rows, 2);
    let tub = eq.modes(BodyRef::Tub).unwrap();
    let mut q = vec![0.0; eq.layout.n()];
    q[tub.start] = 1.0;
    let pt = tub.data().point("MP_TUB1").unwrap();
    let d = ring.points[0].displacement(&q);
    for c in 0..3 {
        assert!((d[c] - pt.w[c][0]).abs() < 1e-15, "{d:?}");
    }
}

/// Points on the front edges with made-up mode rows (deterministic), added to the drum's and
/// the tub's data as the plan's FE models will have them.
fn with_edge_points(m: &mut Model) {
    let mut seed = 0x9E3779B97F4A7C15u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for (body, prefix, x, r) in [
        ("drum", "DRUM_EDGE", 0.17, 0.24),
        ("tub", "TUB_RING", 0.17, 0.27),
    ] {
        let e = m.elastic.iter_mut().find(|e| e.name == body).unwrap();
        let d = e.data.as_mut().unwrap();
        let n = d.modes();
        for k in 0..8 {
            d.points.push(ModalPoint {
                name: format!("{prefix}_{k}"),
                position: ring_point(x, r, k),
                nodes: 12,
                w: std::array::from_fn(|_| (0..n).map(|_| 0.1 * rnd()).collect()),
                phi: std::array::from_fn(|_| vec![0.0; n]),
            });
        }
    }
}

#[test]
fn drum_tub_gap_closes_by_the_radial_relative_elastic_motion() {
    let mut m = reference();
    with_edge_points(&mut m);
    let scene = m.scene(Some("elastic")).unwrap();
    let eq = Equations::new(&m, &scene);
    let gap = DrumGap::new(&m, &eq).unwrap();
    // The clearance from the points' radii: 0.27 - 0.24.
    assert!((gap.clearance - 0.03).abs() < 1e-12, "{}", gap.clearance);
    let (tub, drum) = (
        eq.modes(BodyRef::Tub).unwrap(),
        &eq.elastic_drum().unwrap().modes,
    );
    let (td, dd) = (tub.data(), drum.data());
    let mount = [-0.25, 0.0, 0.45];
    let bearing = td.points.iter().find(|p| p.position == mount).unwrap();
    let row = |p: &ModalPoint, k: usize| v([p.w[0][k], p.w[1][k], p.w[2][k]]);
    let rot_row = |p: &ModalPoint, k: usize| v([p.phi[0][k], p.phi[1][k], p.phi[2][k]]);
    // The first drum eigenmode at 1 mm and the first tub eigenmode at 2 mm.
    let mut q = vec![0.0; eq.layout.n()];
    q[drum.start] = 1e-3;
    q[tub.start] = 2e-3;
    // At 45 degrees each drum edge point sits at the tub ring point one before it; at 22.5
    // degrees halfway between two (linear interpolation of the ring's motion).
    let mut worst: f64 = 0.0;
    for (phi, steps) in [
        (std::f64::consts::FRAC_PI_4, 1.0),
        (std::f64::consts::FRAC_PI_8, 0.5),
    ] {
        let rot = rot_x(phi);
        let mut expect = f64::NEG_INFINITY;
        for k in 0..8 {
            let edge = dd.point(&format!("DRUM_EDGE_{k}")).unwrap();
            let r = rot * (v(edge.position) - v(mount));
            let er = Vector3::new(0.0, r.y, r.z).normalize();
            let drum_d = rot * row(edge, 0) * 1e-3;
            let carried = (row(bearing, 0) + rot_row(bearing, 0).cross(&r)) * 2e-3;
            // The ring points at the edge point's angle: k - 1 (45 deg) or k - 1/2.
            let ring = |j: usize| row(td.point(&format!("TUB_RING_{}", (j + 8) % 8)).unwrap(), 0);
            let ring_d = if steps == 1.0 {
                ring(k + 7)
            } else {
                (ring(k + 7) + ring(k)) * 0.5
            } * 2e-3;
            expect = expect.max(er.dot(&(drum_d + carried - ring_d)));
        }
        let (got, _) = gap.closure(phi, &q);
        worst = worst.max((got - expect).abs() / expect.abs());
    }
    eprintln!("gap closure against the geometry: worst relative difference {worst:e}");
    // Measured 2.6e-16 relative.
    assert!(worst < 2e-15, "{worst:e}");

    // A rigid tub with the elastic drum: only the drum's deflection closes the gap.
    let scene = m.scene(Some("elastic_rigid_tub")).unwrap();
    let eq = Equations::new(&m, &scene);
    let gap = DrumGap::new(&m, &eq).unwrap();
    assert!(gap.mount.is_none() && gap.ring.is_empty());
}

#[test]
fn a_rigid_drum_on_an_elastic_tub_passes_the_checker_and_runs() {
    // The equations put the drum's FE mass on the elastic tub whether or not a scene makes the
    // drum elastic; the checker used to count it only when one did and refused this model
    // (FE tub 45.0 kg + motor 1.5 kg against the rigid tub's 55 kg).
    let src = std::fs::read_to_string(data_dir().join("reference.toml")).unwrap();
    let head = &src[..src.find("[[scenes]]").unwrap()];
    let text = format!(
        "{head}[[scenes]]\nname = \"tub_only\"\neffects = [\"gyroscopic\", \"unbalance.drum\", \
         \"friction_dampers\", \"gasket_damping\", \"element_geometry\", \"unbalance_inertia\", \
         \"elastic.tub\"]\nmax_order = 6.0\n"
    );
    let m = load_str(&text, "tub_only.toml", &data_dir()).unwrap_or_else(|e| panic!("{e}"));
    let scene = m.scene(Some("tub_only")).unwrap();
    let eq = Equations::new(&m, &scene);
    assert!(eq.modes(BodyRef::Tub).is_some() && eq.elastic_drum().is_none());
    let watch = Watch::new(&m, &eq);
    let mut sys = FirstOrder::new(Interpreter::new(&m, &scene));
    let dim = 2 * sys.layout().n();
    let mut solver = Dopri5::new(dim, Options::default());
    let mut sink = MemorySink::default();
    let guard = Guard {
        watch,
        ..Guard::default()
    };
    let opts = RunOptions {
        t_end: 0.2,
        start: Start::Static,
        ..RunOptions::default()
    };
    let s = run_guarded(
        &mut sys,
        &mut solver,
        &opts,
        &Labels::default(),
        (1e-6, 1e-9),
        &mut sink,
        &mut |_| {},
        &guard,
    )
    .unwrap_or_else(|(e, _)| panic!("{e}"));
    assert_eq!(s.status, washdyn_runtime::run::RunStatus::Ok);
    // The door ring is watched with the tub's modes at MP_TUB1 and MP_TUB2; the gap with the
    // rigid drum's edge (its points on the drum's axis frame, turned by the tub's motion at the
    // bearing) against the tub's TUB_RING_k points.
    let w = &s.validity.watched;
    assert!(w[0].contains("elastic tub: modes at 2"), "{w:?}");
    assert!(w[1].contains("rigid drum, elastic tub"), "{w:?}");
    assert!(s.validity.max_door_ring_m > 0.0 && s.validity.max_door_ring_m < 0.03);
    eprintln!("{:#?}", s.validity);
}
