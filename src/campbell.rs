//! `washdyn campbell`: the spinning drum's frequencies over speed (Coriolis, spin softening,
//! stress stiffening; rotating frame) from its modal data, with the excitation orders drawn in,
//! as a CSV table and a PNG (and SVG) plot.

use crate::analysis::plot::init_fonts;
pub use crate::error::campbell::CampbellError;
use crate::error::{FileError, PlotError};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use washdyn_model::ir::modal::{self, ModalData};

/// Frequencies (Hz) of every mode at each speed (rpm), rotating frame.
#[derive(Debug)]
pub struct Campbell {
    pub rpm: Vec<f64>,
    /// hz[i][k]: speed i, mode k (ascending).
    pub hz: Vec<Vec<f64>>,
}

/// The diagram of a spinning body's modal data from 0 to `max_rpm` in `steps` intervals.
pub fn compute(d: &ModalData, max_rpm: f64, steps: usize) -> Result<Campbell, CampbellError> {
    let kg = d
        .geometric_stiffness
        .as_ref()
        .ok_or(CampbellError::NotSpinning)?;
    let rpm: Vec<f64> = (0..=steps)
        .map(|i| max_rpm * i as f64 / steps as f64)
        .collect();
    let n = d.modes();
    let hz = rpm
        .iter()
        .map(|r| {
            let omega = r * std::f64::consts::PI / 30.0;
            let f = washdyn_fe::rotating::try_campbell(&d.frequencies, &d.elementary, kg, omega)
                .map_err(|source| CampbellError::Eigen { rpm: *r, source })?;
            // Below a divergence speed every mode oscillates; a mode that does not (or a
            // non-symmetric stiffness's spurious pairs) leaves no curve to draw.
            if f.len() != n || f.iter().any(|v| !v.is_finite()) {
                return Err(CampbellError::NotOscillating {
                    rpm: *r,
                    oscillating: f.len(),
                    modes: n,
                });
            }
            Ok(f)
        })
        .collect::<Result<_, CampbellError>>()?;
    Ok(Campbell { rpm, hz })
}

/// Largest motor/drum speed ratio: belt drives of washing machines are 10-20 (the reference
/// 11.25), a direct drive 1; beyond 100 the motor order leaves any plot of drum frequencies.
pub const MAX_MOTOR_RATIO: f64 = 100.0;

/// The drum's modal data, top speed (rpm) and motor ratio from `source`: a `.modal.toml` file,
/// or a model (built-in or file) whose elastic drum it takes, through the one resolver.
fn source_data(source: &str) -> Result<(ModalData, Option<f64>, Option<f64>), CampbellError> {
    if source.ends_with(".modal.toml") {
        let p = Path::new(source);
        let d = modal::read_file(p, source).map_err(CampbellError::ModalFile)?;
        let problems = modal::problems(&d);
        if !problems.is_empty() {
            return Err(CampbellError::Problems {
                file: source.to_string(),
                problems,
            });
        }
        return Ok((d, None, None));
    }
    let (m, _) = crate::commands::resolve_model(source)?;
    let d = m
        .elastic_of(washdyn_model::ir::BodyRef::Drum)
        .and_then(|e| e.data.clone())
        .ok_or_else(|| CampbellError::NoElasticDrum {
            model: m.name.clone(),
        })?;
    let top = m.speed.table.iter().map(|r| r[1]).fold(0.0, f64::max);
    let motor = m.rotor(washdyn_model::ir::MOTOR).map(|r| r.ratio);
    Ok((d, Some(top).filter(|t| *t > 0.0), motor))
}

/// Read `source`, compute, write `campbell.csv` and `campbell.png` (`.svg`) into `out`.
pub fn run(
    source: &str,
    max_rpm: Option<f64>,
    motor_ratio: Option<f64>,
    out: &Path,
    svg: bool,
) -> Result<Vec<PathBuf>, CampbellError> {
    let (d, top, motor) = source_data(source)?;
    let max_rpm = max_rpm.or(top).unwrap_or(1400.0);
    let motor_ratio_arg = motor_ratio;
    let motor_ratio = motor_ratio.or(motor).unwrap_or(11.25);
    if !(max_rpm > 0.0 && max_rpm <= washdyn_model::ir::check::MAX_RPM) {
        return Err(CampbellError::MaxRpm { rpm: max_rpm });
    }
    if !(motor_ratio > 0.0 && motor_ratio <= MAX_MOTOR_RATIO) {
        let what = if motor_ratio_arg.is_some() {
            "--motor-ratio"
        } else {
            "the model's rotor `motor`: ratio"
        };
        return Err(CampbellError::MotorRatio {
            what,
            ratio: motor_ratio,
            max: MAX_MOTOR_RATIO,
        });
    }
    let c = compute(&d, max_rpm, 140)?;
    let io = FileError::at::<CampbellError>;
    let plot = PlotError::at::<CampbellError>;
    std::fs::create_dir_all(out).map_err(io(out))?;
    let csv = out.join("campbell.csv");
    let mut text = String::from("drum_rpm");
    let n = c.hz.first().map_or(0, |v| v.len());
    for k in 0..n {
        text += &format!(",mode_{}_hz", k + 1);
    }
    text.push('\n');
    for (r, f) in c.rpm.iter().zip(&c.hz) {
        text += &format!("{r}");
        for v in f {
            text += &format!(",{v}");
        }
        text.push('\n');
    }
    std::fs::write(&csv, text).map_err(io(&csv))?;
    let mut files = vec![csv];
    init_fonts();
    let png = out.join("campbell.png");
    {
        let root = BitMapBackend::new(&png, (1024, 640)).into_drawing_area();
        draw(&root, &c, motor_ratio).map_err(plot(&png))?;
        root.present().map_err(|e| plot(&png)(e.into()))?;
    }
    files.push(png);
    if svg {
        let p = out.join("campbell.svg");
        {
            let root = SVGBackend::new(&p, (1024, 640)).into_drawing_area();
            draw(&root, &c, motor_ratio).map_err(plot(&p))?;
            root.present().map_err(|e| plot(&p)(e.into()))?;
        }
        files.push(p);
    }
    Ok(files)
}

