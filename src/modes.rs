//! `washdyn modes`: the rigid modes of the suspended tub and how much each one strokes the
//! dampers. A damper only damps a mode that moves its ends along its axis (issue 19: with both
//! dampers at x = 0 the conical whirl near 290 rpm did not stroke them), so the table shows,
//! per mode, each damper's axial stroke per unit of the motion that matters, the door ring's.
//!
//! Linearised at rest: the scene's equations on the rigid tub (elastic bodies off), without the
//! unbalances (a load case, not a part of the machine), about the static equilibrium at t = 0
//! with the drum at rest; friction released (f_max = 0: a sliding damper's only stiffness is
//! its bushings'), bushings, springs (with their preload's lateral stiffness) and the gasket's
//! stiffness in; undamped. M and K = -dh/dq (its symmetric part) from the one linearisation
//! (`washdyn_runtime::linearise`: the exact force Jacobians).

use crate::commands::resolve_model;
pub use crate::error::modes::ModesError;
use nalgebra::DMatrix;
use std::path::{Path, PathBuf};
use washdyn_model::equations::Equations;
use washdyn_model::ir::{BodyRef, Model};
use washdyn_runtime::clearance::DoorRing;
use washdyn_runtime::linearise::Linearisation;
use washdyn_runtime::system::Interpreter;

/// One rigid mode.
#[derive(Clone, Debug)]
pub struct RigidMode {
    pub frequency_hz: f64,
    /// (u, alpha) about the tub's rest CoG (m, rad), scaled so that the largest displacement
    /// of the normalisation points is 1 m (i.e. the shape in mm per mm).
    pub shape: [f64; 6],
    /// Share of the mode's kinetic energy in each rigid coordinate (diagonal of M; sums to 1
    /// up to the inertia's products).
    pub energy: [f64; 6],
    /// The dominant motion in words, e.g. "roll (rx) 81 %, lateral (y) 17 %".
    pub description: String,
    /// Per damper (in `Modes::dampers` order): axial extension per unit modal motion,
    /// e_d . (d_b - d_a), m per m of the normalisation points' largest displacement.
    pub strokes: Vec<f64>,
}

/// A damper's tub end and axis.
#[derive(Clone, Debug)]
pub struct DamperGeometry {
    pub name: String,
    /// Tub end relative to the tub's rest CoG, m.
    pub s: [f64; 3],
    /// Unit axis from the tub end to the cabinet end.
    pub axis: [f64; 3],
}

/// The rigid modes of a model in a scene.
#[derive(Clone, Debug)]
pub struct Modes {
    pub model: String,
    pub scene: String,
    pub dampers: Vec<DamperGeometry>,
    /// What the shapes are normalised to.
    pub normalised_to: String,
    pub modes: Vec<RigidMode>,
}

const COORDS: [&str; 6] = [
    "fore-aft (x)",
    "lateral (y)",
    "bounce (z)",
    "roll (rx)",
    "pitch (ry)",
    "yaw (rz)",
];

/// The rigid modes of `model` in `scene` (default: its first scene).
pub fn rigid_modes(model: &Model, scene: Option<&str>) -> Result<Modes, ModesError> {
    let eff = model.scene(scene).map_err(ModesError::Scene)?;
    let mut m = model.clone();
    m.elastic.clear();
    m.unbalances.clear();
    for d in &mut m.friction_dampers {
        d.f_max = 0.0;
    }
    let eq = Equations::new(&m, &eff);
    let mut sys = Interpreter::new(&m, &eff);
    let lin = Linearisation::at_rest(&mut sys, 0.0).map_err(ModesError::Rest)?;
    let (mm, k) = (&lin.m, 0.5 * (&lin.k + lin.k.transpose()));
    let (x, lambda) = washdyn_model::ir::modal::generalised_eigen(mm, &k);

    let p0 = eq.p0();
    let rel = |p: [f64; 3]| [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]];
    let unit = |a: [f64; 3], b: [f64; 3]| {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|v| v / n)
    };
    // A damper's axis points from its tub end to its cabinet end (ends on the tub only: none).
    let mut dampers = Vec::new();
    let mut add = |name: &str, a: &washdyn_model::ir::Attach, b: &washdyn_model::ir::Attach| {
        let (tub, other) = match (a.body, b.body) {
            (BodyRef::Tub, BodyRef::Cabinet) => (a.point, b.point),
            (BodyRef::Cabinet, BodyRef::Tub) => (b.point, a.point),
            _ => return,
        };
        dampers.push(DamperGeometry {
            name: name.to_string(),
            s: rel(tub),
            axis: unit(tub, other),
        });
    };
    if eff.has(&washdyn_model::ir::Effect::FrictionDampers) {
        for d in &model.friction_dampers {
            add(&d.name, &d.a, &d.b);
        }
    }
    for d in &model.dampers {
        add(&d.name, &d.a, &d.b);
    }

    // Normalisation points: the door ring (rigid), else the dampers' tub ends.
    let (points, normalised_to): (Vec<[f64; 3]>, String) = match DoorRing::new(&m, &eq) {
        Some(r) => (
            r.points.iter().map(|p| p.at.s).collect(),
            "1 mm largest displacement of the door ring (its 8 points)".into(),
        ),
        None => (
            dampers.iter().map(|d| d.s).collect(),
            "1 mm largest displacement of the dampers' tub ends".into(),
        ),
    };
    let mut modes = Vec::new();
    for (c, &l) in lambda.iter().enumerate() {
        let mut shape: [f64; 6] = std::array::from_fn(|i| x[(i, c)]);
        let largest = points
            .iter()
            .map(|s| norm(displacement(&shape, *s)))
            .fold(0.0f64, f64::max);
        // Sign: the largest coordinate (in energy) positive.
        let energy = energy_shares(mm, &shape);
        let lead = (0..6)
            .max_by(|&a, &b| energy[a].total_cmp(&energy[b]))
            .unwrap_or(0);
        let sign = if shape[lead] < 0.0 { -1.0 } else { 1.0 };
        if largest > 0.0 {
            shape = shape.map(|v| sign * v / largest);
        }
        let strokes = dampers.iter().map(|d| stroke(&shape, d)).collect();
        modes.push(RigidMode {
            frequency_hz: l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
            shape,
            energy,
            description: describe(&energy),
            strokes,
        });
    }
    Ok(Modes {
        model: model.name.clone(),
        scene: eff.name.clone(),
        dampers,
        normalised_to,
        modes,
    })
}

