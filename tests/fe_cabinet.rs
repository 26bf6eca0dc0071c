//! The cabinet on its feet: masses and attachments (no CalculiX), and with CalculiX its modes,
//! the feet's share of each mode's strain energy that the modal data carries (its
//! `support_springs`) against ccx's own spring energies (`*EL PRINT` ELSE), and the on-feet
//! modes against the rigid cabinet on the same feet (closed form) and the issue's >= 25 Hz. A
//! stiff block on four feet anchors the energy share at its closed form, 1. Without ccx the
//! CalculiX tests skip, except under CI (`CI=true`), where they fail.

use crate::common;
use common::have_ccx;

use std::f64::consts::PI;
use washdyn_fe::bodies::cabinet::Cabinet;
use washdyn_fe::lumping::{MassProps, consistent_mass_props, element_mass};
use washdyn_fe::mesh::{Mesh, Section};
use washdyn_fe::modal::Keep;
use washdyn_fe::pipeline::{BodySpec, build, support_springs};
use washdyn_model::ir::modal::{ElasticBodyKind, ModalData, Support, generalised_eigen};

fn cabinet_spec() -> BodySpec {
    washdyn_fe::bodies::builtin()
        .into_iter()
        .find(|b| b.name == "cabinet")
        .unwrap()
}

/// Mass of the point masses in part `name`.
fn point_masses(m: &Mesh, name: &str) -> f64 {
    let p = m.parts.iter().find(|p| p.name == name).unwrap();
    match p.section {
        Section::Mass { kg } => kg * p.elements.len() as f64,
        _ => panic!("{name}: not point masses"),
    }
}

#[test]
fn the_cabinet_carries_its_parts_and_the_dampers_sit_on_brackets() {
    let c = Cabinet::default();
    let spec = cabinet_spec();
    let m = &spec.mesh;
    let p = consistent_mass_props(m);
    eprintln!("cabinet: {p:?}");
    // The non-suspended mass, 20-30 kg: measured 28.94 kg, CoG (0.036, -0.002, 0.431).
    assert!(p.mass > 20.0 && p.mass < 30.0, "{p:?}");
    // Door 4 kg on the opening's edge (the gasket's node set), worktop 4 kg (its plate's
    // element integral), pump, boards and valves 2 kg: the parts as the issue gives them.
    let door: Vec<&washdyn_fe::mesh::Part> = m
        .parts
        .iter()
        .filter(|p| p.name.starts_with("CAB_DOOR"))
        .collect();
    let kg: f64 = door.iter().map(|p| point_masses(m, &p.name)).sum();
    assert!((kg - 4.0).abs() < 1e-12, "{kg}");
    let mut on: Vec<usize> = door
        .iter()
        .flat_map(|p| p.elements.iter().map(|e| e[0]))
        .collect();
    on.sort_unstable();
    assert_eq!(on, m.nsets["GASKET"]);
    // Evenly along the edge: the ring's centre of mass is the opening's centre.
    let ring = MassProps::of_points(door.iter().flat_map(|p| {
        let Section::Mass { kg } = p.section else {
            unreachable!()
        };
        p.elements.iter().map(move |e| (kg, m.nodes[e[0] - 1]))
    }));
    assert!(
        ring.cog[1].abs() < 1e-12 && (ring.cog[2] - c.door_z).abs() < 1e-12,
        "{ring:?}"
    );
    let mut top = m.clone();
    top.parts.retain(|p| p.name == "CAB_TOP");
    assert!(
        (element_mass(&top) - 4.0).abs() < 1e-9,
        "{}",
        element_mass(&top)
    );
    let carried: f64 = ["CAB_PUMP", "CAB_BOARD", "CAB_VALVES", "CAB_PANEL"]
        .iter()
        .map(|n| point_masses(m, n))
        .sum();
    assert!((carried - 2.0).abs() < 1e-12);
    // The dampers' cabinet ends: a node at each of the plan's points, read with rail nodes
    // (not collinear: the rigid fit gives a rotation too); the old middle pair is gone.
    let expect = [
        [0.18, 0.27, 0.03],
        [0.18, -0.27, 0.03],
        [-0.18, 0.27, 0.03],
        [-0.18, -0.27, 0.03],
    ];
    for (k, x) in expect.iter().enumerate() {
        let name = format!("DAMPER_{}", k + 1);
        let (_, at) = spec.points.iter().find(|(s, _)| *s == name).unwrap();
        assert_eq!(at, x);
        let ids = &m.nsets[&name];
        assert!(ids.iter().any(|&i| m.nodes[i - 1] == *x), "{name}");
        assert!(ids.iter().any(|&i| m.nodes[i - 1][0] != x[0]), "{name}");
        assert!(ids.len() >= 3, "{name}: {ids:?}");
    }
    assert!(spec.points.iter().all(|(_, p)| p[0] != 0.0 || p[2] > 0.1));
    // The feet: the modal data's support springs, at one-node points.
    let points: Vec<(&str, [f64; 3])> = spec.points.iter().map(|(s, p)| (s.as_str(), *p)).collect();
    let feet = support_springs(m, &points).unwrap();
    assert_eq!(feet.len(), 4);
    for (k, f) in feet.iter().enumerate() {
        assert_eq!(f.point, format!("FOOT_{}", k + 1));
        assert_eq!(f.stiffness, [c.k_horizontal, c.k_horizontal, c.k_vertical]);
        assert_eq!(f.stiffness, [4e5, 4e5, 2e6]);
    }
    // All or none: without foot points no springs are recorded; with some, the rest is an error.
    let no_feet: Vec<(&str, [f64; 3])> = points
        .iter()
        .copied()
        .filter(|(s, _)| !s.starts_with("FOOT"))
        .collect();
    assert!(support_springs(m, &no_feet).unwrap().is_empty());
    let one_foot: Vec<(&str, [f64; 3])> = points
        .iter()
        .copied()
        .filter(|(s, _)| !s.starts_with("FOOT") || *s == "FOOT_1")
        .collect();
    let e = support_springs(m, &one_foot).unwrap_err();
    assert!(
        matches!(e, washdyn_fe::error::PipelineError::LoneSpring { .. }),
        "{e}"
    );
    assert!(e.to_string().contains("at no one-node point"), "{e}");
}

