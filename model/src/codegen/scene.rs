//! One scene's type in the generated code (`scene_source_free`), step by step: M1 and h, h
//! alone for large scenes, q'' and its Jacobians, the sensors, then the type around them.

use super::names::{state_inputs, with_states};
use super::{Free, SceneStats, Solve, Traced, mass};
use crate::equations::Equations;
use crate::symbolic::{Emitter, fmt_f64};
use std::fmt::Write;

/// The drive's inputs as the generated functions name them.
const DRIVE: [&str; 3] = ["d.phi", "d.omega", "d.omega_dot"];

/// The generated functions' bodies and the scene's sizes and operation counts: what the type
/// (`type_source`) is written around.
struct Parts {
    np: usize,
    n1: usize,
    n2: usize,
    n: usize,
    nz: usize,
    nc: usize,
    ops_mh: usize,
    ops_acc: usize,
    ops_jac: usize,
    body_mh: String,
    body_acc: String,
    body_sensors: String,
    jac_fn: String,
    jac_impl: String,
    forces_fn: String,
    forces_impl: String,
}

/// As [`scene_source`](super::scene_source) for the traced equations `t` of a model with free
/// parameters `free`: the functions take the parameter array `p` (`PARAMS` by default, a
/// variant's values through `for_variant`).
pub(super) fn scene_source_free(
    eq: &Equations,
    name: &str,
    free: &Free,
    t: &Traced,
) -> (String, SceneStats) {
    let np = free.params.len();
    let (n1, n, nz) = (t.n1, t.n, t.nz);
    let (body_mh, ops_mh) = mass_and_forces_body(t);
    let (forces_fn, forces_impl) = forces_code(t, np);
    let (body_acc, body_jac, ops_acc, ops_jac) = accelerations_body(t, ops_mh);
    let (jac_fn, jac_impl) = jacobians_code(&body_jac, np, n);
    let parts = Parts {
        np,
        n1,
        n2: n - n1,
        n,
        nz,
        nc: eq.n_channels(),
        ops_mh,
        ops_acc,
        ops_jac,
        body_mh,
        body_acc,
        body_sensors: sensors_body(t),
        jac_fn,
        jac_impl,
        forces_fn,
        forces_impl,
    };
    let s = type_source(eq, name, &parts);
    let stats = SceneStats {
        scene: eq.scene.name.clone(),
        type_name: name.to_string(),
        n1,
        n2: parts.n2,
        ops_mass_forces: parts.ops_mh,
        ops_accelerations: parts.ops_acc,
        ops_jacobians: parts.ops_jac,
    };
    (s, stats)
}

/// The body of `mass_and_forces` (M1, h and the element states' rates; M1 from its harmonics
/// when the scene has them) and its operation count.
fn mass_and_forces_body(t: &Traced) -> (String, usize) {
    let drive = DRIVE;
    let (n, nz) = (t.n, t.nz);
    let (g, m1, hz) = &t.mh;
    let (h, zd) = hz.split_at(n);
    let mh_inputs = with_states(state_inputs(n, &drive), nz);
    let (body_mh, ops_mh) = match &t.m1_harmonic {
        None => {
            let mut e = Emitter::new(g, mh_inputs.clone());
            e.assign("m1", m1);
            e.assign("h", h);
            e.assign("zd", zd);
            (
                e.take(),
                g.op_count(&[m1.as_slice(), hz.as_slice()].concat()),
            )
        }
        Some((gm, m1h)) => {
            let mut em = Emitter::with_prefix(gm, state_inputs(n, &drive), "m_");
            em.assign("m1", m1h);
            let mut e = Emitter::new(g, mh_inputs.clone());
            e.assign("h", h);
            e.assign("zd", zd);
            (em.take() + &e.take(), gm.op_count(m1h) + g.op_count(hz))
        }
    };

    (body_mh, ops_mh)
}

