//! The assembled deck of a linear machine (`assemble`): the merged meshes, the carried masses,
//! springs and dampers, the gasket through its eigen-decomposition, the unbalance loads, the
//! sensors, then the `*FREQUENCY` step and one `*STEADY STATE DYNAMICS` step per speed.
//! Separate from the linear machine (`mod.rs`) and from the ties it is built with
//! (`builder.rs`): it is the one place that decides what the deck holds.

use super::builder::{Body, Builder, Dashpot, Rows, Site, Term, merge};
use super::rigid_drum::{point_cloud, unbalance_force};
use super::{Assembly, AssemblyError, SensorNode, Settings};
use crate::deck::Deck;
use crate::error::Error;
use crate::mesh::{Mesh, Section};
use nalgebra::{Matrix6, SymmetricEigen};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use washdyn_model::elements::reference_speed;
use washdyn_model::geom::f::{add, norm, sub, unit};
use washdyn_model::ir::modal::ModalData;
use washdyn_model::ir::{BodyRef, Effect, EffectSet, Elastic, Gasket, Model};

/// Eigen-decomposition of a symmetric positive semi-definite 6 x 6 matrix: (l_i, v_i) with
/// l_i > 1e-9 `scale` (a matrix of round-off, such as D - beta K of a gasket whose D is
/// beta K, gives none).
fn decompose(
    name: &str,
    what: &str,
    k: &[[f64; 6]; 6],
    scale: f64,
) -> Result<Vec<(f64, [f64; 6])>, AssemblyError> {
    let m = Matrix6::from_fn(|i, j| k[i][j]);
    let tol = 1e-9 * scale;
    if (m - m.transpose()).amax() > tol {
        let (name, what) = (name.to_string(), what.to_string());
        let problem = "is not symmetric";
        return Err(AssemblyError::Gasket {
            name,
            what,
            problem,
        });
    }
    let e = SymmetricEigen::new(m);
    let mut out = Vec::new();
    for i in 0..6 {
        let l = e.eigenvalues[i];
        if l < -tol {
            let (name, what) = (name.to_string(), what.to_string());
            let problem = "is not positive semi-definite";
            return Err(AssemblyError::Gasket {
                name,
                what,
                problem,
            });
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

/// The assembled deck of `model` (a `linear_machine`, scene `scene`), with the tub's and the
/// cabinet's meshes (the ones their modal data in `model` came from).
pub fn assemble(
    model: &Model,
    scene: &EffectSet,
    tub: &Mesh,
    cabinet: &Mesh,
    settings: &Settings,
) -> Result<Assembly, Error> {
    let entry = |name: &str| {
        model
            .elastic
            .iter()
            .find(|e| e.name == name)
            .filter(|_| scene.has(&Effect::Elastic(name.into())))
            .ok_or_else(|| AssemblyError::NotElastic { body: name.into() })
    };
    let (et, ec) = (entry("tub")?, entry("cabinet")?);
    let beta = et.stiffness_damping;
    linear(model, scene, [et, ec])?;
    fn data(e: &Elastic) -> Result<&ModalData, AssemblyError> {
        e.data.as_ref().ok_or_else(|| AssemblyError::Unresolved {
            body: e.name.clone(),
        })
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
    carried_masses(&mut b, model, &mut mass)?;
    springs_and_dampers(&mut b, model)?;
    for (gi, g) in model.gaskets.iter().enumerate() {
        gasket(&mut b, model, scene, settings, beta, gi, g)?;
    }
    let loads = unbalances(&mut b, model, scene)?;
    let sensors = sensors(&mut b, model)?;
    let mut d = b.mesh.model_deck();
    ties(&mut d, &b);
    steps(&mut d, &loads, settings, beta);
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

/// What ccx's linear machine has, and washdyn's must have too: refused otherwise, all named.
fn linear(model: &Model, scene: &EffectSet, elastic: [&Elastic; 2]) -> Result<(), AssemblyError> {
    let beta = elastic[0].stiffness_damping;
    let mut refuse = Vec::new();
    if model.gravity != [0.0; 3] {
        refuse.push("gravity (its load stiffness)".to_string());
    }
    for e in elastic {
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
        return Err(AssemblyError::NotLinear { found: refuse });
    }
    Ok(())
}

/// Carried masses: the drum's FE mass (its modal data) as six point masses with its mass,
/// CoG and inertia; other rotors as a point mass on their axis (as `Equations::new`); their
/// masses added to `mass`.
fn carried_masses(b: &mut Builder, model: &Model, mass: &mut f64) -> Result<(), Error> {
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
        *mass += m;
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
    Ok(())
}

/// Springs and dampers between auxiliary nodes at their ends.
fn springs_and_dampers(b: &mut Builder, model: &Model) -> Result<(), Error> {
    let end = |b: &mut Builder, a: &washdyn_model::ir::Attach| -> Result<usize, Error> {
        let s = b.site(model, a.body, a.point)?;
        b.follower(&s, a.point)
    };
    for (i, s) in model.springs.iter().enumerate() {
        let (na, nb) = (end(b, &s.a)?, end(b, &s.b)?);
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
        let (na, nb) = (end(b, &d.a)?, end(b, &d.b)?);
        b.pairs.push((
            format!("WD_DAMPER_{i}"),
            "DASHPOTA",
            na,
            nb,
            Dashpot::Constant(d.damping),
        ));
    }
    Ok(())
}

/// Gasket `gi`: scalar coordinates v_i . [u_a - u_b; theta_a - theta_b], a spring on each
/// of K's eigenvectors and, with the scene's gasket damping, dashpots on D - beta K's and on
/// the hysteretic S K S's.
fn gasket(
    b: &mut Builder,
    model: &Model,
    scene: &EffectSet,
    settings: &Settings,
    beta: f64,
    gi: usize,
    g: &Gasket,
) -> Result<(), Error> {
    let (sa, sb) = (b.site(model, g.a, g.point)?, b.site(model, g.b, g.point)?);
    let rows = |b: &Builder, s: &Site| -> Result<[Rows; 2], Error> {
        Ok([b.rows(s, false)?, b.rows(s, true)?])
    };
    let (ra, rb) = (rows(b, &sa)?, rows(b, &sb)?);
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
    if !scene.has(&Effect::GasketDamping) {
        return Ok(());
    }
    // Rayleigh's beta K share is ccx's: the dashpots carry D - beta K.
    let mut d = g.damping;
    for i in 0..6 {
        for j in 0..6 {
            d[i][j] -= beta * g.stiffness[i][j];
        }
    }
    let viscous = decompose(&g.name, "damping less beta K", &d, amax(&g.damping))?;
    for (i, (c, v)) in viscous.iter().enumerate() {
        let dashpot = Dashpot::Constant(*c);
        grounded_dashpot(
            b,
            g.point,
            format!("WD_GASKET_{gi}_D{i}"),
            combine(v),
            dashpot,
        );
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
            let table = settings
                .speeds_rpm
                .iter()
                .map(|rpm| {
                    let w = rpm * PI / 30.0;
                    (mu / reference_speed(w), w / (2.0 * PI))
                })
                .collect();
            let dashpot = Dashpot::Table(table);
            grounded_dashpot(
                b,
                g.point,
                format!("WD_GASKET_{gi}_H{i}"),
                combine(v),
                dashpot,
            );
        }
    }
    Ok(())
}

/// A dashpot named `set` from a scalar coordinate (`terms`) at `point` to a held node.
fn grounded_dashpot(b: &mut Builder, point: [f64; 3], set: String, terms: Vec<Term>, c: Dashpot) {
    let id = b.scalar(point, terms);
    let ground = b.mesh.fresh_node(add(point, [1.0, 0.0, 0.0]));
    b.ground.push(ground);
    b.pairs.push((set, "DASHPOTA", id, ground, c));
}

/// An unbalance load: node, axis e, mass, radius r0.
type Load = (usize, [f64; 3], f64, [f64; 3]);

/// The unbalances of the drum's order 1 (ratio 1) as forces at their axial position.
fn unbalances(b: &mut Builder, model: &Model, scene: &EffectSet) -> Result<Vec<Load>, Error> {
    let mut loads: Vec<Load> = Vec::new();
    for u in &model.unbalances {
        if !scene.has(&Effect::Unbalance(u.rotor.clone())) {
            continue;
        }
        let r = model
            .rotors
            .iter()
            .find(|r| r.name == u.rotor)
            .ok_or_else(|| AssemblyError::NoRotor {
                unbalance: u.name.clone(),
                rotor: u.rotor.clone(),
            })?;
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
        return Err(AssemblyError::NoUnbalance.into());
    }
    Ok(loads)
}

/// The sensors' nodes (set WD_SENSORS); the held and grounded nodes' sets and boundaries.
fn sensors(b: &mut Builder, model: &Model) -> Result<Vec<SensorNode>, Error> {
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
    Ok(sensors)
}

/// After the merged mesh: the equations and the two-node elements.
fn ties(d: &mut Deck, b: &Builder) {
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
}

/// The `*FREQUENCY` step, then one `*STEADY STATE DYNAMICS` step per speed with the
/// unbalances' loads.
fn steps(d: &mut Deck, loads: &[Load], settings: &Settings, beta: f64) {
    // Loads per unit Omega^2 (the unbalance's pattern), real or imaginary part, scaled.
    let load_lines = |scale: f64, imaginary: bool| -> Vec<String> {
        let mut out = Vec::new();
        for (node, e, m, r0) in loads {
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
}
