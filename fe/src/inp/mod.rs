//! Reading a user's CalculiX (Abaqus-format) input deck into a [`Mesh`]: nodes, elements,
//! node and element sets, materials, sections, point masses, ground springs, rigid bodies and
//! the boundary. The model part only: the deck's own steps are skipped (the pipeline writes
//! the analyses it needs). Units: SI, or mm-t-s as CalculiX users often write them, converted
//! to SI on reading. What the pipeline cannot integrate (other element types, orthotropic
//! materials, constraints) is refused with the file and line, never dropped.

use crate::mesh::{self, Material, Mesh, Part, Rigid, Section};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// The deck's consistent unit system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
pub enum Units {
    /// m, kg, s, N, Pa.
    #[serde(rename = "SI")]
    Si,
    /// mm, t, s, N, MPa (density t/mm^3, springs N/mm).
    #[serde(rename = "mm-t-s")]
    MmTS,
}

impl Units {
    /// Factors to SI: (length, mass, stress, density, stiffness N/m).
    fn factors(self) -> (f64, f64, f64, f64, f64) {
        match self {
            Units::Si => (1.0, 1.0, 1.0, 1.0, 1.0),
            Units::MmTS => (1e-3, 1e3, 1e6, 1e12, 1e3),
        }
    }
}

/// `mesh` (SI) with every number in `units`: what a deck in those units holds (a user's
/// deck in mm-t-s is written this way in the tests and the tutorial).
pub fn in_units(mesh: &Mesh, units: Units) -> Mesh {
    let (fl, fm, fs, frho, fk) = units.factors();
    let mut m = mesh.clone();
    for p in &mut m.nodes {
        *p = p.map(|c| c / fl);
    }
    let scale = |mat: &mut Material| {
        mat.e /= fs;
        mat.rho /= frho;
    };
    for part in &mut m.parts {
        match &mut part.section {
            Section::Shell {
                thickness,
                material,
            } => {
                *thickness /= fl;
                scale(material);
            }
            Section::Solid { material } | Section::ReducedSolid { material } => scale(material),
            Section::Beam {
                width,
                height,
                material,
                ..
            } => {
                *width /= fl;
                *height /= fl;
                scale(material);
            }
            Section::Mass { kg } => *kg /= fm,
            Section::Ground { k, .. } => *k /= fk,
        }
    }
    m
}

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

/// One card: keyword, parameters (upper-cased keys; values as written, upper-cased where they
/// name something), data lines with their line numbers, where it stands.
struct Card {
    keyword: String,
    params: Vec<(String, String)>,
    data: Vec<(usize, Vec<String>)>,
    file: PathBuf,
    line: usize,
}

