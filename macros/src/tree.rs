//! Syntax tree -> the IR's JSON shape (`serde_json::Value`), with every path's tokens recorded.
//!
//! This is where the item language meets the IR: `spring NAME { .. }` becomes an element of
//! `springs` with `name` set, `tub { .. }` the `tub` table. A variant starts from its base file's
//! model instead of an empty one and merges the declarations into it.

use crate::loc::{Diag, Loc, Spans};
use crate::syntax::{Entry, Field, Machine, Name, Object, Value as Syn};
use serde_json::{Map, Number, Value};
use std::collections::HashSet;
use std::path::{Path as FsPath, PathBuf};
use washdyn_model::ir::check::{Path, Seg};
use washdyn_model::ir::toml_file::{Located, load_file, read_speed_csv};

/// Named item kinds: keyword, IR list, and how messages call one.
pub const LISTS: &[(&str, &str, &str)] = &[
    ("rotor", "rotors", "rotor"),
    ("unbalance", "unbalances", "unbalance"),
    ("spring", "springs", "spring"),
    ("damper", "dampers", "damper"),
    ("friction_damper", "friction_dampers", "friction damper"),
    ("gasket", "gaskets", "gasket"),
    ("contact", "contacts", "contact"),
    ("counterweight", "counterweights", "counterweight"),
    ("bolted_joint", "bolted_joints", "bolted joint"),
    ("sensor", "sensors", "sensor"),
    ("scene", "scenes", "scene"),
    ("elastic", "elastic", "elastic body"),
];

/// Blocks without a name, one per machine.
pub const SINGLETONS: &[&str] = &["tub", "cabinet", "speed"];

/// The IR as JSON, where each part came from, and the files read to build it.
pub struct Built {
    pub root: Value,
    pub spans: Spans,
    /// Absolute paths of every file read, for `include_bytes!` (cargo then rebuilds on change).
    pub files: Vec<PathBuf>,
}

/// Build the IR value for `m`; `dir` resolves relative file names (the calling crate's
/// `CARGO_MANIFEST_DIR`). Problems go to `diag`; the result is still as complete as possible.
pub fn build(m: &Machine, dir: &FsPath, diag: &mut Diag) -> Built {
    let mut b = Built {
        root: Value::Object(Map::new()),
        spans: Spans::default(),
        files: Vec::new(),
    };
    let root = Path::default();
    let name_loc = Loc::new(m.name.span());
    let model_name = m.name.to_string();

    // A variant: the base model first, everything declared then applies on top of it.
    let mut from_base: HashSet<Path> = HashSet::new();
    for e in &m.entries {
        if let Entry::Field(f) = e
            && f.key == "base"
        {
            load_base(f, dir, &mut b, &mut from_base, diag);
        }
    }

    b.spans.set(&root, name_loc);
    b.spans.set_item(&root, format!("machine `{model_name}`"));
    b.spans.set(&root.clone().key("name"), name_loc);
    obj(&mut b.root).insert("name".into(), Value::String(model_name));

    let mut singletons: HashSet<String> = HashSet::new();
    for e in &m.entries {
        let Entry::Block { kind, name, body } = e else {
            if let Entry::Field(f) = e {
                top_field(f, &mut b, diag);
            }
            continue;
        };
        let k = kind.to_string();
        let kloc = Loc::new(kind.span());
        if SINGLETONS.contains(&k.as_str()) {
            if let Some(n) = name {
                // Still read the block: the intent is clear and a "missing block" would mislead.
                diag.push(
                    n.loc,
                    format!("`{k}` is a single block and takes no name: `{k} {{ .. }}`"),
                );
            }
            if singletons.insert(k.clone()) {
                singleton(&k, kloc, body, &mut b, diag);
            } else {
                diag.push(kloc, format!("duplicate `{k}` block"));
            }
        } else if let Some(&(_, list, what)) = LISTS.iter().find(|l| l.0 == k) {
            match name {
                Some(n) => named(&k, list, what, n, body, &mut b, &mut from_base, diag),
                None => diag.push(kloc, format!("`{k}` needs a name: `{k} NAME {{ .. }}`")),
            }
        } else {
            diag.push(kloc, unknown_kind(&k));
        }
    }
    resolve_files(&mut b, dir, diag);
    b
}