/// `forces` (h alone) and its `Mechanical` method, for large scenes; empty otherwise.
fn forces_code(t: &Traced, np: usize) -> (String, String) {
    let drive = DRIVE;
    let (n1, n, nz) = (t.n1, t.n, t.nz);
    let (g, _, hz) = &t.mh;
    let (h, zd) = hz.split_at(n);
    let mh_inputs = with_states(state_inputs(n, &drive), nz);
    // h alone, for the run time's structured solve of M1 (large scenes only: it repeats h).
    let forces_fn = if n1 >= mass::LOW_RANK_MIN_N1 {
        let mut e = Emitter::new(g, mh_inputs);
        e.assign("h", h);
        e.assign("zd", zd);
        format!(
            "    /// h and the element states' rates, without M1.\n    #[inline]\n    pub fn forces(p: &[f64; {np}], d: &::washdyn_runtime::model::equations::Drive<f64>, q: &[f64; {n}], qd: &[f64; {n}], z: &[f64; {nz}], h: &mut [f64; {n}], zd: &mut [f64; {nz}]) {{\n{}    }}\n",
            e.take()
        )
    } else {
        String::new()
    };
    let forces_impl = if forces_fn.is_empty() {
        String::new()
    } else {
        // No states given (an evaluation at the assembly state): z = 0, the rates dropped.
        format!(
            "    fn forces(&mut self, t: f64, q: &[f64], qd: &[f64], z: &[f64], h: &mut [f64], zd: &mut [f64]) -> bool {{\n        let d = self.speed.drive(t);\n        let z: [f64; {nz}] = z.try_into().unwrap_or([0.0; {nz}]);\n        let mut rates = [0.0; {nz}];\n        Self::forces(&self.p, &d, q.try_into().expect(\"q\"), qd.try_into().expect(\"qd\"), &z, h.try_into().expect(\"h\"), &mut rates);\n        if let Ok(zd) = <&mut [f64; {nz}]>::try_from(zd) {{\n            *zd = rates;\n        }}\n        true\n    }}\n"
        )
    };
    (forces_fn, forces_impl)
}

/// The bodies of `accelerations` and `jacobians` (empty when q'' is not traced) and their
/// operation counts; `ops_mh`, M1's and h's, is part of a numeric solve's.
fn accelerations_body(t: &Traced, ops_mh: usize) -> (String, String, usize, usize) {
    let drive = DRIVE;
    let (n1, n, nz) = (t.n1, t.n, t.nz);
    let rt = "::washdyn_runtime";
    let (body_acc, body_jac, ops_acc, ops_jac) = match &t.acc {
        Solve::Traced(g, qdd, jq, jqd) => {
            let mut e = Emitter::new(g, state_inputs(n, &drive));
            e.assign("qdd", qdd);
            let body_acc = e.take();
            let mut e = Emitter::new(g, state_inputs(n, &drive));
            e.assign("jq", jq);
            e.assign("jqd", jqd);
            (
                body_acc,
                e.take(),
                g.op_count(qdd),
                g.op_count(&[jq.as_slice(), jqd.as_slice()].concat()),
            )
        }
        Solve::Numeric => {
            let body_acc = format!(
                "let mut m1 = [0.0f64; {n1sq}];\n\
                 Self::mass_and_forces(p, d, q, qd, &[0.0; {nz}], &mut m1, qdd, &mut [0.0; {nz}]);\n\
                 {rt}::model::linalg::cholesky_factor(&mut m1[..], {n1});\n\
                 {rt}::model::linalg::cholesky_solve(&m1[..], {n1}, &mut qdd[..{n1}]);\n",
                n1sq = n1 * n1
            );
            // Traced operations plus the factorisation's n1^3/3 and the solve's 2 n1^2.
            (
                body_acc,
                String::new(),
                ops_mh + n1 * n1 * n1 / 3 + 2 * n1 * n1,
                0,
            )
        }
    };

    (body_acc, body_jac, ops_acc, ops_jac)
}

/// The body of `sensor_values`.
fn sensors_body(t: &Traced) -> String {
    let drive = DRIVE;
    let n = t.n;
    let (g, ch) = &t.sensors;
    let mut names = state_inputs(n, &[]);
    names.extend((0..n).map(|i| format!("qdd[{i}]")));
    names.extend(drive.iter().map(|s| s.to_string()));
    let mut e = Emitter::new(g, names);
    e.assign("out", ch);
    e.take()
}

