//! The item language of `machine!`, read into a small syntax tree that keeps every token's span.
//!
//! It knows nothing about machines: `key: value` fields, `KIND { .. }` blocks and
//! `KIND NAME { .. }` items. Which kinds and keys exist is for `tree` and serde to say, so this
//! stays a generic reader. Errors inside one item's braces are recorded and reading goes on with
//! the next item, so one typo does not hide the rest.

use crate::loc::{Diag, Loc};
use proc_macro2::{Ident, Literal, TokenStream};
use syn::ext::IdentExt;
use syn::parse::{ParseStream, Parser};
use syn::{Attribute, Token, braced, bracketed, token};

/// `NAME { entries }`, with the doc comments written before the name.
pub struct Machine {
    pub docs: Vec<Attribute>,
    pub name: Ident,
    pub entries: Vec<Entry>,
}

pub enum Entry {
    /// `key: value` at the top level.
    Field(Field),
    /// `KIND { .. }` (a singleton) or `KIND NAME { .. }` (a named item).
    Block {
        kind: Ident,
        name: Option<Name>,
        body: Object,
    },
}

/// An item's name: an identifier, or a string for names that are not Rust identifiers.
pub struct Name {
    pub value: String,
    pub loc: Loc,
}

pub struct Field {
    pub key: String,
    pub key_loc: Loc,
    pub value: Value,
}

pub struct Object {
    pub fields: Vec<Field>,
    pub loc: Loc,
    /// A syntax error stopped reading this object; its fields are incomplete.
    pub broken: bool,
}

pub enum Value {
    Num(f64, Loc),
    /// Strings, bare identifiers and dotted identifiers (`unbalance.drum`).
    Str(String, Loc),
    Array(Vec<Value>, Loc),
    Object(Object),
    /// A value already reported as wrong (a non-finite number).
    Bad(Loc),
}

impl Value {
    pub fn loc(&self) -> Loc {
        match self {
            Value::Num(_, l) | Value::Str(_, l) | Value::Array(_, l) | Value::Bad(l) => *l,
            Value::Object(o) => o.loc,
        }
    }
}

/// Read a `machine!` body. Hard errors (the outer shape) end reading; errors inside an item's
/// braces and bad numbers go to `diag` and reading continues.
pub fn parse(input: TokenStream, diag: &mut Diag) -> syn::Result<Machine> {
    Parser::parse2(|s: ParseStream| machine(s, diag), input)
}

fn machine(input: ParseStream, diag: &mut Diag) -> syn::Result<Machine> {
    let docs = docs_only(input, diag)?;
    if input.is_empty() {
        return Err(input.error("expected a machine: `NAME { .. }`"));
    }
    let name: Ident = input
        .parse()
        .map_err(|e| syn::Error::new(e.span(), "expected the machine's name: `NAME { .. }`"))?;
    if !input.peek(token::Brace) {
        return Err(input.error("expected `{` after the machine's name"));
    }
    let content;
    braced!(content in input);
    let mut entries = Vec::new();
    while !content.is_empty() {
        entries.push(entry(&content, diag)?);
    }
    if !input.is_empty() {
        return Err(input.error("one machine per `machine!`: unexpected tokens after it"));
    }
    Ok(Machine {
        docs,
        name,
        entries,
    })
}

/// Outer attributes, of which only doc comments are allowed: they document the declaration.
fn docs_only(input: ParseStream, diag: &mut Diag) -> syn::Result<Vec<Attribute>> {
    let attrs = Attribute::parse_outer(input)?;
    let mut docs = Vec::new();
    for a in attrs {
        if a.path().is_ident("doc") {
            docs.push(a);
        } else {
            let span = a.pound_token.span;
            diag.push(
                Loc::range(span, a.bracket_token.span.join()),
                "only doc comments are allowed inside `machine!`",
            );
        }
    }
    Ok(docs)
}

