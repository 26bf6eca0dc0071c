//! Node prints in CalculiX's `.dat`: `*NODE PRINT, NSET=..` / `U` writes, per eigenmode, a block
//! "displacements (vx,vy,vz) for set NAME and time ..." with one line per node. For a rigid
//! part's ROT NODE that "displacement" is the part's rotation vector (rad).

/// One mode's printed nodes: (node id, three values).
pub type Print = Vec<(usize, [f64; 3])>;

/// Per eigenmode (in file order), the printed nodes of set `set` with their three values.
pub fn node_prints(dat: &str, set: &str) -> Result<Vec<Print>, String> {
    let head = format!("for set {} and time", set.to_ascii_uppercase());
    let mut out = Vec::new();
    let mut lines = dat.lines().enumerate().peekable();
    while let Some((_, l)) = lines.next() {
        if !(l.contains("displacements (vx,vy,vz)") && l.contains(&head)) {
            continue;
        }
        let mut block = Vec::new();
        // A blank line, then one line per node up to the next blank line.
        while lines.peek().is_some_and(|(_, l)| l.trim().is_empty()) {
            lines.next();
        }
        while let Some((i, l)) = lines.next_if(|(_, l)| !l.trim().is_empty()) {
            let f: Vec<&str> = l.split_whitespace().collect();
            let bad = || format!("line {}: not a node print: `{l}`", i + 1);
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

#[cfg(test)]
mod tests {
    use super::*;

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
