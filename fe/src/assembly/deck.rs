//! The assembled deck of a linear machine (`assemble`): the merged meshes, the carried masses,
//! springs and dampers, the gasket through its eigen-decomposition, the unbalance loads, the
//! sensors, then the `*FREQUENCY` step and one `*STEADY STATE DYNAMICS` step per speed.
//! Separate from the linear machine (`mod.rs`) and from the ties it is built with
//! (`builder.rs`): it is the one place that decides what the deck holds.

use super::builder::{Body, Builder, Dashpot, Rows, Site, Term, merge};
use super::rigid_drum::{point_cloud, unbalance_force};
use super::{Assembly, SensorNode, Settings};
use crate::mesh::{Mesh, Section};
use nalgebra::{Matrix6, SymmetricEigen};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use washdyn_model::elements::reference_speed;
use washdyn_model::geom::f::{add, norm, sub, unit};
use washdyn_model::ir::modal::ModalData;
use washdyn_model::ir::{BodyRef, Effect, EffectSet, Model};

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
    fn data(e: &washdyn_model::ir::Elastic) -> Result<&ModalData, String> {
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
    let end = |b: &mut Builder, a: &washdyn_model::ir::Attach| -> Result<usize, String> {
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
