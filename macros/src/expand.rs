//! parse -> IR -> check -> generate, each step adding located findings; all are reported at once.

use crate::loc::{Diag, Loc, Spans};
use crate::syntax::{self, Machine};
use crate::tree::{self, Built, LISTS, SINGLETONS};
use proc_macro2::TokenStream;
use quote::quote;
use serde::de::DeserializeOwned;
use serde_json::Value;
use std::collections::HashSet;
use std::path::Path as FsPath;
use washdyn_model::codegen::generate;
use washdyn_model::ir::check::{CheckError, Path, Seg, check};
use washdyn_model::ir::{
    BoltedJoint, Cabinet, Counterweight, Elastic, FrictionDamper, Gasket, LinearDamper, Model,
    Rotor, Scene, Sensor, SpeedProfile, Spring, Tub, Unbalance, V3,
};

/// The macro: tokens in, a module (or `compile_error!`s) out. `dir` is the calling crate's
/// `CARGO_MANIFEST_DIR`.
pub fn expand(input: TokenStream, dir: &FsPath) -> TokenStream {
    match analyse(input, dir) {
        Ok((machine, model, built)) => emit(&machine, &model, &built),
        Err(diag) => diag
            .into_error()
            .map_or_else(TokenStream::new, |e| e.to_compile_error()),
    }
}

/// Everything up to a checked model, or every finding on the way.
pub fn analyse(input: TokenStream, dir: &FsPath) -> Result<(Machine, Model, Built), Diag> {
    let mut diag = Diag::default();
    let machine = match syntax::parse(input, &mut diag) {
        Ok(m) => m,
        Err(e) => {
            for e in e {
                diag.push(Loc::new(e.span()), e.to_string());
            }
            return Err(diag);
        }
    };
    let mut built = tree::build(&machine, dir, &mut diag);
    let mut model = deserialize(&built, &mut diag);
    if let Some(m) = &mut model {
        // Modal data files: the runtime's one resolver, as for the TOML loader.
        let (files, mut errors) = washdyn_model::ir::modal::resolve(
            m,
            washdyn_model::ir::files::DataFiles::AsWritten(dir),
        );
        built.files.extend(files);
        errors.extend(check(m).err().unwrap_or_default());
        for CheckError { path, message } in errors {
            let loc = built.spans.locate(&path);
            diag.at(&path, loc, with_origin(message, loc, &path, &built.spans));
        }
    }
    match model {
        Some(m) if diag.is_empty() => Ok((machine, m, built)),
        _ => {
            if diag.is_empty() {
                // Unreachable in practice: every dropped value was reported when it was dropped.
                diag.push(
                    Loc::new(machine.name.span()),
                    "the model could not be built",
                );
            }
            Err(diag)
        }
    }
}

