//! Tests of the modal data: the rules name their fields, TOML round trips, truncation and its
//! folded correction modes, moment load cases. `tiny` is a small valid body other tests use.

use super::*;

/// Two unit-mass nodes, two modes: a small, valid body.
pub fn tiny() -> ModalData {
    let id = vec![1.0, 0.0, 0.0, 1.0];
    let z = vec![0.0; 4];
    ModalData {
        body: ElasticBodyKind::Cabinet,
        support: Support::OnSprings,
        source: "test".into(),
        frequencies: vec![10.0, 20.0],
        mass: 2.0,
        cog: [0.0; 3],
        inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        elementary: Elementary {
            c: [vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]],
            s: std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; 2])),
            g: [
                [z.clone(), z.clone(), z.clone()],
                [z.clone(), z.clone(), z.clone()],
                [z.clone(), z.clone(), id],
            ],
        },
        points: vec![ModalPoint {
            name: "FOOT_1".into(),
            position: [0.0; 3],
            nodes: 1,
            w: [vec![0.0; 2], vec![0.0; 2], vec![1.0, 0.0]],
            phi: [vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]],
        }],
        geometric_stiffness: None,
        correction: None,
        basis: None,
        file_modes: None,
        support_springs: Vec::new(),
    }
}

#[test]
fn a_valid_body_has_no_problems_and_round_trips_through_toml() {
    let d = tiny();
    assert_eq!(problems(&d), Vec::<String>::new());
    let back: ModalData = toml::from_str(&d.to_toml()).unwrap();
    assert_eq!(back, d);
}

#[test]
fn each_rule_names_its_field() {
    let mut d = tiny();
    d.elementary.g[2][2].pop();
    d.frequencies[0] = -1.0;
    d.points[0].w[1].push(0.0);
    let p = problems(&d);
    assert!(
        p.iter()
            .any(|m| m.starts_with("elementary.g[z][z]: expected 4"))
    );
    assert!(
        p.iter()
            .any(|m| m.starts_with("frequencies[0]: must be positive"))
    );
    assert!(p.iter().any(|m| m.starts_with("points[0] (FOOT_1).w[y]")));
    // Each block's diagonal is within [0, 1.05]; their sum is the modal mass.
    let mut d = tiny();
    d.elementary.g[2][2][3] = 1.2;
    let p = problems(&d);
    assert_eq!(p.len(), 1);
    assert!(p[0].starts_with("elementary.g[z][z][3]: 1.2e0"), "{p:?}");
    let mut d = tiny();
    d.elementary.g[0][0][3] = 0.5;
    let p = problems(&d);
    assert_eq!(p.len(), 1);
    assert!(p[0].contains("not mass-normalised"), "{p:?}");
}

#[test]
fn gram_identities_and_magnitudes_name_their_field() {
    type Case = (fn(&mut ModalData), &'static str);
    let cases: Vec<Case> = vec![
        (
            |d| d.elementary.g[0][2][1] = 0.5,
            "elementary.g[x][z][1]: 5e-1 exceeds",
        ),
        (
            |d| d.elementary.g[2][2][1] = 0.5,
            "elementary.g[z][z][1]: 5e-1, but",
        ),
        (|d| d.elementary.c[2][0] = 2.0, "elementary.c[z][0]"),
        (|d| d.elementary.s[0][2][0] = 1e3, "elementary.s[x][z][0]"),
        (|d| d.points[0].w[2][0] = 1e4, "points[0] (FOOT_1).w[z]"),
        (
            |d| d.points[0].phi[0][0] = 1.0,
            "points[0] (FOOT_1).phi: a set of 1",
        ),
        (|d| d.mass = 1e5, "mass: must be positive, within"),
        (
            |d| d.cog = [f64::NAN; 3],
            "cog: [NaN, NaN, NaN] must be finite",
        ),
        (|d| d.inertia[1][1] = 5.0, "inertia: principal moments"),
        (
            |d| d.support = Support::Clamped,
            "support: Clamped for the Cabinet",
        ),
        (
            |d| d.basis = Some(vec![1.0, 0.0, 0.0, 1.5]),
            "basis[3]: 1.5",
        ),
    ];
    for (f, want) in cases {
        let mut d = tiny();
        f(&mut d);
        let p = problems(&d);
        assert!(p.iter().any(|m| m.starts_with(want)), "{want}: {p:?}");
    }
}

#[test]
fn truncation_keeps_the_leading_block() {
    let mut d = tiny();
    d.elementary.g[2][2] = vec![1.0, 0.1, 0.2, 1.0];
    d.truncate(1, &[]);
    assert_eq!(d.elementary.g[2][2], vec![1.0]);
    assert_eq!(d.points[0].w[2], vec![1.0]);
    assert_eq!(problems(&d), Vec::<String>::new());
}

/// A body of 6 modes whose last is a correction mode, with one load case at point P.
fn with_correction() -> ModalData {
    let n = 6;
    let mut d = tiny();
    let f = vec![5.0, 8.0, 13.0, 21.0, 34.0, 80.0];
    let eye: Vec<f64> = (0..n * n)
        .map(|i| if i / n == i % n { 1.0 } else { 0.0 })
        .collect();
    d.frequencies = f;
    d.elementary = Elementary {
        c: std::array::from_fn(|_| vec![0.0; n]),
        s: std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; n])),
        g: std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                if a == 2 && b == 2 {
                    eye.clone()
                } else {
                    vec![0.0; n * n]
                }
            })
        }),
    };
    let wz = vec![0.3, -0.2, 0.5, 0.1, -0.4, 0.7];
    let wy = vec![0.1, 0.2, -0.1, 0.3, 0.2, -0.2];
    d.points = vec![ModalPoint {
        name: "P".into(),
        position: [0.0; 3],
        nodes: 4,
        w: [vec![0.0; n], wy, wz.clone()],
        phi: std::array::from_fn(|_| vec![0.0; n]),
    }];
    d.correction = Some(Correction {
        loads: vec![LoadCase::force("P", [0.0, 0.0, 1.0])],
        modes: 1,
        participation: wz[..5].to_vec(),
    });
    d
}

