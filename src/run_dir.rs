//! A run owns its output folder. The run writes into a fresh folder beside the target
//! (`<target>.tmp-<id>`) and renames it into place when it ends (ok, failed or interrupted),
//! so a folder never mixes two runs' files; a target that holds files is refused before
//! anything runs unless `--force` replaces it. Every file carries the run's id (summary.json's
//! `run_id`, the Parquet files' key-value metadata `washdyn.run_id`), and the commands that
//! read a run (`fields`, `compare`, `analyse`) refuse files whose ids disagree.

use crate::error::{Error, OtherRun};
use crate::spec::Field;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

pub use crate::results::RUN_ID_KEY;

/// A run's id: its UTC start time and a suffix unique on this machine
/// (`20261129T195500Z-1a2b3c4d`): sortable, readable, and distinct for runs started in the
/// same second (the process id and a counter).
pub fn new_run_id() -> String {
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap_or_default();
    let n = COUNT.fetch_add(1, Ordering::Relaxed);
    let mix = (u64::from(std::process::id()) << 32) ^ u64::from(now.subsec_nanos()) ^ (n << 48);
    format!(
        "{}-{:08x}",
        utc_stamp(now.as_secs()),
        mix as u32 ^ (mix >> 32) as u32
    )
}

/// `YYYYMMDDThhmmssZ` of seconds since 1970 (Hinnant's days-to-civil; no date crate needed).
fn utc_stamp(secs: u64) -> String {
    let (days, s) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}T{:02}{:02}{:02}Z",
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

/// The folder a run writes into, and where it goes when the run ends.
#[derive(Debug)]
pub struct RunDir {
    pub id: String,
    /// Where the files are while the run goes.
    pub tmp: PathBuf,
    /// Where they go when it ends.
    pub target: PathBuf,
    force: bool,
}

impl RunDir {
    /// Claim `target` for run `id`: refused ([`Field::Force`]) where it holds files, unless
    /// `force`; the fresh folder beside it is created.
    pub fn claim(target: &Path, id: &str, force: bool) -> Result<RunDir, Error> {
        if target.is_file() {
            return Err(Error::io(
                "use as the output folder",
                target,
                std::io::Error::other("it is a file"),
            ));
        }
        if !force && holds_files(target) {
            return Err(Error::setting(
                Field::Force,
                format!(
                    "{} holds {}: give --force to replace it, or --out another folder",
                    target.display(),
                    describe(target)
                ),
            ));
        }
        let name = target
            .file_name()
            .map_or("run".into(), |n| n.to_string_lossy().to_string());
        let tmp = target.with_file_name(format!("{name}.tmp-{id}"));
        fs::create_dir_all(&tmp).map_err(|e| Error::io("create", &tmp, e))?;
        Ok(RunDir {
            id: id.to_string(),
            tmp,
            target: target.to_path_buf(),
            force,
        })
    }

    /// Rename the run's folder into place; with `--force`, what stood there goes (moved aside
    /// first, so the target is never half the old run and half the new).
    pub fn publish(&self) -> Result<PathBuf, Error> {
        let aside = self.target.with_file_name(format!(
            "{}.old-{}",
            self.target
                .file_name()
                .map_or("run".into(), |n| n.to_string_lossy()),
            self.id
        ));
        let replaced = self.target.exists();
        if replaced {
            if !self.force && holds_files(&self.target) {
                return Err(Error::setting(
                    Field::Force,
                    format!(
                        "{} was filled while the run went ({}): the run is kept in {}",
                        self.target.display(),
                        describe(&self.target),
                        self.tmp.display()
                    ),
                ));
            }
            fs::rename(&self.target, &aside).map_err(|e| Error::io("move aside", &aside, e))?;
        }
        fs::rename(&self.tmp, &self.target)
            .map_err(|e| Error::io("rename into place", &self.target, e))?;
        if replaced {
            fs::remove_dir_all(&aside).map_err(|e| Error::io("remove", &aside, e))?;
        }
        Ok(self.target.clone())
    }
}

/// Whether `dir` is a folder with anything in it.
fn holds_files(dir: &Path) -> bool {
    fs::read_dir(dir).is_ok_and(|mut d| d.next().is_some())
}

/// What a folder holds, for a refusal: the run of its summary.json, or its file count.
fn describe(dir: &Path) -> String {
    let summary = fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    match summary {
        Some(s) => format!(
            "the run {} ({} / {}, {})",
            s.get("run_id")
                .and_then(|v| v.as_str())
                .unwrap_or("of an older washdyn"),
            s.get("model").and_then(|v| v.as_str()).unwrap_or("?"),
            s.get("scene").and_then(|v| v.as_str()).unwrap_or("?"),
            s.get("status").and_then(|v| v.as_str()).unwrap_or("?"),
        ),
        None => format!(
            "{} files of something else",
            fs::read_dir(dir).map_or(0, |d| d.count())
        ),
    }
}

/// The run id a result file carries: Parquet's key-value metadata; none for CSV or a file of
/// an older washdyn.
pub fn file_run_id(path: &Path) -> Option<String> {
    if path.extension().is_none_or(|e| e != "parquet") {
        return None;
    }
    crate::results::read_metadata(path)
        .ok()?
        .into_iter()
        .find(|(k, _)| k == RUN_ID_KEY)
        .map(|(_, v)| v)
}

/// The run id of `dir`'s summary.json.
pub fn summary_run_id(dir: &Path) -> Option<String> {
    let text = fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v.get("run_id")?.as_str().map(String::from)
}

/// Refuse `file` when its run id and its folder's summary.json's disagree, naming both. A
/// file or summary without an id (CSV, an older washdyn) passes: there is nothing to compare.
pub fn check_same_run(dir: &Path, file: &Path) -> Result<(), OtherRun> {
    match (summary_run_id(dir), file_run_id(file)) {
        (Some(s), Some(f)) if s != f => Err(OtherRun {
            file: file.to_path_buf(),
            file_id: f,
            summary: dir.join("summary.json"),
            summary_id: s,
        }),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    /// Known instants (`date -u -d @SECS +%Y%m%dT%H%M%SZ`).
    #[test]
    fn utc_stamps_match_date() {
        assert_eq!(super::utc_stamp(0), "19700101T000000Z");
        assert_eq!(super::utc_stamp(951_782_400), "20000229T000000Z");
        assert_eq!(super::utc_stamp(1_796_009_700), "20261130T033500Z");
    }
}
