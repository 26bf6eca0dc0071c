//! The rigid bodies' rules: the tub's mass properties, the rotors, and the unbalances they
//! carry.

use super::{Ctx, Names, Path, asymmetry, norm, sym_eigenvalues};
use crate::ir::{M3, Model};

/// Largest unbalance as a fraction of the tub mass: the equations treat the unbalance as a small
/// addition to the suspended body (test loads are 0.3-1 kg on a 55 kg tub).
pub const MAX_UNBALANCE_FRACTION: f64 = 0.1;

/// The tub: a positive mass, a finite CoG and an inertia tensor some mass distribution has.
pub(super) fn tub(c: &mut Ctx, m: &Model) {
    let tub = Path::of(&["tub"]);
    c.positive(tub.clone().key("mass"), "tub: mass", m.tub.mass);
    c.vec3(tub.clone().key("cog"), "tub: cog", &m.tub.cog);
    inertia(c, tub.key("inertia"), "tub", &m.tub.inertia);
}

/// Rotors: a unique name, a finite axis point, a non-zero axis and ratio, a polar inertia >= 0.
pub(super) fn rotors<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, r) in m.rotors.iter().enumerate() {
        let p = Path::of(&["rotors"]).idx(i);
        names.add(c, p.clone(), "rotor", &r.name);
        let w = format!("rotor `{}`", r.name);
        c.vec3(p.clone().key("axis_point"), &w, &r.axis_point);
        if c.finite(&p.clone().key("axis"), &w, &r.axis) && norm(&r.axis) < 1e-12 {
            c.err(
                p.clone().key("axis"),
                format!("{w}: axis is the zero vector"),
            );
        }
        if c.finite(&p.clone().key("ratio"), &w, &[r.ratio]) && r.ratio == 0.0 {
            c.err(
                p.clone().key("ratio"),
                format!("{w}: ratio must not be zero"),
            );
        }
        c.non_negative(
            p.key("polar_inertia"),
            &format!("{w}: polar_inertia"),
            r.polar_inertia,
        );
    }
}

/// Unbalances: a unique name, a known rotor, a positive mass small against the tub's, a finite
/// position.
pub(super) fn unbalances<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, u) in m.unbalances.iter().enumerate() {
        let p = Path::of(&["unbalances"]).idx(i);
        names.add(c, p.clone(), "unbalance", &u.name);
        let w = format!("unbalance `{}`", u.name);
        if !m.rotors.iter().any(|r| r.name == u.rotor) {
            c.err(
                p.clone().key("rotor"),
                format!("{w}: unknown rotor `{}`", u.rotor),
            );
        }
        c.positive(p.clone().key("mass"), &format!("{w}: mass"), u.mass);
        // Against a valid tub mass only (an invalid one is reported on its own).
        if m.tub.mass > 0.0 && u.mass > MAX_UNBALANCE_FRACTION * m.tub.mass {
            c.err(
                p.clone().key("mass"),
                format!(
                    "{w}: mass {} kg exceeds {MAX_UNBALANCE_FRACTION} x the tub mass ({} kg): the \
                     small-motion model does not hold for such a load",
                    u.mass, m.tub.mass
                ),
            );
        }
        c.vec3(p.key("position"), &w, &u.position);
    }
}

pub(super) fn inertia(c: &mut Ctx, p: Path, who: &str, m: &M3) {
    if !c.finite(&p, &format!("{who}: inertia"), m.as_flattened()) {
        return;
    }
    if let Some((i, j)) = asymmetry(m) {
        c.err(
            // The lower entry: the one most likely mistyped.
            p.idx(j).idx(i),
            format!(
                "{who}: inertia tensor is not symmetric ([{i}][{j}] = {} but [{j}][{i}] = {})",
                m[i][j], m[j][i]
            ),
        );
        return;
    }
    let ev = sym_eigenvalues(m);
    if ev[0] <= 0.0 {
        c.err(
            p,
            format!("{who}: inertia tensor is not positive definite (principal moments {ev:?})"),
        );
    } else if ev[0] + ev[1] < ev[2] * (1.0 - 1e-12) {
        c.err(
            p,
            format!(
                "{who}: principal moments {ev:?} violate the triangle inequality (I1 + I2 >= I3), \
                 no mass distribution has them"
            ),
        );
    }
}
