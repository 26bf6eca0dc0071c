//! An installed binary works anywhere: the built-in reference and its modal data are compiled
//! in, so `washdyn` copied out of the build tree and run from an empty directory checks and runs
//! `reference` (issue 23, point 4; `cargo install --path .` gives the same binary).
//!
//! Three holds, strongest first where the machine allows it:
//! - the copied binary runs from an empty directory (always);
//! - it runs with the checkout hidden: a private mount namespace (`unshare -rm`) with an empty
//!   tmpfs over the workspace root, or, where user namespaces are off, `strace` shows it opens
//!   no file under the root; without either tool the hold is skipped with a note;
//! - no code the binary runs names `CARGO_MANIFEST_DIR` (a tidy check of the source, outside
//!   `#[cfg(test)]` items), which is how the binary used to find the modal data.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The built binary copied into a fresh directory outside the checkout, and an empty working
/// directory beside it.
struct Installed {
    _dir: tempfile::TempDir,
    bin: PathBuf,
    cwd: PathBuf,
}

fn install() -> Installed {
    let dir = tempfile::tempdir().expect("a temporary directory");
    assert!(
        !dir.path().starts_with(root()),
        "the temporary directory {} is inside the checkout",
        dir.path().display()
    );
    let bin = dir.path().join("bin").join("washdyn");
    std::fs::create_dir_all(bin.parent().unwrap()).unwrap();
    std::fs::copy(env!("CARGO_BIN_EXE_washdyn"), &bin).expect("copy the binary");
    let cwd = dir.path().join("empty");
    std::fs::create_dir_all(&cwd).unwrap();
    Installed {
        _dir: dir,
        bin,
        cwd,
    }
}

/// The commands an installed binary must run on `reference`: check, a 0.05 s run (rigid
/// scene) and a 0.02 s run of the elastic scene (every modal file in use), no analysis.
fn commands(out: &Path) -> Vec<Vec<String>> {
    let s = |v: &[&str]| v.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    let out = out.display().to_string();
    vec![
        s(&["check", "reference"]),
        s(&[
            "run",
            "reference",
            "--t-end",
            "0.05",
            "--no-plots",
            "--out",
            &format!("{out}/full"),
        ]),
        s(&[
            "run",
            "reference",
            "--scene",
            "elastic",
            "--t-end",
            "0.02",
            "--no-plots",
            "--backend",
            "interpreted",
            "--out",
            &format!("{out}/elastic"),
        ]),
    ]
}

fn assert_ok(what: &str, out: &Output) {
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_copied_binary_checks_and_runs_the_reference_from_an_empty_directory() {
    let inst = install();
    for args in commands(Path::new("out")) {
        let out = Command::new(&inst.bin)
            .args(&args)
            .current_dir(&inst.cwd)
            .output()
            .expect("start the copied binary");
        assert_ok(&args.join(" "), &out);
        if args[0] == "check" {
            let text = String::from_utf8_lossy(&out.stdout);
            assert!(text.contains("elastic"), "{text}");
        }
    }
    for scene in ["full", "elastic"] {
        let summary = inst.cwd.join("out").join(scene).join("summary.json");
        let json = std::fs::read_to_string(&summary).expect("summary.json written");
        assert!(json.contains("\"status\": \"ok\""), "{json}");
    }
}

/// Whether `tool args` runs here (namespaces may be off, a tool may be missing).
fn works(tool: &str, args: &[&str]) -> bool {
    Command::new(tool)
        .args(args)
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn the_copied_binary_reads_nothing_from_the_checkout() {
    let inst = install();
    let root = root();
    let out_dir = inst.cwd.join("out");
    if works("unshare", &["-rm", "true"]) {
        // Hide the whole checkout behind an empty tmpfs in a private mount namespace.
        for args in commands(&out_dir) {
            let out = Command::new("unshare")
                .args([
                    "-rm",
                    "sh",
                    "-c",
                    "mount -t tmpfs none \"$1\" && shift && exec \"$@\"",
                ])
                .arg("sh")
                .arg(&root)
                .arg(&inst.bin)
                .args(&args)
                .current_dir(&inst.cwd)
                .output()
                .unwrap();
            assert_ok(&format!("{} (checkout hidden)", args.join(" ")), &out);
        }
    } else if works("strace", &["-o", "/dev/null", "true"]) {
        // No namespaces here: trace every file the binary touches instead.
        let log = inst.cwd.parent().unwrap().join("strace.log");
        for args in commands(&out_dir) {
            let out = Command::new("strace")
                .args(["-f", "-e", "trace=%file", "-o"])
                .arg(&log)
                .arg(&inst.bin)
                .args(&args)
                .current_dir(&inst.cwd)
                .output()
                .unwrap();
            assert_ok(&format!("{} (traced)", args.join(" ")), &out);
            let trace = std::fs::read_to_string(&log).unwrap();
            let root = root.display().to_string();
            let touched: Vec<&str> = trace.lines().filter(|l| l.contains(&root)).collect();
            assert!(
                touched.is_empty(),
                "{} touched the checkout:\n{}",
                args.join(" "),
                touched.join("\n")
            );
        }
    } else {
        eprintln!(
            "note: neither `unshare -rm` nor `strace` works here; the checkout was not hidden \
             (the source check below still holds)"
        );
    }
}

/// The lines of `src` outside `#[cfg(test)]` items (brace-counted; enough for this source).
fn outside_tests(src: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut lines = src.lines().enumerate();
    while let Some((i, line)) = lines.next() {
        if line.trim() != "#[cfg(test)]" {
            out.push((i + 1, line));
            continue;
        }
        // Skip the item: up to its closing brace, or its `;` if it has no body.
        let (mut depth, mut opened) = (0i64, false);
        for (_, l) in lines.by_ref() {
            for c in l.chars() {
                match c {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if (opened && depth <= 0) || (!opened && l.trim_end().ends_with(';')) {
                break;
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir)
        .expect("a source directory")
        .flatten()
    {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_code_the_binary_runs_finds_data_through_the_source_tree() {
    // The crates linked into the binary (the macro crate runs at compile time only).
    let mut files = Vec::new();
    for dir in ["models/src", "src", "runtime/src", "fe/src"] {
        rust_files(&root().join(dir), &mut files);
    }
    assert!(files.len() > 50, "found only {} source files", files.len());
    let mut found = Vec::new();
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap();
        if f.file_name().is_some_and(|n| n == "tests.rs") {
            continue; // a `#[cfg(test)] mod tests;` file
        }
        for (line, text) in outside_tests(&src) {
            if text.contains("CARGO_MANIFEST_DIR") {
                let rel = f.strip_prefix(root()).unwrap_or(f);
                found.push(format!("{}:{line}: {}", rel.display(), text.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "code outside tests finds files through the source tree:\n{}",
        found.join("\n")
    );
    // The stripper keeps what it should: the built-in data is compiled in.
    let lib = std::fs::read_to_string(root().join("models/src/lib.rs")).unwrap();
    assert!(
        outside_tests(&lib)
            .iter()
            .any(|(_, l)| l.contains("include_str!(\"../fe/tub.modal.toml\")")),
        "models/src/lib.rs no longer compiles the tub's modal data in"
    );
}

#[test]
fn the_test_stripper_drops_only_test_items() {
    let src = "a\n#[cfg(test)]\nfn t() {\n    x\n}\nb\n#[cfg(test)]\nuse y;\nc\n";
    let kept: Vec<&str> = outside_tests(src).into_iter().map(|(_, l)| l).collect();
    assert_eq!(kept, ["a", "b", "c"]);
}