/// `jacobians` and the `Mechanical` methods that answer with it (or with the force
/// Jacobians alone when q'' has no traced Jacobians).
fn jacobians_code(body_jac: &str, np: usize, n: usize) -> (String, String) {
    let rt = "::washdyn_runtime";
    // The force Jacobians of the same derivation (`equations/jacobian.rs`): every scene has
    // them (`type_source`). Up to the traced size the implicit methods take the traced
    // d q''/d q instead.
    let force_impl = "    fn equations(&self) -> Option<&::washdyn_runtime::model::equations::Equations> {\n        Some(&self.jac.eq)\n    }\n    fn force_jacobians(&mut self, t: f64, q: &[f64], qd: &[f64], hq: &mut [f64], hqd: &mut [f64]) {\n        let d = self.speed.drive(t);\n        self.jac.eval(&d, q, qd, hq, hqd);\n    }\n";
    let (jac_fn, jac_impl) = if body_jac.is_empty() {
        (String::new(), force_impl.to_string())
    } else {
        (
            format!(
                "    /// d q''/d q and d q''/d q' (row-major).\n    #[inline]\n    pub fn jacobians(p: &[f64; {np}], d: &{rt}::model::equations::Drive<f64>, q: &[f64; {n}], qd: &[f64; {n}], jq: &mut [f64; {nsq}], jqd: &mut [f64; {nsq}]) {{\n{body_jac}    }}\n",
                nsq = n * n
            ),
            format!(
                "    fn acceleration_jacobians(&mut self, t: f64, q: &[f64], qd: &[f64], jq: &mut [f64], jqd: &mut [f64]) -> bool {{\n        let d = self.speed.drive(t);\n        Self::jacobians(&self.p, &d, q.try_into().expect(\"q\"), qd.try_into().expect(\"qd\"), jq.try_into().expect(\"jq\"), jqd.try_into().expect(\"jqd\"));\n        true\n    }}\n    fn has_acceleration_jacobians(&self) -> bool {{\n        true\n    }}\n{force_impl}"
            ),
        )
    };
    (jac_fn, jac_impl)
}

/// The scene's type: its struct and the generated functions, then its `system::Mechanical`
/// impl (`mechanical_impl`).
fn type_source(eq: &Equations, name: &str, parts: &Parts) -> String {
    let Parts {
        np,
        n1,
        n2,
        n,
        nz,
        nc,
        ops_mh,
        ops_acc,
        ops_jac,
        body_mh,
        body_acc,
        body_sensors,
        jac_fn,
        forces_fn,
        ..
    } = parts;
    let rt = "::washdyn_runtime";
    // The force Jacobians of the same derivation (`equations/jacobian.rs`) on the model the
    // macro embedded (`model()`), with their own work arrays: every scene has them, so the
    // static start's Newton takes the same bits as the interpreter's.
    let jac_field = format!("\n    jac: {rt}::model::equations::ForceJacobians,");
    let jac_init = format!(
        "\n            jac: {rt}::model::equations::ForceJacobians::for_scene(&model(), Self::SCENE),"
    );
    let channels: Vec<String> = eq
        .sensors
        .iter()
        .flat_map(|s| s.channels.iter().map(|c| format!("{c:?}")))
        .collect();
    let m2: Vec<String> = (0..n2 * n2)
        .map(|k| fmt_f64(if k % (n2 + 1) == 0 { 1.0 } else { 0.0 }))
        .collect();
    let scene = &eq.scene.name;
    let effects: Vec<String> = eq.scene.effects.iter().map(|e| e.name()).collect();
    let mut s = String::new();
    let _ = write!(
        s,
        r#"
/// Scene `{scene}` (effects: {effects}), generated by `machine!`: {n1} + {n2} DOF,
/// M1 and h in {ops_mh} operations, q'' in {ops_acc}, its Jacobians in {ops_jac}.
#[derive(Clone, Debug)]
pub struct {name} {{
    speed: {rt}::model::speed::Speed,{jac_field}
    p: [f64; {np}],
}}

impl Default for {name} {{
    fn default() -> Self {{
        Self::new()
    }}
}}

#[allow(unused_variables, unused_parens, clippy::all)]
impl {name} {{
    pub const SCENE: &'static str = {scene:?};
    pub const N1: usize = {n1};
    pub const N2: usize = {n2};
    pub const N: usize = {n};
    pub const CHANNELS: &'static [&'static str] = &[{channels}];
    const M2: [f64; {n2sq}] = [{m2}];

    pub fn new() -> Self {{
        {name} {{
            speed: {rt}::model::speed::Speed::new(&SPEED_TABLE),{jac_init}
            p: PARAMS,
        }}
    }}

    /// The scene of `variant`, a model that differs from this one in free parameters only
    /// (`FREE`); anything else is refused, naming the first difference.
    pub fn for_variant(variant: &{rt}::model::ir::Model) -> Result<Self, String> {{
        let p = fits(variant)?;
        Ok({name} {{
            speed: {rt}::model::speed::Speed::new(&SPEED_TABLE),
            jac: {rt}::model::equations::ForceJacobians::for_scene(variant, Self::SCENE),
            p: p.try_into().map_err(|_| "free parameter count".to_string())?,
        }})
    }}

    /// M1 (row-major) and h at element states z, and their rates zd.
    #[inline]
    pub fn mass_and_forces(p: &[f64; {np}], d: &{rt}::model::equations::Drive<f64>, q: &[f64; {n}], qd: &[f64; {n}], z: &[f64; {nz}], m1: &mut [f64; {n1sq}], h: &mut [f64; {n}], zd: &mut [f64; {nz}]) {{
{body_mh}    }}

    /// q'' = M^-1 h, with M1 factorised in straight-line code.
    #[inline]
    pub fn accelerations(p: &[f64; {np}], d: &{rt}::model::equations::Drive<f64>, q: &[f64; {n}], qd: &[f64; {n}], qdd: &mut [f64; {n}]) {{
{body_acc}    }}

{jac_fn}{forces_fn}
    /// Sensor channels from q, q', q''.
    #[inline]
    pub fn sensor_values(p: &[f64; {np}], d: &{rt}::model::equations::Drive<f64>, q: &[f64; {n}], qd: &[f64; {n}], qdd: &[f64; {n}], out: &mut [f64; {nc}]) {{
{body_sensors}    }}
}}

"#,
        effects = effects.join(", "),
        channels = channels.join(", "),
        m2 = m2.join(", "),
        n1sq = n1 * n1,
        n2sq = n2 * n2,
    );
    s.push_str(&mechanical_impl(name, parts));
    s
}

