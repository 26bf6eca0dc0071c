//! Parameters by their path in the model: what a study varies and what a model marks as free.
//! One syntax for the study file, the model's `free` list and the error messages:
//! `springs.front_left.stiffness`, `friction_dampers.left.f_max`, `unbalances.test_mass.position.2`,
//! `elastic.cabinet.damping`, or by index `springs[0].stiffness`. A list entry is picked by its
//! `name`; a path must end at a number. Paths are resolved on the IR's serde form (the field
//! names of the TOML file), so every number of the model is reachable without a table of them.

use super::Model;
use super::check::{Path, Seg};
use serde_json::Value;

/// A parameter path that names a number of a given model: its text and its index form.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Param {
    pub text: String,
    pub path: Path,
}

/// Why a path names no number of the model.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("parameter `{path}`: {message}")]
pub struct ParamError {
    pub path: String,
    pub message: String,
}

fn err(path: &str, message: impl Into<String>) -> ParamError {
    ParamError {
        path: path.to_string(),
        message: message.into(),
    }
}

/// Split `a.b[2].c` into its words and indices.
fn tokens(text: &str) -> Result<Vec<Seg>, ParamError> {
    let mut out = Vec::new();
    for word in text.split('.') {
        let (head, mut rest) = match word.find('[') {
            Some(i) => (&word[..i], &word[i..]),
            None => (word, ""),
        };
        if head.is_empty() && (out.is_empty() || rest.is_empty()) {
            return Err(err(text, "empty step"));
        }
        if !head.is_empty() {
            out.push(match head.parse::<usize>() {
                Ok(i) => Seg::Index(i),
                Err(_) => Seg::Key(head.to_string()),
            });
        }
        while !rest.is_empty() {
            let close = rest.find(']').ok_or_else(|| err(text, "`[` without `]`"))?;
            let i = rest[1..close]
                .parse::<usize>()
                .map_err(|_| err(text, format!("`{}` is not an index", &rest[..=close])))?;
            out.push(Seg::Index(i));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(err(text, format!("unexpected `{rest}`")));
            }
        }
    }
    Ok(out)
}

/// The model's serde form without its modal data: those are a file's numbers (megabytes of
/// them), not parameters, and converting them made every check of a model with free
/// parameters slow (the modal-input mutation sweep, 3219 checks, ran out of its time).
fn value(model: &Model) -> Value {
    let mut m = model.clone();
    for e in &mut m.elastic {
        e.data = None;
        e.bare_data = None;
    }
    serde_json::to_value(&m).expect("the IR serialises")
}

/// The names a list's entries go by, for an error message.
fn names(list: &[Value]) -> String {
    let n: Vec<&str> = list
        .iter()
        .filter_map(|v| v.get("name").and_then(Value::as_str))
        .collect();
    if n.is_empty() {
        format!("indices 0..{}", list.len())
    } else {
        n.join(", ")
    }
}

/// Resolve `text` on `model` to the index path of a number.
pub fn resolve(model: &Model, text: &str) -> Result<Param, ParamError> {
    resolve_in(&value(model), text)
}

/// [`resolve`] for several paths, converting the model once.
pub fn resolve_all(model: &Model, texts: &[String]) -> Vec<Result<Param, ParamError>> {
    let root = value(model);
    texts.iter().map(|t| resolve_in(&root, t)).collect()
}

