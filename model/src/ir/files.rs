//! Where a model's data files (modal data, a speed CSV) come from: the file system, relative to
//! the model file, or texts compiled into the binary (the built-in reference, so that an
//! installed binary needs no source tree). Both loaders read them through `DataFiles::read`,
//! and every error names the file: an absolute path on disk, or the embedded file's origin.

use std::borrow::Cow;
use std::path::{Path as FsPath, PathBuf};

/// A data file compiled into the binary, under the name a model file gives it.
#[derive(Clone, Copy, Debug)]
pub struct Embedded {
    /// The name as the model writes it (`file = "../fe/tub.modal.toml"`).
    pub name: &'static str,
    /// What errors call it: where it was compiled from, e.g. `built-in models/fe/tub.modal.toml`.
    pub origin: &'static str,
    pub text: &'static str,
}

/// The source of a model's data files.
#[derive(Clone, Copy, Debug)]
pub enum DataFiles<'a> {
    /// On disk, relative to this directory (the model file's); errors name the absolute path.
    Dir(&'a FsPath),
    /// On disk, relative to this directory (the declaring crate's, for `machine!`); errors name
    /// the file as the declaration writes it, since the compiler points at that text.
    AsWritten(&'a FsPath),
    /// Only these compiled-in texts; a name not among them is an error (nothing is read from
    /// disk).
    Embedded(&'a [Embedded]),
}

/// One data file's text and the name errors give it.
#[derive(Clone, Debug)]
pub struct DataFile<'a> {
    /// An absolute path, or an embedded file's origin.
    pub shown: String,
    /// The path read, for a file on disk (the macro makes cargo watch it).
    pub path: Option<PathBuf>,
    pub text: Cow<'a, str>,
}

impl<'a> DataFiles<'a> {
    /// The file a model names `name`, as errors name it (an absolute path on disk, made so
    /// without touching the file system, or the embedded file's origin).
    pub fn shown(&self, name: &str) -> String {
        match self {
            DataFiles::Dir(base) => absolute(&base.join(name)).display().to_string(),
            DataFiles::AsWritten(_) => name.to_string(),
            DataFiles::Embedded(table) => table
                .iter()
                .find(|e| e.name == name)
                .map_or_else(|| format!("built-in {name}"), |e| e.origin.to_string()),
        }
    }

    /// Read the file the model names `name`; the error names it and says why.
    pub fn read(&self, name: &str) -> Result<DataFile<'a>, FileError> {
        let shown = self.shown(name);
        match self {
            DataFiles::Dir(base) | DataFiles::AsWritten(base) => {
                let path = base.join(name);
                match std::fs::read_to_string(&path) {
                    Ok(text) => Ok(DataFile {
                        shown,
                        path: Some(path),
                        text: Cow::Owned(text),
                    }),
                    Err(e) => Err(FileError {
                        shown,
                        why: format!("cannot read: {e}"),
                    }),
                }
            }
            DataFiles::Embedded(table) => match table.iter().find(|e| e.name == name) {
                Some(e) => Ok(DataFile {
                    shown,
                    path: None,
                    text: Cow::Borrowed(e.text),
                }),
                None => Err(FileError {
                    shown,
                    why: format!(
                        "not among the built-in data files ({})",
                        table.iter().map(|e| e.name).collect::<Vec<_>>().join(", ")
                    ),
                }),
            },
        }
    }
}

/// A data file that could not be read: which (as `DataFiles::shown`) and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{shown}: {why}")]
pub struct FileError {
    pub shown: String,
    pub why: String,
}

/// A file a run used, by absolute path, and a hash of its content (FNV-1a, 64 bits, in hex:
/// change detection, not a signature).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FileHash {
    pub path: String,
    pub fnv1a64: String,
}

/// FNV-1a (64 bits) of `bytes`, as 16 hex digits.
pub fn content_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

impl FileHash {
    /// Hash the file at `path` (kept absolute).
    pub fn of(path: &FsPath) -> Result<FileHash, String> {
        let abs = absolute(path);
        let bytes =
            std::fs::read(&abs).map_err(|e| format!("{}: cannot read: {e}", abs.display()))?;
        Ok(FileHash {
            path: abs.display().to_string(),
            fnv1a64: content_hash(&bytes),
        })
    }

    /// Is the file still as hashed? The error names it.
    pub fn unchanged(&self) -> Result<(), String> {
        let now = FileHash::of(FsPath::new(&self.path))?;
        if now.fnv1a64 != self.fnv1a64 {
            return Err(format!(
                "{}: changed since the run (content hash {} then, {} now)",
                self.path, self.fnv1a64, now.fnv1a64
            ));
        }
        Ok(())
    }
}

/// A model file loaded from `path` and the data files it names (modal data, a speed CSV),
/// hashed: the model file first.
pub fn model_files(path: &FsPath, model: &super::Model) -> Result<Vec<FileHash>, String> {
    let base = path.parent().unwrap_or(FsPath::new(""));
    let mut out = vec![FileHash::of(path)?];
    for e in &model.elastic {
        out.push(FileHash::of(&base.join(&e.file))?);
    }
    if let Some(csv) = &model.speed.csv {
        out.push(FileHash::of(&base.join(csv))?);
    }
    Ok(out)
}

/// `p` made absolute against the working directory (unchanged if that fails).
fn absolute(p: &FsPath) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_files_are_found_by_name_and_errors_name_them() {
        let table = [Embedded {
            name: "../fe/a.modal.toml",
            origin: "built-in models/fe/a.modal.toml",
            text: "x = 1",
        }];
        let files = DataFiles::Embedded(&table);
        let f = files.read("../fe/a.modal.toml").unwrap();
        assert_eq!(f.text, "x = 1");
        assert_eq!(f.shown, "built-in models/fe/a.modal.toml");
        assert!(f.path.is_none());
        let e = files.read("../fe/b.modal.toml").unwrap_err().to_string();
        assert!(
            e.starts_with("built-in ../fe/b.modal.toml: not among the built-in data files"),
            "{e}"
        );
    }

    #[test]
    fn content_hash_is_fnv1a() {
        // The published FNV-1a 64 test vectors.
        assert_eq!(content_hash(b""), "cbf29ce484222325");
        assert_eq!(content_hash(b"a"), "af63dc4c8601ec8c");
        assert_eq!(content_hash(b"foobar"), "85944171f73967e8");
    }

    #[test]
    fn a_changed_file_is_named() {
        let p = std::env::temp_dir().join(format!("washdyn-hash-{}.toml", std::process::id()));
        std::fs::write(&p, "a = 1").unwrap();
        let h = FileHash::of(&p).unwrap();
        assert!(h.unchanged().is_ok());
        std::fs::write(&p, "a = 2").unwrap();
        let e = h.unchanged().unwrap_err();
        assert!(
            e.starts_with(&format!("{}: changed since the run", p.display())),
            "{e}"
        );
        std::fs::remove_file(&p).ok();
    }

    #[test]
    fn files_on_disk_are_named_by_absolute_path() {
        let e = DataFiles::Dir(FsPath::new("no/such"))
            .read("x.modal.toml")
            .unwrap_err()
            .to_string();
        let shown = e.split(": cannot read").next().unwrap();
        assert!(FsPath::new(shown).is_absolute(), "{e}");
        assert!(shown.ends_with("no/such/x.modal.toml"), "{e}");
    }
}
