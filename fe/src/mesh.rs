//! An FE model as data: nodes, element parts with their sections, node sets, rigid parts and
//! boundary conditions. The body generators build a `Mesh`; the deck writer turns it into a
//! CalculiX deck, and the lumping reads the same element geometry, so the masses we integrate
//! and the masses ccx integrates come from one description.

use crate::deck::Deck;
use std::collections::{BTreeMap, HashMap};

/// An isotropic linear-elastic material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Young's modulus, Pa.
    pub e: f64,
    pub nu: f64,
    /// Density, kg/m^3.
    pub rho: f64,
}

/// Element kind and the section that goes with it.
#[derive(Clone, Debug, PartialEq)]
pub enum Section {
    /// S8R: 8-node serendipity shell (corners counter-clockwise, then mid-sides), thickness m.
    Shell { thickness: f64, material: Material },
    /// C3D20: 20-node brick in ccx node order.
    Solid { material: Material },
    /// C3D20R: the same brick with reduced (2 x 2 x 2) integration, ccx's element for a sheet
    /// as one layer of bricks (a full-integration layer locks in bending: a 0.5 mm drum shell
    /// as C3D20 rocks at 135 Hz, as C3D20R at 107.7, as S8R at 107.5). ccx integrates its mass
    /// at the same 8 points.
    ReducedSolid { material: Material },
    /// B32: 3-node beam (end, middle, end), rectangular section: `width` along `normal` (ccx's
    /// 1-direction), `height` across it, m.
    Beam {
        width: f64,
        height: f64,
        normal: [f64; 3],
        material: Material,
    },
    /// Point mass, kg, on one node.
    Mass { kg: f64 },
    /// SPRING1: a spring from one node to the ground, in global direction `dof` (1..3), N/m.
    Ground { dof: usize, k: f64 },
}

/// The ccx element types a `Section` is written as, with their node counts: the types the
/// pipeline integrates, and so the ones a user's deck may hold (`inp`).
pub const ELEMENT_TYPES: [(&str, usize); 6] = [
    ("S8R", 8),
    ("C3D20", 20),
    ("C3D20R", 20),
    ("B32", 3),
    ("MASS", 1),
    ("SPRING1", 1),
];

/// Nodes per element of ccx type `ccx`, if the pipeline takes it.
pub fn nodes_of(ccx: &str) -> Option<usize> {
    ELEMENT_TYPES
        .iter()
        .find(|(t, _)| *t == ccx)
        .map(|(_, n)| *n)
}

impl Section {
    pub fn ccx_type(&self) -> &'static str {
        match self {
            Section::Shell { .. } => "S8R",
            Section::Solid { .. } => "C3D20",
            Section::ReducedSolid { .. } => "C3D20R",
            Section::Beam { .. } => "B32",
            Section::Mass { .. } => "MASS",
            Section::Ground { .. } => "SPRING1",
        }
    }
    pub fn nodes_per_element(&self) -> usize {
        nodes_of(self.ccx_type()).expect("every section's type is in ELEMENT_TYPES")
    }
    pub fn material(&self) -> Option<&Material> {
        match self {
            Section::Shell { material, .. }
            | Section::Solid { material }
            | Section::ReducedSolid { material }
            | Section::Beam { material, .. } => Some(material),
            _ => None,
        }
    }
}

/// Elements of one kind and section, written as one ccx element set (`name`).
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub name: String,
    pub section: Section,
    /// Node ids (1-based) per element.
    pub elements: Vec<Vec<usize>>,
}

/// A rigid part (`*RIGID BODY`): the nodes of `nset` move as one body about `ref_node`; ccx's
/// ROT NODE `rot_node` carries its rotation (printed into the `.dat`).
#[derive(Clone, Debug, PartialEq)]
pub struct Rigid {
    pub nset: String,
    pub ref_node: usize,
    pub rot_node: usize,
}

/// A whole FE model of one body.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub title: String,
    /// Node coordinates, m; node id = index + 1.
    pub nodes: Vec<[f64; 3]>,
    pub parts: Vec<Part>,
    /// Named node sets: attachment points, measurement points, boundaries.
    pub nsets: BTreeMap<String, Vec<usize>>,
    pub rigid: Vec<Rigid>,
    /// Held DOFs: (node set, first dof, last dof), ccx numbering 1..6.
    pub fixed: Vec<(String, usize, usize)>,
    /// Snap grid for `node`: coincident points share one node.
    index: HashMap<[i64; 3], usize>,
}

