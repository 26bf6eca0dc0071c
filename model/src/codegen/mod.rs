//! The code generator: from a checked model to Rust source for a module with the model's IR and
//! one specialised type per scene. Plain Rust, called by the `machine!` macro at compile time and
//! unit-tested here without it.
//!
//! Each scene's equations are traced by running the one derivation (`equations`) over the
//! symbolic scalar: the graph is the same arithmetic the interpreter does, with the model's
//! numbers folded in, zero couplings pruned and common subexpressions shared; constant modal
//! maps stay table loops (`Scalar::mat_vec`). Up to `TRACED_FACTOR_MAX_N` coordinates M1 is
//! factorised symbolically (the fixed-size Cholesky becomes straight-line code) and q'' is
//! differentiated; above, M1 is the table of its harmonics in the rotor angles (`mass.rs`),
//! factorised at run time, and the implicit methods take the force Jacobians by structure
//! (`equations/jacobian.rs`), the same in both back ends.

use crate::equations::{Drive, Equations};
use crate::ir::Model;
use crate::linalg::{cholesky_factor, cholesky_solve};
use crate::scalar::Scalar;
use crate::symbolic::{Graph, Sym, derivative, fmt_f64, trace_params};
use std::fmt::Write;

mod free;
pub mod mass;
mod names;
mod scene;
pub use free::Free;
pub use mass::MassHarmonics;
pub use names::type_name;
use scene::scene_source_free;

/// Why code generation refused a model, and where in it (a free parameter: `free[k]`).
#[derive(Clone, Debug, PartialEq)]
pub struct GenError {
    pub path: crate::ir::check::Path,
    pub message: String,
}

impl GenError {
    fn at(path: crate::ir::check::Path, message: impl ToString) -> Self {
        GenError {
            path,
            message: message.to_string(),
        }
    }

    fn free(k: usize, message: String) -> Self {
        Self::at(
            crate::ir::check::Path::default().key("free").idx(k),
            message,
        )
    }
}

impl std::fmt::Display for GenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl From<String> for GenError {
    fn from(message: String) -> Self {
        Self::at(crate::ir::check::Path::default(), message)
    }
}

/// Size and cost of one scene's generated code.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneStats {
    pub scene: String,
    pub type_name: String,
    pub n1: usize,
    pub n2: usize,
    /// Operations in M1 and h.
    pub ops_mass_forces: usize,
    /// Operations in q'' (M1, h, Cholesky and solve).
    pub ops_accelerations: usize,
    /// Operations in the Jacobians of q''.
    pub ops_jacobians: usize,
}

/// Above this many coordinates, M1 is factorised numerically at run time on fixed-size arrays
/// and no analytic Jacobians are emitted: tracing the Cholesky grows like n1^3, and
/// differentiating through the elements for each coordinate like n x the graph (the rigid tub
/// in 20 cabinet modes: 58 000 operations, 1.7 MB of source, and the models crate no longer
/// compiled in 22 GB; measured with examples/generated_size). M1 and h alone grow like the
/// couplings (design-notes: "Elastic step: structure").
pub const TRACED_FACTOR_MAX_N: usize = 12;

/// How q'' and its Jacobians are generated.
pub enum Solve {
    /// q'' and its Jacobians d/dq, d/dq' (row-major n x n), M1 factorised in the graph.
    Traced(Box<Graph>, Vec<Sym>, Vec<Sym>, Vec<Sym>),
    /// M1 is factorised at run time (checked to depend on no q, q': only on the drum angle).
    /// q'' is not differentiated here (through every element for each of the 2n coordinates
    /// it grew to 6e5 operations at n = 98): the implicit methods take dh/dq and dh/dq' by
    /// structure (`ForceJacobians`).
    Numeric,
}

/// The traced graphs of one scene: what both the emitter and the tests consume.
pub struct Traced {
    pub n1: usize,
    pub n: usize,
    /// Element states (their rates follow h in `mh`).
    pub nz: usize,
    /// Inputs: q (n), q' (n), phi, omega, omega', the element states z (nz). Outputs: M1, and
    /// h followed by z'.
    pub mh: (Graph, Vec<Sym>, Vec<Sym>),
    /// M1 from its fitted harmonics (`mass.rs`), same inputs, when the scene factorises M1 at
    /// run time and M1 has that form: what the generated code evaluates instead of `mh`'s M1.
    pub m1_harmonic: Option<(Graph, Vec<Sym>)>,
    pub acc: Solve,
    /// Inputs: q, q', q''. Outputs: sensor channels.
    pub sensors: (Graph, Vec<Sym>),
}

fn inputs(n: usize) -> (Vec<Sym>, Vec<Sym>, Drive<Sym>) {
    let q: Vec<Sym> = (0..n).map(|_| Sym::input()).collect();
    let qd: Vec<Sym> = (0..n).map(|_| Sym::input()).collect();
    let d = Drive {
        phi: Sym::input(),
        omega: Sym::input(),
        omega_dot: Sym::input(),
    };
    (q, qd, d)
}