/// `pub mod NAME { <generated> }` and one `include_bytes!` per file read.
fn emit(machine: &Machine, model: &Model, built: &Built) -> TokenStream {
    let name = &machine.name;
    let body: TokenStream = match generate(model).and_then(|src| {
        src.parse::<TokenStream>()
            .map_err(|e| format!("the generated code does not parse: {e}").into())
    }) {
        Ok(ts) => ts,
        // A refused free parameter: at its entry of `free`.
        Err(e) if !e.path.0.is_empty() => {
            let loc = built.spans.locate(&e.path);
            return loc.error(e.message).to_compile_error();
        }
        Err(e) => {
            return Loc::new(name.span())
                .error(format!("machine `{name}`: code generation failed: {e}"))
                .to_compile_error();
        }
    };
    let docs = if machine.docs.is_empty() {
        let d = format!(" The machine `{name}`, declared with `machine!`.");
        quote!(#[doc = #d])
    } else {
        let d = &machine.docs;
        quote!(#(#d)*)
    };
    let files = built.files.iter().map(|f| {
        let f = f.display().to_string();
        quote!(
            const _: &[u8] = include_bytes!(#f);
        )
    });
    quote! {
        #docs
        pub mod #name {
            #body
        }
        #(#files)*
    }
}

/// Value -> `Model`. Each section and list element is read on its own first, so a typo in one
/// spring does not hide a wrong type in a sensor; the whole model is then read to catch what
/// only it knows (unknown top-level fields, missing blocks).
fn deserialize(b: &Built, diag: &mut Diag) -> Option<Model> {
    let mut failed: HashSet<String> = HashSet::new();
    if let Value::Object(top) = &b.root {
        for (k, v) in top {
            let p = Path::default().key(k);
            let s = &b.spans;
            let ok = match k.as_str() {
                "gravity" => one::<V3>(v, &p, s, diag),
                "tub" => one::<Tub>(v, &p, s, diag),
                "cabinet" => one::<Cabinet>(v, &p, s, diag),
                "speed" => one::<SpeedProfile>(v, &p, s, diag),
                "rotors" => each::<Rotor>(v, &p, s, diag),
                "unbalances" => each::<Unbalance>(v, &p, s, diag),
                "springs" => each::<Spring>(v, &p, s, diag),
                "dampers" => each::<LinearDamper>(v, &p, s, diag),
                "friction_dampers" => each::<FrictionDamper>(v, &p, s, diag),
                "gaskets" => each::<Gasket>(v, &p, s, diag),
                "sensors" => each::<Sensor>(v, &p, s, diag),
                "scenes" => each::<Scene>(v, &p, s, diag),
                "elastic" => each::<Elastic>(v, &p, s, diag),
                "counterweights" => each::<Counterweight>(v, &p, s, diag),
                "bolted_joints" => each::<BoltedJoint>(v, &p, s, diag),
                _ => true,
            };
            if !ok {
                failed.insert(k.clone());
            }
        }
    }
    match serde_path_to_error::deserialize::<_, Model>(&b.root) {
        Ok(m) if failed.is_empty() => Some(m),
        Ok(_) => None,
        Err(e) => {
            let path = ir_path(&Path::default(), e.path());
            if tree::section(&path).is_none_or(|s| !failed.contains(s)) {
                serde_error(&path, &e.inner().to_string(), &b.spans, diag);
            }
            None
        }
    }
}

fn one<T: DeserializeOwned>(v: &Value, at: &Path, spans: &Spans, diag: &mut Diag) -> bool {
    match serde_path_to_error::deserialize::<_, T>(v) {
        Ok(_) => true,
        Err(e) => {
            serde_error(&ir_path(at, e.path()), &e.inner().to_string(), spans, diag);
            false
        }
    }
}

fn each<T: DeserializeOwned>(v: &Value, at: &Path, spans: &Spans, diag: &mut Diag) -> bool {
    match v {
        // Every element is read (no short circuit): each reports its own error.
        Value::Array(items) => {
            let failed = items
                .iter()
                .enumerate()
                .filter(|(i, it)| !one::<T>(it, &at.clone().idx(*i), spans, diag))
                .count();
            failed == 0
        }
        _ => one::<Vec<T>>(v, at, spans, diag),
    }
}

/// serde_path_to_error's path, below `at`, as the checker's `Path`.
fn ir_path(at: &Path, p: &serde_path_to_error::Path) -> Path {
    let mut out = at.clone();
    for seg in p {
        match seg {
            serde_path_to_error::Segment::Seq { index } => out.0.push(Seg::Index(*index)),
            serde_path_to_error::Segment::Map { key } => out.0.push(Seg::Key(key.clone())),
            serde_path_to_error::Segment::Enum { .. } => {}
            serde_path_to_error::Segment::Unknown => break,
        }
    }
    out
}

/// Place a serde error: an unknown field at its key, a missing field at the item (its name), a
/// wrong value at the value; and name the item in the message.
pub fn serde_error(path: &Path, msg: &str, spans: &Spans, diag: &mut Diag) {
    let (loc, about, msg) = if path.0.len() == 1 && msg.starts_with("unknown field `") {
        (
            spans.locate_key(path),
            Path::default(),
            unknown_top_field(msg),
        )
    } else if msg.starts_with("unknown field `") {
        let parent = Path(path.0[..path.0.len().saturating_sub(1)].to_vec());
        (spans.locate_key(path), parent, with_suggestion(msg))
    } else if let Some(rest) = msg.strip_prefix("missing field `") {
        let field = rest.trim_end_matches('`');
        let msg = if path.0.is_empty() && SINGLETONS.contains(&field) {
            format!("missing block `{field} {{ .. }}`")
        } else {
            msg.to_string()
        };
        (spans.locate(path), path.clone(), msg)
    } else if let Some(rest) = msg.strip_prefix("unknown variant ") {
        let what = match path.0.last() {
            Some(Seg::Key(k)) if k == "body" || k == "a" || k == "b" => "body",
            Some(Seg::Key(k)) if k == "kind" => "sensor kind",
            _ => "value",
        };
        (
            spans.locate(path),
            path.clone(),
            format!("unknown {what} {rest}"),
        )
    } else {
        (spans.locate(path), path.clone(), msg.to_string())
    };
    let (what, rel) = spans.describe(&about);
    let prefix = if rel.0.is_empty() {
        what
    } else {
        format!("{what}, `{rel}`")
    };
    diag.at(
        path,
        loc,
        with_origin(format!("{prefix}: {msg}"), loc, path, spans),
    );
}

/// At the top level serde would offer the IR's lists (`springs`), which are written as items
/// here: name what can be written instead.
fn unknown_top_field(msg: &str) -> String {
    let typo = msg.split('`').nth(1).unwrap_or_default();
    let fields = ["gravity", "base"];
    let kinds = SINGLETONS.iter().chain(LISTS.iter().map(|l| &l.0)).copied();
    let mut out = format!(
        "unknown field `{typo}`; top-level fields are `gravity` and `base`, blocks and items \
         are written `KIND {{ .. }}` / `KIND NAME {{ .. }}`"
    );
    if let Some(s) = crate::suggest::closest(typo, fields.into_iter().chain(kinds)) {
        out.push_str(&format!("; did you mean `{s}`?"));
    }
    out
}

/// serde lists the expected fields in backticks; suggest the closest to the unknown one.
fn with_suggestion(msg: &str) -> String {
    let words: Vec<&str> = msg.split('`').skip(1).step_by(2).collect();
    match words.split_first() {
        Some((typo, known)) => match crate::suggest::closest(typo, known.iter().copied()) {
            Some(s) => format!("{msg}; did you mean `{s}`?"),
            None => msg.to_string(),
        },
        None => msg.to_string(),
    }
}

/// A finding about something inherited from the base file says so: its span is the `base`
/// literal or the redeclared item's name, not the value itself.
fn with_origin(msg: String, loc: Loc, path: &Path, spans: &Spans) -> String {
    if !loc.from_base {
        return msg;
    }
    match spans.describe(path).1 {
        rel if rel.0.is_empty() => format!("{msg} (from the base model)"),
        rel => format!("{msg} (`{rel}` is from the base model)"),
    }
}

/// For tests: the findings of a declaration, in order.
#[cfg(test)]
pub fn findings(src: &str, dir: &FsPath) -> Vec<crate::loc::Diagnostic> {
    match analyse(src.parse().expect("test input tokenizes"), dir) {
        Ok(_) => Vec::new(),
        Err(d) => d.list,
    }
}
