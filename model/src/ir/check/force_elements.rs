//! The force elements' rules: springs (and whether one carries the tub), linear dampers,
//! friction dampers with their moving parts, gaskets with their matrices and loss factors, and
//! contacts. Each element has a unique name and two distinct ends.

use super::{Ctx, Names, Path, asymmetry, norm, sym_eigenvalues};
use crate::ir::{Attach, BodyRef, FrictionLaw, LossFactor, M6, Model, V3};

/// Steepest friction characteristic, s/m: 90 % of f_max at 6.4 um/s already, the near-Coulomb
/// end of the hard-case studies. The damper's regularised damping f_max * slope * 2/pi makes the
/// problem stiff in proportion; at 1e12 s/m the explicit methods' stable step falls below
/// 1e-12 s and a run never ends (and the run's progress budget stops runs too slow to finish).
pub const MAX_FRICTION_SLOPE: f64 = 1e6;

/// Springs: a unique name, two distinct ends, a positive stiffness and free length, and one that
/// carries the tub rather than pulling it down (`spring_carries`).
pub(super) fn springs<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, s) in m.springs.iter().enumerate() {
        let p = Path::of(&["springs"]).idx(i);
        names.add(c, p.clone(), "spring", &s.name);
        let w = format!("spring `{}`", s.name);
        two_points(c, &p, &w, &s.a, &s.b);
        c.positive(
            p.clone().key("stiffness"),
            &format!("{w}: stiffness"),
            s.stiffness,
        );
        c.positive(
            p.clone().key("free_length"),
            &format!("{w}: free_length"),
            s.free_length,
        );
        spring_carries(c, p, &w, s, &m.gravity);
    }
}

/// Linear dampers: a unique name, two distinct ends, a damping >= 0.
pub(super) fn dampers<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, d) in m.dampers.iter().enumerate() {
        let p = Path::of(&["dampers"]).idx(i);
        names.add(c, p.clone(), "damper", &d.name);
        let w = format!("damper `{}`", d.name);
        two_points(c, &p, &w, &d.a, &d.b);
        c.non_negative(p.key("damping"), &format!("{w}: damping"), d.damping);
    }
}

/// Friction dampers: a unique name, two distinct ends, f_max and bearings >= 0, a positive slope
/// up to `MAX_FRICTION_SLOPE`, and a valid moving part if it has one.
pub(super) fn friction_dampers<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, d) in m.friction_dampers.iter().enumerate() {
        let p = Path::of(&["friction_dampers"]).idx(i);
        names.add(c, p.clone(), "friction damper", &d.name);
        let w = format!("friction damper `{}`", d.name);
        two_points(c, &p, &w, &d.a, &d.b);
        c.non_negative(p.clone().key("f_max"), &format!("{w}: f_max"), d.f_max);
        law(c, &p, &w, d);
        if d.slope > MAX_FRICTION_SLOPE {
            c.err(
                p.clone().key("slope"),
                format!(
                    "{w}: slope {} s/m exceeds {MAX_FRICTION_SLOPE:e} s/m (the run would be too \
                     stiff to integrate)",
                    d.slope
                ),
            );
        }
        c.non_negative(
            p.clone().key("bearing_stiffness"),
            &format!("{w}: bearing_stiffness"),
            d.bearing_stiffness,
        );
        c.non_negative(
            p.clone().key("bearing_damping"),
            &format!("{w}: bearing_damping"),
            d.bearing_damping,
        );
        if let Some(mp) = &d.moving_part {
            moving_part(c, p.key("moving_part"), &w, mp);
        }
    }
}

/// A friction damper's law and its parameters: arctan needs a positive slope; elasto-plastic
/// a positive, finite axial stiffness and a breakaway fraction in (0, 1).
fn law(c: &mut Ctx, p: &Path, w: &str, d: &crate::ir::FrictionDamper) {
    match d.law {
        FrictionLaw::Arctan => c.positive(p.clone().key("slope"), &format!("{w}: slope"), d.slope),
        FrictionLaw::ElastoPlastic => {
            let k = p.clone().key("axial_stiffness");
            match d.axial_stiffness {
                Some(v) => c.positive(k, &format!("{w}: axial_stiffness"), v),
                None => c.err(
                    k,
                    format!("{w}: law `elasto_plastic` needs `axial_stiffness` (N/m)"),
                ),
            }
        }
    }
    // The other law's parameter, given for a scene's `friction_law.<law>`: valid too.
    if d.slope != 0.0 && !d.law.is_arctan() {
        c.positive(p.clone().key("slope"), &format!("{w}: slope"), d.slope);
    }
    if let Some(k) = d.axial_stiffness.filter(|_| d.law.is_arctan()) {
        c.positive(
            p.clone().key("axial_stiffness"),
            &format!("{w}: axial_stiffness"),
            k,
        );
    }
    // Below 1: the transition's width (1 - b) z_ss divides the law's rate.
    if let Some(b) = d.breakaway.filter(|b| !(*b > 0.0 && *b < 1.0)) {
        c.err(
            p.clone().key("breakaway"),
            format!("{w}: breakaway must be in (0, 1), got {b}"),
        );
    }
}