/// Per mode of a ccx `.dat`: the spring elements' energy in sets starting with `springs`, and
/// the whole model's (EALL totals).
fn energies(dat: &str, springs: &str) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut lines = dat.lines().peekable();
    while let Some(l) = lines.next() {
        if l.contains("E I G E N V A L U E    N U M B E R") {
            out.push((0.0, 0.0));
        } else if l.contains("internal energy (element, energy) for set")
            && l.split_whitespace()
                .nth(6)
                .is_some_and(|s| s.starts_with(springs))
        {
            lines.next();
            while let Some(r) = lines.next_if(|r| !r.trim().is_empty()) {
                let v: f64 = r.split_whitespace().nth(1).unwrap().parse().unwrap();
                out.last_mut().unwrap().0 += v;
            }
        } else if l.contains("total internal energy for set EALL") {
            lines.next();
            let v = lines.next().unwrap().trim().parse().unwrap();
            out.last_mut().unwrap().1 = v;
        }
    }
    out
}

/// ccx's modes of `mesh` with the energies of the springs in the sets named `springs*`.
fn spring_energies(
    mesh: &Mesh,
    modes: usize,
    dir: &std::path::Path,
) -> (Vec<f64>, Vec<(f64, f64)>) {
    let mut d = mesh.model_deck();
    d.line("*STEP").line("*FREQUENCY").line(&modes.to_string());
    for p in mesh
        .parts
        .iter()
        .filter(|p| matches!(p.section, Section::Ground { .. }))
    {
        d.line(&format!("*EL PRINT, ELSET={}", p.name)).line("ELSE");
    }
    d.line("*EL PRINT, ELSET=EALL, TOTALS=ONLY")
        .line("ELSE")
        .line("*END STEP");
    let p = dir.join("energy.inp");
    std::fs::write(&p, d.text()).unwrap();
    let run = washdyn_fe::ccx::run(&p).unwrap_or_else(|e| panic!("{e}"));
    let dat = std::fs::read_to_string(run.dat()).unwrap();
    let springs = mesh
        .parts
        .iter()
        .find(|p| matches!(p.section, Section::Ground { .. }))
        .unwrap()
        .name
        .clone();
    // The ground springs' parts share a prefix (CAB_FOOT_X, _Y, _Z; FOOT_X ...).
    let prefix = springs.trim_end_matches(|c: char| c != '_').to_string();
    (washdyn_fe::ccx::frequencies(&dat), energies(&dat, &prefix))
}

