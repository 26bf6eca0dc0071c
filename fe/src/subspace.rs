//! Is a field's modal basis the modal data's, up to what another solve of the same deck may
//! change? Modes of (nearly) equal frequency may come out of the eigensolver turned within
//! their subspace, and any mode with either sign; round-off moves the rest by about the
//! printed precision. So the check is per group of (near-)degenerate modes: the principal
//! angles between the two bases' subspaces (their shapes at the modal data's points), and the
//! residual of the best orthogonal map between them (orthogonal because both bases are
//! mass-normalised eigenvectors of one mass matrix). Where a group only turned or flipped, that
//! map re-projects the field onto the data's modes.

use nalgebra::DMatrix;
use std::ops::Range;

/// Frequencies within this relative gap of their neighbour make one group. Another solve
/// perturbs the operator by a relative epsilon and so mixes two modes of relative gap g by about
/// epsilon / g (first-order perturbation theory); two machines' ccx solves of the built-in
/// bodies agree in frequency to 1e-9 (issue 23), so outside a group the mixing stays below
/// 1e-5 even for an epsilon 100 x that, well inside [`SUBSPACE_TOLERANCE`]. The built-in drum's
/// pairs (gap 1e-9), the tub's closest pair (3.7e-5) and the cabinet's (2.0e-5) group; the next
/// gaps (1.3e-4 and up) do not.
pub const DEGENERATE_GAP: f64 = 1e-4;

/// Largest deviation accepted between a group of the field and of the data: the sine of the
/// largest principal angle, and the residual of the best orthogonal map, both relative to the
/// group's amplitude at the points (at least [`FLOOR`] of the largest mode's). ccx prints
/// shapes in E12.5 (6 significant digits, a relative 5e-6 per value), and two machines' solves
/// differ at about 1e-6 (issue 23): 1e-3 is 200 x the print precision and 55 x the largest
/// deviation measured between two machines' solves of the built-in tub and drum (1.8e-5, the
/// tub's correction modes; the drum 1.4e-6), and 1/170 of a mode replaced by its
/// neighbour turned by 10 degrees (0.17), let alone another mesh's or deck's shape (order 1).
pub const SUBSPACE_TOLERANCE: f64 = 1e-3;

/// A group whose amplitude at the points is below this fraction of the largest mode's is held
/// to that floor, not to its own size: the points hardly see it, so round-off of the visible
/// modes mixed into it is no evidence of another shape.
pub const FLOOR: f64 = 1e-3;

/// The groups compared: consecutive eigenmodes (the first `eigenmodes`) whose frequencies are
/// within [`DEGENERATE_GAP`] of their neighbour's, and all correction modes as one group. The
/// correction modes' span is what the static solves define; their split into modes is a small
/// reduced eigenproblem whose Rayleigh quotients are no structural eigenvalues, and another
/// solve mixes them: on this machine's solve of the built-in tub against the committed one,
/// each correction mode alone moved by up to 1.3e-3, the six together by 1.8e-5, the eigenmode
/// groups by at most 1.4e-6 (the drum). A non-finite eigenfrequency stands alone.
pub fn groups(frequencies: &[f64], eigenmodes: usize) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut start = 0;
    for k in 1..=frequencies.len() {
        let close = k < frequencies.len()
            && k != eigenmodes
            && (k > eigenmodes
                || (frequencies[k] - frequencies[k - 1]).abs()
                    <= DEGENERATE_GAP * frequencies[k - 1].abs());
        if !close {
            out.push(start..k);
            start = k;
        }
    }
    out
}

/// One group compared: the sine of its largest principal angle and the residual after the best
/// orthogonal map, each relative to the group's amplitude (with the floor).
#[derive(Clone, Debug, PartialEq)]
pub struct GroupFit {
    pub modes: Range<usize>,
    pub sin_angle: f64,
    pub residual: f64,
}

impl GroupFit {
    /// The larger of the two deviations.
    pub fn deviation(&self) -> f64 {
        self.sin_angle.max(self.residual)
    }
}

/// The field's basis mapped onto the data's: `b ~ a r`, `r` block-diagonal over the groups and
/// orthogonal in each; `fits` per group.
#[derive(Clone, Debug)]
pub struct Alignment {
    pub r: DMatrix<f64>,
    pub fits: Vec<GroupFit>,
}

