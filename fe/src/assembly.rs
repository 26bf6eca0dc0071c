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
//! elements on dependent nodes) is measured in fe/tests/steady_state.rs and listed in
//! docs/full-mesh.md.

use crate::deck::Deck;
use crate::mesh::{Mesh, Rigid, Section};
use crate::modal::{Reading, point_reading_full};
use nalgebra::{Complex, Matrix6, SymmetricEigen};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;
use washdyn_runtime::elements::reference_speed;
use washdyn_runtime::geom::f::{add, cross, norm, sub, unit};
use washdyn_runtime::ir::modal::{ModalData, point_at};
use washdyn_runtime::ir::{BodyRef, Effect, EffectSet, LinearDamper, Model, Scene, SensorKind};

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

/// The penalty springs' frequency with the mass they hold (Hz), and their length (m).
const PENALTY_HZ: f64 = 1e5;
const PENALTY_ARM: f64 = 0.01;

/// One body's mesh and modal data, and where its nodes go in the assembly.
struct Body<'a> {
    mesh: &'a Mesh,
    data: &'a ModalData,
    offset: usize,
    prefix: &'static str,
}

/// Where a model point reads its body: the FE node set and the position the rigid fit is
/// evaluated at (the modal point's, moved with the marker's offset from it, as the equations
/// do: `Equations::new`'s markers and carried masses).
struct Site {
    tub: bool,
    set: String,
    at: [f64; 3],
}

/// One term of an equation: node, dof (1..3), coefficient.
type Term = (usize, usize, f64);
/// Three equations' terms, one per component x, y, z.
type Rows = [Vec<Term>; 3];

/// A two-node element's constant: one value, or (value, frequency Hz) pairs.
enum Dashpot {
    Constant(f64),
    Table(Vec<(f64, f64)>),
}

/// The merged model under construction.
struct Builder<'a> {
    tub: Body<'a>,
    cabinet: Body<'a>,
    mesh: Mesh,
    equations: Vec<Vec<Term>>,
    /// (element set, kind, node a, node b, constant): SPRINGA and DASHPOTA elements.
    pairs: Vec<(String, &'static str, usize, usize, Dashpot)>,
    held: Vec<usize>,
    ground: Vec<usize>,
}