/// The scene type's `system::Mechanical` impl: the trait's methods over the generated
/// functions.
fn mechanical_impl(name: &str, parts: &Parts) -> String {
    let Parts {
        n1,
        n2,
        nz,
        jac_impl,
        forces_impl,
        ..
    } = parts;
    let rt = "::washdyn_runtime";
    format!(
        r#"impl {rt}::system::Mechanical for {name} {{
    fn layout(&self) -> {rt}::model::equations::Layout {{
        {rt}::model::equations::Layout {{ n1: {n1}, n2: {n2}, nz: {nz} }}
    }}
    fn eval(&mut self, t: f64, q: &[f64], qd: &[f64], m1: &mut [f64], h: &mut [f64]) {{
        let d = self.speed.drive(t);
        Self::mass_and_forces(&self.p, &d, q.try_into().expect("q has N entries"), qd.try_into().expect("qd has N entries"), &[0.0; {nz}], m1.try_into().expect("m1 has N1^2 entries"), h.try_into().expect("h has N entries"), &mut [0.0; {nz}]);
    }}
    fn eval_states(&mut self, t: f64, q: &[f64], qd: &[f64], z: &[f64], m1: &mut [f64], h: &mut [f64], zd: &mut [f64]) {{
        let d = self.speed.drive(t);
        Self::mass_and_forces(&self.p, &d, q.try_into().expect("q has N entries"), qd.try_into().expect("qd has N entries"), z.try_into().expect("z has NZ entries"), m1.try_into().expect("m1 has N1^2 entries"), h.try_into().expect("h has N entries"), zd.try_into().expect("zd has NZ entries"));
    }}
    fn m2(&self) -> &[f64] {{
        &Self::M2
    }}
    fn sensors(&self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {{
        let d = self.speed.drive(t);
        Self::sensor_values(&self.p, &d, q.try_into().expect("q"), qd.try_into().expect("qd"), qdd.try_into().expect("qdd"), out.try_into().expect("3 channels per sensor"));
    }}
    fn channel_names(&self) -> Vec<String> {{
        Self::CHANNELS.iter().map(|c| c.to_string()).collect()
    }}
    fn speed(&self) -> &{rt}::model::speed::Speed {{
        &self.speed
    }}
    fn accelerations(&mut self, t: f64, q: &[f64], qd: &[f64], qdd: &mut [f64]) -> bool {{
        let d = self.speed.drive(t);
        Self::accelerations(&self.p, &d, q.try_into().expect("q"), qd.try_into().expect("qd"), qdd.try_into().expect("qdd"));
        true
    }}
{forces_impl}{jac_impl}}}
"#
    )
}