impl Alignment {
    /// The groups the map changes (turned or flipped), beyond round-off.
    pub fn changed(&self) -> Vec<Range<usize>> {
        self.fits
            .iter()
            .filter(|f| {
                let g = &f.modes;
                let block = self.r.view((g.start, g.start), (g.len(), g.len()));
                (block - DMatrix::identity(g.len(), g.len())).amax() > SUBSPACE_TOLERANCE
            })
            .map(|f| f.modes.clone())
            .collect()
    }

    /// The largest deviation of any group.
    pub fn worst(&self) -> f64 {
        self.fits
            .iter()
            .map(GroupFit::deviation)
            .fold(0.0, f64::max)
    }
}

/// Orthonormal columns spanning `m`'s columns (those of singular value above 1e-9 of the
/// largest; none for a zero matrix).
fn range(m: &DMatrix<f64>) -> DMatrix<f64> {
    let svd = m.clone().svd(true, false);
    let u = svd.u.expect("asked for u");
    let top = svd.singular_values.iter().fold(0.0f64, |a, s| a.max(*s));
    let keep: Vec<usize> = (0..svd.singular_values.len())
        .filter(|&i| top > 0.0 && svd.singular_values[i] > 1e-9 * top)
        .collect();
    DMatrix::from_fn(m.nrows(), keep.len(), |r, c| u[(r, keep[c])])
}

