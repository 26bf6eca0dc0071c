//! Where things are: token ranges, the map from IR paths to them, and the error list.
//!
//! The checker speaks in IR paths (`springs[1].stiffness`); this module turns a path into the
//! tokens a user wrote, the way the TOML front end turns it into a file line.

use proc_macro2::{Punct, Spacing, Span, TokenStream};
use quote::{ToTokens, TokenStreamExt};
use std::collections::HashMap;
use std::fmt::Display;
use washdyn_model::ir::check::Path;

/// A range of tokens: `start` and `end` are the first and last token's spans (stable proc_macro
/// cannot join spans, but rustc underlines from one to the other when an error carries both).
#[derive(Clone, Copy, Debug)]
pub struct Loc {
    pub start: Span,
    pub end: Span,
    /// Stands for something inherited from a variant's base file (the span is the `base`
    /// literal, or the name of the redeclared item).
    pub from_base: bool,
    /// Creation order, which follows the source as the parser reads it: findings are sorted by
    /// it so they read top to bottom whatever step found them.
    pub order: usize,
}

thread_local! {
    static NEXT: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

impl Loc {
    pub fn new(span: Span) -> Loc {
        Loc::range(span, span)
    }

    pub fn range(start: Span, end: Span) -> Loc {
        Loc {
            start,
            end,
            from_base: false,
            order: NEXT.with(|n| n.replace(n.get() + 1)),
        }
    }

    /// The same place, marked as standing for something read from the base file.
    pub fn as_base(self) -> Loc {
        Loc {
            from_base: true,
            ..self
        }
    }

    pub fn error(self, message: impl Display) -> syn::Error {
        syn::Error::new_spanned(self, message)
    }
}

impl ToTokens for Loc {
    /// Two placeholder tokens carrying the start and end spans; `syn::Error::new_spanned` reads
    /// only their spans.
    fn to_tokens(&self, tokens: &mut TokenStream) {
        for span in [self.start, self.end] {
            let mut p = Punct::new('#', Spacing::Alone);
            p.set_span(span);
            tokens.append(p);
        }
    }
}

/// One finding, located. Kept apart from `syn::Error` so tests can read the location.
#[derive(Clone, Debug)]
pub struct Diagnostic {
    pub loc: Loc,
    pub message: String,
}

/// Collected findings, and the paths whose values are already known to be broken: a later
/// error at or below such a path is a consequence, not news, and is dropped.
#[derive(Default, Debug)]
pub struct Diag {
    pub list: Vec<Diagnostic>,
    poisoned: Vec<Path>,
}

impl Diag {
    pub fn push(&mut self, loc: Loc, message: impl Into<String>) {
        self.list.push(Diagnostic {
            loc,
            message: message.into(),
        });
    }

    /// Report at `path` unless an earlier finding already covers it.
    pub fn at(&mut self, path: &Path, loc: Loc, message: impl Into<String>) {
        if !self.is_poisoned(path) {
            self.push(loc, message);
        }
    }

    pub fn poison(&mut self, path: Path) {
        self.poisoned.push(path);
    }

    pub fn is_poisoned(&self, path: &Path) -> bool {
        self.poisoned.iter().any(|p| path.0.starts_with(&p.0))
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// All findings as one `syn::Error` (rustc prints each), in source order.
    pub fn into_error(mut self) -> Option<syn::Error> {
        self.list.sort_by_key(|d| d.loc.order);
        self.list
            .into_iter()
            .map(|d| d.loc.error(d.message))
            .reduce(|mut a, b| {
                a.combine(b);
                a
            })
    }
}

/// IR path -> tokens. `values` holds each value's tokens (an item's path holds its name token),
/// `keys` each field's key token (for "unknown field"), `items` what to call the item at a path
/// in messages (``spring `spring_front` ``).
#[derive(Default, Debug)]
pub struct Spans {
    values: HashMap<Path, Loc>,
    keys: HashMap<Path, Loc>,
    items: HashMap<Path, String>,
}

impl Spans {
    pub fn set(&mut self, path: &Path, loc: Loc) {
        self.values.insert(path.clone(), loc);
    }

    pub fn set_key(&mut self, path: &Path, loc: Loc) {
        self.keys.insert(path.clone(), loc);
    }

    pub fn set_item(&mut self, path: &Path, what: String) {
        self.items.insert(path.clone(), what);
    }

    /// Forget everything strictly below `path` (its value is being replaced wholesale).
    pub fn clear_below(&mut self, path: &Path) {
        let below = |p: &Path| p.0.len() > path.0.len() && p.0.starts_with(&path.0);
        self.values.retain(|p, _| !below(p));
        self.keys.retain(|p, _| !below(p));
    }

    /// The value's own location, if recorded.
    pub fn get(&self, path: &Path) -> Option<Loc> {
        self.values.get(path).copied()
    }

    /// The tokens of the deepest recorded prefix of `path`: a missing field points at its item,
    /// a matrix entry at the matrix. The root is always recorded (the model name).
    pub fn locate(&self, path: &Path) -> Loc {
        (0..=path.0.len())
            .rev()
            .find_map(|n| self.values.get(&Path(path.0[..n].to_vec())))
            .copied()
            .unwrap_or_else(|| Loc::new(Span::call_site()))
    }

    /// The key token of the field at `path`, else its value's location.
    pub fn locate_key(&self, path: &Path) -> Loc {
        self.keys
            .get(path)
            .copied()
            .unwrap_or_else(|| self.locate(path))
    }

    /// How messages name the item holding `path`, and the rest of the path below that item.
    pub fn describe(&self, path: &Path) -> (String, Path) {
        for n in (0..=path.0.len()).rev() {
            if let Some(what) = self.items.get(&Path(path.0[..n].to_vec())) {
                return (what.clone(), Path(path.0[n..].to_vec()));
            }
        }
        ("machine".to_string(), path.clone())
    }
}
