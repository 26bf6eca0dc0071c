//! The cards' meaning: one method per keyword (or pass), on the state they build together.
//! The model cards are read in deck order; sections, node sets, rigid bodies and the boundary
//! after them, as they name sets, materials and nodes the deck may define anywhere.

use super::cards::{Card, int, members, num};
use super::{InpError, InpProblem, RESERVED, SKIPPED, Units};
use crate::mesh::{self, Material, Mesh, Part, Rigid, Section};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// A material's cards as read: (E and nu, density), each until its card comes.
type MaterialCards = (Option<(f64, f64)>, Option<f64>);

/// An element as the deck defines it: type, deck node ids, where.
type Element = (String, Vec<i64>, PathBuf, usize);

/// The deck's factors to SI.
struct Factors {
    length: f64,
    mass: f64,
    stress: f64,
    density: f64,
    stiffness: f64,
}

/// The reader's state: the mesh so far and what the later passes look up.
pub(super) struct Reader<'a> {
    all: &'a [Card],
    si: Factors,
    pub(super) mesh: Mesh,
    /// Deck node id -> ours (1-based, in definition order).
    node_id: HashMap<i64, usize>,
    elements: BTreeMap<i64, Element>,
    nsets: BTreeMap<String, Vec<i64>>,
    elsets: BTreeMap<String, Vec<i64>>,
    materials: BTreeMap<String, MaterialCards>,
    /// Cards read after the model cards, by index: sections, rigid bodies, boundaries.
    sections: Vec<usize>,
    rigid: Vec<usize>,
    boundary: Vec<usize>,
}

impl<'a> Reader<'a> {
    pub(super) fn new(all: &'a [Card], units: Units, path: &Path) -> Self {
        let (length, mass, stress, density, stiffness) = units.factors();
        Reader {
            all,
            si: Factors {
                length,
                mass,
                stress,
                density,
                stiffness,
            },
            mesh: Mesh::new(&format!("{} (read by washdyn-fe)", path.display())),
            node_id: HashMap::new(),
            elements: BTreeMap::new(),
            nsets: BTreeMap::new(),
            elsets: BTreeMap::new(),
            materials: BTreeMap::new(),
            sections: Vec::new(),
            rigid: Vec::new(),
            boundary: Vec::new(),
        }
    }

