//! Helpers shared by the integration tests: hand-assembled linear models built from the IR
//! alone, independent of the derivation under test.
#![allow(dead_code)]

pub mod builtin;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use washdyn_model::ir::{BodyRef, Model};

pub fn skew(s: Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -s.z, s.y, s.z, 0.0, -s.x, -s.y, s.x, 0.0)
}

pub fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// T = [I, -s~] maps the tub's (u, alpha) to the displacement of a point at lever s.
pub fn t_point(s: Vector3<f64>) -> DMatrix<f64> {
    let mut t = DMatrix::zeros(3, 6);
    t.view_mut((0, 0), (3, 3)).copy_from(&Matrix3::identity());
    t.view_mut((0, 3), (3, 3)).copy_from(&(-skew(s)));
    t
}

/// Rigid mass matrix about the tub CoG from the IR.
pub fn mass_hand(m: &Model) -> DMatrix<f64> {
    let mut mm = DMatrix::zeros(6, 6);
    for i in 0..3 {
        mm[(i, i)] = m.tub.mass;
        for j in 0..3 {
            mm[(3 + i, 3 + j)] = m.tub.inertia[i][j];
        }
    }
    mm
}

/// Stiffness about rest, assembled by hand from the potential energy: per spring T^T k T with
/// k = k n n^T + (P / L)(I - n n^T) (axial stiffness plus the preload's lateral stiffness), the
/// preload's load stiffness from turning its lever arm, (s.F) I - sym(F s^T) (second-order term
/// of the finite rotation, Hessian of -F.r), and the gasket's T^T K T with T = [[I, -s~], [0, I]].
pub fn stiffness_hand(m: &Model) -> DMatrix<f64> {
    let p0 = v3(m.tub.cog);
    let mut k = DMatrix::zeros(6, 6);
    for s in &m.springs {
        assert_eq!(s.a.body, BodyRef::Tub);
        let d = v3(s.b.point) - v3(s.a.point);
        let l = d.norm();
        let n = d / l;
        let p = s.stiffness * (l - s.free_length);
        let ks =
            s.stiffness * n * n.transpose() + (p / l) * (Matrix3::identity() - n * n.transpose());
        let lever = v3(s.a.point) - p0;
        let t = t_point(lever);
        let ks = DMatrix::from_iterator(3, 3, ks.iter().cloned());
        k += t.transpose() * ks * &t;
        let f = p * n;
        let load = lever.dot(&f) * Matrix3::identity()
            - 0.5 * (f * lever.transpose() + lever * f.transpose());
        for i in 0..3 {
            for j in 0..3 {
                k[(3 + i, 3 + j)] += load[(i, j)];
            }
        }
    }
    for g in &m.gaskets {
        k += gasket_hand(m, g, &g.stiffness);
    }
    k
}

pub fn gasket_hand(m: &Model, g: &washdyn_model::ir::Gasket, mat: &[[f64; 6]; 6]) -> DMatrix<f64> {
    assert_eq!(g.a, BodyRef::Tub);
    let lever = v3(g.point) - v3(m.tub.cog);
    let mut t = DMatrix::identity(6, 6);
    t.view_mut((0, 3), (3, 3)).copy_from(&(-skew(lever)));
    let kg = DMatrix::from_fn(6, 6, |i, j| mat[i][j]);
    t.transpose() * kg * t
}

