//! `washdyn study run | status | collect`: the study's progress bar and report on the terminal;
//! the study itself is `washdyn::study`.

use crate::cli::{StudyCmd, interrupt_flag};
use crate::{Failure, wrote};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::process::ExitCode;
use washdyn::Error;
use washdyn::study;
use washdyn_runtime::run::RunError;

/// Variants whose warnings or errors are printed at most; the rest are counted.
const SHOWN: usize = 10;

/// `washdyn study run | status | collect`.
pub fn study(cmd: StudyCmd) -> Result<ExitCode, Failure> {
    match cmd {
        StudyCmd::Run {
            study: file,
            out,
            jobs,
        } => {
            let mut s = study::Study::load(&file)?;
            s.settings.guard.interrupt = Some(interrupt_flag());
            let out = out.unwrap_or_else(|| s.default_out());
            let jobs =
                jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
            study::check_jobs(jobs)?;
            let plan = study::plan(&s, &out)?;
            let mut stdout = std::io::stdout();
            let _ = writeln!(
                stdout,
                "{}: {} variants, {} to run ({} finished before){}",
                out.display(),
                plan.variants.len(),
                plan.todo.len(),
                plan.variants.len() - plan.todo.len(),
                match plan.removed_tmp {
                    0 => String::new(),
                    n => format!("; removed {n} tmp directories of a killed run"),
                }
            );
            let bar = ProgressBar::new(plan.todo.len() as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} variants [{elapsed_precise}, ETA {eta}] {msg}",
                )
                .expect("valid template"),
            );
            let done = |o: &study::Outcome| {
                bar.inc(1);
                bar.set_message(format!("{}: {}", o.id, o.status));
            };
            let res = study::execute(&s, &plan, jobs, &done)?;
            bar.finish_and_clear();
            // The set-up's own warning (a loose tolerance) is every variant's: said once.
            let common =
                washdyn::accuracy::class::tolerance_warning(s.settings.method, s.settings.tol);
            if let Some(w) = &common {
                eprintln!("warning: {w}");
            }
            // A study's variants often warn alike: the first few here, all in the summaries.
            let warned: Vec<&study::Outcome> = res
                .iter()
                .filter(|o| o.status != "interrupted")
                .filter(|o| o.warnings.iter().any(|w| Some(w) != common.as_ref()))
                .collect();
            for o in warned.iter().take(SHOWN) {
                for w in o.warnings.iter().filter(|w| Some(*w) != common.as_ref()) {
                    eprintln!("warning: variant {}: {w}", o.id);
                }
            }
            if warned.len() > SHOWN {
                eprintln!(
                    "warning: {} more variants warned (the summaries' `warnings` column)",
                    warned.len() - SHOWN
                );
            }
            let failed: Vec<&study::Outcome> =
                res.iter().filter(|o| o.status == "failed").collect();
            for o in failed.iter().take(SHOWN) {
                eprintln!(
                    "variant {} failed: {}",
                    o.id,
                    o.error.as_deref().unwrap_or("")
                );
            }
            let interrupted =
                res.len() < plan.todo.len() || res.iter().any(|o| o.status == "interrupted");
            let _ = writeln!(
                stdout,
                "ran {} variants ({} failed); summaries: {}/summary (washdyn study collect {} \
                 for one table)",
                res.iter().filter(|o| o.status != "interrupted").count(),
                failed.len(),
                out.display(),
                out.display()
            );
            if interrupted {
                let e = Error::integration(RunError::Interrupted { t: 0.0 });
                eprintln!(
                    "interrupted: the finished variants are kept; run the study again to complete it"
                );
                return Err(Failure::Printed(e));
            }
            Ok(if failed.is_empty() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        StudyCmd::Status { dir } => {
            let st = study::status(&dir)?;
            let mut out = std::io::stdout();
            let _ = writeln!(
                out,
                "{}: {} variants: {} done, {} failed, {} missing",
                dir.display(),
                st.total,
                st.done,
                st.failed.len(),
                st.missing.len()
            );
            for (id, e) in &st.failed {
                let _ = writeln!(out, "failed {id}: {e}");
            }
            if !st.missing.is_empty() {
                let _ = writeln!(out, "missing: {}", st.missing.join(", "));
            }
            if st.tmp > 0 {
                let _ = writeln!(
                    out,
                    "{} tmp directories of a killed run (the next `washdyn study run` removes them)",
                    st.tmp
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        StudyCmd::Collect { dir } => {
            let c = study::collect(&dir)?;
            let mut out = std::io::stdout();
            let _ = writeln!(out, "{} rows in variant order", c.rows);
            if !c.missing.is_empty() {
                let _ = writeln!(
                    out,
                    "not in the table (no summary yet): {}",
                    c.missing.join(", ")
                );
            }
            Ok(wrote(c.files))
        }
    }
}