/// `tub { .. }`, `cabinet { .. }`, `speed { .. }`: fields into that table (merged into the base's).
fn singleton(k: &str, kloc: Loc, body: &Object, b: &mut Built, diag: &mut Diag) {
    let path = Path::default().key(k);
    let slot = obj(&mut b.root).entry(k.to_string()).or_insert(Value::Null);
    if b.spans.get(&path).is_some_and(|l| l.from_base) {
        // What the redeclaration leaves as it was now points at the block's keyword.
        record(slot, &path, kloc.as_base(), &mut b.spans);
    }
    // A speed profile is a table or a file: giving one replaces both.
    if k == "speed"
        && let Value::Object(old) = slot
        && body
            .fields
            .iter()
            .any(|f| f.key == "table" || f.key == "csv")
    {
        old.remove("table");
        old.remove("csv");
        b.spans.clear_below(&path);
    }
    put_object(slot, &path, body, &mut b.spans, diag);
    b.spans.set(&path, kloc);
    b.spans.set_item(&path, k.to_string());
    if body.broken {
        diag.poison(path);
    }
}

/// `KIND NAME { .. }`: a new element of the kind's list, or, in a variant, changes to the base's
/// item of that name (once: a name declared twice reaches the checker as a duplicate).
#[allow(clippy::too_many_arguments)]
fn named(
    k: &str,
    list: &str,
    what: &str,
    name: &Name,
    body: &Object,
    b: &mut Built,
    from_base: &mut HashSet<Path>,
    diag: &mut Diag,
) {
    if let Some(f) = body.fields.iter().find(|f| f.key == "name") {
        diag.push(
            f.key_loc,
            format!("the {what}'s name is the one before the braces: `{k} NAME {{ .. }}`"),
        );
        return;
    }
    let list_path = Path::default().key(list);
    let items = obj(&mut b.root)
        .entry(list.to_string())
        .or_insert_with(|| Value::Array(Vec::new()));
    let Value::Array(items) = items else {
        unreachable!("lists are arrays")
    };
    let found = items.iter().enumerate().position(|(i, it)| {
        from_base.contains(&list_path.clone().idx(i))
            && it.get("name").and_then(Value::as_str) == Some(name.value.as_str())
    });
    let i = match found {
        Some(i) => {
            let p = list_path.clone().idx(i);
            from_base.remove(&p);
            // What the redeclaration leaves as it was now points at its name.
            record(&items[i], &p, name.loc.as_base(), &mut b.spans);
            i
        }
        None => {
            let mut fresh = Map::new();
            fresh.insert("name".into(), Value::String(name.value.clone()));
            items.push(Value::Object(fresh));
            items.len() - 1
        }
    };
    let path = list_path.idx(i);
    put_object(&mut items[i], &path, body, &mut b.spans, diag);
    b.spans.set(&path, name.loc);
    b.spans.set(&path.clone().key("name"), name.loc);
    b.spans.set_item(&path, format!("{what} `{}`", name.value));
    if body.broken {
        diag.poison(path);
    }
}

fn unknown_kind(k: &str) -> String {
    let known: Vec<&str> = SINGLETONS
        .iter()
        .copied()
        .chain(LISTS.iter().map(|l| l.0))
        .collect();
    let mut msg = format!("unknown block `{k}`; expected one of: {}", known.join(", "));
    if let Some(s) = crate::suggest::closest(k, known.iter().copied()) {
        msg.push_str(&format!("; did you mean `{s}`?"));
    }
    msg
}

