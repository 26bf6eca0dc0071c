//! Development aid: solve one built-in body and print what it gives.
fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "drum".into());
    let n: usize = std::env::args().nth(2).map_or(20, |s| s.parse().unwrap());
    let mesh = match which.as_str() {
        "drum" => washdyn_fe::bodies::drum::Drum::default().mesh(),
        "tub" => washdyn_fe::bodies::tub::Tub::default().mesh(),
        "cabinet" => washdyn_fe::bodies::cabinet::Cabinet::default().mesh(),
        _ => panic!("unknown body"),
    };
    let dir = std::path::PathBuf::from("/tmp/try").join(&which);
    std::fs::create_dir_all(&dir).unwrap();
    let l = washdyn_fe::lumping::lump(&mesh);
    let p = l.mass_props(&mesh);
    println!(
        "consistent {:?}",
        washdyn_fe::lumping::consistent_mass_props(&mesh)
    );
    println!(
        "{} nodes, {} elements; lumped {p:?}",
        mesh.nodes.len(),
        mesh.element_count()
    );
    for part in &mesh.parts {
        let mut sub = mesh.clone();
        sub.parts.retain(|q| q.name == part.name);
        println!(
            "  {}: {:.4} kg",
            part.name,
            washdyn_fe::lumping::element_mass(&sub)
        );
    }
    let t = std::time::Instant::now();
    match washdyn_fe::modal::solve(&mesh, &dir, &which, n) {
        Ok(s) => {
            let f: Vec<String> = s
                .frd
                .modes
                .iter()
                .map(|m| format!("{:.2}", m.frequency_hz))
                .collect();
            println!(
                "solved in {:.1} s: {}",
                t.elapsed().as_secs_f64(),
                f.join(" ")
            );
        }
        Err(e) => println!("error: {e}"),
    }
}
