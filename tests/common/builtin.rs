//! The built-in tub and drum built with ccx once per test binary, as `washdyn fe modal` builds
//! them (every mode, the correction modes, the drum's prestress, the recovery fields), each on
//! first use: the tub's solve is the suite's longest (285 s of one core), and tests that need
//! only the drum do not wait for it. tests/fields.rs recovers fields from them;
//! tests/fe_bodies.rs holds them against ccx's own mass totals and the committed modal data.

use std::path::PathBuf;
use std::sync::OnceLock;
use washdyn_fe::pipeline::{BodySpec, Report, build};
use washdyn_model::ir::modal::ModalData;

/// One built body: its spec, modal data and report; ccx's files are in `dir()/<spec.name>`,
/// its field file is `dir()/<spec.name>.field.bin`.
pub struct Body {
    pub spec: BodySpec,
    pub data: ModalData,
    pub report: Report,
}

/// The scratch folder of the built bodies.
pub fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("builtin")
}

/// The built-in body `name` ("tub" or "drum"), solved on first use. The caller checks that
/// ccx is there.
pub fn body(name: &str) -> &'static Body {
    static TUB: OnceLock<Body> = OnceLock::new();
    static DRUM: OnceLock<Body> = OnceLock::new();
    let cell = match name {
        "tub" => &TUB,
        "drum" => &DRUM,
        _ => panic!("no built-in body {name} here"),
    };
    cell.get_or_init(|| {
        let spec = washdyn_fe::bodies::builtin()
            .into_iter()
            .find(|b| b.name == name)
            .unwrap();
        let top = dir();
        let (d, field) = (top.join(name), format!("{name}.field.bin"));
        std::fs::remove_dir_all(&d).ok();
        std::fs::create_dir_all(&d).unwrap();
        let (data, report) = build(&spec, &d).unwrap_or_else(|e| panic!("{e}"));
        std::fs::copy(d.join(&field), top.join(&field)).unwrap();
        Body { spec, data, report }
    })
}

/// The tub and the drum, solved side by side (one ccx each) where neither is yet.
pub fn tub_and_drum() -> [&'static Body; 2] {
    std::thread::scope(|s| {
        let drum = s.spawn(|| body("drum"));
        let tub = body("tub");
        [tub, drum.join().unwrap()]
    })
}