fn resolve_in(root: &Value, text: &str) -> Result<Param, ParamError> {
    let mut v = root;
    let mut path = Path::default();
    for seg in tokens(text.trim())? {
        match (v, seg) {
            (Value::Object(map), Seg::Key(k)) => {
                v = map.get(&k).ok_or_else(|| {
                    let keys: Vec<&String> = map.keys().collect();
                    err(
                        text,
                        format!(
                            "no field `{k}` here (fields: {})",
                            keys.iter()
                                .map(|s| s.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    )
                })?;
                path = path.key(&k);
            }
            (Value::Array(list), Seg::Key(k)) => {
                let i = list
                    .iter()
                    .position(|e| e.get("name").and_then(Value::as_str) == Some(k.as_str()))
                    .ok_or_else(|| {
                        err(
                            text,
                            format!("no entry named `{k}` (entries: {})", names(list)),
                        )
                    })?;
                v = &list[i];
                path = path.idx(i);
            }
            (Value::Array(list), Seg::Index(i)) => {
                v = list.get(i).ok_or_else(|| {
                    err(
                        text,
                        format!("index {i} out of range ({} entries)", list.len()),
                    )
                })?;
                path = path.idx(i);
            }
            (Value::Object(_), Seg::Index(i)) => {
                return Err(err(text, format!("index {i} applied to a table")));
            }
            (other, s) => {
                let what = match s {
                    Seg::Key(k) => k,
                    Seg::Index(i) => i.to_string(),
                };
                return Err(err(text, format!("`{what}` applied to {}", kind(other))));
            }
        }
    }
    if !v.is_number() {
        return Err(err(text, format!("names {}, not a number", kind(v))));
    }
    Ok(Param {
        text: text.trim().to_string(),
        path,
    })
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "an absent value",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a text",
        Value::Array(_) => "a list",
        Value::Object(_) => "a table",
    }
}

fn at<'v>(v: &'v mut Value, path: &Path) -> Option<&'v mut Value> {
    path.0.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.get_mut(k.as_str()),
        Seg::Index(i) => v.get_mut(*i),
    })
}

/// The number at a resolved parameter.
pub fn get(model: &Model, p: &Param) -> f64 {
    let mut root = value(model);
    at(&mut root, &p.path)
        .and_then(|v| v.as_f64())
        .expect("a resolved parameter names a number")
}

/// The numbers at resolved parameters, or which one `model` lacks.
pub fn get_all(model: &Model, params: &[Param]) -> Result<Vec<f64>, ParamError> {
    let mut root = value(model);
    params
        .iter()
        .map(|p| {
            at(&mut root, &p.path)
                .and_then(|v| v.as_f64())
                .ok_or_else(|| err(&p.text, "does not name a number of this model"))
        })
        .collect()
}

/// The first place where two JSON values differ, as a path.
fn first_difference(a: &Value, b: &Value, path: Path) -> Option<Path> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, va) in x {
                match y.get(k) {
                    Some(vb) => {
                        if let Some(p) = first_difference(va, vb, path.clone().key(k)) {
                            return Some(p);
                        }
                    }
                    None => return Some(path.key(k)),
                }
            }
            y.keys()
                .find(|k| !x.contains_key(*k))
                .map(|k| path.clone().key(k))
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (va, vb))| first_difference(va, vb, path.clone().idx(i))),
        _ if a == b => None,
        _ => Some(path),
    }
}

/// The values of `base`'s free parameters in `variant`, provided the two models differ in
/// nothing else: what lets code generated for `base` run `variant`. The error names the first
/// number or field that differs and is not free.
pub fn free_values(base: &Model, variant: &Model) -> Result<Vec<f64>, String> {
    let params = base
        .free
        .iter()
        .map(|t| resolve(base, t))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let values = get_all(variant, &params).map_err(|e| e.to_string())?;
    let reset = set(
        variant,
        &params,
        &get_all(base, &params).map_err(|e| e.to_string())?,
    )
    .map_err(|e| e.to_string())?;
    let (mut a, mut b) = (value(base), value(&reset));
    // Neither the free list nor where a modal or curves file was read from is the model's
    // content (the files' data are, and are compared).
    for v in [&mut a, &mut b] {
        if let Value::Object(m) = v {
            m.remove("free");
            if let Some(Value::Array(bodies)) = m.get_mut("elastic") {
                for e in bodies.iter_mut().filter_map(Value::as_object_mut) {
                    e.remove("file");
                    e.remove("bare");
                    e.remove("curves");
                }
            }
        }
    }
    let data = (0..base.elastic.len().min(reset.elastic.len())).find_map(|i| {
        let (x, y) = (&base.elastic[i], &reset.elastic[i]);
        let p = Path::default().key("elastic").idx(i);
        if x.data != y.data {
            Some(p.key("data"))
        } else if x.bare_data != y.bare_data {
            Some(p.key("bare_data"))
        } else {
            None
        }
    });
    match first_difference(&a, &b, Path::default()).or(data) {
        None => Ok(values),
        Some(p) => Err(format!(
            "the variant differs from the generated model `{}` at `{p}`, which is not one of \
             its free parameters ({}): run it with the interpreter",
            base.name,
            if base.free.is_empty() {
                "it has none".to_string()
            } else {
                base.free.join(", ")
            }
        )),
    }
}

