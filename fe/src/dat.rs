//! Node prints in CalculiX's `.dat`: `*NODE PRINT, NSET=..` / `U` writes, per eigenmode, a block
//! "displacements (vx,vy,vz) for set NAME and time ..." with one line per node. For a rigid
//! part's ROT NODE that "displacement" is the part's rotation vector (rad).

use crate::error::ResultsError;

/// One mode's printed nodes: (node id, three values).
pub type Print = Vec<(usize, [f64; 3])>;

/// Per eigenmode (in file order), the printed nodes of set `set` with their three values.
pub fn node_prints(dat: &str, set: &str) -> Result<Vec<Print>, ResultsError> {
    node_table(dat, "displacements (vx,vy,vz)", set)
}

/// Per step (in file order), the reaction forces (`*NODE PRINT` / `RF`) of set `set`.
pub fn reactions(dat: &str, set: &str) -> Result<Vec<Print>, ResultsError> {
    node_table(dat, "forces (fx,fy,fz)", set)
}

/// The blocks "`what` for set SET and time ..." of a `.dat`, one line per node.
fn node_table(dat: &str, what: &str, set: &str) -> Result<Vec<Print>, ResultsError> {
    let head = format!("for set {} and time", set.to_ascii_uppercase());
    let mut out = Vec::new();
    let mut lines = dat.lines().enumerate().peekable();
    while let Some((_, l)) = lines.next() {
        if !(l.contains(what) && l.contains(&head)) {
            continue;
        }
        let mut block = Vec::new();
        // A blank line, then one line per node up to the next blank line.
        while lines.peek().is_some_and(|(_, l)| l.trim().is_empty()) {
            lines.next();
        }
        while let Some((i, l)) = lines.next_if(|(_, l)| !l.trim().is_empty()) {
            let f: Vec<&str> = l.split_whitespace().collect();
            let bad = || ResultsError::NotAPrint {
                line: i + 1,
                what: "node",
                text: l.to_string(),
            };
            if f.len() != 4 {
                return Err(bad());
            }
            let id = f[0].parse::<usize>().map_err(|_| bad())?;
            let mut v = [0.0; 3];
            for k in 0..3 {
                v[k] = f[k + 1].parse::<f64>().map_err(|_| bad())?;
            }
            block.push((id, v));
        }
        out.push(block);
    }
    Ok(out)
}

/// One element's stresses at its integration points, in ccx's point order: (xx, yy, zz, xy, yz,
/// zx) as the `.frd` orders them.
pub type ElementStresses = (usize, Vec<[f64; 6]>);

/// The first block "stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz) for set SET" of a
/// `.dat` (`*EL PRINT, ELSET=SET` / `S`), per element in file order. ccx prints a shell's
/// expanded brick in the shell's own axes unless the print asks for `GLOBAL=YES` (a line then
/// ends with the orientation's name, `_shell_0000000001`: ignored here).
pub fn element_stresses(dat: &str, set: &str) -> Result<Vec<ElementStresses>, ResultsError> {
    let head = format!("for set {} and time", set.to_ascii_uppercase());
    let mut lines = dat.lines().enumerate().peekable();
    let Some(_) =
        lines.find(|(_, l)| l.contains("stresses (elem, integ.pnt.") && l.contains(&head))
    else {
        return Ok(Vec::new());
    };
    while lines.peek().is_some_and(|(_, l)| l.trim().is_empty()) {
        lines.next();
    }
    let mut out: Vec<ElementStresses> = Vec::new();
    while let Some((i, l)) = lines.next_if(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split_whitespace().collect();
        let bad = || ResultsError::NotAPrint {
            line: i + 1,
            what: "stress",
            text: l.to_string(),
        };
        if f.len() < 8 {
            return Err(bad());
        }
        let elem = f[0].parse::<usize>().map_err(|_| bad())?;
        let point = f[1].parse::<usize>().map_err(|_| bad())?;
        let mut v = [0.0; 6];
        for k in 0..6 {
            v[k] = f[k + 2].parse::<f64>().map_err(|_| bad())?;
        }
        // ccx's order xx, yy, zz, xy, xz, yz -> the .frd's xx, yy, zz, xy, yz, zx.
        let s = [v[0], v[1], v[2], v[3], v[5], v[4]];
        match out.last_mut() {
            Some((e, pts)) if *e == elem => {
                if point != pts.len() + 1 {
                    return Err(bad());
                }
                pts.push(s);
            }
            _ => {
                if point != 1 {
                    return Err(bad());
                }
                out.push((elem, vec![s]));
            }
        }
    }
    Ok(out)
}

/// ccx's `EMAS` totals of an element set (`*EL PRINT, TOTALS=ONLY` / `EMAS`): mass, CoG and
/// the second moments about the CoG. Note: ccx's "mass moment of inertia (xx, yy, zz, xy, xz,
/// yz)" is the second-moment tensor J = sum dm r r^T (checked on a beam along x: its "xx" is
/// m L^2 / 12), not the inertia tensor; the inertia is tr(J) E - J (`inertia`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emas {
    pub mass: f64,
    pub cog: [f64; 3],
    /// J about the CoG: xx, yy, zz, xy, xz, yz.
    pub second_moments: [f64; 6],
}

