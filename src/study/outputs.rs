//! What each variant reports beside its parameters, one number a column, the same columns for
//! every variant of a study (fixed by the base model's scene before anything runs, so the
//! partitions share one schema):
//! - `peak_tub_rotation_rad`, `peak_tub_translation_m`, `peak_door_ring_m`: the largest tub
//!   rotation |alpha|, translation |u| and door-ring excursion over the run, as the validity
//!   monitor measured them (`Summary::validity`, runtime/src/clearance.rs); the door ring is
//!   null where the scene watches none;
//! - `<channel>_order<k>_peak` and `..._peak_rpm`: per sensor channel and drum order 1 and 2,
//!   the largest amplitude of the order track over the run (angle-domain tracks of
//!   `washdyn-analysis`, as `washdyn sweep`'s order-1 peaks) and the drum speed where it is;
//! - `top_speed_rpm`, `<cabinet channel>_top_rms`, `..._top_order1`: at top speed (the last
//!   analysis block whose mean speed is within 5 % of the run's highest), each cabinet
//!   channel's RMS about its mean and its order-1 amplitude there.
//!
//! A failed variant's outputs are all null: a peak up to a failure is not the run's peak.

use crate::analysis::{AnalysisOptions, Channel, RunUp, Signals};
use crate::results::unit_of_column;
use crate::simulation::Simulation;
use serde::Serialize;
use washdyn_model::ir::BodyRef;
use washdyn_runtime::run::Summary;

/// Drum orders whose peaks each channel reports.
pub const ORDERS: [f64; 2] = [1.0, 2.0];

/// A window is at top speed when its mean drum speed is at least this share of the run's top.
pub const TOP_SPEED_SHARE: f64 = 0.95;

/// Analysis block, s: order tracks every half block (50 % overlap), each from 8 whole drum
/// revolutions about the block's centre (`AnalysisOptions::order_block_revs`).
const BLOCK_S: f64 = 1.0;

/// The study's output columns: the scene's channels, its cabinet channels, whether the door
/// ring is watched.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Outputs {
    pub channels: Vec<String>,
    pub cabinet: Vec<String>,
    pub door_ring: bool,
}

/// A peak column's name.
pub fn peak_column(channel: &str, order: f64) -> String {
    format!("{channel}_order{order}_peak")
}

impl Outputs {
    /// The columns of a simulation (the base model's: every variant has the same channels).
    pub fn new(sim: &Simulation) -> Outputs {
        let channels = sim.channel_names();
        let cabinet = sim
            .model()
            .sensors
            .iter()
            .filter(|s| s.body == BodyRef::Cabinet)
            .flat_map(|s| s.channels())
            .filter(|c| channels.contains(c))
            .collect();
        Outputs {
            channels,
            cabinet,
            door_ring: sim.guard.watch.door_ring.is_some(),
        }
    }

    /// Every output column with its unit, in the summary's order.
    pub fn columns(&self) -> Vec<(String, &'static str)> {
        let mut c = vec![
            ("peak_tub_rotation_rad".to_string(), "rad"),
            ("peak_tub_translation_m".to_string(), "m"),
            ("peak_door_ring_m".to_string(), "m"),
        ];
        for ch in &self.channels {
            for o in ORDERS {
                let p = peak_column(ch, o);
                c.push((p.clone(), unit_of_column(ch)));
                c.push((format!("{p}_rpm"), "rpm"));
            }
        }
        c.push(("top_speed_rpm".to_string(), "rpm"));
        for ch in &self.cabinet {
            c.push((format!("{ch}_top_rms"), unit_of_column(ch)));
            c.push((format!("{ch}_top_order1"), unit_of_column(ch)));
        }
        c
    }

    /// The columns a Pareto plot may name: the outputs and the run's cost.
    pub fn plottable(&self) -> Vec<String> {
        let mut v: Vec<String> = self.columns().into_iter().map(|(n, _)| n).collect();
        v.extend(["steps", "rhs_evals", "wall_time_s"].map(String::from));
        v
    }

    /// The outputs in a sentence, for an error that names an unknown one.
    pub fn describe(&self) -> String {
        let mut s = "outputs: peak_tub_rotation_rad, peak_tub_translation_m, peak_door_ring_m, \
                     top_speed_rpm, steps, rhs_evals, wall_time_s, and per channel \
                     <channel>_order1_peak, _order2_peak with their _rpm"
            .to_string();
        if !self.cabinet.is_empty() {
            s += ", per cabinet channel <channel>_top_rms, <channel>_top_order1";
        }
        s + &format!("; channels: {}", self.channels.join(", "))
    }

