//! Reading a user's CalculiX (Abaqus-format) input deck into a [`Mesh`]: nodes, elements,
//! node and element sets, materials, sections, point masses, ground springs, rigid bodies and
//! the boundary. The model part only: the deck's own steps are skipped (the pipeline writes
//! the analyses it needs). Units: SI, or mm-t-s as CalculiX users often write them, converted
//! to SI on reading. What the pipeline cannot integrate (other element types, orthotropic
//! materials, constraints) is refused with the file and line, never dropped.
//!
//! The syntax (cards, `*INCLUDE`, numbers and sets) is in `cards.rs`, the unit systems in
//! `units.rs`; this file gives the cards their meaning.

mod cards;
mod units;

pub use units::{Units, in_units};

use crate::mesh::{self, Material, Mesh, Part, Rigid, Section};
use cards::{Card, cards, int, members, num};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// A deck error: where, and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}:{line}: {message}", file.display())]
pub struct DeckError {
    pub file: PathBuf,
    pub line: usize,
    pub message: String,
}

/// Node sets the deck writer (`Mesh::model_deck`) writes itself: not read into the mesh.
const RESERVED: [&str; 2] = ["NALL", "WD_PRINT"];

/// Keywords of analysis set-up the model part may hold and the pipeline replaces: skipped.
const SKIPPED: [&str; 3] = ["*HEADING", "*AMPLITUDE", "*PHYSICAL CONSTANTS"];

/// A material's cards as read: (E and nu, density), each until its card comes.
type MaterialCards = (Option<(f64, f64)>, Option<f64>);

