//! Structured mesh generators on a `Mesh`: quadratic shells, bricks and beams from a map of the
//! unit square, cube or line. Coincident points become one node (`Mesh::node`), which is how the
//! pieces of a body join. Each generator returns the node ids of its grid for node sets.

use crate::lumping::{HEX20, det3, hex20, hex20_jacobian};
use crate::mesh::{Mesh, Section};
use std::collections::BTreeMap;

/// Grid point (i, j) of a (2 nu + 1) x (2 nv + 1) serendipity grid -> node id.
pub type Grid2 = BTreeMap<(usize, usize), usize>;

/// S8R elements over `f(u, v)`, u, v in [0, 1], `nu` x `nv` elements. With `closed_v` the last
/// row of elements joins the first (full circles). Element corners run (u, v) counter-clockwise,
/// so the normal is f_u x f_v.
pub fn shell_grid(
    m: &mut Mesh,
    part: &str,
    section: &Section,
    nu: usize,
    nv: usize,
    closed_v: bool,
    f: impl Fn(f64, f64) -> [f64; 3],
) -> Grid2 {
    shell_grid_masked(m, part, section, nu, nv, closed_v, |_, _| true, f)
}

/// `shell_grid` keeping only the elements (ei, ej) that `keep` accepts (openings); only their
/// nodes are made.
#[allow(clippy::too_many_arguments)]
pub fn shell_grid_masked(
    m: &mut Mesh,
    part: &str,
    section: &Section,
    nu: usize,
    nv: usize,
    closed_v: bool,
    keep: impl Fn(usize, usize) -> bool,
    f: impl Fn(f64, f64) -> [f64; 3],
) -> Grid2 {
    let (gu, gv) = (2 * nu, 2 * nv);
    let mut g = Grid2::new();
    for j in 0..=gv {
        for i in 0..=gu {
            if i % 2 == 1 && j % 2 == 1 {
                continue;
            }
            // Only points of a kept element.
            let touches = (i.saturating_sub(1) / 2..=(i / 2).min(nu - 1)).any(|ei| {
                (j.saturating_sub(1) / 2..=(j / 2).min(nv - 1))
                    .any(|ej| keep(ei, ej) || (closed_v && j == gv && keep(ei, 0)))
            });
            if !touches {
                continue;
            }
            let jj = if closed_v && j == gv { 0 } else { j };
            let id = m.node(f(i as f64 / gu as f64, jj as f64 / gv as f64));
            g.insert((i, j), id);
        }
    }
    let mut elems = Vec::new();
    for ej in 0..nv {
        for ei in 0..nu {
            if !keep(ei, ej) {
                continue;
            }
            let (i, j) = (2 * ei, 2 * ej);
            elems.push(vec![
                g[&(i, j)],
                g[&(i + 2, j)],
                g[&(i + 2, j + 2)],
                g[&(i, j + 2)],
                g[&(i + 1, j)],
                g[&(i + 2, j + 1)],
                g[&(i + 1, j + 2)],
                g[&(i, j + 1)],
            ]);
        }
    }
    m.part(part, section.clone()).elements.extend(elems);
    g
}

/// C3D20 elements over `f(u, v, w)` in the unit cube, `n[0]` x `n[1]` x `n[2]` elements;
/// `closed_v` joins v = 1 to v = 0. Returns the ids of the grid's points (i, j, k) on the
/// (2n + 1)^3 grid that are nodes. Elements with a negative Jacobian are mirrored in w.
pub fn brick_grid(
    m: &mut Mesh,
    part: &str,
    section: &Section,
    n: [usize; 3],
    closed_v: bool,
    f: impl Fn(f64, f64, f64) -> [f64; 3],
) -> BTreeMap<(usize, usize, usize), usize> {
    let g = [2 * n[0], 2 * n[1], 2 * n[2]];
    let mut ids = BTreeMap::new();
    for k in 0..=g[2] {
        for j in 0..=g[1] {
            for i in 0..=g[0] {
                if (i % 2 + j % 2 + k % 2) > 1 {
                    continue;
                }
                let jj = if closed_v && j == g[1] { 0 } else { j };
                let p = f(
                    i as f64 / g[0] as f64,
                    jj as f64 / g[1] as f64,
                    k as f64 / g[2] as f64,
                );
                ids.insert((i, j, k), m.node(p));
            }
        }
    }
    let mut elems = Vec::new();
    for ek in 0..n[2] {
        for ej in 0..n[1] {
            for ei in 0..n[0] {
                let at = |c: &[f64; 3], flip: bool| {
                    let w = if flip { -c[2] } else { c[2] };
                    ids[&(
                        2 * ei + (c[0] + 1.0) as usize,
                        2 * ej + (c[1] + 1.0) as usize,
                        2 * ek + (w + 1.0) as usize,
                    )]
                };
                let mut e: Vec<usize> = HEX20.iter().map(|c| at(c, false)).collect();
                // Orientation: the Jacobian at the centre must be positive.
                let (_, d) = hex20([0.0; 3]);
                let j = hex20_jacobian(&d, |a| m.nodes[e[a] - 1]);
                if det3(j) < 0.0 {
                    e = HEX20.iter().map(|c| at(c, true)).collect();
                }
                elems.push(e);
            }
        }
    }
    m.part(part, section.clone()).elements.extend(elems);
    ids
}