/// What a friction damper lacks to run on `law` (a scene's `friction_law.<law>`).
pub(super) fn law_misses(law: FrictionLaw, d: &crate::ir::FrictionDamper) -> Option<&'static str> {
    match law {
        FrictionLaw::Arctan => (d.slope <= 0.0).then_some("slope"),
        FrictionLaw::ElastoPlastic => d.axial_stiffness.is_none().then_some("axial_stiffness"),
    }
}

/// Gaskets: a unique name, two different bodies, a finite point, symmetric positive
/// semi-definite stiffness and damping, a valid loss factor.
pub(super) fn gaskets<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, g) in m.gaskets.iter().enumerate() {
        let p = Path::of(&["gaskets"]).idx(i);
        names.add(c, p.clone(), "gasket", &g.name);
        let w = format!("gasket `{}`", g.name);
        if g.a == g.b {
            c.err(
                p.clone().key("b"),
                format!("{w}: connects {} to itself", g.a.name()),
            );
        }
        c.vec3(p.clone().key("point"), &w, &g.point);
        sym_psd(
            c,
            p.clone().key("stiffness"),
            &format!("{w}: stiffness"),
            &g.stiffness,
        );
        sym_psd(
            c,
            p.clone().key("damping"),
            &format!("{w}: damping"),
            &g.damping,
        );
        loss_factor(c, p.key("loss_factor"), &w, g.loss_factor.as_ref());
    }
}

/// Contacts: a unique name and the rules of `contact`.
pub(super) fn contacts<'a>(c: &mut Ctx, names: &mut Names<'a>, m: &'a Model) {
    for (i, k) in m.contacts.iter().enumerate() {
        let p = Path::of(&["contacts"]).idx(i);
        names.add(c, p.clone(), "contact", &k.name);
        contact(c, p, k);
    }
}

/// A friction damper's moving part: a body with mass and inertia on stiff bearings, its CoG
/// on the rod.
fn moving_part(c: &mut Ctx, p: Path, w: &str, mp: &crate::ir::MovingPart) {
    let w = format!("{w}: moving_part");
    c.positive(p.clone().key("mass"), &format!("{w}.mass"), mp.mass);
    c.positive(
        p.clone().key("inertia"),
        &format!("{w}.inertia"),
        mp.inertia,
    );
    c.positive(
        p.clone().key("translational_stiffness"),
        &format!("{w}.translational_stiffness"),
        mp.translational_stiffness,
    );
    if !(0.0..=1.0).contains(&mp.cog) {
        c.err(
            p.key("cog"),
            format!("{w}.cog {} is not a fraction of the rod (0 to 1)", mp.cog),
        );
    }
}

/// Largest contact exponent p: Hertz's 1.5 for a point, 10/9 to 1.5 for the laws in use; p
/// above 1 keeps the force C1 at first touch (zero slope at delta = 0).
pub const MAX_CONTACT_EXPONENT: f64 = 3.0;

/// A contact: its rules, one function each.
fn contact(c: &mut Ctx, p: Path, k: &crate::ir::Contact) {
    let w = format!("contact `{}`", k.name);
    contact_bodies(c, &p, &w, k);
    c.vec3(p.clone().key("point"), &w, &k.point);
    if let Some(b) = &k.b_point {
        c.vec3(p.clone().key("b_point"), &w, b);
    }
    contact_normal(c, p.clone().key("normal"), &w, &k.normal);
    c.non_negative(p.clone().key("gap"), &format!("{w}: gap"), k.gap);
    c.positive(
        p.clone().key("stiffness"),
        &format!("{w}: stiffness"),
        k.stiffness,
    );
    contact_exponent(c, p.clone().key("exponent"), &w, k.exponent);
    c.non_negative(p.key("alpha"), &format!("{w}: alpha (s/m)"), k.alpha);
}

/// A contact touches the tub against the cabinet (or the cabinet against the tub): two
/// different bodies, neither the drum (the drum-tub gap is watched, not a contact).
fn contact_bodies(c: &mut Ctx, p: &Path, w: &str, k: &crate::ir::Contact) {
    let allowed = |b: BodyRef| matches!(b, BodyRef::Tub | BodyRef::Cabinet);
    for (key, b) in [("a", k.a), ("b", k.b)] {
        if !allowed(b) {
            c.err(
                p.clone().key(key),
                format!(
                    "{w}: {key} is the {}; a contact is between tub and cabinet",
                    b.name()
                ),
            );
        }
    }
    if k.a == k.b && allowed(k.a) {
        c.err(
            p.clone().key("b"),
            format!("{w}: touches the {} with itself", k.a.name()),
        );
    }
}

/// The normal is a direction: finite and not the zero vector.
fn contact_normal(c: &mut Ctx, p: Path, w: &str, n: &V3) {
    if c.finite(&p, w, n) && norm(n) < 1e-12 {
        c.err(p, format!("{w}: normal is the zero vector"));
    }
}