impl<'a> Builder<'a> {
    fn body(&self, tub: bool) -> &Body<'a> {
        if tub { &self.tub } else { &self.cabinet }
    }

    fn rigid_of(&self, s: &Site) -> Option<&Rigid> {
        self.body(s.tub).mesh.rigid.iter().find(|r| r.nset == s.set)
    }

    /// (node in the assembly, R_i, T_i) of the rigid fit of `s`.
    fn reading(&self, s: &Site) -> Result<Reading, String> {
        let b = self.body(s.tub);
        Ok(point_reading_full(b.mesh, &s.set, s.at)?
            .into_iter()
            .map(|(id, r, t)| (id + b.offset, r, t))
            .collect())
    }

    /// A new node at `p` whose translation follows the site (a rigid part's point, or the
    /// rigid fit of the set by equations).
    fn follower(&mut self, s: &Site, p: [f64; 3]) -> Result<usize, String> {
        let id = self.mesh.fresh_node(p);
        if let Some(r) = self.rigid_of(s) {
            let set = format!("{}{}", self.body(s.tub).prefix, r.nset);
            self.mesh.add_to_set(&set, &[id]);
            return Ok(id);
        }
        for (a, row) in self.rows(s, false)?.into_iter().enumerate() {
            self.tie(id, a + 1, row);
        }
        Ok(id)
    }

    /// A node at `p` for a point mass of `kg` that rides on the site. On a rigid part it joins
    /// the part; elsewhere ccx 2.20 cannot take a MASS element on a dependent node (its matrix
    /// structure misses the mass couplings through the equation: "add_sm_ei: coefficient should
    /// be 0", the coupling dropped), so the mass sits on an independent node held to three
    /// followers of the site (offset along x, y, z) by stiff SPRINGA: a penalty whose mode lies
    /// at `PENALTY_HZ`, so the mass lags the rigid fit by (f / PENALTY_HZ)^2 (1e-6 at 100 Hz).
    fn carrier(&mut self, s: &Site, p: [f64; 3], kg: f64, k: usize) -> Result<usize, String> {
        if self.rigid_of(s).is_some() {
            return self.follower(s, p);
        }
        let id = self.mesh.fresh_node(p);
        let stiffness = kg * (2.0 * PI * PENALTY_HZ).powi(2);
        for a in 0..3 {
            let mut q = p;
            q[a] -= PENALTY_ARM;
            let f = self.follower(s, q)?;
            self.pairs.push((
                format!("WD_MASS_{k}_{a}"),
                "SPRINGA",
                f,
                id,
                Dashpot::Constant(stiffness),
            ));
        }
        Ok(id)
    }

    /// The site's reading as three rows (one per component) of (node, dof, coefficient), of
    /// the translation or of the `rotation`.
    fn rows(&self, s: &Site, rotation: bool) -> Result<Rows, String> {
        if self.rigid_of(s).is_some() {
            return Err(format!(
                "node set {} is a rigid part: only masses and sensors can attach there",
                s.set
            ));
        }
        let mut rows: Rows = Default::default();
        for (id, r, t) in self.reading(s)? {
            let m = if rotation { t } else { r };
            for a in 0..3 {
                for d in 0..3 {
                    rows[a].push((id, d + 1, m[a][d]));
                }
            }
        }
        Ok(rows)
    }

    /// dof `dof` of `node` equals sum c u over `terms` (node, dof, c).
    fn tie(&mut self, node: usize, dof: usize, terms: Vec<Term>) {
        let top = terms.iter().fold(0.0f64, |m, t| m.max(t.2.abs()));
        let mut eq = vec![(node, dof, 1.0)];
        eq.extend(
            terms
                .into_iter()
                .filter(|t| t.2.abs() > 1e-12 * top)
                .map(|(n, d, c)| (n, d, -c)),
        );
        self.equations.push(eq);
    }

    /// A node whose dof 1 is `terms` (other dofs held): a scalar coordinate for SPRING1 and
    /// DASHPOTA elements.
    fn scalar(&mut self, p: [f64; 3], terms: Vec<Term>) -> usize {
        let id = self.mesh.fresh_node(p);
        self.tie(id, 1, terms);
        self.held.push(id);
        id
    }

    /// Where a model point on `body` reads the FE model.
    fn site(&self, model: &Model, body: BodyRef, p: [f64; 3]) -> Result<Site, String> {
        let find = |tub: bool, q: [f64; 3]| -> Result<(String, [f64; 3]), String> {
            let b = self.body(tub);
            let mp = point_at(b.data, q).ok_or_else(|| {
                format!(
                    "no modal point of the {} at {q:?}",
                    if tub { "tub" } else { "cabinet" }
                )
            })?;
            let set = b.mesh.nsets.get(&mp.name).ok_or_else(|| {
                format!("the mesh has no node set {} (stale modal data?)", mp.name)
            })?;
            // The modal data and the mesh must be one (a set regenerated since has another size).
            if set.len() != mp.nodes {
                return Err(format!(
                    "node set {} has {} nodes, the modal data's point {}: regenerate the modal data",
                    mp.name,
                    set.len(),
                    mp.nodes
                ));
            }
            Ok((mp.name.clone(), mp.position))
        };
        match body {
            BodyRef::Tub | BodyRef::Cabinet => {
                let tub = body == BodyRef::Tub;
                let (set, at) = find(tub, p)?;
                Ok(Site { tub, set, at })
            }
            BodyRef::Drum => {
                let mount = drum_mount(model)?;
                let (set, at) = find(true, mount)?;
                Ok(Site {
                    tub: true,
                    set,
                    at: add(at, sub(p, mount)),
                })
            }
            BodyRef::DamperPart(_) => Err("a damper's moving part is not on a mesh".into()),
        }
    }
}