    /// Nulls in every column: a variant that failed.
    pub fn none(&self) -> Vec<f64> {
        vec![f64::NAN; self.columns().len()]
    }

    /// The outputs of a finished run from its summary and its samples (`names`: time_s,
    /// drum_rpm, then the channels; `cols` alike), in [`Outputs::columns`]' order.
    pub fn values(
        &self,
        summary: &Summary,
        names: &[String],
        cols: &[Vec<f64>],
        sample_rate: f64,
    ) -> Vec<f64> {
        let v = &summary.validity;
        let mut out = vec![
            v.max_rotation_rad,
            v.max_translation_m,
            if self.door_ring {
                v.max_door_ring_m
            } else {
                f64::NAN
            },
        ];
        let tracks = Tracks::new(names, cols, sample_rate);
        let runs: Vec<Option<RunUp>> = self
            .channels
            .iter()
            .map(|ch| tracks.as_ref().and_then(|t| t.analyse(ch)))
            .collect();
        for run in &runs {
            for o in ORDERS {
                let peak = run.as_ref().and_then(|r| {
                    r.tracks
                        .iter()
                        .find(|t| t.order == o)
                        .and_then(|t| t.max(&r.blocks))
                });
                match peak {
                    // A channel at zero throughout peaks nowhere.
                    Some((a, rpm)) => out.extend([a, if a > 0.0 { rpm } else { f64::NAN }]),
                    None => out.extend([f64::NAN, f64::NAN]),
                }
            }
        }
        // Every channel has the same blocks: the first one's say where top speed is.
        let top = tracks
            .as_ref()
            .zip(runs.iter().flatten().next())
            .and_then(|(t, r)| t.top_block(r));
        out.push(top.as_ref().map_or(f64::NAN, |(_, rpm, _)| *rpm));
        for ch in &self.cabinet {
            let at_top = top
                .as_ref()
                .zip(tracks.as_ref())
                .and_then(|((k, _, range), t)| {
                    let w = &t.data(ch)?[range.clone()];
                    let mean = w.iter().sum::<f64>() / w.len() as f64;
                    let rms =
                        (w.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / w.len() as f64).sqrt();
                    let i = self.channels.iter().position(|c| c == ch)?;
                    let order1 = runs[i]
                        .as_ref()
                        .and_then(|r| r.tracks.iter().find(|t| t.order == 1.0)?.amplitude[*k]);
                    Some((rms, order1.unwrap_or(f64::NAN)))
                });
            let (rms, o1) = at_top.unwrap_or((f64::NAN, f64::NAN));
            out.extend([rms, o1]);
        }
        out
    }
}

/// A run's samples ready for order tracks.
struct Tracks {
    signals: Signals,
    opts: AnalysisOptions,
}

impl Tracks {
    fn new(names: &[String], cols: &[Vec<f64>], sample_rate: f64) -> Option<Tracks> {
        let (t, rpm) = (cols.first()?, cols.get(1)?);
        let channels = names
            .iter()
            .zip(cols)
            .skip(2)
            .map(|(n, d)| Channel::new(n.clone(), d.clone()))
            .collect();
        let signals =
            Signals::from_uniform(*t.first()?, sample_rate, rpm.clone(), channels).ok()?;
        let opts = AnalysisOptions {
            block_length_s: BLOCK_S,
            track_orders: ORDERS.to_vec(),
            motor_orders: 0,
            cascades: false,
            svg: false,
            ..AnalysisOptions::default()
        };
        Some(Tracks { signals, opts })
    }

    fn data(&self, channel: &str) -> Option<&[f64]> {
        self.signals.channel(channel).map(|c| c.data.as_slice())
    }

    /// The channel's order tracks; `None` where the run is too short for one block.
    fn analyse(&self, channel: &str) -> Option<RunUp> {
        let c = self.signals.channel(channel)?;
        RunUp::analyse(&self.signals, c, &self.opts).ok()
    }

    /// The last block of `run` at top speed: its index, mean speed and samples.
    fn top_block(&self, run: &RunUp) -> Option<(usize, f64, std::ops::Range<usize>)> {
        let s = &self.signals;
        let top = s.drum_rpm.iter().fold(0.0f64, |m, r| m.max(r.abs()));
        let k = run
            .blocks
            .iter()
            .rposition(|b| top > 0.0 && b.rpm >= TOP_SPEED_SHARE * top)?;
        let start = run.layout.starts(s.len()).nth(k)?;
        Some((k, run.blocks[k].rpm, start..start + run.layout.len))
    }
}
