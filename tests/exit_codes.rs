//! One exit-code table for every command (issue 50 point 7): the code follows the error's
//! cause, not the command that met it. The table is `washdyn --help`'s, and the README shows
//! the same text.

use crate::common;

/// The README's table is the one `washdyn --help` prints (src/cli/mod.rs, EXIT_CODES), line
/// for line.
#[test]
fn the_readme_shows_the_help_table() {
    let out = common::washdyn_in(&["--help"], std::path::Path::new("."));
    let help = String::from_utf8_lossy(&out.stdout);
    let table = &help[help.find("Exit codes").expect("a table in --help")..];
    let table = table.trim_end();
    assert!(table.lines().count() >= 8, "{table}");
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    assert!(
        readme.contains(table),
        "README.md lacks --help's table:\n{table}"
    );
}

fn code(args: &[&str], dir: &std::path::Path) -> (Option<i32>, String) {
    let o = common::washdyn_in(args, dir);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A model that is neither built in nor a file is 3 under every command that takes one (before,
/// `modes`, `campbell`, `fields` and `fe reference` gave 5); an `--out` that is a file is 4 for
/// `run` and `analyse` alike (before, `analyse` gave 5).
#[test]
fn one_cause_one_code_whichever_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let no_model = "no_such_model";
    for args in [
        vec!["run", no_model, "--out", "r"],
        vec!["modes", no_model, "--out", "m"],
        vec!["campbell", no_model, "--out", "c"],
        vec![
            "fe",
            "reference",
            "--model",
            no_model,
            "--out",
            "f",
            "--work",
            "w",
        ],
    ] {
        let (c, err) = code(&args, d);
        assert_eq!(c, Some(3), "{args:?}: {err}");
        assert!(err.contains("neither a built-in model"), "{args:?}: {err}");
    }
    // A short run with its states gives `fields` and `analyse` a run to read (0.3 s: longer
    // than the analysis' shortest block).(0.3 s: longer
    // than the analysis' shortest block).
    let (c, err) = code(
        &[
            "run",
            "reference",
            "--t-end",
            "0.3",
            "--states",
            "--no-plots",
            "--out",
            "run",
        ],
        d,
    );
    assert_eq!(c, Some(0), "{err}");
    let (c, err) = code(
        &[
            "fields", "run", "--times", "0.01", "--model", no_model, "--out", "fl",
        ],
        d,
    );
    assert_eq!(c, Some(3), "fields: {err}");
    std::fs::write(d.join("file"), "not a folder").unwrap();
    for args in [
        vec![
            "run",
            "reference",
            "--t-end",
            "0.05",
            "--no-plots",
            "--out",
            "file",
        ],
        vec!["analyse", "run/sensors.parquet", "--out", "file"],
    ] {
        let (c, err) = code(&args, d);
        assert_eq!(c, Some(4), "{args:?}: {err}");
    }
    // Nothing was written by the refused commands.
    for out in ["r", "m", "c", "f", "fl"] {
        assert!(!d.join(out).exists(), "{out} was written");
    }
}