/// Static displacement at P along `a` under a unit force along `b` there:
/// sum w_a w_b / omega^2.
fn static_at_p(d: &ModalData, a: usize, b: usize) -> f64 {
    let p = &d.points[0];
    (0..d.modes())
        .map(|k| p.w[a][k] * p.w[b][k] / (2.0 * std::f64::consts::PI * d.frequencies[k]).powi(2))
        .sum()
}

#[test]
fn truncation_folds_the_dropped_modes_static_share_at_the_load_points() {
    let full = with_correction();
    assert_eq!(problems(&full), Vec::<String>::new());
    let mut d = full.clone();
    d.truncate(2, &[]);
    // 2 eigenmodes and 2 folded shapes (one load case, `FOLD_BLOCKS` Krylov blocks) of the
    // dropped modes and the correction mode.
    assert_eq!(FOLD_BLOCKS, 2);
    assert_eq!(d.modes(), 4);
    assert_eq!(d.eigenmodes(), 2);
    // The file's modes in the new ones: 6 x 4, the kept eigenmodes map to themselves; the
    // folded columns live on the dropped modes 3-5 and the correction mode 6.
    let t = d.basis.clone().unwrap();
    assert_eq!(t.len(), 24);
    assert_eq!((t[0], t[5]), (1.0, 1.0));
    for c in [2, 3] {
        assert!((0..6).all(|r| (r >= 2) == (t[r * 4 + c] != 0.0)));
    }
    assert_eq!(problems(&d), Vec::<String>::new());
    // The folded shapes are combinations of modes 3-6, so their frequencies lie among theirs.
    assert!(
        d.frequencies[2] > 13.0 && d.frequencies[3] < 80.0,
        "{:?}",
        d.frequencies
    );
    // Modal mass stays the identity, and the static response along the load is the full
    // model's to round-off (the closed form: the same sum over all modes).
    assert!(d.mass_normalisation_error() < 1e-12);
    for a in [1, 2] {
        let (x, y) = (static_at_p(&full, a, 2), static_at_p(&d, a, 2));
        assert!((x - y).abs() < 1e-12 * x.abs(), "{a}: {x} {y}");
    }
    // The second block keeps the receptance's next term too: H(omega) = sum w^2 / omega_k^2
    // + omega^2 sum w^2 / omega_k^4 + ...; the closed form's second sum to round-off.
    let second = |d: &ModalData| -> f64 {
        let p = &d.points[0];
        (0..d.modes())
            .map(|k| p.w[2][k].powi(2) / (2.0 * std::f64::consts::PI * d.frequencies[k]).powi(4))
            .sum()
    };
    let (x, y) = (second(&full), second(&d));
    assert!((x - y).abs() < 1e-12 * x, "{x} {y}");
    let a = static_at_p(&full, 2, 2);
    // Plain truncation would have lost modes 3-5's share.
    let mut plain = full.clone();
    plain.correction = None;
    plain.truncate(2, &[]);
    assert!((static_at_p(&plain, 2, 2) - a).abs() > 0.05 * a.abs());
    // A force along y is no load case: its response is not held (the fold is for the listed
    // loads only).
    let yy = static_at_p(&full, 1, 1);
    assert!((static_at_p(&d, 1, 1) - yy).abs() > 1e-3 * yy.abs());
}