/// The model with `values[k]` at `params[k]`. Values must be finite (JSON has no NaN); the
/// checker then judges the new model as any other.
pub fn set(model: &Model, params: &[Param], values: &[f64]) -> Result<Model, ParamError> {
    let mut root = value(model);
    for (p, &x) in params.iter().zip(values) {
        let n = serde_json::Number::from_f64(x)
            .ok_or_else(|| err(&p.text, format!("value {x} is not a finite number")))?;
        let slot = at(&mut root, &p.path)
            .ok_or_else(|| err(&p.text, "does not name a number of this model"))?;
        if !slot.is_number() {
            return Err(err(&p.text, "does not name a number of this model"));
        }
        *slot = Value::Number(n);
    }
    let mut out: Model = serde_json::from_value(root).map_err(|e| {
        let text: Vec<&str> = params.iter().map(|p| p.text.as_str()).collect();
        err(
            &text.join(", "),
            format!("the model does not take these values: {e}"),
        )
    })?;
    for (e, o) in out.elastic.iter_mut().zip(&model.elastic) {
        e.data = o.data.clone();
        e.bare_data = o.bare_data.clone();
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> Model {
        crate::ir::toml_file::load_unresolved(
            include_str!("../../../models/data/reference.toml"),
            "reference.toml",
            crate::ir::files::DataFiles::Embedded(&[]),
        )
        .expect("reference model parses")
    }

    #[test]
    fn names_and_indices_reach_the_same_number() {
        let m = model();
        let named = resolve(&m, "springs.spring_rear_right.stiffness").unwrap();
        let indexed = resolve(&m, "springs[1].stiffness").unwrap();
        assert_eq!(named.path, indexed.path);
        assert_eq!(named.path.to_string(), "springs[1].stiffness");
        assert_eq!(get(&m, &named), m.springs[1].stiffness);
        let u = resolve(&m, "unbalances.test_mass.position.2").unwrap();
        assert_eq!(get(&m, &u), 0.69);
        let f = resolve(&m, "friction_dampers.damper_front_left.f_max").unwrap();
        assert_eq!(get(&m, &f), m.friction_dampers[0].f_max);
    }

    #[test]
    fn set_changes_only_the_named_number() {
        let m = model();
        let p = resolve(&m, "springs[1].stiffness").unwrap();
        let v = set(&m, std::slice::from_ref(&p), &[1234.5]).unwrap();
        assert_eq!(v.springs[1].stiffness, 1234.5);
        let mut back = v.clone();
        back.springs[1].stiffness = m.springs[1].stiffness;
        assert_eq!(back, m);
    }

    #[test]
    fn free_values_accept_free_changes_only() {
        let mut m = model();
        m.free = vec!["springs.spring_front.stiffness".into()];
        let p = resolve(&m, &m.free[0]).unwrap();
        let v = set(&m, std::slice::from_ref(&p), &[3000.0]).unwrap();
        assert_eq!(free_values(&m, &v), Ok(vec![3000.0]));
        let mut w = v.clone();
        w.springs[1].stiffness = 1.0;
        let e = free_values(&m, &w).unwrap_err();
        assert!(e.contains("at `springs[1].stiffness`"), "{e}");
        w = v.clone();
        w.sensors.pop();
        let e = free_values(&m, &w).unwrap_err();
        assert!(e.contains("at `sensors`"), "{e}");
    }

    #[test]
    fn bad_paths_say_why() {
        let m = model();
        for (path, says) in [
            (
                "springs.nosuch.stiffness",
                "entries: spring_rear_left, spring_rear_right",
            ),
            ("springs[99].stiffness", "out of range"),
            ("springs[0].stiff", "no field `stiff`"),
            ("springs[0]", "a table, not a number"),
            ("name", "a text, not a number"),
            ("springs..stiffness", "empty step"),
            ("springs[x].stiffness", "not an index"),
        ] {
            let e = resolve(&m, path).unwrap_err().to_string();
            assert!(e.contains(says) && e.contains(path), "{path}: {e}");
        }
        let p = resolve(&m, "springs[0].stiffness").unwrap();
        let e = set(&m, &[p], &[f64::NAN]).unwrap_err().to_string();
        assert!(e.contains("not a finite number"), "{e}");
    }
}