/// Compare the field's shapes `a` with the data's `b` (rows: components at the points; columns:
/// modes, in the same order) group by group. `Ok` holds the map and each group's fit; `Err` the
/// first group beyond [`SUBSPACE_TOLERANCE`] (a non-finite value counts as infinitely far).
pub fn align(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    groups: &[Range<usize>],
) -> Result<Alignment, GroupFit> {
    assert_eq!(a.shape(), b.shape(), "both bases at the same points");
    let n = b.ncols();
    let largest = (0..n).map(|k| b.column(k).norm()).fold(0.0f64, f64::max);
    let mut r = DMatrix::zeros(n, n);
    let mut fits = Vec::with_capacity(groups.len());
    for g in groups {
        let aa = a.columns(g.start, g.len()).into_owned();
        let bb = b.columns(g.start, g.len()).into_owned();
        if !(aa.iter().chain(bb.iter()).all(|x| x.is_finite()) && largest.is_finite()) {
            return Err(GroupFit {
                modes: g.clone(),
                sin_angle: f64::INFINITY,
                residual: f64::INFINITY,
            });
        }
        // The group's size: its largest singular value, held to the floor.
        let size = bb.clone().singular_values().amax();
        let scale = size.max(FLOOR * largest).max(f64::MIN_POSITIVE);
        // Best orthogonal map (Procrustes): a^T b = U S V^T, r = U V^T.
        let svd = (aa.transpose() * &bb).svd(true, true);
        let rg = svd.u.expect("asked for u") * svd.v_t.expect("asked for v^T");
        let residual = (&aa * &rg - &bb).norm() / scale;
        // Principal angles between the spans: cosines are the singular values of Qa^T Qb.
        let (qa, qb) = (range(&aa), range(&bb));
        let sin_angle = if qa.ncols() != qb.ncols() {
            1.0
        } else if qa.ncols() == 0 {
            0.0
        } else {
            let cos_min = (qa.transpose() * &qb).singular_values().min().min(1.0);
            (1.0 - cos_min * cos_min).max(0.0).sqrt()
        } * size
            / scale;
        let fit = GroupFit {
            modes: g.clone(),
            sin_angle,
            residual,
        };
        if fit.deviation() > SUBSPACE_TOLERANCE {
            return Err(fit);
        }
        r.view_mut((g.start, g.start), (g.len(), g.len()))
            .copy_from(&rg);
        fits.push(fit);
    }
    Ok(Alignment { r, fits })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shapes at 8 points (24 rows) of 5 modes, none parallel: a fixed pseudo-random matrix.
    fn shapes() -> DMatrix<f64> {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        DMatrix::from_fn(24, 5, |_, _| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % 2001) as f64 / 1000.0 - 1.0
        })
    }

    /// Modes 2 and 3 (0-based 1, 2) a degenerate pair; the rest apart.
    const FREQ: [f64; 5] = [10.0, 20.0, 20.0 * (1.0 + 1e-9), 30.0, 40.0];

    #[test]
    fn groups_join_close_frequencies_and_keep_correction_modes_apart() {
        assert_eq!(groups(&FREQ, 5), vec![0..1, 1..3, 3..4, 4..5]);
        // The same pair split by the eigenmode/correction boundary; the correction modes one
        // group, whatever their frequencies.
        assert_eq!(groups(&FREQ, 2), vec![0..1, 1..2, 2..5]);
        assert_eq!(groups(&FREQ, 4), vec![0..1, 1..3, 3..4, 4..5]);
        assert_eq!(
            groups(&[1.0, f64::NAN, f64::NAN, 2.0], 4),
            vec![0..1, 1..2, 2..3, 3..4]
        );
        assert!(groups(&[], 0).is_empty());
    }

    #[test]
    fn the_same_basis_aligns_to_the_identity() {
        let a = shapes();
        let al = align(&a, &a, &groups(&FREQ, 5)).unwrap();
        assert!((&al.r - DMatrix::identity(5, 5)).amax() < 1e-12);
        assert!(al.worst() < 1e-12, "{}", al.worst());
        assert!(al.changed().is_empty());
    }

    #[test]
    fn a_turned_degenerate_pair_and_a_flipped_sign_are_accepted_and_reprojected() {
        let a = shapes();
        // The data's solve: the pair turned by 30 degrees, mode 4 (0-based 3) flipped, and a
        // round-off of 1e-6 relative on every value (another machine, issue 23).
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let mut b = a.clone();
        for r in 0..a.nrows() {
            let (x, y) = (a[(r, 1)], a[(r, 2)]);
            b[(r, 1)] = c * x - s * y;
            b[(r, 2)] = s * x + c * y;
            b[(r, 3)] = -a[(r, 3)];
        }
        let mut noisy = b.clone();
        for (i, v) in noisy.iter_mut().enumerate() {
            *v *= 1.0 + 1e-6 * if i % 2 == 0 { 1.0 } else { -1.0 };
        }
        let al = align(&a, &noisy, &groups(&FREQ, 5)).unwrap();
        assert!(al.worst() < 1e-5, "{}", al.worst());
        assert_eq!(al.changed(), vec![1..3, 3..4]);
        // Re-projected, the field's shapes are the data's.
        assert!(
            (&a * &al.r - &b).amax() < 1e-5,
            "{}",
            (&a * &al.r - &b).amax()
        );
        assert!((al.r[(3, 3)] + 1.0).abs() < 1e-9);
        assert!(
            (al.r[(1, 2)] - s).abs() < 1e-5 && (al.r[(2, 1)] + s).abs() < 1e-5,
            "{}",
            al.r
        );
        // Exactly: the map is the turn and the flip.
        let al = align(&a, &b, &groups(&FREQ, 5)).unwrap();
        assert!(al.worst() < 1e-12, "{}", al.worst());
        assert!((&a * &al.r - &b).amax() < 1e-12);
    }

    #[test]
    fn another_shape_or_a_turn_across_a_gap_is_refused_naming_the_group() {
        let a = shapes();
        // Mode 5 (0-based 4) another shape: mode 1's.
        let mut b = a.clone();
        b.set_column(4, &a.column(0));
        let e = align(&a, &b, &groups(&FREQ, 5)).unwrap_err();
        assert_eq!(e.modes, 4..5);
        assert!(e.sin_angle > 0.1, "{e:?}");
        // Modes 1 and 4 (0-based 0, 3: different frequencies) mixed by 10 degrees.
        let (c, s) = (10f64.to_radians().cos(), 10f64.to_radians().sin());
        let mut b = a.clone();
        for r in 0..a.nrows() {
            let (x, y) = (a[(r, 0)], a[(r, 3)]);
            b[(r, 0)] = c * x - s * y;
            b[(r, 3)] = s * x + c * y;
        }
        let e = align(&a, &b, &groups(&FREQ, 5)).unwrap_err();
        assert_eq!(e.modes, 0..1);
        // A mode scaled by 1 % (not mass-normalised alike): same span, refused by the residual.
        let mut b = a.clone();
        b.column_mut(3).scale_mut(1.01);
        let e = align(&a, &b, &groups(&FREQ, 5)).unwrap_err();
        assert_eq!(e.modes, 3..4);
        assert!(e.sin_angle < 1e-12 && e.residual > 5e-3, "{e:?}");
        // A NaN is infinitely far.
        let mut b = a.clone();
        b[(0, 2)] = f64::NAN;
        let e = align(&a, &b, &groups(&FREQ, 5)).unwrap_err();
        assert_eq!(e.modes, 1..3);
        assert!(e.deviation().is_infinite());
    }
}