/// Points closer than this (m) are one node.
const SNAP: f64 = 1e-7;

impl Mesh {
    pub fn new(title: &str) -> Mesh {
        Mesh {
            title: title.into(),
            ..Mesh::default()
        }
    }
    /// The node at `p`: an existing one within `SNAP`, else a new one. Shared nodes are how the
    /// generated pieces (shell, bricks, beams) join.
    pub fn node(&mut self, p: [f64; 3]) -> usize {
        let key = p.map(|c| (c / SNAP).round() as i64);
        // A point near a cell boundary may have its twin in a neighbouring cell.
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let k = [key[0] + dx, key[1] + dy, key[2] + dz];
                    if let Some(&id) = self.index.get(&k) {
                        let q = self.nodes[id - 1];
                        if (0..3).all(|i| (q[i] - p[i]).abs() <= SNAP) {
                            return id;
                        }
                    }
                }
            }
        }
        self.nodes.push(p);
        let id = self.nodes.len();
        self.index.insert(key, id);
        id
    }
    /// A new node even where one exists (ccx's REF and ROT nodes, ground points).
    pub fn fresh_node(&mut self, p: [f64; 3]) -> usize {
        self.nodes.push(p);
        self.nodes.len()
    }
    /// The part called `name`, created with `section` if new.
    pub fn part(&mut self, name: &str, section: Section) -> &mut Part {
        let i = match self.parts.iter().position(|p| p.name == name) {
            Some(i) => {
                // One part, one section: a second section under the same name would be lost.
                assert!(
                    self.parts[i].section == section,
                    "part {name} already has another section"
                );
                i
            }
            None => {
                self.parts.push(Part {
                    name: name.into(),
                    section,
                    elements: Vec::new(),
                });
                self.parts.len() - 1
            }
        };
        &mut self.parts[i]
    }
    /// Add ids to the node set `name` (kept sorted, without repeats).
    pub fn add_to_set(&mut self, name: &str, ids: &[usize]) {
        let s = self.nsets.entry(name.into()).or_default();
        s.extend_from_slice(ids);
        s.sort_unstable();
        s.dedup();
    }
    /// The node nearest to `p` among `candidates` (all nodes if `None`).
    pub fn nearest(&self, p: [f64; 3], candidates: Option<&[usize]>) -> usize {
        let d = |id: usize| {
            let q = self.nodes[id - 1];
            (0..3).map(|i| (q[i] - p[i]).powi(2)).sum::<f64>()
        };
        let all: Vec<usize>;
        let c = match candidates {
            Some(c) => c,
            None => {
                all = (1..=self.nodes.len()).collect();
                &all
            }
        };
        *c.iter()
            .min_by(|a, b| d(**a).total_cmp(&d(**b)))
            .expect("no candidate nodes")
    }
    /// Node ids used by at least one element of a part.
    pub fn element_nodes(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self
            .parts
            .iter()
            .flat_map(|p| p.elements.iter().flatten().copied())
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }
    /// Number of elements over all parts.
    pub fn element_count(&self) -> usize {
        self.parts.iter().map(|p| p.elements.len()).sum()
    }

    /// The CalculiX deck of this model: mesh, sections, rigid parts, boundary, and a
    /// `*FREQUENCY` step for `modes` eigenmodes that also prints the ROT NODEs and the model's
    /// mass properties (`EMAS`) into the `.dat`.
    pub fn deck(&self, modes: usize) -> Deck {
        self.frequency_deck(modes, false)
    }

    /// `deck`, or with `stresses` the same step writing ccx's 3-D output (expanded shells and
    /// beams) and the stresses: one solve then gives the shapes (`stress::mid_surface`) and the
    /// surface stresses for recovery.
    pub fn frequency_deck(&self, modes: usize, stresses: bool) -> Deck {
        let mut d = self.model_deck();
        d.line("*STEP").line("*FREQUENCY").line(&modes.to_string());
        self.output_requests(&mut d, stresses);
        d.line("*END STEP");
        d
    }

    /// Everything before the first step.
    pub fn model_deck(&self) -> Deck {
        let mut d = Deck::new(&self.title);
        let nodes: Vec<(usize, [f64; 3])> = self
            .nodes
            .iter()
            .enumerate()
            .map(|(i, p)| (i + 1, *p))
            .collect();
        d.nodes(Some("NALL"), &nodes);
        let mut next = 1;
        for p in &self.parts {
            let elems: Vec<(usize, Vec<usize>)> = p
                .elements
                .iter()
                .map(|e| {
                    next += 1;
                    (next - 1, e.clone())
                })
                .collect();
            d.elements(p.section.ccx_type(), &p.name, &elems);
        }
        let names: Vec<&str> = self.parts.iter().map(|p| p.name.as_str()).collect();
        d.line("*ELSET, ELSET=EALL");
        for c in names.chunks(8) {
            d.line(&c.join(", "));
        }
        for (name, ids) in &self.nsets {
            d.nset(name, ids);
        }
        let mut mats: Vec<&Material> = Vec::new();
        for p in &self.parts {
            if let Some(m) = p.section.material()
                && !mats.iter().any(|q| q.name == m.name)
            {
                mats.push(m);
            }
        }
        for m in mats {
            d.material(&m.name, m.e, m.nu, m.rho);
        }
        for p in &self.parts {
            match &p.section {
                Section::Shell {
                    thickness,
                    material,
                } => {
                    d.line(&format!(
                        "*SHELL SECTION, ELSET={}, MATERIAL={}",
                        p.name, material.name
                    ))
                    .line(&format!("{thickness:.9e}"));
                }
                Section::Solid { material } | Section::ReducedSolid { material } => {
                    d.line(&format!(
                        "*SOLID SECTION, ELSET={}, MATERIAL={}",
                        p.name, material.name
                    ));
                }
                Section::Beam {
                    width,
                    height,
                    normal,
                    material,
                } => {
                    d.line(&format!(
                        "*BEAM SECTION, ELSET={}, MATERIAL={}, SECTION=RECT",
                        p.name, material.name
                    ))
                    .line(&format!("{width:.9e}, {height:.9e}"))
                    .line(&format!(
                        "{:e}, {:e}, {:e}",
                        normal[0], normal[1], normal[2]
                    ));
                }
                Section::Mass { kg } => {
                    d.line(&format!("*MASS, ELSET={}", p.name))
                        .line(&format!("{kg:.9e},"));
                }
                Section::Ground { dof, k } => {
                    // ccx wants the stiffness with a trailing comma (`1e5` alone is "without data").
                    d.line(&format!("*SPRING, ELSET={}", p.name))
                        .line(&dof.to_string())
                        .line(&format!("{k:.9e},"));
                }
            }
        }
        if !self.rigid.is_empty() {
            d.nset("WD_PRINT", &self.printed_nodes());
        }
        for r in &self.rigid {
            d.line(&format!(
                "*RIGID BODY, NSET={}, REF NODE={}, ROT NODE={}",
                r.nset, r.ref_node, r.rot_node
            ));
        }
        if !self.fixed.is_empty() {
            d.line("*BOUNDARY");
            for (set, a, b) in &self.fixed {
                d.line(&format!("{set}, {a}, {b}"));
            }
        }
        d
    }

    /// Nodes whose motion the `.dat` must print: ccx's `.frd` with `OUTPUT=2D` holds only the
    /// nodes of structural elements, so the rigid parts' own nodes (point masses), REF and ROT
    /// nodes (the rotation) come from a `*NODE PRINT`.
    pub fn printed_nodes(&self) -> Vec<usize> {
        let mut v: Vec<usize> = Vec::new();
        for r in &self.rigid {
            v.extend(self.nsets.get(&r.nset).into_iter().flatten());
            v.push(r.ref_node);
            v.push(r.rot_node);
        }
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Mode shapes at the original nodes (`.frd`; with `stresses` at the expanded nodes, with
    /// the stresses), the rigid parts' nodes and rotations and the mass properties (`.dat`).
    pub fn output_requests(&self, d: &mut Deck, stresses: bool) {
        if stresses {
            d.line("*NODE FILE").line("U").line("*EL FILE").line("S");
        } else {
            d.line("*NODE FILE, OUTPUT=2D").line("U");
        }
        if !self.rigid.is_empty() {
            d.line("*NODE PRINT, NSET=WD_PRINT").line("U");
        }
        d.line("*EL PRINT, ELSET=EALL, TOTALS=ONLY").line("EMAS");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coincident_points_share_a_node() {
        let mut m = Mesh::new("t");
        let a = m.node([0.1, 0.2, 0.3]);
        let b = m.node([0.1 + 3e-8, 0.2, 0.3 - 3e-8]);
        let c = m.node([0.1 + 1e-5, 0.2, 0.3]);
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(m.nodes.len(), 2);
    }
}