/// u + alpha x s.
pub fn displacement(shape: &[f64; 6], s: [f64; 3]) -> [f64; 3] {
    let (u, a) = (&shape[..3], &shape[3..]);
    [
        u[0] + a[1] * s[2] - a[2] * s[1],
        u[1] + a[2] * s[0] - a[0] * s[2],
        u[2] + a[0] * s[1] - a[1] * s[0],
    ]
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Axial extension of a damper (cabinet end fixed) for the tub motion `shape`.
fn stroke(shape: &[f64; 6], d: &DamperGeometry) -> f64 {
    let v = displacement(shape, d.s);
    -(v[0] * d.axis[0] + v[1] * d.axis[1] + v[2] * d.axis[2])
}

/// Each coordinate's share of x^T M x from M's diagonal.
fn energy_shares(mm: &DMatrix<f64>, x: &[f64; 6]) -> [f64; 6] {
    let e: [f64; 6] = std::array::from_fn(|i| mm[(i, i)] * x[i] * x[i]);
    let total: f64 = e.iter().sum();
    e.map(|v| if total > 0.0 { v / total } else { 0.0 })
}

/// The coordinates holding at least 10 % of the energy, largest first.
fn describe(energy: &[f64; 6]) -> String {
    let mut idx: Vec<usize> = (0..6).collect();
    idx.sort_by(|&a, &b| energy[b].total_cmp(&energy[a]));
    idx.iter()
        .filter(|&&i| energy[i] >= 0.1)
        .map(|&i| format!("{} {:.0} %", COORDS[i], 100.0 * energy[i]))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The table as markdown (docs/reference-machine.md shows it).
pub fn markdown(m: &Modes) -> String {
    let mut s = format!(
        "Rigid modes of the suspended tub: model `{}`, scene `{}`. Linearised at rest (static \
         equilibrium at t = 0, drum at rest, unbalances off), friction released (f_max = 0), \
         damper bushings, springs and gasket stiffness in; undamped. Each shape is scaled to \
         {}; u and alpha are the tub's translation (mm) and rotation (mrad) about its rest \
         CoG for that. Stroke: the damper's axial extension e_d . (d_cabinet - d_tub), in mm \
         per mm of door-ring motion (equally the axial relative velocity of its ends per unit \
         modal velocity).\n\n",
        m.model, m.scene, m.normalised_to
    );
    s.push_str("| mode | f (Hz) | dominant motion (kinetic energy) | u (mm) | alpha (mrad) |");
    for d in &m.dampers {
        s.push_str(&format!(" {} |", d.name));
    }
    s.push_str("\n|---|---|---|---|---|");
    for _ in &m.dampers {
        s.push_str("---|");
    }
    s.push('\n');
    for (i, md) in m.modes.iter().enumerate() {
        let v = |a: &[f64], k: f64| {
            a.iter()
                .map(|x| format!("{:.3}", x * k))
                .collect::<Vec<_>>()
                .join(", ")
        };
        s.push_str(&format!(
            "| {} | {:.2} | {} | {} | {} |",
            i + 1,
            md.frequency_hz,
            md.description,
            v(&md.shape[..3], 1.0),
            // Per 1 m at the ring: m and rad; per 1 mm: mm and mrad, the same numbers.
            v(&md.shape[3..], 1.0),
        ));
        for st in &md.strokes {
            s.push_str(&format!(" {st:.3} |"));
        }
        s.push('\n');
    }
    s
}

/// `washdyn modes`: the table on stdout and in `OUT/modes.md` (default out/<model>/).
pub fn run(spec: &str, scene: Option<&str>, out: Option<&Path>) -> Result<PathBuf, ModesError> {
    let (model, _) = resolve_model(spec)?;
    let modes = rigid_modes(&model, scene)?;
    let text = markdown(&modes);
    print!("{text}");
    let dir = out.map_or_else(|| PathBuf::from("out").join(&model.name), Path::to_path_buf);
    let io = |action, path: &Path| {
        let path = path.to_path_buf();
        move |source| {
            ModesError::Io(crate::error::ActionError {
                action,
                path,
                source,
            })
        }
    };
    std::fs::create_dir_all(&dir).map_err(io("create", &dir))?;
    let file = dir.join("modes.md");
    std::fs::write(&file, text).map_err(io("write", &file))?;
    Ok(file)
}