/// 1 < p <= MAX_CONTACT_EXPONENT.
fn contact_exponent(c: &mut Ctx, p: Path, w: &str, e: f64) {
    if c.finite(&p, w, &[e]) && !(e > 1.0 && e <= MAX_CONTACT_EXPONENT) {
        c.err(
            p,
            format!(
                "{w}: exponent {e} must lie in (1, {MAX_CONTACT_EXPONENT}]: above 1 the force \
                 is C1 at first touch, which the implicit methods need (Hertz: 1.5)"
            ),
        );
    }
}

/// A suspension spring carries the tub: hanging in tension above it or compressed below it,
/// its force on the tub at the reference position has no large component along gravity. One
/// that pulls the tub down (a tension spring whose cabinet end lies below the tub end, e.g. a
/// mirrored coordinate) adds to the weight instead; the static start then sits far off and a
/// run drifts. Refused when the force on the tub points within 60 degrees of gravity.
fn spring_carries(c: &mut Ctx, p: Path, what: &str, s: &crate::ir::Spring, g: &V3) {
    let all = [s.a.point, s.b.point, *g];
    // Other rules report non-finite or non-positive numbers; this one needs sane ones.
    let sane = all.iter().flatten().all(|v| v.is_finite())
        && s.stiffness > 0.0
        && s.free_length > 0.0
        && s.a.body != s.b.body
        && norm(g) > 0.0;
    if !sane {
        return;
    }
    // From the tub end to the other end.
    let (tub, other, other_key) = if s.a.body == BodyRef::Tub {
        (s.a.point, s.b.point, "b")
    } else {
        (s.b.point, s.a.point, "a")
    };
    let d = [other[0] - tub[0], other[1] - tub[1], other[2] - tub[2]];
    let len = norm(&d);
    if len < 1e-9 {
        return;
    }
    // Tension (len > free length) pulls the tub end towards the other end.
    let f = s.stiffness * (len - s.free_length);
    let along_g = f * (d[0] * g[0] + d[1] * g[1] + d[2] * g[2]) / (len * norm(g));
    if along_g > 0.5 * f.abs() {
        c.err(
            p.key(other_key).key("point"),
            format!(
                "{what}: at the reference position it pulls the tub along gravity ({along_g:.1} N \
                 of its {:.1} N); a suspension spring hangs the tub in tension from above or \
                 supports it in compression from below (an end mirrored?)",
                f.abs()
            ),
        );
    }
}

fn two_points(c: &mut Ctx, p: &Path, what: &str, a: &Attach, b: &Attach) {
    let fa = c.finite(&p.clone().key("a").key("point"), what, &a.point);
    let fb = c.finite(&p.clone().key("b").key("point"), what, &b.point);
    if a.body == b.body {
        c.err(
            p.clone().key("b").key("body"),
            format!("{what}: both ends on the {}", a.body.name()),
        );
    }
    if fa && fb {
        let d = [
            b.point[0] - a.point[0],
            b.point[1] - a.point[1],
            b.point[2] - a.point[2],
        ];
        if norm(&d) < 1e-9 {
            c.err(
                p.clone().key("b").key("point"),
                format!("{what}: both ends at the same point, the axis is undefined"),
            );
        }
    }
}

/// A gasket's loss factor: one number, or a list of 6 (x, y, z, rx, ry, rz); each finite and
/// >= 0 (S K S is then positive semi-definite with K).
fn loss_factor(c: &mut Ctx, p: Path, what: &str, eta: Option<&LossFactor>) {
    match eta {
        None => {}
        Some(LossFactor::Uniform(e)) => c.non_negative(p, &format!("{what}: loss_factor"), *e),
        Some(LossFactor::PerDirection(v)) if v.len() != 6 => c.err(
            p,
            format!(
                "{what}: loss_factor needs one number or 6 (x, y, z, rx, ry, rz), got a list of {}",
                v.len()
            ),
        ),
        Some(LossFactor::PerDirection(v)) => {
            for (i, e) in v.iter().enumerate() {
                c.non_negative(p.clone().idx(i), &format!("{what}: loss_factor"), *e);
            }
        }
    }
}

fn sym_psd(c: &mut Ctx, p: Path, what: &str, m: &M6) {
    if !c.finite(&p, what, m.as_flattened()) {
        return;
    }
    if let Some((i, j)) = asymmetry(m) {
        c.err(
            // The lower entry: the one most likely mistyped.
            p.idx(j).idx(i),
            format!(
                "{what} is not symmetric ([{i}][{j}] = {} but [{j}][{i}] = {})",
                m[i][j], m[j][i]
            ),
        );
        return;
    }
    let ev = sym_eigenvalues(m);
    let scale = ev[5].abs().max(1e-300);
    if ev[0] < -1e-12 * scale {
        c.err(
            p,
            format!(
                "{what} is not positive semi-definite (smallest eigenvalue {:e})",
                ev[0]
            ),
        );
    }
}