/// B32 elements from `a` to `b`, `n` elements; returns the line's node ids.
pub fn beam_line(
    m: &mut Mesh,
    part: &str,
    section: &Section,
    a: [f64; 3],
    b: [f64; 3],
    n: usize,
) -> Vec<usize> {
    let ids: Vec<usize> = (0..=2 * n)
        .map(|i| {
            let t = i as f64 / (2 * n) as f64;
            m.node(std::array::from_fn(|c| a[c] + t * (b[c] - a[c])))
        })
        .collect();
    let elems: Vec<Vec<usize>> = (0..n)
        .map(|e| vec![ids[2 * e], ids[2 * e + 1], ids[2 * e + 2]])
        .collect();
    m.part(part, section.clone()).elements.extend(elems);
    ids
}

/// The piecewise-linear map of t in [0, 1] through `stations` at equal steps of t: a grid of
/// `stations.len() - 1` elements over it has its element ends at the stations and its
/// mid-side nodes half way (graded meshes from the uniform generators).
pub fn piecewise(stations: &[f64], t: f64) -> f64 {
    let n = stations.len() - 1;
    let s = (t * n as f64).clamp(0.0, n as f64);
    let k = (s.floor() as usize).min(n - 1);
    stations[k] + (s - k as f64) * (stations[k + 1] - stations[k])
}

/// C3D20 bricks of a polar block about the x axis through (., 0, `zc`): radii `rs`, axial
/// stations `xs`, and `n_circ` elements over the angles [a0, a0 + span] (from +z towards +y;
/// a full circle if `span` is 2 pi). Element ends sit at the stations, so blocks with common
/// stations share their nodes.
#[allow(clippy::too_many_arguments)]
pub fn polar_bricks(
    m: &mut Mesh,
    part: &str,
    section: &Section,
    zc: f64,
    rs: &[f64],
    xs: &[f64],
    (a0, span, n_circ): (f64, f64, usize),
) -> BTreeMap<(usize, usize, usize), usize> {
    let closed = (span - 2.0 * std::f64::consts::PI).abs() < 1e-12;
    brick_grid(
        m,
        part,
        section,
        [rs.len() - 1, n_circ, xs.len() - 1],
        closed,
        |u, v, w| on_circle(piecewise(xs, w), 0.0, zc, piecewise(rs, u), a0 + span * v),
    )
}

/// A point on a circle about the x axis through (., yc, zc): angle from +z towards +y.
pub fn on_circle(x: f64, yc: f64, zc: f64, r: f64, angle: f64) -> [f64; 3] {
    [x, yc + r * angle.sin(), zc + r * angle.cos()]
}

/// Node ids of `m` within `radius` of `p` (sorted).
pub fn near(
    m: &Mesh,
    ids: impl IntoIterator<Item = usize>,
    p: [f64; 3],
    radius: f64,
) -> Vec<usize> {
    let mut v: Vec<usize> = ids
        .into_iter()
        .filter(|&id| {
            let q = m.nodes[id - 1];
            (0..3).map(|i| (q[i] - p[i]).powi(2)).sum::<f64>() <= radius * radius
        })
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lumping::element_mass;
    use crate::mesh::Material;
    use std::f64::consts::PI;

    fn steel() -> Material {
        Material {
            name: "STEEL".into(),
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        }
    }

    #[test]
    fn closed_cylinder_and_annular_bricks_have_the_analytic_mass() {
        let mut m = Mesh::new("t");
        let s = Section::Shell {
            thickness: 0.001,
            material: steel(),
        };
        let g = shell_grid(&mut m, "CYL", &s, 4, 24, true, |u, v| {
            on_circle(0.3 * u, 0.0, 0.0, 0.2, 2.0 * PI * v)
        });
        // 9 x 48 grid points minus the 4 x 24 element centres, the seam shared.
        assert_eq!(m.nodes.len(), 9 * 48 - 4 * 24);
        assert_eq!(g.len(), 9 * 49 - 4 * 24);
        let shell = element_mass(&m);
        let exact = 2.0 * PI * 0.2 * 0.3 * 0.001 * 7850.0;
        assert!((shell / exact - 1.0).abs() < 1e-5, "{shell} vs {exact}");
        let b = Section::Solid { material: steel() };
        brick_grid(&mut m, "RING", &b, [2, 24, 1], true, |u, v, w| {
            on_circle(-0.05 * w, 0.0, 0.0, 0.05 + 0.05 * u, 2.0 * PI * v)
        });
        let ring = element_mass(&m) - shell;
        let exact = PI * (0.1f64.powi(2) - 0.05f64.powi(2)) * 0.05 * 7850.0;
        assert!((ring / exact - 1.0).abs() < 1e-5, "{ring} vs {exact}");
    }
}
