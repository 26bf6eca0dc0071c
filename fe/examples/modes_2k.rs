//! Modal data of one built-in body with every mode up to a frequency, for issue 21's
//! truncation study (docs/truncation.md): the built-in spec with `solve_modes` eigenmodes,
//! every one below `max_hz` kept, the spec's correction modes, no recovery field; no spin unless
//! `spin` follows (the basis study compares bases at standstill; a simulation of the spinning
//! drum needs its geometric stiffness, one static solve more).
//!
//! `cargo run --release -p washdyn-fe --example modes_2k -- BODY SOLVE_MODES MAX_HZ OUT_DIR [spin]`
//! writes `OUT_DIR/BODY.modal.toml` and prints the frequencies' range.

fn main() -> Result<(), String> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (body, solve, max_hz, out, flag) = match &a[..] {
        [b, s, m, o] => (b, s, m, o, ""),
        [b, s, m, o, k] if k == "spin" || k == "dampers" => (b, s, m, o, k.as_str()),
        _ => return Err("usage: modes_2k BODY SOLVE_MODES MAX_HZ OUT_DIR [spin|dampers]".into()),
    };
    let spin = flag == "spin";
    let solve: usize = solve
        .parse()
        .map_err(|_| format!("SOLVE_MODES `{solve}`"))?;
    let max_hz: f64 = max_hz.parse().map_err(|_| format!("MAX_HZ `{max_hz}`"))?;
    let mut spec = washdyn_fe::bodies::builtin()
        .into_iter()
        .find(|s| s.name == *body)
        .ok_or_else(|| format!("no built-in body `{body}`"))?;
    spec.solve_modes = solve;
    spec.keep.max_hz = max_hz;
    spec.keep.max_modes = solve;
    spec.recovery = false;
    if !spin {
        spec.spin = None;
    }
    // `dampers`: the cabinet's static give along each friction damper's rod at its bracket as
    // correction modes too (the built-in data leaves them out: a correction mode there puts
    // the friction slope on a small modal mass), for a reference with every element load's
    // static give.
    if flag == "dampers" {
        use washdyn_runtime::geom::f::{norm, sub, unit};
        let model = washdyn_fe::bodies::reference_model();
        for d in &model.friction_dampers {
            // The bracket's node set: the body's point at the damper's cabinet end.
            let end = [&d.a, &d.b]
                .into_iter()
                .find(|e| e.body == washdyn_runtime::ir::BodyRef::Cabinet)
                .ok_or_else(|| format!("{}: no end on the cabinet", d.name))?;
            let dist = |p: [f64; 3]| norm(sub(p, end.point));
            let (set, at) = spec
                .points
                .iter()
                .min_by(|x, y| dist(x.1).total_cmp(&dist(y.1)))
                .ok_or("the cabinet has no points")?;
            if dist(*at) > 5e-3 {
                return Err(format!("{}: no cabinet point at its bracket", d.name));
            }
            let dir = unit(sub(d.b.point, d.a.point));
            eprintln!("{}: correction load at {set} along {dir:?}", d.name);
            let case = washdyn_runtime::ir::modal::LoadCase::force(set, dir);
            spec.correction.push(case);
        }
    }
    let out = std::path::Path::new(out);
    let work = out.join(format!("{body}_work"));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let (data, r) = washdyn_fe::pipeline::build(&spec, &work)?;
    let p = out.join(format!("{body}.modal.toml"));
    std::fs::write(&p, data.to_toml()).map_err(|e| e.to_string())?;
    let f = &data.frequencies;
    println!(
        "{body}: {} modes kept ({} eigen), {:.1} to {:.1} Hz (ccx {:.1} s); highest solved {:.1} Hz; {}",
        f.len(),
        data.eigenmodes(),
        f[0],
        f[f.len() - 1],
        r.solve_s,
        r.all_frequencies.last().copied().unwrap_or(0.0),
        p.display()
    );
    Ok(())
}
