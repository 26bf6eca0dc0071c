//! The Pareto front of a study: the variants no other variant beats in every output at once
//! (e.g. smaller tub displacement and smaller cabinet acceleration), which are the only ones
//! worth a designer's choice between competing outputs.

/// Whether smaller or larger values of an output are better.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    /// Smaller is better (displacements, accelerations, forces).
    Minimise,
    /// Larger is better (margins, clearances).
    Maximise,
}

/// Whether variant `a` dominates `b`: at least as good in every output and better in one.
/// Any NaN output makes the answer `false` (a failed variant neither dominates nor is dominated).
pub fn dominates(a: &[f64], b: &[f64], senses: &[Sense]) -> bool {
    let mut better = false;
    for ((&x, &y), s) in a.iter().zip(b).zip(senses) {
        let (x, y) = match s {
            Sense::Minimise => (x, y),
            Sense::Maximise => (-x, -y),
        };
        if x.is_nan() || y.is_nan() || x > y {
            return false;
        }
        better |= x < y;
    }
    better
}

/// Indices of the non-dominated variants, ascending. `outputs[k]` holds variant k's outputs, one
/// per entry of `senses`.
/// - A variant with a NaN output failed: it is never on the front and removes no other variant.
/// - Exact ties: equal variants do not dominate each other, so all of them are on the front or
///   none (the ids tell a designer they are alternatives).
/// - Infinite outputs are values like any other (worst or best in their output).
///
/// Order-independent: permuting the variants permutes the front the same way. Sorting first
/// makes it O(n log n + n f) for n variants and a front of f.
///
/// # Panics
/// If a variant has not one output per sense.
pub fn front<P: AsRef<[f64]>>(outputs: &[P], senses: &[Sense]) -> Vec<usize> {
    let m = senses.len();
    for (k, o) in outputs.iter().enumerate() {
        assert_eq!(o.as_ref().len(), m, "variant {k}: one output per sense");
    }
    // Oriented to minimise every output; -0.0 made +0.0 so the sort puts every dominator first.
    let key = |k: usize, j: usize| {
        let v = outputs[k].as_ref()[j];
        let v = if senses[j] == Sense::Maximise { -v } else { v };
        v + 0.0
    };
    let mut order: Vec<usize> = (0..outputs.len())
        .filter(|&k| outputs[k].as_ref().iter().all(|v| !v.is_nan()))
        .collect();
    // Lexicographic: whatever dominates a variant comes before it. Stable, so ties keep their
    // input order (the result is sorted at the end anyway).
    order.sort_by(|&p, &q| {
        (0..m)
            .map(|j| key(p, j).total_cmp(&key(q, j)))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    // A variant beaten by an earlier one that is off the front is beaten by that one's own
    // dominator on the front (transitivity): checking the front so far is enough.
    let mut on_front: Vec<usize> = Vec::new();
    for k in order {
        let beaten = on_front
            .iter()
            .any(|&f| dominates(outputs[f].as_ref(), outputs[k].as_ref(), senses));
        if !beaten {
            on_front.push(k);
        }
    }
    on_front.sort_unstable();
    on_front
}