/// Viscous damping by hand at drum speed `omega` (rad/s): linear dampers T^T c n n^T T and the
/// gasket's T^T D T, D its viscous matrix plus its hysteretic part's time-domain equivalent
/// S K S / max(|omega|, 2 pi) (ir::Gasket::hysteretic_damping, written out here: eta K for one
/// loss factor).
pub fn damping_hand(m: &Model, omega: f64) -> DMatrix<f64> {
    let p0 = v3(m.tub.cog);
    let mut c = DMatrix::zeros(6, 6);
    for d in &m.dampers {
        let n = (v3(d.b.point) - v3(d.a.point)).normalize();
        let t = t_point(v3(d.a.point) - p0);
        let cn = DMatrix::from_iterator(3, 3, (d.damping * n * n.transpose()).iter().cloned());
        c += t.transpose() * cn * &t;
    }
    for g in &m.gaskets {
        let eta = g
            .loss_factor
            .as_ref()
            .map_or([0.0; 6], |l| l.per_direction());
        let reference = omega.abs().max(2.0 * std::f64::consts::PI);
        let d: [[f64; 6]; 6] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                g.damping[i][j] + (eta[i] * eta[j]).sqrt() * g.stiffness[i][j] / reference
            })
        });
        c += gasket_hand(m, g, &d);
    }
    c
}

/// Natural frequencies (Hz, ascending) of M q'' + K q = 0 for symmetric K and SPD M.
pub fn frequencies(mm: &DMatrix<f64>, k: &DMatrix<f64>) -> Vec<f64> {
    let l = mm.clone().cholesky().expect("M SPD").l();
    let li = l.try_inverse().unwrap();
    let a = &li * k * li.transpose();
    let a = 0.5 * (&a + a.transpose());
    let mut ev: Vec<f64> = a
        .symmetric_eigenvalues()
        .iter()
        .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    ev.sort_by(|a, b| a.total_cmp(b));
    ev
}

pub fn dvec(v: &[f64]) -> DVector<f64> {
    DVector::from_column_slice(v)
}

/// Whether an external tool a test needs is there (`ok`). Without it the test skips with a
/// message, except under CI (`CI=true`), where it fails: `.ci/run` installs it (`install`).
pub fn required_tool(ok: bool, what: &str, install: &str) -> bool {
    if !ok {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must install {what} ({install}) for this test"
        );
        eprintln!("skipped: {what} not found ({install})");
    }
    ok
}

/// Whether python3 imports `modules` (`import pyuff, pyarrow`): `required_tool` for the
/// independent references from PyPI.
pub fn python_modules(modules: &str) -> bool {
    let ok = std::process::Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .status()
        .is_ok_and(|s| s.success());
    required_tool(
        ok,
        &format!("python3 with {modules}"),
        &format!("python3 -m pip install {}", modules.replace(',', "")),
    )
}