fn entry(input: ParseStream, diag: &mut Diag) -> syn::Result<Entry> {
    docs_only(input, diag)?;
    let kind = input.call(Ident::parse_any).map_err(|e| {
        syn::Error::new(
            e.span(),
            "expected a field `key: value`, a block `KIND { .. }` or an item `KIND NAME { .. }`",
        )
    })?;
    if input.peek(Token![:]) {
        input.parse::<Token![:]>()?;
        let value = value(input, diag)?;
        if !input.is_empty() {
            input
                .parse::<Token![,]>()
                .map_err(|e| syn::Error::new(e.span(), "expected `,` after the field's value"))?;
        }
        return Ok(Entry::Field(Field {
            key: kind.unraw().to_string(),
            key_loc: Loc::new(kind.span()),
            value,
        }));
    }
    let name = if input.peek(token::Brace) {
        None
    } else if input.peek(Ident::peek_any) {
        let id = input.call(Ident::parse_any)?;
        Some(Name {
            value: id.unraw().to_string(),
            loc: Loc::new(id.span()),
        })
    } else if input.peek(syn::LitStr) {
        let s: syn::LitStr = input.parse()?;
        Some(Name {
            value: s.value(),
            loc: Loc::new(s.span()),
        })
    } else {
        return Err(input.error(format!(
            "expected `:` (a field), `{{` (a block) or a name (an item) after `{kind}`"
        )));
    };
    if !input.peek(token::Brace) {
        return Err(input.error("expected `{` and the item's fields"));
    }
    let body = object(input, diag)?;
    if input.peek(Token![,]) {
        input.parse::<Token![,]>()?;
    }
    Ok(Entry::Block { kind, name, body })
}

/// `{ key: value, .. }`. A syntax error inside is recorded, the rest of the braces skipped and
/// the object marked broken; the caller goes on after the closing brace.
fn object(input: ParseStream, diag: &mut Diag) -> syn::Result<Object> {
    let content;
    let brace = braced!(content in input);
    let mut fields = Vec::new();
    let broken = match fields_into(&content, diag, &mut fields) {
        Ok(()) => false,
        Err(e) => {
            diag.list.push(crate::loc::Diagnostic {
                loc: Loc::range(e.span(), e.span()),
                message: e.to_string(),
            });
            skip_rest(&content)?;
            true
        }
    };
    Ok(Object {
        fields,
        loc: Loc::new(brace.span.join()),
        broken,
    })
}

/// Pass an error inside nested brackets up, leaving the brackets consumed: syn reports tokens
/// left in a dropped group as an extra "unexpected token" at the very end, which would turn a
/// recoverable error in one item into a fatal one for the whole machine.
fn unwind(content: ParseStream, read: syn::Result<()>) -> syn::Result<()> {
    if read.is_err() {
        skip_rest(content)?;
    }
    read
}

fn skip_rest(input: ParseStream) -> syn::Result<()> {
    input.step(|cursor| {
        let mut rest = *cursor;
        while let Some((_, next)) = rest.token_tree() {
            rest = next;
        }
        Ok(((), rest))
    })
}

fn fields_into(input: ParseStream, diag: &mut Diag, out: &mut Vec<Field>) -> syn::Result<()> {
    while !input.is_empty() {
        docs_only(input, diag)?;
        let key = input
            .call(Ident::parse_any)
            .map_err(|e| syn::Error::new(e.span(), "expected a field name"))?;
        input.parse::<Token![:]>()?;
        let value = value(input, diag)?;
        let key_str = key.unraw().to_string();
        if out.iter().any(|f| f.key == key_str) {
            diag.push(Loc::new(key.span()), format!("duplicate field `{key_str}`"));
        } else {
            out.push(Field {
                key: key_str,
                key_loc: Loc::new(key.span()),
                value,
            });
        }
        if input.is_empty() {
            break;
        }
        input
            .parse::<Token![,]>()
            .map_err(|e| syn::Error::new(e.span(), "expected `,` between fields"))?;
    }
    Ok(())
}

