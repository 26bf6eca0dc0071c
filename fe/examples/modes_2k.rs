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
    let (body, solve, max_hz, out, spin) = match &a[..] {
        [b, s, m, o] => (b, s, m, o, false),
        [b, s, m, o, k] if k == "spin" => (b, s, m, o, true),
        _ => return Err("usage: modes_2k BODY SOLVE_MODES MAX_HZ OUT_DIR [spin]".into()),
    };
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
    let out = std::path::Path::new(out);
    let work = out.join(format!("{body}_work"));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let (data, r) = washdyn_fe::pipeline::build(&spec, &work).map_err(|e| e.to_string())?;
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
