//! The speed profile's rules: points, strictly increasing time, rpm within [0, `MAX_RPM`].

use super::{Ctx, Path};
use crate::ir::Model;

/// Highest drum speed a profile may ask for, rpm: household spin speeds end near 1800 rpm; the
/// bound leaves room for studies beyond, but not for a typo (a profile to 1e6 rpm displaced the
/// drum front by metres).
pub const MAX_RPM: f64 = 3000.0;

/// The drum speed profile (its table; a CSV file is read into it before the check).
pub(super) fn speed(c: &mut Ctx, m: &Model) {
    let sp = Path::of(&["speed"]);
    if m.speed.table.is_empty() {
        c.err(sp.clone().key("table"), "speed: the profile has no points");
    }
    for (i, row) in m.speed.table.iter().enumerate() {
        let p = sp.clone().key("table").idx(i);
        if !c.finite(&p, "speed", row) {
            continue;
        }
        if i > 0 && row[0] <= m.speed.table[i - 1][0] {
            c.err(
                p.clone(),
                format!(
                    "speed: time must increase strictly, but row {i} has t = {} after t = {}",
                    row[0],
                    m.speed.table[i - 1][0]
                ),
            );
        }
        if row[1] < 0.0 {
            c.err(p, format!("speed: negative rpm {} at row {i}", row[1]));
        } else if row[1] > MAX_RPM {
            c.err(
                p,
                format!(
                    "speed: {} rpm at row {i} exceeds the limit of {MAX_RPM} rpm",
                    row[1]
                ),
            );
        }
    }
}
