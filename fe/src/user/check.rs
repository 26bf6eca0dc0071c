//! The rules of a user's spec that need no solve, run before ccx starts: the modal data's own
//! rules (`ir::modal::problems`) on what the spec and the deck already fix (the mass and
//! centre of gravity from the elements, the points' places and names, the correction loads,
//! the springs to the ground, the spin), so a mistake is refused in a second, at its line,
//! rather than after minutes of ccx by the check of the data it made. The units first: a
//! deck read in the wrong ones shows in everything else.

use super::{SpecProblem, UnitsReading, UserSpec};
use crate::inp::Units;
use crate::lumping::consistent_mass_props;
use crate::mesh::Mesh;
use washdyn_model::geom::f::norm;
use washdyn_model::ir::check::MAX_RPM;
use washdyn_model::ir::modal::{
    LoadKind, MASS_RANGE, MAX_EXTENT, MAX_SUPPORT_STIFFNESS, UNIT_TOLERANCE,
};

/// A refusal: the line of the spec (where known) and what.
pub(super) type Refusal = (Option<usize>, SpecProblem);

/// The spec's line of the `n`-th (from 0) occurrence of `needle`, else of its first.
fn line(text: &str, needle: &str, n: usize) -> Option<usize> {
    let at = text
        .match_indices(needle)
        .nth(n)
        .or_else(|| text.match_indices(needle).next())?;
    Some(super::line_of(text, at.0))
}

/// The spec's line of `needle` on a later line than its first (a name given twice), else of
/// its first.
fn second_line(text: &str, needle: &str) -> Option<usize> {
    let first = text.find(needle)?;
    let next = text[first..].find('\n').map_or(text.len(), |i| first + i);
    let at = text[next..].find(needle).map_or(first, |i| next + i);
    Some(super::line_of(text, at))
}

/// `v <= max`, and false for NaN (as the modal data's rules have it).
fn at_most(v: f64, max: f64) -> bool {
    v <= max
}

/// Plausible mass of a tub, drum or cabinet, kg: tighter than the modal data's `MASS_RANGE`
/// (any part, 1 g to 10 t), as these three are the machine's big parts (the committed drum
/// 9.5 kg, cabinet 29 kg, tub 44 kg; a whole machine with its counterweights under 100 kg).
/// A deck read in the wrong units is off by 1000 in mass (mm-t-s for SI or back), which the
/// wide range lets through for a drum of 9.5 kg (9.5 t) and this one does not.
pub(super) const BODY_MASS: (f64, f64) = (0.1, 500.0);

/// Whether a deck of mass `r.mass` and CoG `r.cog` from the origin is a tub, drum or
/// cabinet: `BODY_MASS` (within the modal data's `MASS_RANGE`) and `MAX_EXTENT`.
fn a_part(r: &UnitsReading) -> bool {
    const _: () = assert!(BODY_MASS.0 >= MASS_RANGE.0 && BODY_MASS.1 <= MASS_RANGE.1);
    (BODY_MASS.0..=BODY_MASS.1).contains(&r.mass) && r.cog <= MAX_EXTENT
}

/// The deck's mass and CoG from its elements (the consistent mass's integrals, which the modal
/// data's mass is, plus the point masses) are a washing machine's part's; else refused at
/// `units`, with the unit systems that would make it one.
pub(super) fn units(text: &str, spec: &UserSpec, mesh: &Mesh) -> Result<(), Refusal> {
    let p = consistent_mass_props(mesh);
    let read = UnitsReading {
        units: spec.units,
        mass: p.mass,
        cog: norm(p.cog),
    };
    if a_part(&read) {
        return Ok(());
    }
    let (l0, m0) = spec.units.length_and_mass();
    let fits = Units::ALL
        .into_iter()
        .filter(|u| *u != spec.units)
        .map(|units| {
            let (l, m) = units.length_and_mass();
            UnitsReading {
                units,
                mass: read.mass * m / m0,
                cog: read.cog * l / l0,
            }
        })
        .filter(a_part)
        .collect();
    Err((line(text, "units", 0), SpecProblem::Units { read, fits }))
}

