//! Size of the generated code for the reference machine's full elastic scene as the mode
//! counts grow (issue 9: measure before building; the generator must grow gently).
//! `cargo run --release --example generated_size [tub drum cabinet]...`, e.g. `10 6 10 34 12 30`.

use std::time::Instant;
use washdyn_model::codegen::{scene_source, trace_equations};
use washdyn_model::equations::Equations;
use washdyn_model::ir::Scene;

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("mode counts"))
        .collect();
    let sets: Vec<[usize; 3]> = if args.is_empty() {
        vec![[6, 4, 6], [12, 8, 12], [20, 12, 20], [34, 12, 30]]
    } else {
        args.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
    };
    println!(
        "tub drum cabinet | n1 n2 | ops M1+h (M1, h) | ops q'' | ops Jacobians | source kB | lines | generate s"
    );
    for [nt, nd, nc] in sets {
        // The TOML file (not the models crate: this measures what that crate would compile).
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/data/reference.toml");
        let mut m = washdyn_model::ir::toml_file::load_file(&path).expect("reference model");
        for e in &mut m.elastic {
            let n = match e.name.as_str() {
                "tub" => nt,
                "drum" => nd,
                _ => nc,
            };
            e.data.as_mut().unwrap().truncate(n, &[]);
        }
        let mut effects: Vec<String> = m.scenes[0].effects.clone();
        effects.extend(
            [
                "elastic.tub",
                "elastic.drum",
                "elastic.cabinet",
                "centrifugal_stiffening",
            ]
            .map(String::from),
        );
        m.scenes.retain(|s| s.name != "elastic");
        m.scenes.push(Scene {
            name: "elastic".into(),
            effects,
            max_order: None,
            solver: None,
        });
        let eff = m.scene(Some("elastic")).unwrap();
        let t = Instant::now();
        let eq = Equations::new(&m, &eff);
        let (src, st) = scene_source(&eq, "Elastic");
        let secs = t.elapsed().as_secs_f64();
        let t = trace_equations(&eq);
        let (g, m1, h) = &t.mh;
        // What the generated code evaluates for M1: its table of harmonics when fitted.
        let m1_ops = t
            .m1_harmonic
            .as_ref()
            .map_or(g.op_count(m1), |(gm, s)| gm.op_count(s));
        println!(
            "{nt} {nd} {nc} | {} {} | {} ({}, {}) | {} | {} | {:.0} | {} | {:.1}",
            st.n1,
            st.n2,
            st.ops_mass_forces,
            m1_ops,
            g.op_count(h),
            st.ops_accelerations,
            st.ops_jacobians,
            src.len() as f64 / 1e3,
            src.lines().count(),
            secs
        );
        if let Ok(p) = std::env::var("WRITE_SOURCE") {
            std::fs::write(format!("{p}_{nt}_{nd}_{nc}.rs"), &src).unwrap();
        }
    }
}