fn drum_mount(model: &Model) -> Result<[f64; 3], String> {
    model
        .rotors
        .iter()
        .find(|r| r.name == "drum")
        .map(|r| r.mount_point())
        .ok_or_else(|| "the model has no rotor `drum`".to_string())
}

/// Eigen-decomposition of a symmetric positive semi-definite 6 x 6 matrix: (l_i, v_i) with
/// l_i > 1e-9 `scale` (a matrix of round-off, such as D - beta K of a gasket whose D is
/// beta K, gives none).
fn decompose(
    name: &str,
    what: &str,
    k: &[[f64; 6]; 6],
    scale: f64,
) -> Result<Vec<(f64, [f64; 6])>, String> {
    let m = Matrix6::from_fn(|i, j| k[i][j]);
    let tol = 1e-9 * scale;
    if (m - m.transpose()).amax() > tol {
        return Err(format!("gasket {name}: {what} is not symmetric"));
    }
    let e = SymmetricEigen::new(m);
    let mut out = Vec::new();
    for i in 0..6 {
        let l = e.eigenvalues[i];
        if l < -tol {
            return Err(format!(
                "gasket {name}: {what} is not positive semi-definite"
            ));
        }
        if l > tol {
            let v = e.eigenvectors.column(i);
            out.push((l, std::array::from_fn(|j| v[j])));
        }
    }
    Ok(out)
}

