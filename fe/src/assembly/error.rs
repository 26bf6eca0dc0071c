//! What the full-mesh deck refuses: a machine that is not linear, a scene or model that lacks
//! what the deck is built from, modal data that is not its mesh's; and a ccx answer that is
//! not the deck's.

/// An error of the full-mesh deck or its answer.
#[derive(Debug, thiserror::Error)]
pub enum AssemblyError {
    #[error("the scene must make the {body} elastic")]
    NotElastic { body: String },
    #[error(
        "the full-mesh deck is a linear machine; this one has {} (use `linear_machine`)",
        found.join(", ")
    )]
    NotLinear { found: Vec<String> },
    #[error("{body}: modal data not resolved")]
    Unresolved { body: String },
    #[error("gasket {name}: {what} {problem}")]
    Gasket {
        name: String,
        what: String,
        problem: &'static str,
    },
    #[error("unbalance {unbalance}: no rotor {rotor}")]
    NoRotor { unbalance: String, rotor: String },
    #[error("no drum-order-1 unbalance in the scene")]
    NoUnbalance,
    #[error("the model has no rotor `drum`")]
    NoDrum,
    #[error("a damper's moving part is not on a mesh")]
    DamperPart,
    #[error("a counterweight is a rigid body, not on a mesh")]
    Counterweight,
    #[error("node set {set} is a rigid part: only masses and sensors can attach there")]
    RigidPart { set: String },
    #[error("no modal point of the {body} at {at:?}")]
    NoModalPoint { body: &'static str, at: [f64; 3] },
    #[error("the mesh has no node set {set} (stale modal data?)")]
    StaleSet { set: String },
    #[error(
        "node set {set} has {mesh} nodes, the modal data's point {data}: regenerate the modal data"
    )]
    SetSize {
        set: String,
        mesh: usize,
        data: usize,
    },
    #[error("{job}.dat: {prints} sensor prints for {speeds} speeds (real and imaginary each)")]
    SensorPrints {
        job: String,
        prints: usize,
        speeds: usize,
    },
    #[error("{job}.dat: sensor node {node} not printed")]
    NotPrinted { job: String, node: usize },
}
