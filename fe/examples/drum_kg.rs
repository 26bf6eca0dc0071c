//! Development aid: build the built-in drum (every step of `fe modal`) in a scratch folder and
//! print the report, its frequencies at rest and spinning at the reference speed (the modal
//! data's, and as ccx's own prestressed step has it: `PrestressReport::as_ccx`) and, with a
//! mode count, ccx's own prestressed `*FREQUENCY` at the reference speed for those modes.
//!
//! `cargo run --release -p washdyn-fe --example drum_kg -- OUT_DIR [SOLVE_MODES MAX_HZ] [CCX_MODES]`
//! writes `OUT_DIR/drum.modal.toml`.

fn main() -> Result<(), String> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let out = std::path::PathBuf::from(a.first().ok_or("usage: drum_kg OUT_DIR [..]")?);
    let mut spec = washdyn_fe::bodies::builtin().remove(1);
    if let (Some(s), Some(h)) = (a.get(1), a.get(2)) {
        spec.solve_modes = s.parse().map_err(|_| "SOLVE_MODES")?;
        spec.keep.max_hz = h.parse().map_err(|_| "MAX_HZ")?;
        spec.keep.max_modes = spec.solve_modes;
    }
    let reference: Option<usize> = a
        .get(3)
        .map(|m| m.parse())
        .transpose()
        .map_err(|_| "CCX_MODES")?;
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    let t = std::time::Instant::now();
    let (data, r) = washdyn_fe::pipeline::build(&spec, &out).map_err(|e| e.to_string())?;
    println!("{r}");
    println!("build {:.1} s", t.elapsed().as_secs_f64());
    let size = std::fs::metadata(out.join("drum.frd")).map_or(0, |m| m.len());
    println!("drum.frd {:.1} MB", size as f64 / 1e6);
    let kg = data.geometric_stiffness.as_ref().ok_or("no K_G")?;
    let w = kg.reference_speed;
    let f0 = &data.frequencies;
    let ours = washdyn_fe::rotating::reduced_frequencies(f0, &data.elementary, kg, w);
    let as_ccx = r.prestress.as_ref().ok_or("no prestress")?.as_ccx(kg);
    let like = washdyn_fe::rotating::reduced_frequencies(f0, &data.elementary, &as_ccx, w);
    let p = out.join("drum.modal.toml");
    std::fs::write(&p, data.to_toml()).map_err(|e| e.to_string())?;
    let theirs = match reference {
        Some(m) => {
            let t = std::time::Instant::now();
            let (frd, _) = washdyn_fe::rotating::solve_prestressed(
                &spec.mesh,
                &out,
                "drum_reference",
                &spec.spin.as_ref().ok_or("no spin")?.centrifugal(),
                m,
            )
            .map_err(|e| e.to_string())?;
            println!(
                "ccx prestressed reference, {m} modes: {:.1} s",
                t.elapsed().as_secs_f64()
            );
            frd.modes.iter().map(|m| m.frequency_hz).collect()
        }
        None => Vec::new(),
    };
    println!(" mode   at rest  spinning  as ccx's     ccx   (as ccx's - ccx)/ccx");
    for k in 0..f0.len() {
        let c = theirs.get(k).copied().unwrap_or(f64::NAN);
        println!(
            "{k:5} {:9.4} {:9.4} {:9.4} {:9.4} {:10.2e}",
            f0[k],
            ours[k],
            like[k],
            c,
            (like[k] - c) / c
        );
    }
    Ok(())
}
