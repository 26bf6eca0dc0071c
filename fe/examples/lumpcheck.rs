//! Development aid: the drum's lumping error per part, to see where it comes from.
use washdyn_fe::lumping::lump;
use washdyn_fe::modal::{self, Keep};
fn main() {
    let drum = washdyn_fe::bodies::drum::Drum::default();
    let mesh = drum.mesh();
    let dir = std::path::PathBuf::from("/tmp/try/lc");
    std::fs::create_dir_all(&dir).unwrap();
    let s = modal::solve(&mesh, &dir, "d", 12).unwrap();
    let l = lump(&mesh);
    let keep = Keep {
        rigid_below_hz: 0.0,
        max_hz: 1e9,
        max_modes: 12,
    };
    let modes = modal::select(&mesh, &s.frd, &s.prints, keep).unwrap();
    for (k, m) in modes.iter().enumerate() {
        let mut per = Vec::new();
        for p in &mesh.parts {
            let mut ids: Vec<usize> = p.elements.iter().flatten().copied().collect();
            ids.sort();
            ids.dedup();
            let e: f64 = ids
                .iter()
                .map(|id| {
                    let w = m.w.get(id).copied().unwrap_or([0.0; 3]);
                    l.node_mass[id - 1] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
                })
                .sum();
            per.push(format!("{}={:.3}", p.name, e));
        }
        println!("{k} {:.1} Hz: {}", m.frequency_hz, per.join(" "));
    }
}