impl Card {
    fn param(&self, key: &str) -> Option<&str> {
        self.params
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    fn err(&self, line: usize, message: impl Into<String>) -> DeckError {
        DeckError {
            file: self.file.clone(),
            line,
            message: message.into(),
        }
    }
    fn need(&self, key: &str) -> Result<String, DeckError> {
        self.param(key)
            .map(str::to_uppercase)
            .ok_or_else(|| self.err(self.line, format!("{} needs {key}=", self.keyword)))
    }
    /// The first data line, or an error naming the card.
    fn first(&self) -> Result<&(usize, Vec<String>), DeckError> {
        self.data
            .first()
            .ok_or_else(|| self.err(self.line, format!("{} has no data line", self.keyword)))
    }
}

/// A number of a data line, or an error naming the field.
fn num(
    card: &Card,
    line: usize,
    fields: &[String],
    i: usize,
    what: &str,
) -> Result<f64, DeckError> {
    let s = fields
        .get(i)
        .ok_or_else(|| card.err(line, format!("{}: missing {what}", card.keyword)))?;
    let v: f64 = s.replace(['d', 'D'], "e").parse().map_err(|_| {
        card.err(
            line,
            format!("{}: {what} `{s}` is not a number", card.keyword),
        )
    })?;
    if !v.is_finite() {
        return Err(card.err(line, format!("{}: {what} is {v}", card.keyword)));
    }
    Ok(v)
}

fn int(card: &Card, line: usize, s: &str, what: &str) -> Result<i64, DeckError> {
    s.parse().map_err(|_| {
        card.err(
            line,
            format!("{}: {what} `{s}` is not an integer", card.keyword),
        )
    })
}

/// Split the deck into cards, following `*INCLUDE` (relative to the including file).
fn cards(path: &Path, out: &mut Vec<Card>, depth: usize) -> Result<(), DeckError> {
    let text = std::fs::read_to_string(path).map_err(|e| DeckError {
        file: path.to_path_buf(),
        line: 0,
        message: format!("cannot read: {e}"),
    })?;
    let mut continued = false;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with("**") {
            continue;
        }
        if let Some(rest) = l.strip_prefix('*') {
            let mut parts = rest.split(',').map(str::trim);
            let keyword = format!("*{}", parts.next().unwrap_or("").to_uppercase());
            let mut params = Vec::new();
            for p in parts.filter(|p| !p.is_empty()) {
                let (k, v) = p.split_once('=').unwrap_or((p, ""));
                params.push((k.trim().to_uppercase(), v.trim().to_string()));
            }
            if keyword == "*INCLUDE" {
                let Some((_, inc)) = params.iter().find(|(k, _)| k == "INPUT") else {
                    return Err(DeckError {
                        file: path.to_path_buf(),
                        line,
                        message: "*INCLUDE needs INPUT=".into(),
                    });
                };
                if depth > 8 {
                    return Err(DeckError {
                        file: path.to_path_buf(),
                        line,
                        message: "*INCLUDE nested deeper than 8 (a cycle?)".into(),
                    });
                }
                let inc = path
                    .parent()
                    .unwrap_or(Path::new("."))
                    .join(inc.trim_matches('"'));
                cards(&inc, out, depth + 1)?;
                continued = false;
                continue;
            }
            out.push(Card {
                keyword,
                params,
                data: Vec::new(),
                file: path.to_path_buf(),
                line,
            });
            continued = false;
            continue;
        }
        let Some(card) = out.last_mut() else {
            return Err(DeckError {
                file: path.to_path_buf(),
                line,
                message: "data before the first keyword".into(),
            });
        };
        let fields: Vec<String> = l
            .split(',')
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect();
        // A line ending with a comma continues on the next (elements of more than 16 nodes);
        // MASS and SPRING data end with one by ccx's convention and stand alone.
        let joins = continued && card.keyword == "*ELEMENT";
        match card.data.last_mut() {
            Some(last) if joins => last.1.extend(fields),
            _ => card.data.push((line, fields)),
        }
        continued = l.ends_with(',');
    }
    Ok(())
}

/// A set's members: ids, or (for `GENERATE`) first, last, step; names of sets already
/// defined are expanded.
fn members(
    card: &Card,
    sets: &BTreeMap<String, Vec<i64>>,
    generate: bool,
) -> Result<Vec<i64>, DeckError> {
    let mut ids = Vec::new();
    for (line, f) in &card.data {
        if generate {
            let a = int(card, *line, f.first().map_or("", |s| s), "first id")?;
            let b = int(card, *line, f.get(1).map_or("", |s| s), "last id")?;
            let step = match f.get(2) {
                Some(s) => int(card, *line, s, "step")?,
                None => 1,
            };
            if step <= 0 || b < a {
                return Err(card.err(*line, "GENERATE needs first <= last and a positive step"));
            }
            ids.extend((a..=b).step_by(step as usize));
            continue;
        }
        for s in f {
            match s.parse::<i64>() {
                Ok(id) => ids.push(id),
                Err(_) => {
                    let name = s.to_uppercase();
                    let set = sets.get(&name).ok_or_else(|| {
                        card.err(
                            *line,
                            format!("{}: no set `{s}` defined above", card.keyword),
                        )
                    })?;
                    ids.extend(set);
                }
            }
        }
    }
    Ok(ids)
}

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