impl Emas {
    /// The inertia tensor about the CoG.
    pub fn inertia(&self) -> [[f64; 3]; 3] {
        let s = self.second_moments;
        let j = [[s[0], s[3], s[4]], [s[3], s[1], s[5]], [s[4], s[5], s[2]]];
        let tr = s[0] + s[1] + s[2];
        std::array::from_fn(|a| std::array::from_fn(|b| if a == b { tr } else { 0.0 } - j[a][b]))
    }
}

/// The first `EMAS` totals of set `set` in a `.dat`.
pub fn emas(dat: &str, set: &str) -> Option<Emas> {
    let tail = format!("for set {} and time", set.to_ascii_uppercase());
    let values = |head: &str| -> Option<Vec<f64>> {
        let mut lines = dat.lines();
        lines.find(|l| l.trim_start().starts_with(head) && l.contains(&tail))?;
        let row = lines.find(|l| !l.trim().is_empty())?;
        row.split_whitespace().map(|v| v.parse().ok()).collect()
    };
    let mass = *values("total mass for set")?.first()?;
    let cog = values("center of gravity")?;
    let j = values("total mass moment of inertia about the center")?;
    Some(Emas {
        mass,
        cog: [*cog.first()?, *cog.get(1)?, *cog.get(2)?],
        second_moments: j.get(..6)?.try_into().ok()?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn emas_totals_as_ccx_prints_them() {
        let dat = " total mass for set EALL and time  0.1000000E+01\n\n        6.280000E-01\n\n \
                   total mass moment of inertia (xx,yy,zz,xy,xz,yz) for set EALL and time  0.1000000E+01\n\n        \
                   8.373333E-03  2.093333E-05  2.093333E-05 -6.776264E-21 -6.098637E-20  1.058791E-21\n\n \
                   center of gravity for set EALL and time  0.1000000E+01\n\n        1.000000E-01 -1.726437E-19 -8.200574E-19\n\n \
                   total mass moment of inertia about the center ofgravity (xx,yy,zz,xy,xz,yz) for set EALL and time  0.1000000E+01\n\n        \
                   2.093333E-03  2.093333E-05  2.093333E-05  4.065758E-21 -9.486769E-21  1.058791E-21\n";
        let e = emas(dat, "eall").unwrap();
        assert_eq!(e.mass, 0.628);
        assert_eq!(e.cog[0], 0.1);
        // A 0.2 m beam along x (20 mm square): I_yy = m (L^2 + a^2) / 12.
        let i = e.inertia();
        assert!((i[1][1] - (2.093333e-3 + 2.093333e-5)).abs() < 1e-12);
        assert!((i[0][0] - 2.0 * 2.093333e-5).abs() < 1e-12);
    }

    #[test]
    fn element_stresses_in_the_frd_order() {
        // As ccx 2.20 prints them (a shell's expanded brick in global axes ends with its
        // orientation's name).
        let dat = "\n stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz) for set WD_SPIN and \
                   time  0.1000000E+01\n\n         3   1  1.0E+06  2.0E+06  3.0E+06  4.0E+06  \
                   5.0E+06  6.0E+06 _shell_0000000003   \n         3   2  1 2 3 4 5 6\n        \
                   12   1  -1 -2 -3 -4 -5 -6\n\n";
        let s = element_stresses(dat, "wd_spin").unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].0, 3);
        assert_eq!(s[0].1[0], [1e6, 2e6, 3e6, 4e6, 6e6, 5e6]);
        assert_eq!(s[0].1[1], [1.0, 2.0, 3.0, 4.0, 6.0, 5.0]);
        assert_eq!(s[1], (12, vec![[-1.0, -2.0, -3.0, -4.0, -6.0, -5.0]]));
        assert!(element_stresses(dat, "other").unwrap().is_empty());
    }

    #[test]
    fn blocks_per_mode() {
        // As ccx 2.20 prints them.
        let dat = "\n                    E I G E N V A L U E    N U M B E R     1\n\n\n \
                   displacements (vx,vy,vz) for set WD_ROT and time  0.1000000E+01\n\n         \
                   7  1.000000E-01 -2.000000E+00  0.000000E+00\n        \
                   12  3.0E+00  0.0 0.0\n\n                    E I G E N V A L U E    N U M B E R     2\n\n\n \
                   displacements (vx,vy,vz) for set WD_ROT and time  0.1000000E+01\n\n         \
                   7  5.000000E-01  0.000000E+00  0.000000E+00\n        12  0 0 1\n";
        let p = node_prints(dat, "wd_rot").unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!(p[0], vec![(7, [0.1, -2.0, 0.0]), (12, [3.0, 0.0, 0.0])]);
        assert_eq!(p[1][1], (12, [0.0, 0.0, 1.0]));
    }
}