/// The built `washdyn` run with `args` in `dir`, as a user would from there.
pub fn washdyn_in(args: &[&str], dir: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_washdyn"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// Whether ccx can run (`required_tool` for CalculiX).
pub fn have_ccx() -> bool {
    required_tool(
        washdyn_fe::ccx::available(),
        "CalculiX",
        "apt-get install calculix-ccx",
    )
}

/// A scene linearised about a rest point q0 (q' = 0): M = blockdiag(M1, E), C = -dh/dq',
/// K = -dh/dq, and h at q0.
pub struct Linearised {
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub k: DMatrix<f64>,
    pub h0: Vec<f64>,
}

/// The tests' own linearisation, the one difference path they keep: central differences of
/// the interpreter's h with step `eps` about q0 (q' = 0) at drive `d`, independent of the
/// production one (`washdyn_runtime::linearise`, the exact force Jacobians) that
/// tests/jacobians.rs holds it to. Its error: truncation eps^2 h''' / 6 and round-off
/// ~ 1e-16 |h| / eps.
pub fn differences(
    eq: &washdyn_model::equations::Equations,
    d: &washdyn_model::equations::Drive<f64>,
    q0: &[f64],
    eps: f64,
) -> Linearised {
    let (n, n1) = (eq.layout.n(), eq.layout.n1);
    let z = vec![0.0; n];
    let mut m1 = vec![0.0; n1 * n1];
    let mut h0 = vec![0.0; n];
    eq.eval(d, q0, &z, &mut m1, &mut h0);
    let mut m = DMatrix::<f64>::identity(n, n);
    for i in 0..n1 {
        for j in 0..n1 {
            m[(i, j)] = m1[i * n1 + j];
        }
    }
    let mut k = DMatrix::zeros(n, n);
    let mut c = DMatrix::zeros(n, n);
    for j in 0..n {
        for (mat, vel) in [(&mut k, false), (&mut c, true)] {
            let base = if vel { &z[..] } else { q0 };
            let (mut p, mut q) = (base.to_vec(), base.to_vec());
            p[j] = base[j] + eps;
            q[j] = base[j] - eps;
            let (mut hp, mut hm) = (vec![0.0; n], vec![0.0; n]);
            if vel {
                eq.eval(d, q0, &p, &mut m1, &mut hp);
                eq.eval(d, q0, &q, &mut m1, &mut hm);
            } else {
                eq.eval(d, &p, &z, &mut m1, &mut hp);
                eq.eval(d, &q, &z, &mut m1, &mut hm);
            }
            for i in 0..n {
                mat[(i, j)] = -(hp[i] - hm[i]) / (2.0 * eps);
            }
        }
    }
    Linearised { m, c, k, h0 }
}

/// `differences` about q = 0 at constant drum speed `omega` (rad/s), phi = 0.
pub fn linearise_at_speed(
    eq: &washdyn_model::equations::Equations,
    omega: f64,
    eps: f64,
) -> Linearised {
    let d = washdyn_model::equations::Drive {
        phi: 0.0,
        omega,
        omega_dot: 0.0,
    };
    differences(eq, &d, &vec![0.0; eq.layout.n()], eps)
}

/// Run python3 with `script` and arguments; its stdout (the Parquet and study tests read our
/// files with pyarrow, DuckDB and pandas, independent readers).
pub fn python<S: AsRef<std::ffi::OsStr>>(script: &str, args: &[S]) -> String {
    let out = std::process::Command::new("python3")
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "python failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Every file of a study's dataset under `out`, by path, but those under the top-level
/// directories `skip` (wall times in `timing/`, a Slurm run's `slurm/`): the bytes a re-run
/// or another engine must reproduce.
pub fn dataset_bytes(
    out: &std::path::Path,
    skip: &[&str],
) -> std::collections::BTreeMap<std::path::PathBuf, Vec<u8>> {
    let mut files = std::collections::BTreeMap::new();
    let mut stack = vec![out.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            let rel = p.strip_prefix(out).unwrap().to_path_buf();
            if p.is_dir() {
                if !skip.iter().any(|s| rel == std::path::Path::new(s)) {
                    stack.push(p);
                }
            } else {
                files.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    files
}

/// Two back ends' energy tables (`energy.parquet`'s columns: time, rpm, the kinetic energy, then
/// the categories) compared: the largest difference over the kinetic energy and every
/// category, and the largest category value (the flow it is read against).
pub fn energy_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
    let scale = a[3..].iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a[2..]
        .iter()
        .flatten()
        .zip(b[2..].iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    (worst, scale)
}

/// A scene's equations with dh/dq and dh/dq' at rest, q = q' = 0, drum still: where bearings
/// and bolts are undeflected and a friction law is its slope.
pub fn at_rest(
    model: &Model,
    scene: &str,
) -> (
    washdyn_model::equations::Equations,
    DMatrix<f64>,
    DMatrix<f64>,
) {
    use washdyn_model::equations::{Drive, Equations, JacobianWork};
    let s = model.scene(Some(scene)).unwrap();
    let eq = Equations::new(model, &s);
    let n = eq.layout.n();
    let (q, qd) = (vec![0.0; n], vec![0.0; n]);
    let (mut hq, mut hqd) = (vec![0.0; n * n], vec![0.0; n * n]);
    let d = Drive {
        phi: 0.0,
        omega: 0.0,
        omega_dot: 0.0,
    };
    eq.force_jacobians(&d, &q, &qd, &mut JacobianWork::new(&eq), &mut hq, &mut hqd);
    (
        eq,
        DMatrix::from_row_slice(n, n, &hq),
        DMatrix::from_row_slice(n, n, &hqd),
    )
}
