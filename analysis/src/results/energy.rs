//! The energy table of `run --energy` (`energy.parquet` or `.csv`): the balance by category,
//! kept in memory and written when the run ends, and the lines the energy plot draws from it.

use std::io;
use std::path::{Path, PathBuf};

use super::Format;
use super::table::TableWriter;

/// `energy.parquet` (or .csv): the balance by category every `ENERGY_ROW_S` of simulated
/// time: time_s, drum_rpm, kinetic_J, then each category's work since the start (J; drive and
/// gravity as done on the vibration, a stored or dissipated category's work is minus its
/// stored energy or the energy it took), and the residual T - T0 - sum W. A few thousand rows
/// a run-up: kept in memory, written at the end (also when the run fails).
pub struct EnergyRecorder {
    path: PathBuf,
    format: Format,
    pub categories: Vec<washdyn_model::equations::Category>,
    /// time_s, drum_rpm, kinetic_J, the categories' work, residual_J.
    pub cols: Vec<Vec<f64>>,
    /// The run's id, written into the file's metadata.
    pub run_id: Option<String>,
}

impl EnergyRecorder {
    pub fn new(dir: &Path, format: Format) -> EnergyRecorder {
        EnergyRecorder {
            path: dir.join(format!("energy.{}", format.extension())),
            format,
            categories: Vec::new(),
            cols: Vec::new(),
            run_id: None,
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The lines the energy plot shows, from the rows: the drive's work, the kinetic energy,
    /// the energy stored (springs and bearings with the gasket's stiffness; modal strain;
    /// gravity), dissipated by each dissipative element and by modal damping (each as a
    /// positive amount since the start), and the residual T - T0 - sum W.
    pub fn lines(&self) -> (Vec<f64>, Vec<crate::plot::EnergyLine>) {
        use crate::plot::EnergyLine;
        use washdyn_model::equations::Kind;
        let t = self.cols.first().cloned().unwrap_or_default();
        let rows = t.len();
        let col = |i: usize| &self.cols[3 + i];
        let sum = |pick: &dyn Fn(&washdyn_model::equations::Category) -> bool, sign: f64| {
            let mut v = vec![0.0; rows];
            for (i, c) in self.categories.iter().enumerate() {
                if pick(c) {
                    for (x, w) in v.iter_mut().zip(col(i)) {
                        *x += sign * w;
                    }
                }
            }
            v
        };
        let k0 = self
            .cols
            .get(2)
            .and_then(|c| c.first())
            .copied()
            .unwrap_or(0.0);
        let mut lines = vec![
            EnergyLine {
                name: "drive work".into(),
                values: sum(&|c| c.kind == Kind::Drive, 1.0),
            },
            EnergyLine {
                name: "kinetic (T - T0)".into(),
                values: self.cols[2].iter().map(|k| k - k0).collect(),
            },
            EnergyLine {
                name: "stored: elements".into(),
                values: sum(
                    &|c| c.kind == Kind::Stored && !c.name.ends_with("strain"),
                    -1.0,
                ),
            },
            EnergyLine {
                name: "stored: modal strain".into(),
                values: sum(&|c| c.name.ends_with("modal strain"), -1.0),
            },
            EnergyLine {
                name: "gravity (potential)".into(),
                values: sum(&|c| c.kind == Kind::Gravity, -1.0),
            },
            EnergyLine {
                name: "dissipated: modal damping".into(),
                values: sum(&|c| c.name.ends_with("modal damping"), -1.0),
            },
        ];
        for (i, c) in self.categories.iter().enumerate() {
            if c.kind == Kind::Dissipated && !c.name.ends_with("modal damping") {
                lines.push(EnergyLine {
                    name: c.name.clone(),
                    values: col(i).iter().map(|w| -w).collect(),
                });
            }
        }
        lines.push(EnergyLine {
            name: "residual".into(),
            values: self.cols.last().cloned().unwrap_or_default(),
        });
        // Lines that stay zero (a rigid scene's modal strain) say nothing.
        lines.retain(|l| l.values.iter().any(|v| *v != 0.0));
        (t, lines)
    }

    /// Column names: time_s, drum_rpm, kinetic_J, `<category>_J` (spaces as underscores),
    /// residual_J.
    pub fn names(&self) -> Vec<String> {
        let mut names = vec!["time_s".into(), "drum_rpm".into(), "kinetic_J".into()];
        names.extend(
            self.categories
                .iter()
                .map(|c| format!("{}_J", c.name.replace(' ', "_"))),
        );
        names.push("residual_J".into());
        names
    }

    pub(super) fn row(&mut self, t: f64, rpm: f64, kinetic: f64, work: &[f64]) {
        let k0 = self
            .cols
            .get(2)
            .and_then(|c| c.first())
            .copied()
            .unwrap_or(kinetic);
        let residual = kinetic - k0 - work.iter().sum::<f64>();
        let row = [t, rpm, kinetic]
            .into_iter()
            .chain(work.iter().copied())
            .chain([residual]);
        for (c, v) in self.cols.iter_mut().zip(row) {
            c.push(v);
        }
    }

    pub(super) fn finish(&mut self) -> io::Result<()> {
        if self.cols.is_empty() {
            return Ok(());
        }
        let names = self.names();
        let mut metadata: Vec<(String, String)> = names
            .iter()
            .map(|c| {
                let unit = match c.as_str() {
                    "time_s" => "s",
                    "drum_rpm" => "rpm",
                    _ => "J",
                };
                (format!("unit:{c}"), unit.to_string())
            })
            .collect();
        for c in &self.categories {
            metadata.push((
                format!("kind:{}_J", c.name.replace(' ', "_")),
                serde_json::to_string(&c.kind).expect("serialises"),
            ));
        }
        metadata.push((
            "washdyn".into(),
            "energy balance by category (model/src/equations/energy.rs): kinetic energy of the \
             vibration and each category's work since the start; residual = T - T0 - sum of the \
             work"
                .into(),
        ));
        metadata.extend(super::run_id_entry(&self.run_id));
        let mut w = TableWriter::create_f64(&self.path, self.format, &names, &metadata)?;
        let cols: Vec<&[f64]> = self.cols.iter().map(Vec::as_slice).collect();
        w.append_slices(&cols)?;
        w.finish()
    }
}