fn amax(m: &[[f64; 6]; 6]) -> f64 {
    m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Merge `mesh` into `into`: nodes after the existing ones, parts, sets and materials prefixed.
fn merge(into: &mut Mesh, mesh: &Mesh, prefix: &str) {
    let off = into.nodes.len();
    into.nodes.extend_from_slice(&mesh.nodes);
    for p in &mesh.parts {
        let mut section = p.section.clone();
        match &mut section {
            Section::Shell { material, .. }
            | Section::Solid { material }
            | Section::Beam { material, .. } => {
                material.name = format!("{prefix}{}", material.name)
            }
            _ => {}
        }
        let part = into.part(&format!("{prefix}{}", p.name), section);
        part.elements = p
            .elements
            .iter()
            .map(|e| e.iter().map(|id| id + off).collect())
            .collect();
    }
    for (name, ids) in &mesh.nsets {
        let ids: Vec<usize> = ids.iter().map(|id| id + off).collect();
        into.add_to_set(&format!("{prefix}{name}"), &ids);
    }
    for r in &mesh.rigid {
        into.rigid.push(Rigid {
            nset: format!("{prefix}{}", r.nset),
            ref_node: r.ref_node + off,
            rot_node: r.rot_node + off,
        });
    }
    for (set, a, b) in &mesh.fixed {
        into.fixed.push((format!("{prefix}{set}"), *a, *b));
    }
}

/// The complex amplitude of an unbalance's force (N) at drum speed omega (rad/s), for
/// f(t) = Re[F e^{i phi}]: m (ratio omega)^2 (r0 - i e x r0), r0 its radius vector at angle 0
/// (`UnbalanceDef::motion`: radial = r0 cos + (e x r0) sin).
fn unbalance_force(
    mass: f64,
    ratio: f64,
    e: [f64; 3],
    r0: [f64; 3],
    omega: f64,
) -> [Complex<f64>; 3] {
    let w2 = mass * (ratio * omega).powi(2);
    let t = cross(e, r0);
    std::array::from_fn(|a| Complex::new(w2 * r0[a], -w2 * t[a]))
}

/// The assembled deck of `model` (a `linear_machine`, scene `scene`), with the tub's and the
/// cabinet's meshes (the ones their modal data in `model` came from).
pub fn assemble(
    model: &Model,
    scene: &EffectSet,
    tub: &Mesh,
    cabinet: &Mesh,
    settings: &Settings,
) -> Result<Assembly, String> {
    let entry = |name: &str| {
        model
            .elastic
            .iter()
            .find(|e| e.name == name)
            .filter(|_| scene.has(&Effect::Elastic(name.into())))
            .ok_or_else(|| format!("the scene must make the {name} elastic"))
    };
    let (et, ec) = (entry("tub")?, entry("cabinet")?);
    // What ccx's linear machine has, and washdyn's must have too.
    let beta = et.stiffness_damping;
    let mut refuse = Vec::new();
    if model.gravity != [0.0; 3] {
        refuse.push("gravity (its load stiffness)".to_string());
    }
    for e in [et, ec] {
        if e.damping != 0.0 || e.support_damping.is_some() || e.stiffness_damping != beta {
            refuse.push(format!(
                "the {}'s damping other than one Rayleigh beta for tub and cabinet",
                e.name
            ));
        }
    }
    for s in &model.springs {
        let l = norm(sub(s.b.point, s.a.point));
        if (s.free_length - l).abs() > 1e-12 || s.quadratic_stiffness != 0.0 {
            refuse.push(format!("spring {}: preload or quadratic stiffness", s.name));
        }
    }
    if !model.friction_dampers.is_empty() && scene.has(&Effect::FrictionDampers) {
        refuse.push("friction dampers".into());
    }
    for e in [
        Effect::Gyroscopic,
        Effect::ElementGeometry,
        Effect::UnbalanceInertia,
        Effect::Elastic("drum".into()),
    ] {
        if scene.has(&e) {
            refuse.push(format!("effect `{}`", e.name()));
        }
    }
    if !refuse.is_empty() {
        return Err(format!(
            "the full-mesh deck is a linear machine; this one has {} (use `linear_machine`)",
            refuse.join(", ")
        ));
    }
    fn data(e: &washdyn_runtime::ir::Elastic) -> Result<&ModalData, String> {
        e.data
            .as_ref()
            .ok_or_else(|| format!("{}: modal data not resolved", e.name))
    }
    let mut b = Builder {
        tub: Body {
            mesh: tub,
            data: data(et)?,
            offset: 0,
            prefix: "T_",
        },
        cabinet: Body {
            mesh: cabinet,
            data: data(ec)?,
            offset: tub.nodes.len(),
            prefix: "C_",
        },
        mesh: Mesh::new(
            "washdyn full-mesh machine: tub and cabinet meshes, rigid drum, linear elements",
        ),
        equations: Vec::new(),
        pairs: Vec::new(),
        held: Vec::new(),
        ground: Vec::new(),
    };
    merge(&mut b.mesh, tub, "T_");
    merge(&mut b.mesh, cabinet, "C_");
    let (mesh_nodes, mesh_elements) = (b.mesh.nodes.len(), b.mesh.element_count());
    let mut mass = b.tub.data.mass + b.cabinet.data.mass;

    // Carried masses: the drum's FE mass (its modal data) as six point masses with its mass,
    // CoG and inertia; other rotors as a point mass on their axis (as `Equations::new`).
    let mut point_masses: Vec<([f64; 3], f64, [f64; 3])> = Vec::new(); // (at, kg, mount)
    for r in &model.rotors {
        let drum = model
            .elastic
            .iter()
            .find(|e| e.name == r.name && r.name == "drum")
            .and_then(|e| e.data.as_ref());
        let (m, c, inertia) = match drum {
            Some(d) => (d.mass, d.cog, d.inertia),
            None => (r.mass, r.axis_point, [[0.0; 3]; 3]),
        };
        if m == 0.0 {
            continue;
        }
        mass += m;
        for (p, kg) in point_cloud(m, c, inertia) {
            point_masses.push((p, kg, r.mount_point()));
        }
    }
    for (k, (p, kg, mount)) in point_masses.iter().enumerate() {
        let s = b.site(model, BodyRef::Tub, *mount)?;
        let s = Site {
            at: add(s.at, sub(*p, *mount)),
            ..s
        };
        let id = b.carrier(&s, *p, *kg, k)?;
        b.mesh
            .part(&format!("WD_MASS_{k}"), Section::Mass { kg: *kg })
            .elements = vec![vec![id]];
    }

    // Springs and dampers between auxiliary nodes at their ends.
    let end = |b: &mut Builder, a: &washdyn_runtime::ir::Attach| -> Result<usize, String> {
        let s = b.site(model, a.body, a.point)?;
        b.follower(&s, a.point)
    };
    for (i, s) in model.springs.iter().enumerate() {
        let (na, nb) = (end(&mut b, &s.a)?, end(&mut b, &s.b)?);
        b.pairs.push((
            format!("WD_SPRING_{i}"),
            "SPRINGA",
            na,
            nb,
            Dashpot::Constant(s.stiffness),
        ));
    }
    for (i, d) in model.dampers.iter().enumerate() {
        // The Rayleigh share of the springs is ccx's beta K: not a dashpot.
        if d.name.ends_with("_beta")
            && model
                .springs
                .iter()
                .any(|s| d.name == format!("{}_beta", s.name))
        {
            continue;
        }
        let (na, nb) = (end(&mut b, &d.a)?, end(&mut b, &d.b)?);
        b.pairs.push((
            format!("WD_DAMPER_{i}"),
            "DASHPOTA",
            na,
            nb,
            Dashpot::Constant(d.damping),
        ));
    }

    // The gasket: scalar coordinates v_i . [u_a - u_b; theta_a - theta_b].
    for (gi, g) in model.gaskets.iter().enumerate() {
        let (sa, sb) = (b.site(model, g.a, g.point)?, b.site(model, g.b, g.point)?);
        let rows = |b: &Builder, s: &Site| -> Result<[Rows; 2], String> {
            Ok([b.rows(s, false)?, b.rows(s, true)?])
        };
        let (ra, rb) = (rows(&b, &sa)?, rows(&b, &sb)?);
        let combine = |v: &[f64; 6]| -> Vec<Term> {
            let mut acc: BTreeMap<(usize, usize), f64> = BTreeMap::new();
            for (rs, sign) in [(&ra, 1.0), (&rb, -1.0)] {
                for (block, r) in rs.iter().enumerate() {
                    for a in 0..3 {
                        for &(n, d, c) in &r[a] {
                            *acc.entry((n, d)).or_default() += sign * v[3 * block + a] * c;
                        }
                    }
                }
            }
            acc.into_iter().map(|((n, d), c)| (n, d, c)).collect()
        };
        for (i, (l, v)) in decompose(&g.name, "stiffness", &g.stiffness, amax(&g.stiffness))?
            .iter()
            .enumerate()
        {
            let id = b.scalar(g.point, combine(v));
            b.mesh
                .part(
                    &format!("WD_GASKET_{gi}_K{i}"),
                    Section::Ground { dof: 1, k: *l },
                )
                .elements = vec![vec![id]];
        }
        if scene.has(&Effect::GasketDamping) {
            // Rayleigh's beta K share is ccx's: the dashpots carry D - beta K.
            let mut d = g.damping;
            for i in 0..6 {
                for j in 0..6 {
                    d[i][j] -= beta * g.stiffness[i][j];
                }
            }
            for (i, (c, v)) in decompose(&g.name, "damping less beta K", &d, amax(&g.damping))?
                .iter()
                .enumerate()
            {
                let id = b.scalar(g.point, combine(v));
                let ground = b.mesh.fresh_node(add(g.point, [1.0, 0.0, 0.0]));
                b.ground.push(ground);
                b.pairs.push((
                    format!("WD_GASKET_{gi}_D{i}"),
                    "DASHPOTA",
                    id,
                    ground,
                    Dashpot::Constant(*c),
                ));
            }
            // The hysteretic part S K S acts as the viscous S K S / Omega_ref at the drum
            // speed (`elements::Gasket`): frequency-dependent dashpots, exact at the steps'
            // frequencies (ccx interpolates its table linearly in cycles/time).
            let h = g.hysteretic_damping();
            if h.iter().flatten().any(|v| *v != 0.0) {
                for (i, (mu, v)) in decompose(&g.name, "S K S", &h, amax(&h))?
                    .iter()
                    .enumerate()
                {
                    let id = b.scalar(g.point, combine(v));
                    let ground = b.mesh.fresh_node(add(g.point, [1.0, 0.0, 0.0]));
                    b.ground.push(ground);
                    let table = settings
                        .speeds_rpm
                        .iter()
                        .map(|rpm| {
                            let w = rpm * PI / 30.0;
                            (mu / reference_speed(w), w / (2.0 * PI))
                        })
                        .collect();
                    b.pairs.push((
                        format!("WD_GASKET_{gi}_H{i}"),
                        "DASHPOTA",
                        id,
                        ground,
                        Dashpot::Table(table),
                    ));
                }
            }
        }
    }

    // The unbalances of the drum's order 1 (ratio 1) as forces at their axial position.
    let mut loads: Vec<(usize, [f64; 3], f64, [f64; 3])> = Vec::new(); // node, e, m, r0
    for u in &model.unbalances {
        if !scene.has(&Effect::Unbalance(u.rotor.clone())) {
            continue;
        }
        let r = model
            .rotors
            .iter()
            .find(|r| r.name == u.rotor)
            .ok_or_else(|| format!("unbalance {}: no rotor {}", u.name, u.rotor))?;
        if r.ratio != 1.0 {
            continue;
        }
        let e = unit(r.axis);
        let mount = r.mount_point();
        let rho = sub(u.position, mount);
        let along = rho[0] * e[0] + rho[1] * e[1] + rho[2] * e[2];
        let axial = e.map(|c| c * along);
        let p = add(mount, axial);
        let s = b.site(model, BodyRef::Tub, mount)?;
        let s = Site {
            at: add(s.at, axial),
            ..s
        };
        let id = b.follower(&s, p)?;
        loads.push((id, e, u.mass, sub(rho, axial)));
    }
    if loads.is_empty() {
        return Err("no drum-order-1 unbalance in the scene".into());
    }

    // Sensors.
    let mut sensors = Vec::new();
    for s in &model.sensors {
        let site = b.site(model, s.body, s.point)?;
        let node = b.follower(&site, s.point)?;
        sensors.push(SensorNode {
            kind: s.kind,
            channels: s.channels(),
            node,
        });
    }
    let ids: Vec<usize> = sensors.iter().map(|s| s.node).collect();
    b.mesh.add_to_set("WD_SENSORS", &ids);
    if !b.held.is_empty() {
        let held = b.held.clone();
        b.mesh.add_to_set("WD_HELD", &held);
        b.mesh.fixed.push(("WD_HELD".into(), 2, 3));
    }
    if !b.ground.is_empty() {
        let g = b.ground.clone();
        b.mesh.add_to_set("WD_GROUND", &g);
        b.mesh.fixed.push(("WD_GROUND".into(), 1, 3));
    }

    // The deck: the merged mesh, then equations and the two-node elements.
    let mut d = b.mesh.model_deck();
    d.line("*EQUATION");
    for eq in &b.equations {
        d.line(&eq.len().to_string());
        let terms: Vec<String> = eq
            .iter()
            .map(|(n, k, c)| format!("{n},{k},{c:.12e}"))
            .collect();
        for (i, chunk) in terms.chunks(4).enumerate() {
            let more = (i + 1) * 4 < terms.len();
            d.line(&format!(
                "{}{}",
                chunk.join(","),
                if more { "," } else { "" }
            ));
        }
    }
    for (id, (set, kind, na, nb, c)) in (b.mesh.element_count() + 1..).zip(&b.pairs) {
        d.line(&format!("*ELEMENT, TYPE={kind}, ELSET={set}"))
            .line(&format!("{id}, {na}, {nb}"));
        let card = if *kind == "SPRINGA" {
            "*SPRING"
        } else {
            "*DASHPOT"
        };
        d.line(&format!("{card}, ELSET={set}")).line("");
        match c {
            Dashpot::Constant(c) => {
                d.line(&format!("{c:.12e},"));
            }
            Dashpot::Table(t) => {
                let mut t = t.clone();
                t.sort_by(|a, b| a.1.total_cmp(&b.1));
                t.dedup_by(|a, b| a.1 == b.1);
                for (c, f) in t {
                    d.line(&format!("{c:.12e}, {f:.12e}"));
                }
            }
        }
    }
    // Loads per unit Omega^2 (the unbalance's pattern), real or imaginary part, scaled.
    let load_lines = |scale: f64, imaginary: bool| -> Vec<String> {
        let mut out = Vec::new();
        for (node, e, m, r0) in &loads {
            let f = unbalance_force(*m, 1.0, *e, *r0, 1.0);
            for (a, fa) in f.iter().enumerate() {
                let v = scale * if imaginary { fa.im } else { fa.re };
                out.push(format!("{node}, {}, {v:.12e}", a + 1));
            }
        }
        out
    };
    d.line("*STEP")
        .line("*FREQUENCY, STORAGE=YES")
        .line(&settings.modes.to_string());
    // Point loads of the later steps must exist in the frequency step (ccx: the MPCs that
    // expand shell nodes are built there).
    d.line("*CLOAD");
    for l in load_lines(0.0, false) {
        d.line(&l);
    }
    d.line("*EL PRINT, ELSET=EALL, TOTALS=ONLY")
        .line("EMAS")
        .line("*END STEP");
    for rpm in &settings.speeds_rpm {
        let omega = rpm * PI / 30.0;
        let hz = format!("{:.12e}", omega / (2.0 * PI));
        d.line("*STEP")
            .line("*STEADY STATE DYNAMICS")
            .line(&format!("{hz}, {hz}, 2"))
            .line("*MODAL DAMPING, RAYLEIGH")
            .line(&format!(",,0.,{beta:.12e}"))
            .line("*CLOAD");
        for l in load_lines(omega * omega, false) {
            d.line(&l);
        }
        d.line("*CLOAD, LOAD CASE=2");
        for l in load_lines(omega * omega, true) {
            d.line(&l);
        }
        d.line("*NODE PRINT, NSET=WD_SENSORS")
            .line("U")
            .line("*END STEP");
    }
    let point_mass = b
        .mesh
        .parts
        .iter()
        .map(|p| match p.section {
            Section::Mass { kg } => kg * p.elements.len() as f64,
            _ => 0.0,
        })
        .sum();
    Ok(Assembly {
        deck: d,
        sensors,
        settings: settings.clone(),
        beta,
        aux_nodes: b.mesh.nodes.len() - mesh_nodes,
        mesh_nodes,
        mesh_elements,
        mass,
        point_mass,
    })
}

/// Six point masses of total `mass` with CoG `cog` and inertia tensor `inertia` (about the
/// CoG): m / 6 at cog +- d_k e_k along the principal axes of the second moments J = tr(I) / 2 E
/// - I (J = sum m r r^T), with 2 (m / 6) d_k^2 = J_k.
pub fn point_cloud(mass: f64, cog: [f64; 3], inertia: [[f64; 3]; 3]) -> Vec<([f64; 3], f64)> {
    let tr = 0.5 * (inertia[0][0] + inertia[1][1] + inertia[2][2]);
    let j = nalgebra::Matrix3::from_fn(|a, b| if a == b { tr } else { 0.0 } - inertia[a][b]);
    let e = SymmetricEigen::new(j);
    let mut out = Vec::new();
    for k in 0..3 {
        let d = (3.0 * e.eigenvalues[k].max(0.0) / mass).sqrt();
        let v = e.eigenvectors.column(k);
        for s in [1.0, -1.0] {
            out.push((std::array::from_fn(|a| cog[a] + s * d * v[a]), mass / 6.0));
        }
    }
    out
}

/// ccx's answer: the assembled machine's eigenfrequencies and, per speed, every channel's
/// complex amplitude (drum order 1, channel(t) = Re[a e^{i phi}], phi the drum angle).
#[derive(Clone, Debug)]
pub struct Solution {
    pub frequencies: Vec<f64>,
    /// Drum speeds, rpm.
    pub rpm: Vec<f64>,
    /// Per speed, the channels in the model's sensor order (3 per sensor), accelerations as
    /// -w^2 u.
    pub channels: Vec<Vec<Complex<f64>>>,
    /// ccx's total mass (`EMAS` of the elements plus the point masses), kg.
    pub mass: Option<f64>,
    pub wall_s: f64,
}

/// Write the deck as `<dir>/<job>.inp`, run ccx, read the eigenfrequencies and the sensors'
/// amplitudes back.
pub fn solve(a: &Assembly, dir: &Path, job: &str) -> Result<Solution, String> {
    let path = dir.join(format!("{job}.inp"));
    std::fs::write(&path, a.deck.text()).map_err(|e| format!("{}: {e}", path.display()))?;
    // Every core: the assembled machine's eigen-solve is most of the reference's time.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let run = crate::ccx::run_threads(&path, threads).map_err(|e| e.to_string())?;
    let dat = std::fs::read_to_string(run.dat()).map_err(|e| format!("{job}.dat: {e}"))?;
    let prints =
        crate::dat::node_prints(&dat, "WD_SENSORS").map_err(|e| format!("{job}.dat: {e}"))?;
    // The real and imaginary parts per speed, the last 2 n prints (ccx prints nothing else
    // for the set: the request is made in the steady-state steps).
    let n = a.settings.speeds_rpm.len();
    if prints.len() != 2 * n {
        return Err(format!(
            "{job}.dat: {} sensor prints for {n} speeds (real and imaginary each)",
            prints.len()
        ));
    }
    let get = |p: &[(usize, [f64; 3])], node: usize| {
        p.iter()
            .find(|(id, _)| *id == node)
            .map(|(_, v)| *v)
            .ok_or_else(|| format!("{job}.dat: sensor node {node} not printed"))
    };
    let mut channels = Vec::new();
    for (s, rpm) in a.settings.speeds_rpm.iter().enumerate() {
        let w = rpm * PI / 30.0;
        let mut ch = Vec::new();
        for sn in &a.sensors {
            let (r, i) = (
                get(&prints[2 * s], sn.node)?,
                get(&prints[2 * s + 1], sn.node)?,
            );
            let f = match sn.kind {
                SensorKind::Displacement => 1.0,
                SensorKind::Acceleration => -w * w,
            };
            for k in 0..3 {
                ch.push(Complex::new(f * r[k], f * i[k]));
            }
        }
        channels.push(ch);
    }
    Ok(Solution {
        frequencies: crate::ccx::frequencies(&dat),
        rpm: a.settings.speeds_rpm.clone(),
        channels,
        mass: crate::dat::emas(&dat, "EALL").map(|e| e.mass + a.point_mass),
        wall_s: run.wall_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_cloud_reproduces_mass_cog_and_inertia() {
        let inertia = [[0.21, 0.01, -0.02], [0.01, 0.33, 0.0], [-0.02, 0.0, 0.32]];
        let cog = [-0.1, 0.01, 0.45];
        let pts = point_cloud(8.4, cog, inertia);
        let p = crate::lumping::MassProps::of_points(pts.iter().map(|(x, m)| (*m, *x)));
        assert!((p.mass - 8.4).abs() < 1e-12);
        for a in 0..3 {
            assert!((p.cog[a] - cog[a]).abs() < 1e-14);
            for b in 0..3 {
                assert!((p.inertia[a][b] - inertia[a][b]).abs() < 1e-13, "{a}{b}");
            }
        }
    }

    #[test]
    fn unbalance_force_turns_with_the_drum() {
        // r0 = +z at angle 0, axis +x: at phi = 90 deg the force points along -y (e x z = -y).
        let f = unbalance_force(0.6, 1.0, [1.0, 0.0, 0.0], [0.0, 0.0, 0.24], 10.0);
        let at = |phi: f64| -> [f64; 3] {
            std::array::from_fn(|a| (f[a] * Complex::from_polar(1.0, phi)).re)
        };
        let q = at(PI / 2.0);
        assert!(
            (q[1] + 0.6 * 0.24 * 100.0).abs() < 1e-12 && q[2].abs() < 1e-12,
            "{q:?}"
        );
        let z = at(0.0);
        assert!((z[2] - 14.4).abs() < 1e-12);
    }
}