fn value(input: ParseStream, diag: &mut Diag) -> syn::Result<Value> {
    if input.peek(token::Bracket) {
        let content;
        let bracket = bracketed!(content in input);
        let mut items = Vec::new();
        let read = (|| {
            while !content.is_empty() {
                items.push(value(&content, diag)?);
                if content.is_empty() {
                    break;
                }
                content.parse::<Token![,]>()?;
            }
            Ok(())
        })();
        unwind(&content, read)?;
        return Ok(Value::Array(items, Loc::new(bracket.span.join())));
    }
    if input.peek(token::Brace) {
        let content;
        let brace = braced!(content in input);
        let mut fields = Vec::new();
        let read = fields_into(&content, diag, &mut fields);
        unwind(&content, read)?;
        return Ok(Value::Object(Object {
            fields,
            loc: Loc::new(brace.span.join()),
            broken: false,
        }));
    }
    if input.peek(Token![-]) {
        let minus: Token![-] = input.parse()?;
        let lit: Literal = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), "expected a number after `-`"))?;
        let loc = Loc::range(minus.span, lit.span());
        return Ok(match number(&lit) {
            Ok(Num::Number(v)) => Value::Num(-v, loc),
            Ok(Num::Str(_)) => {
                return Err(syn::Error::new(lit.span(), "expected a number after `-`"));
            }
            Err(msg) => {
                diag.push(loc, msg);
                Value::Bad(loc)
            }
        });
    }
    if input.peek(syn::Lit) && !input.peek(syn::LitBool) {
        let lit: Literal = input.parse()?;
        let loc = Loc::new(lit.span());
        return Ok(match number(&lit) {
            Ok(Num::Number(v)) => Value::Num(v, loc),
            Ok(Num::Str(s)) => Value::Str(s, loc),
            Err(msg) => {
                diag.push(loc, msg);
                Value::Bad(loc)
            }
        });
    }
    if input.peek(Ident::peek_any) {
        let first = input.call(Ident::parse_any)?;
        let mut text = first.unraw().to_string();
        let mut end = first.span();
        while input.peek(Token![.]) && input.peek2(Ident::peek_any) {
            input.parse::<Token![.]>()?;
            let next = input.call(Ident::parse_any)?;
            text.push('.');
            text.push_str(&next.unraw().to_string());
            end = next.span();
        }
        return Ok(Value::Str(text, Loc::range(first.span(), end)));
    }
    Err(input.error("expected a value: a number, a string, a name, `[..]` or `{..}`"))
}

/// What a literal token holds.
#[derive(Debug, PartialEq)]
pub enum Num {
    Number(f64),
    Str(String),
}

/// The one literal reader: float (`0.45`, `6.8e-4`, `1f64`), integer (`4000`, `0x10`) or string.
/// A leading `-` is a separate token and the caller's business; a literal that carries its own
/// minus (from a `macro_rules!` fragment) is read here too. Non-finite and suffixed numbers
/// (other than `f64`) are errors with the message to show at the token.
pub fn number(lit: &Literal) -> Result<Num, String> {
    let text = lit.to_string();
    let (neg, unsigned) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.as_str()),
    };
    let parsed = syn::parse_str::<syn::Lit>(unsigned)
        .map_err(|_| format!("expected a number or a string, found `{text}`"))?;
    let v = match &parsed {
        syn::Lit::Float(f) => {
            suffix(f.suffix(), &text)?;
            f.base10_parse::<f64>().map_err(|e| e.to_string())?
        }
        syn::Lit::Int(i) => {
            suffix(i.suffix(), &text)?;
            i.base10_digits()
                .parse::<f64>()
                .map_err(|e| e.to_string())?
        }
        syn::Lit::Str(s) if !neg => return Ok(Num::Str(s.value())),
        _ => return Err(format!("expected a number or a string, found `{text}`")),
    };
    if !v.is_finite() {
        return Err(format!(
            "number `{text}` is out of range: it is not a finite f64"
        ));
    }
    Ok(Num::Number(if neg { -v } else { v }))
}

fn suffix(s: &str, text: &str) -> Result<(), String> {
    if s.is_empty() || s == "f64" {
        Ok(())
    } else {
        Err(format!(
            "number `{text}`: the suffix `{s}` is not allowed (numbers are f64)"
        ))
    }
}
