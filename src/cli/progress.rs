//! One progress reporter for every long command (`run`, `fe`, `study`, `accuracy`, `fields`):
//! on a terminal an indicatif bar whose message carries the projected end; elsewhere (a Slurm
//! job, a pipe) a plain `progress: ...` line on stderr at least every [`INTERVAL_S`] seconds, so
//! a log says the command is alive and how far it is (indicatif draws nothing there).

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};
use washdyn_runtime::run::{CostFit, Progress};

/// The most seconds between two progress lines when stderr is not a terminal.
pub const INTERVAL_S: f64 = 10.0;

/// Shortens [`INTERVAL_S`] (seconds, at most it), for tests and impatient logs.
pub const INTERVAL_ENV: &str = "WASHDYN_PROGRESS_INTERVAL_S";

/// The interval between lines: [`INTERVAL_ENV`] when it is a positive number up to
/// [`INTERVAL_S`], else [`INTERVAL_S`].
fn interval() -> Duration {
    let s = std::env::var(INTERVAL_ENV)
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| *s > 0.0 && *s <= INTERVAL_S)
        .unwrap_or(INTERVAL_S);
    Duration::from_secs_f64(s)
}

/// The current line: set by the command as it goes, or computed when shown (a ccx solve's
/// elapsed time moves while nothing calls back).
type Line = Box<dyn Fn() -> String + Send>;

#[derive(Default)]
struct State {
    line: Option<Line>,
    stop: bool,
}

type Shared = Arc<(Mutex<State>, Condvar)>;

fn lock(shared: &Shared) -> MutexGuard<'_, State> {
    shared.0.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A command's progress: [`Reporter::set`] as it goes, [`Reporter::say`] for one-off lines;
/// a thread shows the line (on a terminal every second in the bar, else on stderr every
/// interval, the first after at most a second). Dropping it stops the thread, clears the bar.
pub struct Reporter {
    bar: Option<ProgressBar>,
    shared: Shared,
    ticker: Option<std::thread::JoinHandle<()>>,
    started: Instant,
}

impl Reporter {
    /// A bar of `len` steps on a terminal (0: a spinner); a plain line elsewhere.
    pub fn new(len: u64) -> Reporter {
        let terminal = std::io::stderr().is_terminal();
        let bar = terminal.then(|| {
            let (bar, template) = match len {
                0 => (ProgressBar::new_spinner(), "{spinner} {msg}"),
                n => (ProgressBar::new(n), "{bar:40} {msg}"),
            };
            bar.set_style(ProgressStyle::with_template(template).expect("valid template"));
            bar
        });
        let shared: Shared = Arc::default();
        let every = match terminal {
            true => Duration::from_secs(1),
            false => interval(),
        };
        let ticker = {
            let (shared, bar) = (shared.clone(), bar.clone());
            std::thread::spawn(move || tick(&shared, bar.as_ref(), every))
        };
        Reporter {
            bar,
            shared,
            ticker: Some(ticker),
            started: Instant::now(),
        }
    }

    /// Wall time since the reporter started, s.
    pub fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The line now (and the bar's position, on a terminal).
    pub fn set(&self, position: Option<u64>, line: String) {
        if let Some(bar) = &self.bar {
            if let Some(p) = position {
                bar.set_position(p);
            }
            bar.set_message(line.clone());
        }
        lock(&self.shared).line = Some(Box::new(move || line.clone()));
    }

    /// The bar's position (on a terminal), the line left as it is.
    pub fn position(&self, position: u64) {
        if let Some(bar) = &self.bar {
            bar.set_position(position);
        }
    }

    /// A line computed each time it is shown.
    pub fn live(&self, line: impl Fn() -> String + Send + 'static) {
        lock(&self.shared).line = Some(Box::new(line));
    }

    /// One line on stderr now (above the bar on a terminal).
    pub fn say(&self, text: &str) {
        match &self.bar {
            Some(bar) => bar.println(text),
            None => eprintln!("{text}"),
        }
    }
}

impl Drop for Reporter {
    fn drop(&mut self) {
        lock(&self.shared).stop = true;
        self.shared.1.notify_all();
        if let Some(t) = self.ticker.take() {
            let _ = t.join();
        }
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// The reporter's thread: shows the line every `every` (the first after at most a second)
/// until stopped.
fn tick(shared: &Shared, bar: Option<&ProgressBar>, every: Duration) {
    let mut wait = every.min(Duration::from_secs(1));
    let mut st = lock(shared);
    loop {
        let deadline = Instant::now() + wait;
        while !st.stop {
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            st = shared
                .1
                .wait_timeout(st, deadline - now)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
        if st.stop {
            return;
        }
        if let Some(line) = &st.line {
            match bar {
                Some(bar) => bar.set_message(line()),
                None => eprintln!("progress: {}", line()),
            }
        }
        wait = every;
    }
}

/// On Ctrl-C (SIGTERM, SIGHUP) say what was kept, `interrupted: <kept()>`, and exit 130: for
/// the commands that write as they go and have no place to stop between steps.
pub fn on_interrupt(kept: impl Fn() -> String + Send + 'static) {
    let said = ctrlc::set_handler(move || {
        eprintln!("interrupted: {}", kept());
        std::process::exit(130);
    });
    if let Err(e) = said {
        eprintln!("warning: Ctrl-C will not say what was kept: {e}");
    }
}

/// A run's progress line, its projection clocked from the run's first step (a periodic start's
/// iterations and the set-up are no integration work).
#[derive(Default)]
pub struct RunLine {
    /// When the integration was first seen, with its simulated time and swept angle then.
    clock: Option<(Instant, f64, f64)>,
    /// The run's cost model, fitted to its history since then.
    fit: CostFit,
}

impl RunLine {
    /// `t = 12.40 / 178.38 s, drum 420 rpm, 52 311 steps, 35 s wall, projected end in 6 min
    /// 10 s`, with `wall_s` the command's wall time so far.
    pub fn line(&mut self, p: &Progress, wall_s: f64) -> String {
        if let Some((k, r)) = p.start {
            return format!(
                "t = {:.2} / {:.2} s, periodic start at {:.0} rpm: {k} periods, residual {r:.1e} \
                 x tolerance, {} wall",
                p.t,
                p.t_end,
                p.rpm,
                duration(wall_s)
            );
        }
        let (since, t_c, s_c) = *self.clock.get_or_insert((Instant::now(), p.t, p.swept_rad));
        if p.t > t_c {
            let wall = since.elapsed().as_secs_f64();
            self.fit.add(wall, p.t - t_c, p.swept_rad - s_c);
        }
        let projected = self
            .fit
            .remaining_s(p.t_end - p.t, p.swept_end_rad - p.swept_rad);
        format!(
            "t = {:.2} / {:.2} s, drum {:.0} rpm, {} steps, {} wall, projected end {}",
            p.t,
            p.t_end,
            p.rpm,
            grouped(p.steps),
            duration(wall_s),
            match projected {
                Some(s) => format!("in {}", duration(s)),
                None => "not yet known".into(),
            }
        )
    }
}

/// `52 311`: digits in groups of three.
pub fn grouped(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// `35 s`, `6 min 10 s`, `2 h 05 min`.
pub fn duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, s % 3600 / 60),
    }
}