#[test]
fn moment_load_cases_read_old_files_and_fold_through_phi() {
    // The serde form: files without `kind` hold forces (and write back without it); a
    // moment says `kind = "moment"`.
    let force: LoadCase = toml::from_str("point = \"P\"\ndirection = [0.0, 0.0, 1.0]").unwrap();
    assert_eq!(force, LoadCase::force("P", [0.0, 0.0, 1.0]));
    assert!(!toml::to_string(&force).unwrap().contains("kind"));
    let moment = LoadCase::moment("P", [1.0, 0.0, 0.0]);
    let text = toml::to_string(&moment).unwrap();
    assert!(text.contains("kind = \"moment\""), "{text}");
    assert_eq!(toml::from_str::<LoadCase>(&text).unwrap(), moment);

    // A moment about x at P, whose rotation phi_x per mode is `tx`: the participation is
    // phi . direction, and truncation folds the dropped modes' static rotation at P.
    let mut full = with_correction();
    let tx = vec![0.2, 0.1, -0.3, 0.25, 0.15, -0.1];
    full.points[0].phi[0] = tx.clone();
    let c = full.correction.as_mut().unwrap();
    c.loads.push(moment);
    c.participation = (0..5)
        .flat_map(|k| [full.points[0].w[2][k], tx[k]])
        .collect();
    assert_eq!(problems(&full), Vec::<String>::new());
    let rot = |d: &ModalData| -> f64 {
        let p = &d.points[0];
        (0..d.modes())
            .map(|k| p.phi[0][k].powi(2) / (2.0 * std::f64::consts::PI * d.frequencies[k]).powi(2))
            .sum()
    };
    let mut d = full.clone();
    d.truncate(2, &[]);
    // 2 eigenmodes and 4 folded shapes (two load cases, two blocks each).
    assert_eq!(d.modes(), 6);
    assert!((rot(&d) - rot(&full)).abs() < 1e-12 * rot(&full));
    assert_eq!(problems(&d), Vec::<String>::new());

    // Checker rules: a moment at a point without rotation, a participation that is not
    // the point's, a direction that is no unit vector.
    let mut bad = full.clone();
    bad.points[0].nodes = 2;
    let c = bad.correction.as_mut().unwrap();
    c.loads[1].kind = LoadKind::Force;
    c.loads[0].direction = [0.0, 0.0, 2.0];
    let p = problems(&bad);
    assert!(
        p.iter()
            .any(|m| m.starts_with("correction.participation (load 1)")),
        "{p:?}"
    );
    assert!(
        p.iter()
            .any(|m| m.starts_with("correction.loads[0].direction")),
        "{p:?}"
    );
    bad.correction.as_mut().unwrap().loads[1].kind = LoadKind::Moment;
    let p = problems(&bad);
    assert!(p.iter().any(|m| m.contains("give no rotation")), "{p:?}");
}

/// `elementary.g` may be left out where no equation reads it (the cabinet: 35 of 36 MB at 406
/// modes), not on the spinning drum; the file round-trips with it empty or absent and
/// truncation keeps it out.
#[test]
fn g_may_be_left_out_of_a_cabinet_not_of_a_drum() {
    let mut d = tiny();
    d.elementary.g = Default::default();
    assert_eq!(problems(&d), Vec::<String>::new());
    let text = d.to_toml();
    let back: ModalData = toml::from_str(&text).unwrap();
    assert_eq!(back, d);
    let without = text.replace("g = [[[], [], []], [[], [], []], [[], [], []]]\n", "");
    assert_ne!(without, text, "{text}");
    let back: ModalData = toml::from_str(&without).unwrap();
    assert_eq!(back, d);
    let mut cut = d.clone();
    cut.truncate(1, &[]);
    assert!(!cut.elementary.has_g());
    d.body = ElasticBodyKind::Drum;
    d.support = Support::Clamped;
    assert!(
        problems(&d)
            .iter()
            .any(|m| m.starts_with("elementary.g: missing")),
        "{:?}",
        problems(&d)
    );
}
