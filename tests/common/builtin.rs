//! The built-in tub and drum built with ccx once per test binary, as `washdyn fe modal` builds
//! them (every mode, the correction modes, the drum's prestress, the recovery fields): the
//! tub's solve is the suite's longest, and two test files need it. tests/fields.rs recovers
//! fields from it; tests/fe_bodies.rs holds it against ccx's own mass totals and the committed
//! modal data.

use std::path::PathBuf;
use std::sync::OnceLock;
use washdyn_fe::pipeline::{BodySpec, Report, build};
use washdyn_runtime::ir::modal::ModalData;

/// One built body: its spec, modal data and report; ccx's files are in
/// `Built::dir/<spec.name>`.
pub struct Body {
    pub spec: BodySpec,
    pub data: ModalData,
    pub report: Report,
}

pub struct Built {
    /// The scratch folder: `<body>.field.bin` for each body, ccx's files in `<body>/`.
    pub dir: PathBuf,
    pub bodies: Vec<Body>,
}

/// The tub and the drum, side by side (one ccx each, in folders of their own). The caller
/// checks that ccx is there.
pub fn tub_and_drum() -> &'static Built {
    static BUILT: OnceLock<Built> = OnceLock::new();
    BUILT.get_or_init(|| {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("builtin");
        std::fs::remove_dir_all(&dir).ok();
        std::fs::create_dir_all(&dir).unwrap();
        let specs = washdyn_fe::bodies::builtin();
        let bodies = std::thread::scope(|s| {
            let jobs: Vec<_> = specs
                .into_iter()
                .take(2)
                .map(|spec| {
                    let (d, name) = (dir.join(&spec.name), format!("{}.field.bin", spec.name));
                    let top = &dir;
                    s.spawn(move || {
                        std::fs::create_dir_all(&d).unwrap();
                        let (data, report) = build(&spec, &d).unwrap_or_else(|e| panic!("{e}"));
                        std::fs::copy(d.join(&name), top.join(&name)).unwrap();
                        Body { spec, data, report }
                    })
                })
                .collect();
            jobs.into_iter().map(|j| j.join().unwrap()).collect()
        });
        Built { dir, bodies }
    })
}