/// d outputs / d q and d outputs / d q' (row-major, outputs x n), inside a trace.
fn jacobians(out: &[Sym], n: usize) -> (Vec<Sym>, Vec<Sym>) {
    let m = out.len();
    let mut jq = vec![Sym::c(0.0); m * n];
    let mut jqd = vec![Sym::c(0.0); m * n];
    for j in 0..n {
        let dj = derivative(out, j as u32);
        let dvj = derivative(out, (n + j) as u32);
        for i in 0..m {
            jq[i * n + j] = dj[i];
            jqd[i * n + j] = dvj[i];
        }
    }
    (jq, jqd)
}

/// Trace a scene's equations.
pub fn trace_equations(eq: &Equations) -> Traced {
    trace_free(eq, &[])
}

/// As [`trace_equations`], for equations of a model whose free numbers are `stand_ins`
/// (`Free::stand_in_model`): those become the graph's parameters.
pub fn trace_free(eq: &Equations, stand_ins: &[f64]) -> Traced {
    let (n1, n, nz) = (eq.layout.n1, eq.layout.n(), eq.layout.nz);
    let ((m1, h), g_mh) = trace_params(stand_ins, || {
        let (q, qd, d) = inputs(n);
        let z: Vec<Sym> = (0..nz).map(|_| Sym::input()).collect();
        let mut m1 = vec![Sym::c(0.0); n1 * n1];
        let mut h = vec![Sym::c(0.0); n + nz];
        let (hm, zd) = h.split_at_mut(n);
        eq.eval_states(&d, &q, &qd, &z, &mut m1, hm);
        eq.state_rates(&q, &qd, &z, zd);
        (m1, h)
    });
    // With element states q'' is not traced (it would need them as inputs too): M1 is
    // factorised at run time, the implicit methods difference the whole Jacobian.
    let acc = if n <= TRACED_FACTOR_MAX_N && nz == 0 {
        let ((qdd, jq, jqd), g_acc) = trace_params(stand_ins, || {
            let (q, qd, d) = inputs(n);
            let mut m1 = vec![Sym::c(0.0); n1 * n1];
            let mut h = vec![Sym::c(0.0); n];
            eq.eval(&d, &q, &qd, &mut m1, &mut h);
            let mut qdd = h.clone();
            // The interpreter's own factorisation, traced (a non-SPD M1 shows as NaN).
            cholesky_factor(&mut m1, n1);
            cholesky_solve(&m1, n1, &mut qdd[..n1]);
            // M2 = I for mass-normalised modes (the interpreter's M2): nothing to solve.
            let (jq, jqd) = jacobians(&qdd, n);
            (qdd, jq, jqd)
        });
        Solve::Traced(Box::new(g_acc), qdd, jq, jqd)
    } else {
        // A dependency pass over the traced M1 (inputs 0..2n are q and q').
        let dep = g_mh.depends_on(0..2 * n as u32);
        assert!(
            m1.iter().all(|s| !dep[s.0 as usize]),
            "M1 depends on q or q': the numeric factorisation needs M1(phi) only"
        );
        Solve::Numeric
    };
    // The harmonic form needs M1 to depend on phi alone (inputs 2n + 1, 2n + 2: omega, omega').
    let m1_harmonic = match acc {
        Solve::Numeric => {
            let on_rates = g_mh.depends_on(2 * n as u32 + 1..2 * n as u32 + 3);
            if m1.iter().any(|s| on_rates[s.0 as usize]) {
                None
            } else {
                mass::fit(eq).map(|f| f.trace(n))
            }
        }
        Solve::Traced(..) => None,
    };
    let (ch, g_s) = trace_params(stand_ins, || {
        let q: Vec<Sym> = (0..n).map(|_| Sym::input()).collect();
        let qd: Vec<Sym> = (0..n).map(|_| Sym::input()).collect();
        let qdd: Vec<Sym> = (0..n).map(|_| Sym::input()).collect();
        let d = Drive {
            phi: Sym::input(),
            omega: Sym::input(),
            omega_dot: Sym::input(),
        };
        (0..eq.sensors.len())
            .flat_map(|i| eq.sensor(i, &d, &q, &qd, &qdd))
            .collect::<Vec<Sym>>()
    });
    Traced {
        n1,
        n,
        nz,
        mh: (g_mh, m1, h),
        m1_harmonic,
        acc,
        sensors: (g_s, ch),
    }
}

/// Rust source of one scene's type, and its statistics.
pub fn scene_source(eq: &Equations, name: &str) -> (String, SceneStats) {
    scene_source_free(eq, name, &Free::default(), &trace_equations(eq))
}