/// Each spec point's `at` lies among the deck's nodes: within their bounding box grown by
/// `points::FAR` (the farthest a point may be read from the structure).
pub(super) fn positions(text: &str, spec: &UserSpec, mesh: &Mesh) -> Result<(), Refusal> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.nodes {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    for p in &spec.points {
        let Some(at) = p.at else { continue };
        let off = (0..3)
            .map(|i| (lo[i] - at[i]).max(at[i] - hi[i]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt();
        // `at` not finite is `points`' refusal.
        if off > super::points::FAR {
            let point = p.name.clone();
            let problem = SpecProblem::PointOffMesh {
                point,
                at,
                off,
                bounds: Box::new([lo, hi]),
            };
            return Err((line(text, &format!("\"{}\"", p.name), 0), problem));
        }
    }
    Ok(())
}

/// The body's points as placed (`points::points`): their names unique, each correction load a
/// unit direction and a moment only at a set that turns, the springs to the ground each at a
/// one-node point of its own and no stiffer than a support.
pub(super) fn placed(
    text: &str,
    spec: &UserSpec,
    mesh: &Mesh,
    points: &[(String, [f64; 3])],
) -> Result<(), Refusal> {
    for (i, (name, _)) in points.iter().enumerate() {
        if points[..i].iter().any(|(n, _)| n == name) {
            let at = second_line(text, &format!("\"{name}\""));
            let point = name.clone();
            return Err((at, SpecProblem::DuplicatePoint { point }));
        }
    }
    for (index, c) in spec.correction.iter().enumerate() {
        let at = line(text, "direction", index);
        let point = c.point.clone();
        if !at_most((norm(c.direction) - 1.0).abs(), UNIT_TOLERANCE) {
            let direction = c.direction;
            let problem = SpecProblem::CorrectionDirection {
                index,
                point,
                direction,
            };
            return Err((at, problem));
        }
        let nodes = mesh.nsets.get(&c.point).map_or(0, Vec::len);
        if c.kind == LoadKind::Moment && nodes < 3 {
            let problem = SpecProblem::MomentOnFewNodes {
                index,
                point,
                nodes,
            };
            return Err((at, problem));
        }
    }
    springs(text, mesh, points)
}

/// The springs to the ground as the modal data will record them (`pipeline::support_springs`).
fn springs(text: &str, mesh: &Mesh, points: &[(String, [f64; 3])]) -> Result<(), Refusal> {
    let at = line(text, "points", 0);
    let refs: Vec<(&str, [f64; 3])> = points.iter().map(|(n, p)| (n.as_str(), *p)).collect();
    let springs = crate::pipeline::support_springs(mesh, &refs).map_err(|e| {
        let crate::error::PipelineError::LoneSpring { part, node } = e else {
            unreachable!("support_springs refuses lone springs only: {e}")
        };
        let at_node = mesh.nodes[node - 1];
        (at, SpecProblem::LoneSpring { part, at: at_node })
    })?;
    for s in springs {
        if s.stiffness
            .iter()
            .any(|k| !(*k >= 0.0 && *k <= MAX_SUPPORT_STIFFNESS))
        {
            let problem = SpecProblem::SupportStiffness {
                point: s.point,
                stiffness: s.stiffness,
            };
            return Err((at, problem));
        }
    }
    Ok(())
}

/// The spin's speed within the machine's and its axis point inside the machine (the modal
/// data's `geometric_stiffness` rules).
pub(super) fn spin(text: &str, spec: &UserSpec) -> Result<(), Refusal> {
    let Some(s) = spec.spin else { return Ok(()) };
    if s.reference_rpm > MAX_RPM {
        let problem = SpecProblem::SpinSpeed {
            rpm: s.reference_rpm,
        };
        return Err((line(text, "reference_rpm", 0), problem));
    }
    if !at_most(norm(s.axis_point), MAX_EXTENT) {
        let problem = SpecProblem::SpinAxisPoint { at: s.axis_point };
        return Err((line(text, "axis_point", 0), problem));
    }
    Ok(())
}