    /// The cards in deck order, steps skipped; the cards naming others kept for later.
    pub(super) fn model_cards(&mut self) -> Result<(), InpError> {
        let all = self.all;
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
                "*NODE" => self.node(card)?,
                "*ELEMENT" => self.element(card)?,
                "*NSET" | "*ELSET" => self.set(card)?,
                "*MATERIAL" => {
                    let name = card.need("NAME")?;
                    self.materials.insert(name, (None, None));
                }
                "*ELASTIC" | "*DENSITY" => self.material_data(ci)?,
                "*SHELL SECTION" | "*SOLID SECTION" | "*BEAM SECTION" | "*MASS" | "*SPRING" => {
                    self.sections.push(ci)
                }
                "*RIGID BODY" => self.rigid.push(ci),
                "*BOUNDARY" => self.boundary.push(ci),
                k if SKIPPED.contains(&k) => {}
                other => {
                    let keyword = other.to_string();
                    return Err(card.err(card.line, InpProblem::UnsupportedKeyword { keyword }));
                }
            }
        }
        Ok(())
    }

    /// `*NODE`: coordinates (missing ones zero, ccx's rule), optionally into a set.
    fn node(&mut self, card: &Card) -> Result<(), InpError> {
        let set = card.param("NSET").map(str::to_uppercase);
        for (line, f) in &card.data {
            let id = int(card, *line, f.first().map_or("", |s| s), "node id")?;
            let mut p = [0.0; 3];
            for (i, c) in p.iter_mut().enumerate() {
                if f.len() > i + 1 {
                    *c = self.si.length * num(card, *line, f, i + 1, "coordinate")?;
                }
            }
            if self.node_id.contains_key(&id) {
                let what = "node";
                return Err(card.err(*line, InpProblem::DefinedTwice { what, id }));
            }
            self.mesh.nodes.push(p);
            self.node_id.insert(id, self.mesh.nodes.len());
            if let Some(s) = &set {
                self.nsets.entry(s.clone()).or_default().push(id);
            }
        }
        Ok(())
    }

    /// `*ELEMENT`: of a type the pipeline integrates, optionally into a set.
    fn element(&mut self, card: &Card) -> Result<(), InpError> {
        let kind = card.need("TYPE")?;
        let Some(n) = mesh::nodes_of(&kind) else {
            let supported = mesh::ELEMENT_TYPES.iter().map(|(t, _)| *t).collect();
            let problem = InpProblem::UnsupportedElement { kind, supported };
            return Err(card.err(card.line, problem));
        };
        let set = card.param("ELSET").map(str::to_uppercase);
        for (line, f) in &card.data {
            let id = int(card, *line, f.first().map_or("", |s| s), "element id")?;
            if f.len() != n + 1 {
                let (kind, nodes, given) = (kind.clone(), n, f.len() - 1);
                let problem = InpProblem::NodeCount {
                    id,
                    kind,
                    nodes,
                    given,
                };
                return Err(card.err(*line, problem));
            }
            let nodes = f[1..]
                .iter()
                .map(|s| int(card, *line, s, "node id"))
                .collect::<Result<Vec<_>, _>>()?;
            if self
                .elements
                .insert(id, (kind.clone(), nodes, card.file.clone(), *line))
                .is_some()
            {
                let what = "element";
                return Err(card.err(*line, InpProblem::DefinedTwice { what, id }));
            }
            if let Some(s) = &set {
                self.elsets.entry(s.clone()).or_default().push(id);
            }
        }
        Ok(())
    }

    /// `*NSET`, `*ELSET`: members added to the set.
    fn set(&mut self, card: &Card) -> Result<(), InpError> {
        let (key, sets) = if card.keyword == "*NSET" {
            ("NSET", &mut self.nsets)
        } else {
            ("ELSET", &mut self.elsets)
        };
        let name = card.need(key)?;
        let generate = card.params.iter().any(|(k, _)| k == "GENERATE");
        let ids = members(card, sets, generate)?;
        sets.entry(name).or_default().extend(ids);
        Ok(())
    }

    /// `*ELASTIC`, `*DENSITY` (card `ci`): the last `*MATERIAL` above gets them.
    fn material_data(&mut self, ci: usize) -> Result<(), InpError> {
        let all = self.all;
        let card = &all[ci];
        let keyword = card.keyword.clone();
        let Some(name) = all[..ci]
            .iter()
            .rev()
            .find(|c| c.keyword == "*MATERIAL")
            .and_then(|c| c.param("NAME"))
            .map(str::to_uppercase)
        else {
            return Err(card.err(card.line, InpProblem::OutsideMaterial { keyword }));
        };
        let (line, f) = card.first()?;
        if card.data.len() > 1 {
            let problem = InpProblem::TemperatureDependent { keyword };
            return Err(card.err(card.data[1].0, problem));
        }
        let entry = self.materials.get_mut(&name).expect("material card seen");
        if keyword == "*ELASTIC" {
            if let Some(t) = card.param("TYPE")
                && !t.eq_ignore_ascii_case("ISO")
            {
                let kind = t.to_string();
                return Err(card.err(card.line, InpProblem::Anisotropic { kind }));
            }
            let e = self.si.stress * num(card, *line, f, 0, "Young's modulus")?;
            let nu = num(card, *line, f, 1, "Poisson's ratio")?;
            if e <= 0.0 || !(-1.0 < nu && nu < 0.5) {
                return Err(card.err(*line, InpProblem::NotAMaterial { e, nu }));
            }
            entry.0 = Some((e, nu));
        } else {
            let rho = self.si.density * num(card, *line, f, 0, "density")?;
            if rho <= 0.0 {
                return Err(card.err(*line, InpProblem::Density { rho }));
            }
            entry.1 = Some(rho);
        }
        Ok(())
    }

    /// Our id of deck node `id`.
    fn node_of(&self, card: &Card, line: usize, id: i64) -> Result<usize, InpError> {
        self.node_id
            .get(&id)
            .copied()
            .ok_or_else(|| card.err(line, InpProblem::NoNode { id }))
    }

    /// The complete material a section card names.
    fn material(&self, card: &Card) -> Result<Material, InpError> {
        let name = card.need("MATERIAL")?;
        let Some((el, rho)) = self.materials.get(&name) else {
            return Err(card.err(card.line, InpProblem::NoMaterial { name }));
        };
        let lacks = |card_name| {
            let name = name.clone();
            card.err(
                card.line,
                InpProblem::MaterialLacks {
                    name,
                    card: card_name,
                },
            )
        };
        let (e, nu) = el.ok_or_else(|| lacks("*ELASTIC"))?;
        let rho = rho.ok_or_else(|| lacks("*DENSITY"))?;
        Ok(Material { name, e, nu, rho })
    }

    /// The section cards: each element of their sets gets exactly one; then none lacks one.
    pub(super) fn sections(&mut self) -> Result<(), InpError> {
        let mut owner: HashMap<i64, usize> = HashMap::new();
        let all = self.all;
        for ci in self.sections.clone() {
            let card = &all[ci];
            let set = card.need("ELSET")?;
            let ids = self
                .elsets
                .get(&set)
                .filter(|ids| !ids.is_empty())
                .ok_or_else(|| {
                    let set = set.clone();
                    card.err(card.line, InpProblem::NoElementSet { set })
                })?;
            let section = self.section(card, ids[0])?;
            let part = self.part(ci, set, section, ids, &mut owner)?;
            self.mesh.parts.push(part);
        }
        if let Some((id, (kind, _, file, line))) =
            self.elements.iter().find(|(id, _)| !owner.contains_key(id))
        {
            return Err(InpError {
                file: file.clone(),
                line: *line,
                problem: InpProblem::NoSection {
                    id: *id,
                    kind: kind.clone(),
                },
            });
        }
        Ok(())
    }

    /// The section a section card defines (`first` is an element of its set).
    fn section(&self, card: &Card, first: i64) -> Result<Section, InpError> {
        let positive = |v: f64, what: &'static str, line: usize| {
            if v > 0.0 {
                Ok(v)
            } else {
                let keyword = card.keyword.clone();
                Err(card.err(
                    line,
                    InpProblem::NotPositive {
                        keyword,
                        what,
                        value: v,
                    },
                ))
            }
        };
        let si = &self.si;
        Ok(match card.keyword.as_str() {
            "*SHELL SECTION" => {
                if card.param("OFFSET").is_some() || card.param("COMPOSITE").is_some() {
                    return Err(card.err(card.line, InpProblem::ShellOffset));
                }
                let (line, f) = card.first()?;
                let t = si.length * num(card, *line, f, 0, "thickness")?;
                Section::Shell {
                    thickness: positive(t, "thickness", *line)?,
                    material: self.material(card)?,
                }
            }
            "*SOLID SECTION" => {
                let m = self.material(card)?;
                // The element type decides full or reduced integration: one part per type.
                let kind = self.elements.get(&first).map(|e| e.0.as_str());
                if kind == Some("C3D20R") {
                    Section::ReducedSolid { material: m }
                } else {
                    Section::Solid { material: m }
                }
            }
            "*BEAM SECTION" => self.beam(card, &positive)?,
            "*MASS" => {
                let (line, f) = card.first()?;
                let kg = positive(si.mass * num(card, *line, f, 0, "mass")?, "mass", *line)?;
                Section::Mass { kg }
            }
            _ => {
                // *SPRING for SPRING1: the dof line, then the stiffness.
                let (l1, f1) = card.first()?;
                let dof = int(card, *l1, f1.first().map_or("", |s| s), "degree of freedom")?;
                if !(1..=3).contains(&dof) {
                    return Err(card.err(*l1, InpProblem::SpringDof { dof }));
                }
                let (l2, f2) = card.data.get(1).ok_or_else(|| {
                    let (keyword, what) = ("*SPRING", "its stiffness line");
                    card.err(card.line, InpProblem::MissingLine { keyword, what })
                })?;
                let k = si.stiffness * num(card, *l2, f2, 0, "stiffness")?;
                Section::Ground {
                    dof: dof as usize,
                    k: positive(k, "stiffness", *l2)?,
                }
            }
        })
    }

    /// `*BEAM SECTION`: rectangular, width and height, then the 1-direction.
    fn beam(
        &self,
        card: &Card,
        positive: &dyn Fn(f64, &'static str, usize) -> Result<f64, InpError>,
    ) -> Result<Section, InpError> {
        let shape = card.need("SECTION")?;
        if shape != "RECT" {
            return Err(card.err(card.line, InpProblem::BeamShape { shape }));
        }
        let fl = self.si.length;
        let (line, f) = card.first()?;
        let w = positive(fl * num(card, *line, f, 0, "width")?, "width", *line)?;
        let h = positive(fl * num(card, *line, f, 1, "height")?, "height", *line)?;
        let (l2, n) = card.data.get(1).ok_or_else(|| {
            let (keyword, what) = ("*BEAM SECTION", "the 1-direction line");
            card.err(card.line, InpProblem::MissingLine { keyword, what })
        })?;
        let normal = [
            num(card, *l2, n, 0, "1-direction x")?,
            num(card, *l2, n, 1, "1-direction y")?,
            num(card, *l2, n, 2, "1-direction z")?,
        ];
        Ok(Section::Beam {
            width: w,
            height: h,
            normal,
            material: self.material(card)?,
        })
    }

    /// The part of section card `ci`: its set's elements, each of a type the section takes
    /// and of no other section (`owner`: element -> its section's card).
    fn part(
        &self,
        ci: usize,
        set: String,
        section: Section,
        ids: &[i64],
        owner: &mut HashMap<i64, usize>,
    ) -> Result<Part, InpError> {
        let card = &self.all[ci];
        let mut part = Part {
            name: set,
            section,
            elements: Vec::new(),
        };
        for &id in ids {
            let (kind, nodes, file, line) = self.elements.get(&id).ok_or_else(|| {
                let set = part.name.clone();
                card.err(card.line, InpProblem::SetElementUndefined { set, id })
            })?;
            if *kind != part.section.ccx_type() {
                let (kind, set, keyword) = (kind.clone(), part.name.clone(), card.keyword.clone());
                return Err(InpError {
                    file: file.clone(),
                    line: *line,
                    problem: InpProblem::WrongSection {
                        id,
                        kind,
                        set,
                        keyword,
                    },
                });
            }
            if let Some(prev) = owner.insert(id, ci) {
                let first = self.all[prev].line;
                return Err(card.err(card.line, InpProblem::SecondSection { id, first }));
            }
            part.elements.push(
                nodes
                    .iter()
                    .map(|&n| self.node_of(card, *line, n))
                    .collect::<Result<Vec<_>, _>>()?,
            );
        }
        Ok(part)
    }

    /// The node sets into the mesh, but NALL and WD_PRINT, the sets the deck writer makes
    /// itself (a deck it wrote is read back).
    pub(super) fn node_sets(&mut self) -> Result<(), InpError> {
        let card = &self.all[0];
        for (name, ids) in self
            .nsets
            .iter()
            .filter(|(n, _)| !RESERVED.contains(&n.as_str()))
        {
            let mut ours = Vec::with_capacity(ids.len());
            for &id in ids {
                ours.push(self.node_id.get(&id).copied().ok_or_else(|| {
                    let set = name.clone();
                    card.err(0, InpProblem::SetNodeUndefined { set, id })
                })?);
            }
            self.mesh.add_to_set(name, &ours);
        }
        Ok(())
    }

    /// `*RIGID BODY`: a node set and its REF NODE and ROT NODE.
    pub(super) fn rigid_bodies(&mut self) -> Result<(), InpError> {
        let all = self.all;
        for ci in self.rigid.clone() {
            let card = &all[ci];
            let nset = card.need("NSET")?;
            if !self.mesh.nsets.contains_key(&nset) {
                let set = nset;
                return Err(card.err(card.line, InpProblem::NoNodeSet { set }));
            }
            let refnode = |key: &'static str| -> Result<usize, InpError> {
                let s = card
                    .param(key)
                    .ok_or_else(|| card.err(card.line, InpProblem::RigidBodyNeeds { key }))?;
                self.node_of(card, card.line, int(card, card.line, s, key)?)
            };
            let (ref_node, rot_node) = (refnode("REF NODE")?, refnode("ROT NODE")?);
            self.mesh.rigid.push(Rigid {
                nset,
                ref_node,
                rot_node,
            });
        }
        Ok(())
    }

    /// `*BOUNDARY`: node or node set, first and last dof; no prescribed values.
    pub(super) fn boundaries(&mut self) -> Result<(), InpError> {
        let all = self.all;
        for ci in self.boundary.clone() {
            let card = &all[ci];
            for (line, f) in &card.data {
                let target = f.first().map_or("", |s| s.as_str());
                let a = int(card, *line, f.get(1).map_or("", |s| s), "first dof")?;
                let b = match f.get(2) {
                    Some(s) => int(card, *line, s, "last dof")?,
                    None => a,
                };
                if f.len() > 3 {
                    return Err(card.err(*line, InpProblem::PrescribedValue));
                }
                if !(1 <= a && a <= b && b <= 6) {
                    let (first, last) = (a, b);
                    return Err(card.err(*line, InpProblem::BoundaryDofs { first, last }));
                }
                let set = match target.parse::<i64>() {
                    Ok(id) => {
                        let name = format!("WD_BC_{id}");
                        let n = self.node_of(card, *line, id)?;
                        self.mesh.add_to_set(&name, &[n]);
                        name
                    }
                    Err(_) => {
                        let name = target.to_uppercase();
                        if !self.mesh.nsets.contains_key(&name) {
                            let set = target.to_string();
                            return Err(card.err(*line, InpProblem::NoNodeSet { set }));
                        }
                        name
                    }
                };
                self.mesh.fixed.push((set, a as usize, b as usize));
            }
        }
        Ok(())
    }
}
