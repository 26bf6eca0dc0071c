//! The assembled linear machine in CalculiX: the tub's and the cabinet's full meshes, the drum
//! as rigid point masses, the springs, dampers and the gasket between them, solved with
//! `*STEADY STATE DYNAMICS` for the drum's order-1 unbalance force. It is the full-mesh
//! reference for washdyn's Ritz model of the same linear machine (`linear_machine`): what the
//! Ritz basis leaves out shows as a difference in the sensors' harmonic amplitudes.
//!
//! Every attachment of the model (a force element's end, a sensor, a carried mass, the
//! unbalance's load point) is an auxiliary node tied by `*EQUATION` to the rigid fit of its FE
//! node set, `modal::point_reading_full`: the same relation the modal data's points use, so the
//! ties add no stiffness; a rotation is carried as the translational dofs of a second auxiliary
//! node. Nodes of a rigid part (`*RIGID BODY`) are dependent already: a mass there joins the part.
//! The gasket's 6 x 6 K (and D) enters through its eigen-decomposition K = sum l_i v_i v_i^T: a
//! scalar auxiliary dof s_i = v_i . [du; dtheta] (an equation over both bodies' sets) on a
//! SPRING1 of stiffness l_i (a DASHPOTA to a held node for D), its other dofs held.
//!
//! What this relies on in ccx 2.20 (Rayleigh damping with dashpots in steady-state dynamics,
//! frequency tables of dashpots, equations on shell nodes, the load cases' convention, MASS
//! elements on dependent nodes) is measured in tests/fe_steady_state.rs and listed in
//! docs/full-mesh.md.
//!
//! This file holds the linear machine (`linear_machine`) and what the deck and its answer are;
//! the rest lives beside it: the merged mesh with its ties under construction (`builder.rs`),
//! the deck built from the model (`deck.rs`, `assemble`), the drum as the deck carries it
//! (`rigid_drum.rs`) and running ccx and reading its answer back (`solve.rs`).

mod builder;
mod deck;
mod error;
mod rigid_drum;
mod solve;

pub use deck::assemble;
pub use error::AssemblyError;
pub use rigid_drum::point_cloud;
pub use solve::{Solution, solve};

use crate::deck::Deck;
use washdyn_model::geom::f::{norm, sub};
use washdyn_model::ir::{LinearDamper, Model, Scene, SensorKind};

/// The scene of `linear_machine`'s model.
pub const SCENE: &str = "full_mesh";

/// How the comparison machine departs from the reference.
#[derive(Clone, Copy, Debug)]
pub struct LinearSpec {
    /// Rayleigh beta, s, on the tub and the cabinet (and, as ccx applies it to the assembled K,
    /// c = beta k along the springs and D = beta K in the gasket).
    pub beta: f64,
    /// The linear damper standing in for each friction damper, N s/m.
    pub damper: f64,
}

impl Default for LinearSpec {
    /// beta = 1e-4 s: 1 % of critical at 32 Hz, 3 % at 95 Hz. A 300 N s/m damper dissipates per
    /// cycle what a 100 N friction damper does at 1 mm stroke and 17 Hz (4 F / (pi w X)), the
    /// tub's order-1 motion in the upper half of the run-up.
    fn default() -> Self {
        LinearSpec {
            beta: 1e-4,
            damper: 300.0,
        }
    }
}

/// The linear time-invariant machine of `model` that both washdyn (harmonic.rs) and the
/// assembled CalculiX deck describe: no gravity and springs at their free length (no preload,
/// so no load stiffness, which ccx's linear steps lack), friction dampers replaced by linear
/// ones (their rubber bearings left out), no gyroscopic moments, the drum's unbalances as
/// prescribed forces, the drum rigid (its FE mass carried at the bearing), the tub and the
/// cabinet elastic with Rayleigh beta only (no modal damping ratio, no support damping), and
/// the scene `SCENE`.
pub fn linear_machine(model: &Model, spec: &LinearSpec) -> Model {
    let mut m = model.clone();
    m.gravity = [0.0; 3];
    for s in &mut m.springs {
        s.free_length = norm(sub(s.b.point, s.a.point));
        s.quadratic_stiffness = 0.0;
    }
    for d in std::mem::take(&mut m.friction_dampers) {
        m.dampers.push(LinearDamper {
            name: d.name,
            a: d.a,
            b: d.b,
            damping: spec.damper,
        });
    }
    // ccx's Rayleigh damping acts on the assembled stiffness: the springs' and the gasket's too.
    for s in &m.springs {
        m.dampers.push(LinearDamper {
            name: format!("{}_beta", s.name),
            a: s.a,
            b: s.b,
            damping: spec.beta * s.stiffness,
        });
    }
    for g in &mut m.gaskets {
        for i in 0..6 {
            for j in 0..6 {
                g.damping[i][j] += spec.beta * g.stiffness[i][j];
            }
        }
    }
    for e in &mut m.elastic {
        e.damping = 0.0;
        e.support_damping = None;
        e.stiffness_damping = spec.beta;
    }
    m.scenes = vec![Scene {
        name: SCENE.into(),
        effects: vec![
            "unbalance.drum".into(),
            "gasket_damping".into(),
            "elastic.tub".into(),
            "elastic.cabinet".into(),
        ],
        max_order: None,
        solver: None,
    }];
    m
}

/// What the deck is solved for.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Eigenmodes of the assembled machine in the `*FREQUENCY` step (the modal basis of
    /// ccx's steady-state dynamics).
    pub modes: usize,
    /// Drum speeds, rpm: one `*STEADY STATE DYNAMICS` step each at drum order 1.
    pub speeds_rpm: Vec<f64>,
}

/// A sensor of the model as an auxiliary node of the deck.
#[derive(Clone, Debug)]
pub struct SensorNode {
    pub kind: SensorKind,
    /// The model's three channel names (x, y, z).
    pub channels: [String; 3],
    pub node: usize,
}

/// The assembled deck and what reading its results needs.
#[derive(Clone, Debug)]
pub struct Assembly {
    pub deck: Deck,
    pub sensors: Vec<SensorNode>,
    pub settings: Settings,
    /// Nodes and elements of the meshes (before the auxiliary nodes), and auxiliary nodes.
    pub mesh_nodes: usize,
    pub aux_nodes: usize,
    pub mesh_elements: usize,
    /// Rayleigh beta, s.
    pub beta: f64,
    /// The machine's mass as the Ritz model has it: tub and cabinet FE bodies, drum, rotors.
    pub mass: f64,
    /// The point masses (MASS elements) in the deck, kg: ccx's `EMAS` leaves them out.
    pub point_mass: f64,
}
