//! `washdyn fields`: its arguments, what it prints, its progress (grids recovered) and what
//! Ctrl-C keeps.

use super::Failure;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::{Arc, Mutex, PoisonError};
use washdyn::Error;

/// `washdyn fields`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// The run's output directory (summary.json, states.parquet).
    pub run: PathBuf,
    /// The model, when the run's was a file (default: the summary's model).
    #[arg(long)]
    pub model: Option<String>,
    /// Instants, s (comma-separated).
    #[arg(long, value_delimiter = ',')]
    pub times: Option<Vec<f64>>,
    /// FROM:TO:STEP, s.
    #[arg(long)]
    pub range: Option<String>,
    /// One drum revolution from this time, s (36 frames).
    #[arg(long)]
    pub revolution: Option<f64>,
    /// Instead of grids: the drum's front-edge deformation over the run against speed
    /// (drum_edge.csv, .png), every STRIDE-th stored sample.
    #[arg(long, value_name = "STRIDE")]
    pub drum_edge: Option<usize>,
    /// Also write the drum-edge plot as SVG.
    #[arg(long)]
    pub svg: bool,
    /// Where `washdyn fe modal` left the field files (<body>.field.bin).
    #[arg(long, default_value = "out/fe/work")]
    pub fe: PathBuf,
    /// Output directory (default: RUN/fields).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn fields(a: Args) -> Result<ExitCode, Failure> {
    let Args {
        run,
        model,
        times,
        range,
        revolution,
        drum_edge,
        svg,
        fe,
        out,
    } = a;
    use washdyn::fields::{Request, Times};
    let request = match (times, range, revolution, drum_edge) {
        (Some(t), None, None, None) => {
            washdyn::fields::check_times("--times", &t).map(|()| Request::Fields(Times::List(t)))
        }
        (None, Some(r), None, None) => parse_range(&r).map(Request::Fields),
        (None, None, Some(t), None) => washdyn::fields::check_times("--revolution", &[t])
            .map(|()| Request::Fields(Times::Revolution(t))),
        (None, None, None, Some(0)) => Err(Error::setting(
            "--drum-edge",
            "--drum-edge: the stride must be at least 1",
        )),
        (None, None, None, Some(stride)) => Ok(Request::DrumEdge { stride, svg }),
        _ => Err(Error::setting(
            "--times",
            "give exactly one of --times, --range, --revolution, --drum-edge",
        )),
    }?;
    let dir = out.clone().unwrap_or_else(|| run.join("fields"));
    // Grids written, of how many, the last.
    let kept = Arc::new(Mutex::new((0, 0, PathBuf::new())));
    let k = kept.clone();
    super::progress::on_interrupt(move || {
        let (n, total, last) = &*k.lock().unwrap_or_else(PoisonError::into_inner);
        match n {
            0 => format!("no grid written yet in {}", dir.display()),
            n => format!(
                "{n} of {total} grids written in {} (the last {}); a body's .pvd collection \
                 comes after its grids",
                dir.display(),
                last.display()
            ),
        }
    });
    let reporter = super::progress::Reporter::new(0);
    reporter.set(None, "reading the run's states and the field files".into());
    let mut frame = |n: usize, total: usize, path: &std::path::Path| {
        *kept.lock().unwrap_or_else(PoisonError::into_inner) = (n, total, path.to_path_buf());
        reporter.set(None, format!("{n} / {total} grids recovered"));
    };
    let w = washdyn::fields::fields_command_with(
        &run,
        model.as_deref(),
        &request,
        &fe,
        out.as_deref(),
        &mut frame,
    )
    .map_err(Error::from)?;
    drop(reporter);
    for n in &w.notes {
        eprintln!("note: {n}");
    }
    println!(
        "wrote {} files, {:.1} MB in {:.2} s",
        w.files.len(),
        w.bytes as f64 / 1e6,
        w.seconds
    );
    if let Some((body, m, node, t)) = w.largest {
        println!(
            "largest displacement {:.4} mm: {body} node {node} at t = {t:.3} s",
            m * 1e3
        );
    }
    if let Some((body, pa, node, t)) = w.peak_stress {
        println!(
            "peak von Mises stress {:.2} MPa: {body} node {node} at t = {t:.3} s",
            pa * 1e-6
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// `FROM:TO:STEP` of `washdyn fields --range`, or the setting refused.
fn parse_range(r: &str) -> Result<washdyn::fields::Times, Error> {
    let refused = || {
        Error::setting(
            "--range",
            format!("--range `{r}`: expected FROM:TO:STEP in seconds"),
        )
    };
    let v: Vec<f64> = r
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| refused())?;
    match v[..] {
        [a, b, dt] => Ok(washdyn::fields::Times::Range(a, b, dt)),
        _ => Err(refused()),
    }
}