/// Frequencies (Hz) of `body` as a rigid body on `springs` (point, stiffness per direction):
/// M = diag(m E, I_cog), K = sum T^T diag(k) T with T = [E, -(r - cog)~].
fn rigid_on_springs(body: &MassProps, springs: &[([f64; 3], [f64; 3])]) -> Vec<f64> {
    let mut m = nalgebra::DMatrix::zeros(6, 6);
    for i in 0..3 {
        m[(i, i)] = body.mass;
        for j in 0..3 {
            m[(3 + i, 3 + j)] = body.inertia[i][j];
        }
    }
    let mut k = nalgebra::DMatrix::zeros(6, 6);
    for (r, ks) in springs {
        let a: Vec<f64> = (0..3).map(|i| r[i] - body.cog[i]).collect();
        let skew = nalgebra::Matrix3::new(0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0);
        let mut t = nalgebra::DMatrix::zeros(3, 6);
        for i in 0..3 {
            t[(i, i)] = 1.0;
            for j in 0..3 {
                t[(i, 3 + j)] = -skew[(i, j)];
            }
        }
        let d = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(ks));
        k += t.transpose() * d * t;
    }
    let (_, lambda) = generalised_eigen(&m, &k);
    lambda.iter().map(|l| l.sqrt() / (2.0 * PI)).collect()
}

/// The modal data's foot share of every eigenmode against ccx's spring energies; returns the
/// data and the shares.
fn shares_against_ccx(spec: &BodySpec, dir: &std::path::Path) -> (ModalData, Vec<f64>) {
    let (data, _) = build(spec, dir).unwrap();
    assert_eq!(data.support_springs.len(), 4);
    let e = data.support_energy();
    let (freq, en) = spring_energies(&spec.mesh, spec.solve_modes, dir);
    let mut worst = 0.0f64;
    for k in 0..data.eigenmodes() {
        // The same solve: the same frequencies (the .frd's 10 digits against the .dat's 7).
        assert!((freq[k] - data.frequencies[k]).abs() < 1e-6 * freq[k]);
        let (springs, total) = en[k];
        // ccx's total is omega^2 / 2 (mass-normalised modes): measured to its 7 digits.
        let w2 = (2.0 * PI * freq[k]).powi(2);
        assert!((total / (0.5 * w2) - 1.0).abs() < 1e-5, "{k}: {total} {w2}");
        // The share from the shapes at the foot points against ccx's energies, to the .frd's
        // 6 digits: measured up to 1.8e-6 (cabinet), 1.6e-6 (block).
        let d = (e[k] - springs / total).abs();
        assert!(d < 2e-5, "{k}: {} vs {}", e[k], springs / total);
        worst = worst.max(d);
    }
    eprintln!(
        "{}: foot share against ccx's energies: worst {worst:.1e}",
        spec.name
    );
    (data, e)
}

#[test]
fn a_stiff_block_on_four_feet_puts_all_its_strain_energy_in_them() {
    // Closed form: a rigid body on springs stores all its strain energy in them (e = 1), at
    // the frequencies of the rigid body on those springs. A 0.3 m steel cube (2 x 2 x 2 C3D20,
    // its elastic modes in the kHz) on feet of 0.5-2e5 N/m (rigid modes at 4-15 Hz): its own
    // strain energy is of order (f / f_elastic)^2, 1e-4.
    if !have_ccx() {
        return;
    }
    let mut m = Mesh::new("stiff block on feet");
    let steel = washdyn_fe::bodies::drum::steel();
    washdyn_fe::bodies::geometry::brick_grid(
        &mut m,
        "BLOCK",
        &Section::Solid { material: steel },
        [2, 2, 2],
        false,
        |u, v, w| [0.3 * u - 0.15, 0.3 * v - 0.15, 0.3 * w],
    );
    let ks = [1e5, 0.5e5, 2e5];
    let mut points = Vec::new();
    let mut feet = Vec::new();
    for (k, (x, y)) in [(0.15, 0.15), (0.15, -0.15), (-0.15, 0.15), (-0.15, -0.15)]
        .iter()
        .enumerate()
    {
        let p = [*x, *y, 0.0];
        let id = m.nearest(p, None);
        assert_eq!(m.nodes[id - 1], p);
        m.add_to_set(&format!("FOOT_{}", k + 1), &[id]);
        points.push((format!("FOOT_{}", k + 1), p));
        feet.push((p, ks));
    }
    let ids: Vec<usize> = points.iter().map(|(s, _)| m.nsets[s][0]).collect();
    for (dof, name) in [(1, "FOOT_X"), (2, "FOOT_Y"), (3, "FOOT_Z")] {
        m.part(
            name,
            Section::Ground {
                dof,
                k: ks[dof - 1],
            },
        )
        .elements = ids.iter().map(|&i| vec![i]).collect();
    }
    let spec = BodySpec {
        name: "block".into(),
        kind: ElasticBodyKind::Cabinet,
        support: Support::OnSprings,
        mesh: m.clone(),
        solve_modes: 6,
        keep: Keep {
            rigid_below_hz: 0.0,
            max_hz: f64::INFINITY,
            max_modes: 6,
        },
        points,
        spin: None,
        correction: Vec::new(),
        correction_order: 1,
        recovery: false,
    };
    let dir = tempfile::tempdir().unwrap();
    let (data, e) = shares_against_ccx(&spec, dir.path());
    let rigid = rigid_on_springs(&consistent_mass_props(&m), &feet);
    eprintln!(
        "block: {:?} Hz, e {e:?}; rigid {rigid:?} Hz",
        data.frequencies
    );
    for k in 0..6 {
        // Measured: 1 - e up to 9.3e-5, frequencies up to 5.7e-5 below the rigid body's
        // (Rayleigh: about half the energy deficit).
        assert!((1.0 - e[k]).abs() < 3e-4, "{k}: {e:?}");
        assert!((data.frequencies[k] / rigid[k] - 1.0).abs() < 2e-4, "{k}");
    }
}