type PResult = Result<(), Box<dyn std::error::Error + Send + Sync>>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    c: &Campbell,
    motor: f64,
) -> PResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let max_rpm = *c.rpm.last().unwrap_or(&1.0);
    let f_max =
        c.hz.iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(*v))
            .max(1.0)
            * 1.05;
    let mut chart = ChartBuilder::on(root)
        .caption(
            "drum: Campbell diagram (drum frame; Coriolis, spin softening, stiffening)",
            ("sans-serif", 24),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..max_rpm, 0.0..f_max)?;
    chart
        .configure_mesh()
        .x_desc("drum speed [rpm]")
        .y_desc("frequency [Hz]")
        .label_style(("sans-serif", 18))
        .axis_desc_style(("sans-serif", 20))
        .draw()?;
    let n = c.hz.first().map_or(0, |v| v.len());
    for k in 0..n {
        chart.draw_series(LineSeries::new(
            c.rpm
                .iter()
                .zip(&c.hz)
                .filter_map(|(r, f)| f.get(k).map(|v| (*r, *v))),
            BLUE.stroke_width(2),
        ))?;
    }
    // Excitation orders as the stationary frame counts them: drum orders 1 to 3, motor order 1.
    // The frequencies are the drum frame's: a mode with n waves round the drum meets a
    // stationary order k where its frequency equals (k -+ n) x speed, so the lines mark speed
    // ranges, not exact crossings. The drum's own unbalance is static in its frame.
    let orders: Vec<(f64, String)> = vec![
        (1.0, "drum order 1".into()),
        (2.0, "order 2".into()),
        (3.0, "order 3".into()),
        (motor, format!("motor order 1 (= {motor})")),
    ];
    for (o, label) in orders {
        let end = (max_rpm, o * max_rpm / 60.0);
        let end = if end.1 > f_max {
            (f_max * 60.0 / o, f_max)
        } else {
            end
        };
        chart.draw_series(DashedLineSeries::new(
            vec![(0.0, 0.0), end],
            6,
            4,
            RED.stroke_width(1),
        ))?;
        chart.draw_series(std::iter::once(Text::new(
            label,
            (end.0 * 0.97 - max_rpm * 0.12, end.1 * 0.97),
            ("sans-serif", 16).into_font().color(&RED),
        )))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drum() -> ModalData {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fe/drum.modal.toml");
        modal::read_file(&p, "drum.modal.toml").unwrap()
    }

    #[test]
    fn at_rest_the_diagram_starts_at_the_modal_frequencies() {
        // At zero speed the reduced problem is diag(omega_0^2): its frequencies are the file's.
        let d = drum();
        let c = compute(&d, 1400.0, 4).unwrap();
        for (a, b) in c.hz[0].iter().zip(&d.frequencies) {
            assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
        }
        // Modes come in pairs that split with speed (the rocking pair).
        assert!(c.hz[4][1] - c.hz[4][0] > 10.0, "{:?}", c.hz[4]);
    }

    #[test]
    fn refuses_a_body_that_does_not_spin_and_a_bad_speed() {
        let mut d = drum();
        d.geometric_stiffness = None;
        let e = compute(&d, 1400.0, 4).unwrap_err();
        assert!(matches!(e, CampbellError::NotSpinning), "{e}");
        assert!(e.to_string().contains("not a spinning body"), "{e}");
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fe/drum.modal.toml");
        let p = p.to_str().unwrap();
        let e = run(p, Some(-5.0), None, Path::new("/nonexistent"), false).unwrap_err();
        assert!(matches!(e, CampbellError::MaxRpm { rpm: -5.0 }), "{e}");
        assert!(e.to_string().contains("--max-rpm"), "{e}");
    }

    #[test]
    fn a_model_gives_its_drum_top_speed_and_motor_ratio() {
        let (d, top, motor) = source_data("reference").unwrap();
        assert_eq!(d.frequencies, drum().frequencies);
        assert_eq!((top, motor), (Some(1400.0), Some(11.25)));
    }
}
