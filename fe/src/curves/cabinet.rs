//! The reference cabinet's side panels (`#[ignore]`d: ccx's modal solve of the cabinet and its
//! nonlinear statics take many minutes). Measured (ccx 2.20, one thread, the machine shared):
//! 24 s for 40 modes, 3-4 min per nonlinear static solve; one mode (37, 105.65 Hz, the most
//! side-panel of the lowest 40) at 1, 2 (fitted) and 1.5 (unseen) sheet thicknesses was
//! refused, fit.residual 0.93: see the notes before trusting curves from it.

use super::{dominant, from_modes, linear_modes};
use crate::bodies::builtin;

/// The side panels' dominant modes among the cabinet's lowest (`WASHDYN_CURVES_MODES`, 2 unless
/// set; paired when more than one), at loads a linear panel would take to 1 and 2 sheet
/// thicknesses (0.7 mm; unseen: 1.5; all scaled by `WASHDYN_CURVES_THICKNESSES`) at the mode's
/// largest displacement, both signs. Writes `<WASHDYN_CURVES_OUT or a temp dir>/
/// cabinet.curves.toml`; prints the chosen modes, the residuals and ccx's times.
#[test]
#[ignore = "ccx on the full cabinet: about 4 min of modal solve and minutes per nonlinear static solve"]
fn cabinet_side_panels() {
    let spec = builtin().into_iter().find(|b| b.name == "cabinet").unwrap();
    let mesh = &spec.mesh;
    let tmp = tempfile::tempdir().unwrap();
    let out = std::env::var("WASHDYN_CURVES_OUT")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|_| tmp.path().to_path_buf());
    // With an output folder, ccx's decks and results stay in its `work` (a refused fit can
    // then be examined); else in the temporary folder.
    let dir = match std::env::var("WASHDYN_CURVES_OUT") {
        Ok(_) => out.join("work"),
        Err(_) => tmp.path().to_path_buf(),
    };
    std::fs::create_dir_all(&dir).unwrap();
    let dir = dir.as_path();
    let t0 = std::time::Instant::now();
    let all = linear_modes("cabinet", mesh, 40, spec.keep, dir).unwrap();
    let modal_s = t0.elapsed().as_secs_f64();
    let mut side: Vec<usize> = mesh
        .parts
        .iter()
        .filter(|p| p.name == "CAB_SIDE")
        .flat_map(|p| p.elements.iter().flatten().copied())
        .collect();
    side.sort_unstable();
    side.dedup();
    let count: usize = std::env::var("WASHDYN_CURVES_MODES").map_or(2, |s| s.parse().unwrap());
    let chosen = dominant(&all, &side, count);
    let peak = |k: usize| {
        all[k]
            .w
            .values()
            .map(|u| u.iter().map(|x| x * x).sum::<f64>().sqrt())
            .fold(0.0, f64::max)
    };
    // `WASHDYN_CURVES_THICKNESSES`: the fitted level in sheet thicknesses (1 unless set; the
    // fit takes it and twice it, the unseen check 1.5 times it).
    let level: f64 =
        std::env::var("WASHDYN_CURVES_THICKNESSES").map_or(1.0, |s| s.parse().unwrap());
    let unit = level * 0.0007 / chosen.iter().map(|&k| peak(k)).fold(0.0, f64::max);
    eprintln!(
        "modal solve {modal_s:.0} s; chosen {chosen:?} at {:?} Hz; level unit {unit:.3e}",
        chosen
            .iter()
            .map(|&k| all[k].frequency_hz)
            .collect::<Vec<_>>()
    );
    let t1 = std::time::Instant::now();
    let (c, report) = from_modes(
        "cabinet",
        mesh,
        all,
        &chosen,
        (&[unit, 2.0 * unit], &[1.5 * unit]),
        count > 1,
        0.05,
        dir,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "{} nonlinear solves: {:?} s ({:.0} s in all); G - E {:.1e}; residual {:.2e}, unseen \
         {:.2e}",
        report.solve_s.len(),
        report.solve_s,
        t1.elapsed().as_secs_f64(),
        report.normalisation,
        c.fit.residual,
        c.fit.unseen_residual
    );
    let text = "# Characteristic curves of the cabinet's side panels (issue 52), written by \
                washdyn-fe's curves::cabinet test (#[ignore]d; cargo test -p washdyn-fe \
                cabinet_side_panels -- --ignored).\n"
        .to_string()
        + &toml::to_string(&c).unwrap();
    std::fs::write(out.join("cabinet.curves.toml"), text).unwrap();
}
