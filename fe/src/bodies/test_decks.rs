//! Decks with closed-form answers, to check the FE chain (deck writer, ccx, import).

use crate::deck::Deck;

/// A cantilever of B32 beams along x, clamped at x = 0: length `l`, square section of side `a`,
/// steel (E 210 GPa, nu 0.3, rho 7850), `n` elements, `modes` eigenmodes. Euler-Bernoulli:
/// f_i = (beta_i l)^2 / (2 pi l^2) sqrt(E I / (rho A)), beta l = 1.8751, 4.6941, 7.8548.
pub fn cantilever(l: f64, a: f64, n: usize, modes: usize) -> Deck {
    let mut d = Deck::new(&format!("cantilever, {n} B32 elements"));
    let nodes: Vec<(usize, [f64; 3])> = (0..=2 * n)
        .map(|i| (i + 1, [l * i as f64 / (2 * n) as f64, 0.0, 0.0]))
        .collect();
    d.nodes(Some("NALL"), &nodes);
    let elems: Vec<(usize, Vec<usize>)> = (0..n)
        .map(|e| (e + 1, vec![2 * e + 1, 2 * e + 2, 2 * e + 3]))
        .collect();
    d.elements("B32", "EALL", &elems)
        .nset("CLAMP", &[1])
        .nset("TIP", &[2 * n + 1])
        .line("*BOUNDARY")
        .line("CLAMP, 1, 6")
        .material("STEEL", 210e9, 0.3, 7850.0)
        .line("*BEAM SECTION, ELSET=EALL, MATERIAL=STEEL, SECTION=RECT")
        .line(&format!("{a}, {a}"))
        .line("0, 0, 1")
        .line("*STEP")
        .line("*FREQUENCY")
        .line(&modes.to_string())
        .line("*NODE FILE, OUTPUT=2D")
        .line("U")
        .line("*END STEP");
    d
}
