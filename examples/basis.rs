//! Each body's basis against every mode of its FE model to 2 kHz (issue 21): the receptances
//! between the `elastic` scene's element load points on the body and to its sensors
//! (`washdyn::basis`), over the order band (150 Hz: drum orders 1-6 at 1400 rpm) and the
//! analysis band (300 Hz), for the committed modal data as the scenes cut it and for the 2 kHz
//! data cut the same way. The deep data first:
//! `cargo run --release -p washdyn-fe --example modes_2k -- drum 262 2000 DIR spin` (262
//! eigenmodes to 1972 Hz and the 3 correction modes; ccx 785-1160 s) and `... -- cabinet 400
//! 2000 DIR` (400 modes reach 772 Hz, ccx 830 s; its 40 mm shells resolve the panels' bending
//! to about 700 Hz, so modes to 2 kHz of this mesh would not be the cabinet's); the tub's
//! committed data already reaches 1916 Hz. Then
//! `cargo run --release --example basis -- DIR > docs/truncation-bodies.md`.

use washdyn::accuracy::TRUNCATION_CUTS_HZ;
use washdyn::analysis::metrics::BAND_HZ;
use washdyn::basis::{Damped, basis_error, cut, grid, ports};
use washdyn_model::ir::BodyRef;
use washdyn_model::ir::modal::{ModalData, read_file};

/// Drum order 6 at 1400 rpm is 140 Hz: the orders the order plots show.
const ORDER_BAND_HZ: f64 = 150.0;

fn main() -> Result<(), String> {
    let dir = std::env::args()
        .nth(1)
        .ok_or("usage: basis DIR (the modes_2k data)")?;
    let model = washdyn_models::reference();
    let scene = model.scene(Some("elastic")).map_err(|e| format!("{e:?}"))?;
    println!("# Each body's modal basis against its modes to 2 kHz\n");
    println!(
        "Regenerate: `cargo run --release --example basis -- DIR > docs/truncation-bodies.md` \
         (examples/basis.rs says how DIR is made). Receptances between the `elastic` scene's \
         element load points on each body and from them to its sensors, with the simulation's \
         modal damping, body held at its frame (`washdyn::basis`); error = sqrt(sum |H - H_ref|^2 \
         / sum |H_ref|^2) over all pairs at 1 Hz steps, and the worst output channel's max |H - \
         H_ref| / max |H_ref| (over its inputs and the band). Reference: every eigenmode of the body's FE model to 2 kHz plus its \
         static correction modes. `committed`: the repository's modal data (models/fe) as a \
         scene with that cut keeps it (eigenmodes to the cut, correction modes, the dropped \
         modes' static response to every element load); `2 kHz data`: the same cut of the \
         reference data. The `elastic` scene cuts at 210 Hz, `elastic_fine` at 700 Hz.\n"
    );
    let (fo, fa) = (grid(ORDER_BAND_HZ, 1.0), grid(BAND_HZ, 1.0));
    for body in BodyRef::ALL {
        let Some((e, committed)) = model.modes_in(body, &scene) else {
            continue;
        };
        let path = std::path::Path::new(&dir).join(format!("{}.modal.toml", e.name));
        if !path.exists() {
            println!("({}: no {} in DIR)\n", e.name, path.display());
            continue;
        }
        let reference = read_file(&path, &path.display().to_string())?;
        let committed = committed.clone();
        let (inputs, outputs) = ports(&model, &scene, body, &reference);
        let r = Damped::new(e, &reference);
        let eig = reference.eigenmodes();
        println!(
            "## {} ({} eigenmodes to {:.0} Hz + {} correction; committed: {} to {:.0} Hz + {})\n",
            e.name,
            eig,
            reference.frequencies[eig - 1],
            reference.modes() - eig,
            committed.eigenmodes(),
            committed.frequencies[committed.eigenmodes() - 1],
            committed.modes() - committed.eigenmodes(),
        );
        println!(
            "{} inputs, {} outputs.\n\n| basis | cut Hz | eigenmodes | coordinates | error to \
             {ORDER_BAND_HZ:.0} Hz | worst channel | error to {BAND_HZ:.0} Hz | worst channel | \
             worst channel to {BAND_HZ:.0} Hz |\n|---|---|---|---|---|---|---|---|---|",
            inputs.len(),
            outputs.len()
        );
        let row = |name: &str, cutoff: Option<f64>, d: &ModalData| {
            let t = Damped::new(e, d);
            let (a, b) = (
                basis_error(&r, &t, &outputs, &inputs, &fo),
                basis_error(&r, &t, &outputs, &inputs, &fa),
            );
            println!(
                "| {name} | {} | {} | {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {} |",
                cutoff.map_or("all".into(), |c| format!("{c:.0}")),
                d.eigenmodes(),
                d.modes(),
                a.overall,
                a.worst,
                b.overall,
                b.worst,
                b.worst_output
            );
        };
        row("committed", None, &committed);
        for c in TRUNCATION_CUTS_HZ {
            row("committed", Some(c), &cut(&committed, c, &inputs));
        }
        for c in TRUNCATION_CUTS_HZ {
            row("2 kHz data", Some(c), &cut(&reference, c, &inputs));
        }
        println!();
    }
    Ok(())
}