/// Rust source (items) of a module for a checked model: `MODEL_JSON`, `model()`, the speed
/// table, one type per scene implementing `system::Mechanical`, and `system(scene)` to pick one
/// by name at run time.
pub fn generate(model: &Model) -> Result<String, GenError> {
    generate_with_stats(model).map(|(s, _)| s)
}

/// As `generate`, with the statistics of each scene.
pub fn generate_with_stats(model: &Model) -> Result<(String, Vec<SceneStats>), GenError> {
    let json = serde_json::to_string(model).map_err(|e| e.to_string())?;
    let table: Vec<String> = model
        .speed
        .table
        .iter()
        .map(|r| format!("[{}, {}]", fmt_f64(r[0]), fmt_f64(r[1])))
        .collect();
    let mut s = String::new();
    let _ = write!(
        s,
        "/// The model's IR, as the macro filled it.\n\
         pub const MODEL_JSON: &str = {json:?};\n\
         /// The model's IR (the interpreter's input).\n\
         pub fn model() -> ::washdyn_runtime::model::ir::Model {{\n\
             ::washdyn_runtime::serde_json::from_str(MODEL_JSON).expect(\"the macro wrote valid JSON\")\n\
         }}\n\
         /// The model, read from `MODEL_JSON` once: what a variant is compared with (an elastic\n\
         /// machine's JSON holds its modal data, milliseconds to read).\n\
         fn base() -> &'static ::washdyn_runtime::model::ir::Model {{\n\
             static BASE: ::std::sync::OnceLock<::washdyn_runtime::model::ir::Model> = ::std::sync::OnceLock::new();\n\
             BASE.get_or_init(model)\n\
         }}\n\
         /// `variant`'s values of the free parameters where it differs from this model in those\n\
         /// only, else the first other difference: whether the generated scenes run it\n\
         /// (`system_for`), without building one.\n\
         pub fn fits(variant: &::washdyn_runtime::model::ir::Model) -> Result<Vec<f64>, String> {{\n\
             ::washdyn_runtime::model::ir::param::free_values(base(), variant)\n\
         }}\n\
         /// The drum speed profile (time s, rpm).\n\
         pub const SPEED_TABLE: [[f64; 2]; {}] = [{}];\n",
        table.len(),
        table.join(", ")
    );
    let free = Free::of(model)?;
    let traced_model = free.stand_in_model(model)?;
    let _ = write!(
        s,
        "/// The free parameters (paths into the model), which the scenes take as inputs.\n\
         pub const FREE: &[&str] = &[{}];\n\
         /// Their values in this model.\n\
         pub const PARAMS: [f64; {}] = [{}];\n",
        free.params
            .iter()
            .map(|p| format!("{:?}", p.text))
            .collect::<Vec<_>>()
            .join(", "),
        free.values.len(),
        free.values
            .iter()
            .map(|v| fmt_f64(*v))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut stats = Vec::new();
    let mut arms = String::new();
    let mut variant_arms = String::new();
    let names = model.scene_names();
    for scene in &names {
        let eff = model.scene(Some(scene))?;
        let eq = Equations::new(&traced_model, &eff);
        let t = trace_free(&eq, &free.stand_ins);
        let (g, m1, h) = &t.mh;
        let (gs, ch) = &t.sensors;
        free.verify(model, &eff, (g, m1, h), (gs, ch))?;
        let tn = type_name(scene);
        let (src, st) = scene_source_free(&eq, &tn, &free, &t);
        s.push_str(&src);
        let _ = writeln!(arms, "        {scene:?} => Some(Box::new({tn}::new())),");
        let _ = writeln!(
            variant_arms,
            "        {scene:?} => Some({tn}::for_variant(variant).map(|s| Box::new(s) as Box<dyn ::washdyn_runtime::system::Mechanical + Send>)),"
        );
        stats.push(st);
    }
    let _ = write!(
        s,
        "\n/// The generated system of a scene for `variant`, a model that differs from this one \
         in free parameters only (`None`: no such scene; `Err`: another difference).\n\
         pub fn system_for(scene: &str, variant: &::washdyn_runtime::model::ir::Model) -> Option<Result<Box<dyn ::washdyn_runtime::system::Mechanical + Send>, String>> {{\n\
             match scene {{\n{variant_arms}        _ => None,\n    }}\n}}\n"
    );
    let _ = write!(
        s,
        "\n/// The scenes, in declaration order.\n\
         pub const SCENES: &[&str] = &[{}];\n\
         /// The generated system of a scene, by name.\n\
         pub fn system(scene: &str) -> Option<Box<dyn ::washdyn_runtime::system::Mechanical + Send>> {{\n\
             match scene {{\n{arms}        _ => None,\n    }}\n}}\n",
        names
            .iter()
            .map(|n| format!("{n:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok((s, stats))
}

#[cfg(test)]
mod tests;
