//! `machine!` rejects broken machines at compile time, each error at the offending token.
//! Cases: `tests/ui/*.rs`, expected output beside each in `.stderr`
//! (regenerate with `TRYBUILD=overwrite`, then read them). The cases use the reference machine's
//! files (`../models/data`, `../models/fe`) as bases, staged beside the case crate.

use std::path::{Path, PathBuf};

/// trybuild compiles the cases in its own crate under the target directory, so that crate's
/// `CARGO_MANIFEST_DIR` is where `machine!` resolves base files: stage the fixture files there.
fn stage_fixtures() {
    let target = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("CARGO_TARGET_TMPDIR is <target>/tmp");
    let project = target.join("tests/trybuild/washdyn-macros/ui-data");
    std::fs::create_dir_all(&project).expect("create the trybuild project's ui-data");
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = std::fs::read_dir(here.join("tests/ui-data"))
        .expect("tests/ui-data")
        .map(|e| e.expect("dir entry").path())
        .collect();
    let models = here.join("../models");
    files.push(models.join("data/reference.toml"));
    for f in files {
        std::fs::copy(&f, project.join(f.file_name().expect("a file"))).expect("copy fixture");
    }
    // The reference's modal data and curves, where its `../fe/` paths point from ui-data.
    let fe = project.parent().expect("ui-data has a parent").join("fe");
    std::fs::create_dir_all(&fe).expect("create the trybuild project's fe");
    let files = ["tub", "tub_bare", "drum", "cabinet"]
        .map(|body| format!("{body}.modal.toml"))
        .into_iter()
        .chain(["cabinet.curves.toml".to_string()]);
    for name in files {
        std::fs::copy(models.join("fe").join(&name), fe.join(&name)).expect("copy modal data");
    }
}

#[test]
fn ui() {
    stage_fixtures();
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