#[test]
fn cabinet_modes_and_foot_energy_match_calculix() {
    if !have_ccx() {
        return;
    }
    // The built-in cabinet's eigenmodes (no correction modes, no field: the shares of ccx's
    // modes are what is compared), 30 of them (to about 88 Hz).
    let mut spec = cabinet_spec();
    spec.correction = Vec::new();
    spec.recovery = false;
    spec.solve_modes = 30;
    spec.keep.max_modes = 30;
    let dir = tempfile::tempdir().unwrap();
    let (data, e) = shares_against_ccx(&spec, dir.path());
    let mass = consistent_mass_props(&spec.mesh);
    let c = Cabinet::default();
    let feet: Vec<([f64; 3], [f64; 3])> = (1..=4)
        .map(|k| {
            let id = spec.mesh.nsets[&format!("FOOT_{k}")][0];
            (
                spec.mesh.nodes[id - 1],
                [c.k_horizontal, c.k_horizontal, c.k_vertical],
            )
        })
        .collect();
    let rigid = rigid_on_springs(&mass, &feet);
    eprintln!("rigid cabinet on its feet: {rigid:.2?} Hz");
    eprintln!(" mode      Hz   foot share");
    for (k, f) in data
        .frequencies
        .iter()
        .enumerate()
        .take_while(|(_, f)| **f < 60.0)
    {
        eprintln!("{:5} {f:7.2} {:10.3}", k + 1, e[k]);
    }
    // On-feet modes: more than half of the strain energy in the feet. Measured: sway in y
    // 26.40 Hz (e 0.79) and x 27.37 Hz (0.84), yaw 43.56 Hz (0.85), bounce with pitch 82.45 Hz
    // (0.79); roll and pitch otherwise spread over modes at 62-86 Hz (e 0.2-0.49). The rigid
    // cabinet on the same feet (closed form) sways at 29.20 / 29.27 Hz: the body (mostly the
    // front panel beside the door opening) takes the rest, so each elastic on-feet mode lies
    // below (Rayleigh) and within 15 % of its rigid counterpart (26.40 / 29.20 = 0.90).
    let on_feet: Vec<(f64, f64)> = (0..data.eigenmodes())
        .filter(|&k| e[k] > 0.5)
        .map(|k| (data.frequencies[k], e[k]))
        .collect();
    eprintln!("on-feet modes (Hz, share): {on_feet:.3?}");
    assert!(on_feet.len() >= 3, "{on_feet:?}");
    let (sway, _) = on_feet[0];
    assert!(
        sway <= rigid[0] && sway > 0.85 * rigid[0],
        "{sway} vs {rigid:?}"
    );
    assert!(on_feet[1].0 < rigid[1], "{on_feet:?} vs {rigid:?}");
    // Issue 19: the cabinet's on-feet modes >= 25 Hz. Measured: the lowest, the y sway, at
    // 26.40 Hz, and it is the cabinet's first mode (no panel mode below it).
    assert!(on_feet.iter().all(|(f, _)| *f >= 25.0), "{on_feet:?}");
    assert_eq!(data.frequencies[0], sway);
    assert!(sway < 30.0, "{on_feet:?}");
    // Panel modes ride on the feet hardly at all: the first (48.40 Hz, front and back) stores
    // 2.9 % there, the least below 60 Hz (50.08 Hz, the sides) 1.3 %.
    let panel = (0..data.eigenmodes())
        .filter(|&k| data.frequencies[k] < 60.0)
        .map(|k| e[k])
        .fold(1.0f64, f64::min);
    assert!(panel < 0.05, "{e:?}");
}
