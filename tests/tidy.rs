//! Documents held to the code (rust-analyzer's tidy tests): every source file or script that
//! README.md, ARCHITECTURE.md and docs/*.md name exists, and every example, bench and script they
//! tell the reader to run is there. A renamed file or a removed example fails here, not in a
//! reader's shell.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file of the repository (relative, with '/'), without build output and VCS data.
fn files() -> Vec<String> {
    fn walk(dir: &Path, base: &Path, out: &mut Vec<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = e.file_name().to_string_lossy().to_string();
            if name == "target" || name.starts_with('.') {
                continue;
            }
            if p.is_dir() {
                walk(&p, base, out);
            } else if let Ok(rel) = p.strip_prefix(base) {
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let mut out = Vec::new();
    walk(&root(), &root(), &mut out);
    out
}

/// The documents: README, ARCHITECTURE and docs/*.md.
fn documents() -> Vec<(String, String)> {
    let mut docs: Vec<PathBuf> = vec![root().join("README.md"), root().join("ARCHITECTURE.md")];
    let mut more: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    more.sort();
    docs.extend(more);
    docs.into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("readable");
            (p.file_name().unwrap().to_string_lossy().to_string(), text)
        })
        .collect()
}

/// Words as a path would be written: letters, digits and `/._-`.
fn tokens(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_alphanumeric() || "/._-".contains(c)))
        .map(|t| t.trim_matches('.'))
        .filter(|t| !t.is_empty())
}

#[test]
fn every_source_file_and_script_a_document_names_exists() {
    let files = files();
    let mut missing = Vec::new();
    let mut checked = 0;
    for (doc, text) in documents() {
        for tok in tokens(&text) {
            let tok = tok.trim_start_matches("./");
            let named = [".rs", ".sh"].iter().any(|x| tok.ends_with(x))
                && tok.chars().next().is_some_and(|c| c.is_alphanumeric());
            if !named {
                continue;
            }
            checked += 1;
            let found = files
                .iter()
                .any(|f| f == tok || f.ends_with(&format!("/{tok}")));
            if !found {
                missing.push(format!("{doc}: {tok}"));
            }
        }
    }
    missing.sort();
    missing.dedup();
    // The documents name files 166 times (measured): far fewer means the scan broke.
    assert!(
        checked >= 50,
        "only {checked} file names found: the scan is broken"
    );
    assert!(
        missing.is_empty(),
        "named but not in the tree: {missing:#?}"
    );
}

#[test]
fn every_example_bench_and_script_a_document_runs_exists() {
    let mut missing = Vec::new();
    let mut seen = 0;
    for (doc, text) in documents() {
        let words: Vec<&str> = text.split_whitespace().collect();
        for w in words.windows(2) {
            let name = w[1].trim_matches(|c: char| !(c.is_alphanumeric() || "/._-".contains(c)));
            let path = match w[0].trim_start_matches('`') {
                "--example" => format!("examples/{name}.rs"),
                "--bench" => format!("benches/{name}.rs"),
                "bash" if name.ends_with(".sh") => name.to_string(),
                _ => continue,
            };
            seen += 1;
            if !root().join(&path).exists() {
                missing.push(format!("{doc}: {} {name} ({path})", w[0]));
            }
        }
    }
    // The documents run examples, benches and scripts 7 times (measured): far fewer means the
    // scan broke.
    assert!(seen >= 4, "only {seen} commands found: the scan is broken");
    assert!(
        missing.is_empty(),
        "documents run what is not there: {missing:#?}"
    );
}