fn top_field(f: &Field, b: &mut Built, diag: &mut Diag) {
    let k = f.key.as_str();
    let hint = match k {
        "base" => return, // read before everything else
        "name" => Some("the machine's name is the identifier before the braces".to_string()),
        _ if SINGLETONS.contains(&k) => Some(format!("write `{k}` as a block: `{k} {{ .. }}`")),
        _ => LISTS
            .iter()
            .find(|l| l.1 == k)
            .map(|l| format!("declare {k} one by one as items: `{} NAME {{ .. }}`", l.0)),
    };
    if let Some(h) = hint {
        diag.push(f.key_loc, h);
        return;
    }
    let path = Path::default().key(k);
    b.spans.set_key(&path, f.key_loc);
    let slot = obj(&mut b.root).entry(k.to_string()).or_insert(Value::Null);
    put(slot, &path, &f.value, &mut b.spans, diag);
}

/// Write `v` at `path` into `target`: objects merge field by field (so a variant can change one
/// coordinate of an attachment), everything else replaces what was there.
fn put(target: &mut Value, path: &Path, v: &Syn, spans: &mut Spans, diag: &mut Diag) {
    match v {
        Syn::Object(o) => put_object(target, path, o, spans, diag),
        Syn::Array(items, loc) => {
            spans.clear_below(path);
            spans.set(path, *loc);
            let mut arr = vec![Value::Null; items.len()];
            for (i, (slot, it)) in arr.iter_mut().zip(items).enumerate() {
                put(slot, &path.clone().idx(i), it, spans, diag);
            }
            *target = Value::Array(arr);
        }
        Syn::Num(x, loc) => {
            spans.clear_below(path);
            spans.set(path, *loc);
            // Whole non-negative numbers as integers, so counts (`modes: 20`) read as usize;
            // serde reads an integer into an f64 field as well.
            *target = if *x >= 0.0 && x.fract() == 0.0 && *x < 9.0e15 {
                Value::Number(Number::from(*x as u64))
            } else {
                Number::from_f64(*x).map_or(Value::Null, Value::Number)
            };
        }
        Syn::Str(s, loc) => {
            spans.clear_below(path);
            spans.set(path, *loc);
            *target = Value::String(s.clone());
        }
        Syn::Bad(loc) => {
            spans.clear_below(path);
            spans.set(path, *loc);
            *target = Value::Null;
            diag.poison(path.clone());
        }
    }
}

fn put_object(target: &mut Value, path: &Path, o: &Object, spans: &mut Spans, diag: &mut Diag) {
    if !target.is_object() {
        spans.clear_below(path);
        *target = Value::Object(Map::new());
    }
    spans.set(path, o.loc);
    for f in &o.fields {
        let p = path.clone().key(&f.key);
        spans.set_key(&p, f.key_loc);
        let slot = obj(target).entry(f.key.clone()).or_insert(Value::Null);
        put(slot, &p, &f.value, spans, diag);
    }
}

fn obj(v: &mut Value) -> &mut Map<String, Value> {
    if !v.is_object() {
        *v = Value::Object(Map::new());
    }
    match v {
        Value::Object(m) => m,
        _ => unreachable!(),
    }
}

/// `base: "file.toml"`: load and check the base model with the TOML front end and make it the
/// starting point. Every part of it points at the `base` literal until redeclared.
fn load_base(
    f: &Field,
    dir: &FsPath,
    b: &mut Built,
    from_base: &mut HashSet<Path>,
    diag: &mut Diag,
) {
    let Syn::Str(rel, loc) = &f.value else {
        diag.push(
            f.value.loc(),
            "`base` is the path of a model file, as a string: `base: \"data/reference.toml\"`",
        );
        diag.poison(Path::default());
        return;
    };
    let file = dir.join(rel);
    let model = match load_file(&file) {
        Ok(m) => m,
        Err(e) => {
            for l in e.errors {
                diag.push(*loc, format!("base model: {}", located(rel, &l)));
            }
            // Whatever else is wrong follows from the missing base.
            diag.poison(Path::default());
            return;
        }
    };
    b.files.push(file.clone());
    // The base's data files are relative to the base file; here they resolve against `dir`.
    let mut model = model;
    let rel_dir = std::path::Path::new(rel)
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default();
    for e in &mut model.elastic {
        e.file = normalise(&rel_dir.join(&e.file));
        for f in [&mut e.bare, &mut e.curves].into_iter().flatten() {
            *f = normalise(&rel_dir.join(&*f));
        }
    }
    if let Some(csv) = &model.speed.csv {
        let base_dir = file.parent().map(PathBuf::from).unwrap_or_default();
        b.files.push(base_dir.join(csv));
    }
    let value = match serde_json::to_value(&model) {
        Ok(v) => v,
        Err(e) => {
            diag.push(*loc, format!("base model: {e}"));
            diag.poison(Path::default());
            return;
        }
    };
    let base_loc = loc.as_base();
    record(&value, &Path::default(), base_loc, &mut b.spans);
    if let Value::Object(top) = &value {
        for &(_, list, what) in LISTS {
            if let Some(Value::Array(items)) = top.get(list) {
                for (i, it) in items.iter().enumerate() {
                    let p = Path::default().key(list).idx(i);
                    let name = it.get("name").and_then(Value::as_str).unwrap_or("?");
                    b.spans.set_item(&p, format!("{what} `{name}`"));
                    from_base.insert(p);
                }
            }
        }
        for s in SINGLETONS {
            b.spans.set_item(&Path::default().key(s), s.to_string());
        }
    }
    b.root = value;
}

