//! The merged model under construction: both meshes with their nodes renumbered and their
//! names prefixed, and every attachment of the model as an auxiliary node tied to the rigid
//! fit of its FE node set (followers, point-mass carriers, scalar dofs). Separate from the deck
//! (`deck.rs`) as the mechanics of the ties, which the deck only calls.

use super::AssemblyError;
use crate::error::{Error, PipelineError};
use crate::mesh::{Mesh, Rigid, Section};
use crate::modal::{Reading, point_reading_full};
use std::f64::consts::PI;
use washdyn_model::geom::f::{add, sub};
use washdyn_model::ir::modal::{ModalData, point_at};
use washdyn_model::ir::{BodyRef, Model};

/// The penalty springs' frequency with the mass they hold (Hz), and their length (m).
const PENALTY_HZ: f64 = 1e5;
const PENALTY_ARM: f64 = 0.01;

/// One body's mesh and modal data, and where its nodes go in the assembly.
pub(super) struct Body<'a> {
    pub(super) mesh: &'a Mesh,
    pub(super) data: &'a ModalData,
    pub(super) offset: usize,
    pub(super) prefix: &'static str,
}

/// Where a model point reads its body: the FE node set and the position the rigid fit is
/// evaluated at (the modal point's, moved with the marker's offset from it, as the equations
/// do: `Equations::new`'s markers and carried masses).
pub(super) struct Site {
    pub(super) tub: bool,
    pub(super) set: String,
    pub(super) at: [f64; 3],
}

/// One term of an equation: node, dof (1..3), coefficient.
pub(super) type Term = (usize, usize, f64);
/// Three equations' terms, one per component x, y, z.
pub(super) type Rows = [Vec<Term>; 3];

/// A two-node element's constant: one value, or (value, frequency Hz) pairs.
pub(super) enum Dashpot {
    Constant(f64),
    Table(Vec<(f64, f64)>),
}

/// The merged model under construction.
pub(super) struct Builder<'a> {
    pub(super) tub: Body<'a>,
    pub(super) cabinet: Body<'a>,
    pub(super) mesh: Mesh,
    pub(super) equations: Vec<Vec<Term>>,
    /// (element set, kind, node a, node b, constant): SPRINGA and DASHPOTA elements.
    pub(super) pairs: Vec<(String, &'static str, usize, usize, Dashpot)>,
    pub(super) held: Vec<usize>,
    pub(super) ground: Vec<usize>,
}

impl<'a> Builder<'a> {
    fn body(&self, tub: bool) -> &Body<'a> {
        if tub { &self.tub } else { &self.cabinet }
    }

    fn rigid_of(&self, s: &Site) -> Option<&Rigid> {
        self.body(s.tub).mesh.rigid.iter().find(|r| r.nset == s.set)
    }

    /// (node in the assembly, R_i, T_i) of the rigid fit of `s`.
    fn reading(&self, s: &Site) -> Result<Reading, PipelineError> {
        let b = self.body(s.tub);
        Ok(point_reading_full(b.mesh, &s.set, s.at)?
            .into_iter()
            .map(|(id, r, t)| (id + b.offset, r, t))
            .collect())
    }

    /// A new node at `p` whose translation follows the site (a rigid part's point, or the
    /// rigid fit of the set by equations).
    pub(super) fn follower(&mut self, s: &Site, p: [f64; 3]) -> Result<usize, Error> {
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
    pub(super) fn carrier(
        &mut self,
        s: &Site,
        p: [f64; 3],
        kg: f64,
        k: usize,
    ) -> Result<usize, Error> {
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
    pub(super) fn rows(&self, s: &Site, rotation: bool) -> Result<Rows, Error> {
        if self.rigid_of(s).is_some() {
            let set = s.set.clone();
            return Err(AssemblyError::RigidPart { set }.into());
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
    pub(super) fn scalar(&mut self, p: [f64; 3], terms: Vec<Term>) -> usize {
        let id = self.mesh.fresh_node(p);
        self.tie(id, 1, terms);
        self.held.push(id);
        id
    }

    /// Where a model point on `body` reads the FE model.
    pub(super) fn site(
        &self,
        model: &Model,
        body: BodyRef,
        p: [f64; 3],
    ) -> Result<Site, AssemblyError> {
        let find = |tub: bool, q: [f64; 3]| -> Result<(String, [f64; 3]), AssemblyError> {
            let b = self.body(tub);
            let mp = point_at(b.data, q).ok_or(AssemblyError::NoModalPoint {
                body: if tub { "tub" } else { "cabinet" },
                at: q,
            })?;
            let set = b.mesh.nsets.get(&mp.name).ok_or_else(|| {
                let set = mp.name.clone();
                AssemblyError::StaleSet { set }
            })?;
            // The modal data and the mesh must be one (a set regenerated since has another size).
            if set.len() != mp.nodes {
                return Err(AssemblyError::SetSize {
                    set: mp.name.clone(),
                    mesh: set.len(),
                    data: mp.nodes,
                });
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
            BodyRef::DamperPart(_) => Err(AssemblyError::DamperPart),
            BodyRef::Counterweight(_) => Err(AssemblyError::Counterweight),
        }
    }
}

fn drum_mount(model: &Model) -> Result<[f64; 3], AssemblyError> {
    model
        .rotors
        .iter()
        .find(|r| r.name == "drum")
        .map(|r| r.mount_point())
        .ok_or(AssemblyError::NoDrum)
}

/// Merge `mesh` into `into`: nodes after the existing ones, parts, sets and materials prefixed.
pub(super) fn merge(into: &mut Mesh, mesh: &Mesh, prefix: &str) {
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
