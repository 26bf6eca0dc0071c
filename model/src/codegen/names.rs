//! The names generated code gives a scene's type and its state inputs.

/// `rigid_low_speed` -> `RigidLowSpeed`.
pub fn type_name(scene: &str) -> String {
    let mut out = String::new();
    for part in scene.split(['_', '-']).filter(|p| !p.is_empty()) {
        let mut c = part.chars();
        if let Some(f) = c.next() {
            out.extend(f.to_uppercase());
            out.push_str(c.as_str());
        }
    }
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "Scene");
    }
    out
}

/// q and q' as the generated functions name them, then `extra` (the drive).
pub(super) fn state_inputs(n: usize, extra: &[&str]) -> Vec<String> {
    (0..n)
        .map(|i| format!("q[{i}]"))
        .chain((0..n).map(|i| format!("qd[{i}]")))
        .chain(extra.iter().map(|s| s.to_string()))
        .collect()
}

/// `state_inputs` followed by the element states z.
pub(super) fn with_states(mut names: Vec<String>, nz: usize) -> Vec<String> {
    names.extend((0..nz).map(|i| format!("z[{i}]")));
    names
}
