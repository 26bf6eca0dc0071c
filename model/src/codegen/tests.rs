use super::*;
use crate::ir::Model;
use crate::speed::Speed;

fn reference() -> Model {
    crate::ir::toml_file::reference_for_tests()
}

#[test]
fn type_names() {
    assert_eq!(type_name("rigid_low_speed"), "RigidLowSpeed");
    assert_eq!(type_name("full"), "Full");
    assert_eq!(type_name("2x"), "Scene2x");
}

/// The traced graph, evaluated numerically, reproduces `Equations::eval` (same derivation,
/// so only round-off may differ) for random states and times.
#[test]
fn traced_graph_agrees_with_interpreter() {
    let m = reference();
    for scene in m.scene_names() {
        let eff = m.scene(Some(&scene)).unwrap();
        let eq = Equations::new(&m, &eff);
        let t = trace_equations(&eq);
        let speed = Speed::new(&m.speed.table);
        let n = t.n;
        let mut rng = 0x2545F4914F6CDD1Du64;
        let mut r = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..20 {
            let q: Vec<f64> = (0..n).map(|_| 0.01 * r()).collect();
            let qd: Vec<f64> = (0..n).map(|_| 0.1 * r()).collect();
            let time = 200.0 * (r() + 0.5);
            let d = speed.drive(time);
            let mut inputs = q.clone();
            inputs.extend(&qd);
            inputs.extend([d.phi, d.omega, d.omega_dot]);
            // The element states at their assembly value (what `eval` takes).
            inputs.extend(vec![0.0; t.nz]);
            let mut m1 = vec![0.0; t.n1 * t.n1];
            let mut h = vec![0.0; n];
            eq.eval(&d, &q, &qd, &mut m1, &mut h);
            let (g, sm1, sh) = &t.mh;
            let gm1 = g.eval(&inputs, sm1);
            let gh = g.eval(&inputs, sh);
            let scale = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for i in 0..n {
                assert!(
                    (gh[i] - h[i]).abs() <= 1e-12 * scale,
                    "h[{i}]: {} vs {}",
                    gh[i],
                    h[i]
                );
            }
            for i in 0..m1.len() {
                assert!((gm1[i] - m1[i]).abs() <= 1e-12 * m1[0].abs());
            }
        }
    }
}

/// Which numbers of the reference can be free: the generator proves each (`free.rs`) or
/// refuses it with its name. Printed with `--nocapture`.
#[test]
fn free_parameters_are_proven_or_refused() {
    let base = reference();
    let candidates = [
        "springs.spring_front.stiffness",
        "springs.spring_front.free_length",
        "friction_dampers.damper_front_left.f_max",
        "friction_dampers.damper_front_left.slope",
        "friction_dampers.damper_front_left.bearing_stiffness",
        "gaskets.door_gasket.stiffness[0][0]",
        "unbalances.test_mass.mass",
        "tub.mass",
    ];
    let mut ok = Vec::new();
    for c in candidates {
        let mut m = base.clone();
        m.free = vec![c.to_string()];
        match generate(&m) {
            Ok(src) => {
                assert!(src.contains("p[0]"), "{c}: free but never read");
                ok.push(c);
            }
            Err(e) => {
                println!("{c}: {e}");
                assert!(e.message.contains(c), "{e}");
                assert_eq!(e.path.to_string(), "free[0]");
            }
        }
    }
    println!("free: {ok:?}");
    // The force elements' own numbers enter the forces as they are.
    for c in &candidates[..3] {
        assert!(ok.contains(c), "{c}: {ok:?}");
    }
    // The tub's mass is in M1.
    assert!(!ok.contains(&"tub.mass"));
}

#[test]
fn generated_source_mentions_every_scene() {
    let m = reference();
    let (src, stats) = generate_with_stats(&m).unwrap();
    assert_eq!(stats.len(), 11);
    assert!(src.contains("pub struct Full") && src.contains("pub struct RigidLowSpeed"));
    assert!(
        src.contains("pub struct PanelCurves") && src.contains("pub struct CabinetCounterweights")
    );
    assert!(src.contains("pub struct Elastic") && src.contains("pub struct DamperMass"));
    assert!(src.contains("pub struct ElasticFine") && src.contains("pub struct Counterweights"));
    assert!(src.contains("pub struct Contact") && src.contains("f64::max("));
    // Leaving effects out shrinks the code.
    let ops = |scene: &str| {
        let st = stats.iter().find(|s| s.scene == scene).expect(scene);
        st.ops_accelerations
    };
    assert!(ops("rigid_low_speed") < ops("full"), "{stats:?}");
}
