//! Running CalculiX (`ccx`) on a deck and telling success from failure.
//!
//! ccx exits 0 after many `*ERROR`s and prints its complaints to stdout, mostly without a line
//! number. We scan its output for `*ERROR` (and for warnings that mean a card was ignored), and
//! point at the deck's line where the message names something we can find there: a card image it
//! could not interpret, the keyword it was reading, or the node it did not know.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// How a ccx run failed.
#[derive(Debug, thiserror::Error)]
pub enum CcxError {
    #[error(
        "CalculiX (`{program}`) was not found: install it with `apt-get install calculix-ccx` \
         (Debian/Ubuntu), or set WASHDYN_CCX to its path"
    )]
    Missing { program: String },
    #[error("cannot run CalculiX on {deck}: {source}")]
    Io {
        deck: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}", render(.deck, .messages))]
    Deck {
        deck: PathBuf,
        /// Each error with the deck line it refers to, where known.
        messages: Vec<(Option<usize>, String)>,
    },
}

fn render(deck: &Path, messages: &[(Option<usize>, String)]) -> String {
    messages
        .iter()
        .map(|(line, m)| match line {
            Some(l) => format!("{}:{l}: ccx: {m}", deck.display()),
            None => format!("{}: ccx: {m}", deck.display()),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// What a successful run left: the job's files and ccx's own wall time.
#[derive(Debug, Clone)]
pub struct CcxRun {
    /// `<dir>/<job>` without extension: `.dat`, `.frd` beside it.
    pub job: PathBuf,
    pub wall_s: f64,
    pub stdout: String,
}

impl CcxRun {
    pub fn dat(&self) -> PathBuf {
        self.job.with_extension("dat")
    }
    pub fn frd(&self) -> PathBuf {
        self.job.with_extension("frd")
    }
}

/// The ccx program: `WASHDYN_CCX` or `ccx` on the PATH.
pub fn program() -> String {
    std::env::var("WASHDYN_CCX").unwrap_or_else(|_| "ccx".into())
}

/// Whether ccx can be started.
pub fn available() -> bool {
    Command::new(program())
        .arg("-v")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("This is Version"))
}

/// ccx's version string ("2.20"), if it runs.
pub fn version() -> Option<String> {
    let o = Command::new(program()).arg("-v").output().ok()?;
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let v = text.split("This is Version").nth(1)?;
    Some(v.split_whitespace().next()?.to_string())
}

/// A ccx solve starting or ending, for the observer a program set ([`observe`]).
#[derive(Debug, Clone, Copy)]
pub enum Event<'a> {
    Started { deck: &'a Path },
    Finished { deck: &'a Path, wall_s: f64 },
}

type Observer = Box<dyn Fn(Event<'_>) + Send + Sync>;
static OBSERVER: std::sync::OnceLock<Observer> = std::sync::OnceLock::new();

/// Let `f` hear when each ccx solve starts and ends: a solve runs for minutes deep inside the
/// FE pipelines, and a command's progress says which (once a process; false if already set).
pub fn observe(f: impl Fn(Event<'_>) + Send + Sync + 'static) -> bool {
    OBSERVER.set(Box::new(f)).is_ok()
}

fn tell(e: Event<'_>) {
    if let Some(f) = OBSERVER.get() {
        f(e);
    }
}

/// Run ccx on `deck` (`<dir>/<job>.inp`) in the deck's folder; errors from its output.
pub fn run(deck: &Path) -> Result<CcxRun, CcxError> {
    run_threads(deck, 1)
}

/// `run` on `threads` threads: for a solve whose degenerate pairs nothing compares with
/// another solve (the full-mesh reference's coupled modes only enter its sums over modes).
pub fn run_threads(deck: &Path, threads: usize) -> Result<CcxRun, CcxError> {
    let threads = threads.max(1).to_string();
    let io = |source| CcxError::Io {
        deck: deck.to_path_buf(),
        source,
    };
    let dir = deck.parent().filter(|d| !d.as_os_str().is_empty());
    let dir = dir.unwrap_or(Path::new("."));
    let job = deck
        .file_stem()
        .ok_or_else(|| io(std::io::Error::other("deck has no file name")))?;
    let text = std::fs::read_to_string(deck).map_err(io)?;
    let start = Instant::now();
    tell(Event::Started { deck });
    let out = Command::new(program())
        .arg("-i")
        .arg(job)
        .current_dir(dir)
        // One thread (`run`): ccx's threaded assembly and solvers sum in an order that
        // varies from run to run, and a degenerate mode pair (the drum's) then comes back
        // rotated. One thread makes a solve repeatable, so that field files and modal data
        // from two solves agree (measured: tub frequencies moved in the 9th digit, the drum's
        // pairs turned, between two runs of the same deck).
        .env("OMP_NUM_THREADS", &threads)
        .env("NUMBER_OF_CPUS", &threads)
        .env("CCX_NPROC_STIFFNESS", &threads)
        .env("CCX_NPROC_EQUATION_SOLVER", &threads)
        .env("CCX_NPROC_RESULTS", &threads)
        .output();
    tell(Event::Finished {
        deck,
        wall_s: start.elapsed().as_secs_f64(),
    });
    let out = out.map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => CcxError::Missing { program: program() },
        _ => io(e),
    })?;
    let stdout =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    let messages = errors(&stdout, &text);
    if !messages.is_empty() {
        return Err(CcxError::Deck {
            deck: deck.to_path_buf(),
            messages,
        });
    }
    if !out.status.success() {
        return Err(CcxError::Deck {
            deck: deck.to_path_buf(),
            messages: vec![(None, format!("exited with {}", out.status))],
        });
    }
    Ok(CcxRun {
        job: dir.join(job),
        wall_s: start.elapsed().as_secs_f64(),
        stdout,
    })
}

/// The `*ERROR` messages of a ccx output (each with its continuation lines), and the warnings
/// that a card was not interpreted (ccx then goes on without it: a silent wrong model), each with
/// the deck line it refers to where we can find it.
pub fn errors(stdout: &str, deck: &str) -> Vec<(Option<usize>, String)> {
    let lines: Vec<&str> = stdout.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        let is_error = l.starts_with("*ERROR");
        let ignored_card = l.starts_with("*WARNING") && l.contains("Card image");
        if !(is_error || ignored_card) {
            i += 1;
            continue;
        }
        // The message: this line and its indented continuation lines.
        let mut msg = vec![l.to_string()];
        let mut card = None;
        let mut j = i + 1;
        while j < lines.len() {
            let c = lines[j];
            if c.trim().is_empty() || c.trim_start().starts_with('*') && !c.starts_with("    ") {
                break;
            }
            if msg.last().is_some_and(|m| m.contains("Card image")) {
                card = Some(c.trim().to_string());
            }
            msg.push(c.trim().to_string());
            j += 1;
        }
        // "Card image:" may stand on the next warning line, with the card on the line after.
        if card.is_none() && l.contains("Card image") && j < lines.len() {
            let next = lines[j].trim();
            if let Some(c) = lines
                .get(j + 1)
                .filter(|_| next.starts_with("*WARNING reading the input file. Card image:"))
            {
                card = Some(c.trim().to_string());
                j += 2;
            }
        }
        let text = msg.join(" ");
        let line = card
            .as_deref()
            .and_then(|c| find_line(deck, |d| d.trim().eq_ignore_ascii_case(c)))
            .or_else(|| locate(&text, deck));
        let text = match &card {
            Some(c) if ignored_card => format!("card not understood, ignored: `{c}`"),
            _ => text,
        };
        // The summary line "at least one fatal error message" repeats the others.
        if !text.contains("at least one fatal") {
            out.push((line, text));
        }
        i = j.max(i + 1);
    }
    out
}

/// 1-based line of the first deck line matching `f`.
fn find_line(deck: &str, f: impl Fn(&str) -> bool) -> Option<usize> {
    deck.lines().position(f).map(|i| i + 1)
}

/// The deck line an `*ERROR reading *KEYWORD: ... node N ...` message is about: the data line of
/// that keyword's block that starts with N, or else the keyword line.
fn locate(msg: &str, deck: &str) -> Option<usize> {
    let kw = msg
        .split("*ERROR reading ")
        .nth(1)?
        .split([':', ' '])
        .next()?
        .to_ascii_uppercase();
    let lines: Vec<&str> = deck.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim_start().to_ascii_uppercase().starts_with(&kw))?;
    let node = msg
        .split_whitespace()
        .skip_while(|w| !w.eq_ignore_ascii_case("node"))
        .nth(1)
        .and_then(|w| w.parse::<u64>().ok());
    if let Some(n) = node {
        for (k, l) in lines.iter().enumerate().skip(start + 1) {
            if l.trim_start().starts_with('*') {
                break;
            }
            let first = l.split(',').next().unwrap_or("").trim();
            if first.parse::<u64>().ok() == Some(n) {
                return Some(k + 1);
            }
        }
    }
    Some(start + 1)
}

/// Eigenfrequencies (Hz) from a `.dat` of a `*FREQUENCY` step (the real part's cycles/time
/// column of the eigenvalue table).
pub fn frequencies(dat: &str) -> Vec<f64> {
    let mut out = Vec::new();
    let mut inside = false;
    for l in dat.lines() {
        if l.contains("E I G E N V A L U E   O U T P U T") {
            inside = true;
            continue;
        }
        if !inside {
            continue;
        }
        let f: Vec<&str> = l.split_whitespace().collect();
        match f.first().map(|s| s.parse::<usize>()) {
            Some(Ok(_)) if f.len() >= 4 => {
                if let Ok(hz) = f[3].parse::<f64>() {
                    out.push(hz);
                }
            }
            Some(Ok(_)) | Some(Err(_)) if !out.is_empty() => break,
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_errors_and_their_lines() {
        // ccx 2.20's own messages for a deck whose *BOUNDARY names an unknown node.
        let deck = "*NODE\n1, 0, 0, 0\n*BOUNDARY\n1, 1, 3\n999, 1, 6\n*STEP\n";
        let out = " *ERROR reading *BOUNDARY:\n        node          999  is not defined\n\n \
                   *ERROR in calinput: at least one fatal\n        error message while reading the\n";
        let e = errors(out, deck);
        assert_eq!(e.len(), 1, "{e:?}");
        assert_eq!(e[0].0, Some(5));
        assert!(e[0].1.contains("999"), "{e:?}");
    }

    #[test]
    fn ignored_card_is_an_error_at_its_line() {
        let deck = "*MATERIAL, NAME=STEEL\n*DENSTY\n7850\n";
        let out = " *WARNING in calinput. Card image cannot be inter    preted:\n \
                   *WARNING reading the input file. Card image:\n          *DENSTY\n\n";
        let e = errors(out, deck);
        assert_eq!(e[0].0, Some(2), "{e:?}");
        assert!(e[0].1.contains("*DENSTY"));
    }

    #[test]
    fn eigenvalue_table() {
        let dat = "     E I G E N V A L U E   O U T P U T\n\n MODE NO    EIGENVALUE  ...\n\n      \
                   1   0.1122255E+05   0.1059365E+03   0.1686033E+02   0.0000000E+00\n      \
                   2   0.4464833E+06   0.6681941E+03   0.1063464E+03   0.0000000E+00\n\n";
        assert_eq!(frequencies(dat), vec![16.86033, 106.3464]);
    }
}
