//! The CalculiX result file (`.frd`, ASCII): node coordinates and, per eigenmode, the
//! displacements at the nodes (`*NODE FILE, OUTPUT=2D`: the mid-surface nodes of shells and the
//! line nodes of beams, not ccx's expanded 3-D nodes). Fixed width: a record key (` -1`), the
//! node number (I10) and values (E12.5 each; negative numbers touch their neighbour).

use crate::error::ResultsError;

/// One eigenmode: its number, frequency and nodal displacements (mass-normalised, as ccx writes
/// them), in the order of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    pub number: usize,
    pub frequency_hz: f64,
    pub disp: Vec<(usize, [f64; 3])>,
}

/// What an `.frd` holds that we read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frd {
    pub nodes: Vec<(usize, [f64; 3])>,
    pub modes: Vec<Mode>,
    /// Displacements of each `*STATIC` step's result block, in file order.
    pub statics: Vec<Vec<(usize, [f64; 3])>>,
    /// Stresses (xx, yy, zz, xy, yz, zx; Pa per unit modal coordinate) per eigenmode, in file
    /// order, when the deck asked for them (`*EL FILE` / `S`).
    pub stresses: Vec<Vec<(usize, [f64; 6])>>,
    /// Stresses of each `*STATIC` step, in file order, when asked for.
    pub static_stresses: Vec<Vec<(usize, [f64; 6])>>,
    /// Elements as ccx writes them (number, nodes): with 3-D output, the expanded shells and
    /// beams (20-node bricks) under their original numbers.
    pub elements: Vec<(usize, Vec<usize>)>,
}

/// A ` -1` record: node id and N values (3 for coordinates and displacements, 6 for stresses).
fn record<const N: usize>(l: &str, line: usize) -> Result<(usize, [f64; N]), ResultsError> {
    let bad = |what| ResultsError::Record {
        line,
        what,
        text: l.to_string(),
    };
    let id = l
        .get(3..13)
        .and_then(|s| s.trim().parse::<usize>().ok())
        .ok_or_else(|| bad("no node number"))?;
    let mut v = [0.0; N];
    for (k, x) in v.iter_mut().enumerate() {
        let s = l
            .get(13 + 12 * k..25 + 12 * k)
            .ok_or_else(|| bad("short record"))?;
        *x = s.trim().parse().map_err(|_| bad("not a number"))?;
    }
    Ok((id, v))
}

/// The displacement and stress records of one result block (up to its ` -3`), each `Some` when
/// the block held that quantity.
type Block = (
    Option<Vec<(usize, [f64; 3])>>,
    Option<Vec<(usize, [f64; 6])>>,
);

fn result_block<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Result<Block, ResultsError> {
    let (mut disp, mut stress) = (None, None);
    let (mut is_disp, mut is_stress) = (false, false);
    for (k, l) in lines {
        if l.starts_with(" -4") {
            is_disp = l.contains("DISP");
            is_stress = l.contains("STRESS");
        }
        if l.starts_with(" -3") {
            break;
        }
        if is_disp {
            let d = disp.get_or_insert_with(Vec::new);
            if l.starts_with(" -1") {
                d.push(record(l, k + 1)?);
            }
        }
        if is_stress {
            let s = stress.get_or_insert_with(Vec::new);
            if l.starts_with(" -1") {
                s.push(record(l, k + 1)?);
            }
        }
    }
    Ok((disp, stress))
}

/// Parse an `.frd` text; errors name the line.
pub fn parse(text: &str) -> Result<Frd, ResultsError> {
    let bad = |k: usize, what| ResultsError::Line { line: k + 1, what };
    let mut frd = Frd::default();
    let mut lines = text.lines().enumerate().peekable();
    while let Some((i, l)) = lines.next() {
        let t = l.trim_start();
        if t.starts_with("2C") {
            // Node coordinates.
            for (k, l) in lines.by_ref() {
                if l.starts_with(" -3") {
                    break;
                }
                if l.starts_with(" -1") {
                    frd.nodes.push(record(l, k + 1)?);
                }
            }
        } else if t.starts_with("3C") {
            // Elements: ` -1 number type group material`, then ` -2` lines of node numbers.
            for (k, l) in lines.by_ref() {
                if l.starts_with(" -3") {
                    break;
                }
                if l.starts_with(" -1") {
                    let n = l
                        .split_whitespace()
                        .nth(1)
                        .and_then(|x| x.parse::<usize>().ok())
                        .ok_or_else(|| bad(k, "no element number"))?;
                    frd.elements.push((n, Vec::new()));
                } else if l.starts_with(" -2") {
                    let e = frd
                        .elements
                        .last_mut()
                        .ok_or_else(|| bad(k, "nodes before an element"))?;
                    for x in l.split_whitespace().skip(1) {
                        e.1.push(x.parse().map_err(|_| bad(k, "bad node number"))?);
                    }
                }
            }
        } else if t.starts_with("100CL") && !t.contains("MODAL") {
            // A static step's result block.
            let (disp, stress) = result_block(&mut lines)?;
            frd.statics.extend(disp);
            frd.static_stresses.extend(stress);
        } else if t.starts_with("100CL") {
            let f: Vec<&str> = t.split_whitespace().collect();
            let frequency_hz = f
                .get(2)
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| ResultsError::NoFrequency {
                    line: i + 1,
                    text: l.to_string(),
                })?;
            // The mode number ends the field before `MODAL`.
            let number = f
                .iter()
                .find(|w| w.ends_with("MODAL"))
                .and_then(|w| w.trim_end_matches("MODAL").parse::<usize>().ok())
                .unwrap_or(frd.modes.len() + 1);
            let (disp, stress) = result_block(&mut lines)?;
            frd.stresses.extend(stress);
            if let Some(disp) = disp {
                frd.modes.push(Mode {
                    number,
                    frequency_hz,
                    disp,
                });
            }
        }
    }
    Ok(frd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_width_records_with_touching_negatives() {
        let text = "    2C                         2                                     1\n \
                    -1         1 0.00000E+00 0.00000E+00 0.00000E+00\n \
                    -1         2 1.00000E-01-2.50000E-01 3.00000E+00\n -3\n  \
                    100CL  101 43.81153056          21                     2    1MODAL      1\n \
                    -4  DISP        4    1\n -5  D1          1    2    1    0\n \
                    -1         2-7.03691E-15 8.27897E-16-7.67061E-01\n -3\n";
        let f = parse(text).unwrap();
        assert_eq!(f.nodes[1], (2, [0.1, -0.25, 3.0]));
        assert_eq!(f.modes.len(), 1);
        assert_eq!(f.modes[0].number, 1);
        assert_eq!(f.modes[0].frequency_hz, 43.81153056);
        assert_eq!(
            f.modes[0].disp[0],
            (2, [-7.03691e-15, 8.27897e-16, -0.767061])
        );
    }
}