/// Read a deck (and its includes) in `units` into a [`Mesh`] in SI. Node ids are renumbered
/// 1..n in the order the deck defines them (the pipeline's meshes number densely).
pub fn read(path: &Path, units: Units) -> Result<Mesh, DeckError> {
    let mut all = Vec::new();
    cards(path, &mut all, 0)?;
    let (fl, fm, fs, frho, fk) = units.factors();
    let mut mesh = Mesh::new(&format!("{} (read by washdyn-fe)", path.display()));
    // Deck id -> our id; elements: deck id -> (type, deck node ids, line).
    let mut node_id: HashMap<i64, usize> = HashMap::new();
    let mut elements: BTreeMap<i64, (String, Vec<i64>, PathBuf, usize)> = BTreeMap::new();
    let mut nsets: BTreeMap<String, Vec<i64>> = BTreeMap::new();
    let mut elsets: BTreeMap<String, Vec<i64>> = BTreeMap::new();
    let mut materials: BTreeMap<String, MaterialCards> = BTreeMap::new();
    // Section cards after the sets and materials they name: (card index).
    let mut sections: Vec<usize> = Vec::new();
    let mut rigid: Vec<usize> = Vec::new();
    let mut boundary: Vec<usize> = Vec::new();
    let mut in_step = false;
    for (ci, card) in all.iter().enumerate() {
        let kw = card.keyword.as_str();
        if in_step {
            if kw == "*END STEP" {
                in_step = false;
            }
            continue;
        }
        match kw {
            "*STEP" => in_step = true,
            "*NODE" => {
                let set = card.param("NSET").map(str::to_uppercase);
                for (line, f) in &card.data {
                    let id = int(card, *line, f.first().map_or("", |s| s), "node id")?;
                    let mut p = [0.0; 3];
                    for (i, c) in p.iter_mut().enumerate() {
                        // Missing coordinates are zero (ccx's rule).
                        if f.len() > i + 1 {
                            *c = fl * num(card, *line, f, i + 1, "coordinate")?;
                        }
                    }
                    if node_id.contains_key(&id) {
                        return Err(card.err(*line, format!("node {id} defined twice")));
                    }
                    mesh.nodes.push(p);
                    node_id.insert(id, mesh.nodes.len());
                    if let Some(s) = &set {
                        nsets.entry(s.clone()).or_default().push(id);
                    }
                }
            }
            "*ELEMENT" => {
                let kind = card.need("TYPE")?;
                let Some(n) = mesh::nodes_of(&kind) else {
                    let supported: Vec<&str> =
                        mesh::ELEMENT_TYPES.iter().map(|(t, _)| *t).collect();
                    return Err(card.err(
                        card.line,
                        format!(
                            "element type {kind} is not supported (supported: {}); \
                             the pipeline integrates the mass of these only",
                            supported.join(", ")
                        ),
                    ));
                };
                let set = card.param("ELSET").map(str::to_uppercase);
                for (line, f) in &card.data {
                    let id = int(card, *line, f.first().map_or("", |s| s), "element id")?;
                    if f.len() != n + 1 {
                        return Err(card.err(
                            *line,
                            format!(
                                "element {id}: {kind} has {n} nodes, the line gives {}",
                                f.len() - 1
                            ),
                        ));
                    }
                    let nodes = f[1..]
                        .iter()
                        .map(|s| int(card, *line, s, "node id"))
                        .collect::<Result<Vec<_>, _>>()?;
                    if elements
                        .insert(id, (kind.clone(), nodes, card.file.clone(), *line))
                        .is_some()
                    {
                        return Err(card.err(*line, format!("element {id} defined twice")));
                    }
                    if let Some(s) = &set {
                        elsets.entry(s.clone()).or_default().push(id);
                    }
                }
            }
            "*NSET" | "*ELSET" => {
                let (key, sets) = if kw == "*NSET" {
                    ("NSET", &mut nsets)
                } else {
                    ("ELSET", &mut elsets)
                };
                let name = card.need(key)?;
                let generate = card.params.iter().any(|(k, _)| k == "GENERATE");
                let ids = members(card, sets, generate)?;
                sets.entry(name).or_default().extend(ids);
            }
            "*MATERIAL" => {
                let name = card.need("NAME")?;
                materials.insert(name, (None, None));
            }
            "*ELASTIC" | "*DENSITY" => {
                let Some(name) = all[..ci]
                    .iter()
                    .rev()
                    .find(|c| c.keyword == "*MATERIAL")
                    .and_then(|c| c.param("NAME"))
                    .map(str::to_uppercase)
                else {
                    return Err(card.err(card.line, format!("{kw} outside a *MATERIAL")));
                };
                let (line, f) = card.first()?;
                if card.data.len() > 1 {
                    return Err(card.err(
                        card.data[1].0,
                        format!("{kw}: temperature-dependent data is not supported"),
                    ));
                }
                let entry = materials.get_mut(&name).expect("material card seen");
                if kw == "*ELASTIC" {
                    if let Some(t) = card.param("TYPE")
                        && !t.eq_ignore_ascii_case("ISO")
                    {
                        return Err(card.err(
                            card.line,
                            format!("*ELASTIC, TYPE={t}: only isotropic materials are supported"),
                        ));
                    }
                    let e = fs * num(card, *line, f, 0, "Young's modulus")?;
                    let nu = num(card, *line, f, 1, "Poisson's ratio")?;
                    if e <= 0.0 || !(-1.0 < nu && nu < 0.5) {
                        return Err(card.err(
                            *line,
                            format!("*ELASTIC: E = {e} Pa, nu = {nu} is not a material"),
                        ));
                    }
                    entry.0 = Some((e, nu));
                } else {
                    let rho = frho * num(card, *line, f, 0, "density")?;
                    if rho <= 0.0 {
                        return Err(card.err(*line, format!("*DENSITY: {rho} kg/m^3")));
                    }
                    entry.1 = Some(rho);
                }
            }
            "*SHELL SECTION" | "*SOLID SECTION" | "*BEAM SECTION" | "*MASS" | "*SPRING" => {
                sections.push(ci)
            }
            "*RIGID BODY" => rigid.push(ci),
            "*BOUNDARY" => boundary.push(ci),
            k if SKIPPED.contains(&k) => {}
            other => {
                return Err(card.err(
                    card.line,
                    format!(
                        "{other} is not supported in the model part (supported: *NODE, *ELEMENT, \
                         *NSET, *ELSET, *MATERIAL, *ELASTIC, *DENSITY, *SHELL SECTION, *SOLID \
                         SECTION, *BEAM SECTION, *MASS, *SPRING, *RIGID BODY, *BOUNDARY, \
                         *INCLUDE; steps are skipped)"
                    ),
                ));
            }
        }
    }
    let node = |card: &Card, line: usize, id: i64| -> Result<usize, DeckError> {
        node_id
            .get(&id)
            .copied()
            .ok_or_else(|| card.err(line, format!("node {id} is not defined")))
    };
    let material = |card: &Card| -> Result<Material, DeckError> {
        let name = card.need("MATERIAL")?;
        let (el, rho) = materials
            .get(&name)
            .ok_or_else(|| card.err(card.line, format!("no material `{name}` defined")))?;
        let (e, nu) =
            el.ok_or_else(|| card.err(card.line, format!("material `{name}` has no *ELASTIC")))?;
        let rho =
            rho.ok_or_else(|| card.err(card.line, format!("material `{name}` has no *DENSITY")))?;
        Ok(Material { name, e, nu, rho })
    };
    // Each element gets exactly one section.
    let mut owner: HashMap<i64, usize> = HashMap::new();
    for &ci in &sections {
        let card = &all[ci];
        let set = card.need("ELSET")?;
        let ids = elsets
            .get(&set)
            .filter(|ids| !ids.is_empty())
            .ok_or_else(|| {
                card.err(
                    card.line,
                    format!("no element set `{set}` with elements defined"),
                )
            })?;
        let positive = |v: f64, what: &str, line: usize| {
            if v > 0.0 {
                Ok(v)
            } else {
                Err(card.err(
                    line,
                    format!("{}: {what} must be positive, got {v}", card.keyword),
                ))
            }
        };
        let section = match card.keyword.as_str() {
            "*SHELL SECTION" => {
                if card.param("OFFSET").is_some() || card.param("COMPOSITE").is_some() {
                    return Err(
                        card.err(card.line, "shell offsets and composites are not supported")
                    );
                }
                let (line, f) = card.first()?;
                let t = positive(
                    fl * num(card, *line, f, 0, "thickness")?,
                    "thickness",
                    *line,
                )?;
                Section::Shell {
                    thickness: t,
                    material: material(card)?,
                }
            }
            "*SOLID SECTION" => {
                let m = material(card)?;
                // The element type decides full or reduced integration: one part per type.
                let kind = elements
                    .get(&ids[0])
                    .map(|e| e.0.clone())
                    .unwrap_or_default();
                if kind == "C3D20R" {
                    Section::ReducedSolid { material: m }
                } else {
                    Section::Solid { material: m }
                }
            }
            "*BEAM SECTION" => {
                let shape = card.need("SECTION")?;
                if shape != "RECT" {
                    return Err(card.err(
                        card.line,
                        format!("*BEAM SECTION, SECTION={shape}: only RECT is supported"),
                    ));
                }
                let (line, f) = card.first()?;
                let w = positive(fl * num(card, *line, f, 0, "width")?, "width", *line)?;
                let h = positive(fl * num(card, *line, f, 1, "height")?, "height", *line)?;
                let (l2, n) = card.data.get(1).ok_or_else(|| {
                    card.err(card.line, "*BEAM SECTION needs the 1-direction line")
                })?;
                let normal = [
                    num(card, *l2, n, 0, "1-direction x")?,
                    num(card, *l2, n, 1, "1-direction y")?,
                    num(card, *l2, n, 2, "1-direction z")?,
                ];
                Section::Beam {
                    width: w,
                    height: h,
                    normal,
                    material: material(card)?,
                }
            }
            "*MASS" => {
                let (line, f) = card.first()?;
                let kg = positive(fm * num(card, *line, f, 0, "mass")?, "mass", *line)?;
                Section::Mass { kg }
            }
            _ => {
                // *SPRING for SPRING1: the dof line, then the stiffness.
                let (l1, f1) = card.first()?;
                let dof = int(card, *l1, f1.first().map_or("", |s| s), "degree of freedom")?;
                if !(1..=3).contains(&dof) {
                    return Err(card.err(*l1, format!("*SPRING: dof {dof}, not 1, 2 or 3")));
                }
                let (l2, f2) = card
                    .data
                    .get(1)
                    .ok_or_else(|| card.err(card.line, "*SPRING needs its stiffness line"))?;
                let k = positive(fk * num(card, *l2, f2, 0, "stiffness")?, "stiffness", *l2)?;
                Section::Ground {
                    dof: dof as usize,
                    k,
                }
            }
        };
        let mut part = Part {
            name: set.clone(),
            section,
            elements: Vec::new(),
        };
        for id in ids {
            let (kind, nodes, file, line) = elements.get(id).ok_or_else(|| {
                card.err(
                    card.line,
                    format!("element set `{set}`: element {id} is not defined"),
                )
            })?;
            if *kind != part.section.ccx_type() {
                return Err(DeckError {
                    file: file.clone(),
                    line: *line,
                    message: format!(
                        "element {id} ({kind}) in `{set}` does not take {}",
                        card.keyword
                    ),
                });
            }
            if let Some(prev) = owner.insert(*id, ci) {
                return Err(card.err(
                    card.line,
                    format!(
                        "element {id} already has a section (line {})",
                        all[prev].line
                    ),
                ));
            }
            part.elements.push(
                nodes
                    .iter()
                    .map(|&n| node(card, *line, n))
                    .collect::<Result<Vec<_>, _>>()?,
            );
        }
        mesh.parts.push(part);
    }
    if let Some((id, (kind, _, file, line))) =
        elements.iter().find(|(id, _)| !owner.contains_key(id))
    {
        return Err(DeckError {
            file: file.clone(),
            line: *line,
            message: format!("element {id} ({kind}) has no section"),
        });
    }
    // NALL and WD_PRINT are the sets the deck writer makes itself (a deck it wrote is read back).
    for (name, ids) in nsets
        .iter()
        .filter(|(n, _)| !RESERVED.contains(&n.as_str()))
    {
        let card = &all[0];
        let mut ours = Vec::with_capacity(ids.len());
        for &id in ids {
            ours.push(node_id.get(&id).copied().ok_or_else(|| {
                card.err(0, format!("node set `{name}`: node {id} is not defined"))
            })?);
        }
        mesh.add_to_set(name, &ours);
    }
    for &ci in &rigid {
        let card = &all[ci];
        let nset = card.need("NSET")?;
        if !mesh.nsets.contains_key(&nset) {
            return Err(card.err(card.line, format!("no node set `{nset}` defined")));
        }
        let refnode = |key: &str| -> Result<usize, DeckError> {
            let s = card.param(key).ok_or_else(|| {
                card.err(
                    card.line,
                    format!(
                        "*RIGID BODY needs {key}= (the pipeline reads the part's rotation there)"
                    ),
                )
            })?;
            node(card, card.line, int(card, card.line, s, key)?)
        };
        let (ref_node, rot_node) = (refnode("REF NODE")?, refnode("ROT NODE")?);
        mesh.rigid.push(Rigid {
            nset,
            ref_node,
            rot_node,
        });
    }
    for &ci in &boundary {
        let card = &all[ci];
        for (line, f) in &card.data {
            let target = f.first().map_or("", |s| s.as_str());
            let a = int(card, *line, f.get(1).map_or("", |s| s), "first dof")?;
            let b = match f.get(2) {
                Some(s) => int(card, *line, s, "last dof")?,
                None => a,
            };
            if f.len() > 3 {
                return Err(card.err(*line, "*BOUNDARY: prescribed values are not supported"));
            }
            if !(1 <= a && a <= b && b <= 6) {
                return Err(card.err(*line, format!("*BOUNDARY: dofs {a} to {b}")));
            }
            let set = match target.parse::<i64>() {
                Ok(id) => {
                    let name = format!("WD_BC_{id}");
                    let n = node(card, *line, id)?;
                    mesh.add_to_set(&name, &[n]);
                    name
                }
                Err(_) => {
                    let name = target.to_uppercase();
                    if !mesh.nsets.contains_key(&name) {
                        return Err(card.err(*line, format!("no node set `{target}` defined")));
                    }
                    name
                }
            };
            mesh.fixed.push((set, a as usize, b as usize));
        }
    }
    if mesh.parts.is_empty() {
        return Err(DeckError {
            file: path.to_path_buf(),
            line: 0,
            message: "the deck defines no elements with sections".into(),
        });
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests;