/// `data/../fe/x` -> `fe/x` (lexically; the path need not exist).
fn normalise(p: &std::path::Path) -> String {
    let mut out: Vec<&std::ffi::OsStr> = Vec::new();
    for c in p.components() {
        match c {
            std::path::Component::ParentDir if out.last().is_some_and(|l| *l != "..") => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            c => out.push(c.as_os_str()),
        }
    }
    out.iter()
        .map(|c| c.to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// Point every path of `v` at `loc`.
fn record(v: &Value, path: &Path, loc: Loc, spans: &mut Spans) {
    spans.set(path, loc);
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                record(x, &path.clone().key(k), loc, spans);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                record(x, &path.clone().idx(i), loc, spans);
            }
        }
        _ => {}
    }
}

/// A loader finding, naming the file as the user wrote it.
fn located(rel: &str, l: &Located) -> String {
    if l.line == 0 {
        format!("{rel}: {}", l.message)
    } else {
        format!("{rel}:{}:{}: {}", l.line, l.column, l.message)
    }
}

/// Data files named in the declaration: the speed CSV is read into `table` (as the TOML front
/// end does). Modal data files are read after deserialisation by the runtime's resolver (one for
/// both front ends). Names from a base file were resolved by its loader already.
fn resolve_files(b: &mut Built, dir: &FsPath, diag: &mut Diag) {
    let speed = Path::default().key("speed");
    let csv_path = speed.clone().key("csv");
    let table_path = speed.clone().key("table");
    let declared = |b: &Built, p: &Path| b.spans.get(p).is_some_and(|l| !l.from_base);
    if declared(b, &csv_path)
        && let Some(Value::String(csv)) = b.root.pointer("/speed/csv").cloned()
    {
        let loc = b.spans.locate(&csv_path);
        if declared(b, &table_path) {
            diag.push(loc, "speed: give either `table` or `csv`, not both");
            diag.poison(speed);
        } else {
            let file = dir.join(&csv);
            match read_speed_csv(&file) {
                Ok(rows) => {
                    let table = rows
                        .iter()
                        .map(|r| {
                            Value::Array(
                                r.iter()
                                    .map(|x| {
                                        Number::from_f64(*x).map_or(Value::Null, Value::Number)
                                    })
                                    .collect(),
                            )
                        })
                        .collect();
                    if let Some(Value::Object(s)) = b.root.get_mut("speed") {
                        s.insert("table".into(), Value::Array(table));
                    }
                    b.spans.clear_below(&table_path);
                    b.spans.set(&table_path, loc);
                    b.files.push(file);
                }
                Err(l) => {
                    diag.push(loc, format!("speed profile: {}", located(&csv, &l)));
                    diag.poison(speed);
                }
            }
        }
    }
}

/// The first key of a path, if any (which IR section it is in).
pub fn section(p: &Path) -> Option<&str> {
    match p.0.first() {
        Some(Seg::Key(k)) => Some(k),
        _ => None,
    }
}
