//! Unit tests over proc_macro2 token streams (no compiler involved): the literal reader, and that
//! every kind of finding lands on the token a user needs to see.

use crate::expand::{analyse, findings};
use crate::loc::{Diag, Diagnostic, Loc};
use crate::syntax::{self, Num, number};
use crate::tree;
use proc_macro2::{Literal, TokenStream};
use std::path::{Path as FsPath, PathBuf};
use washdyn_model::ir::check::Path;

fn lit(src: &str) -> Literal {
    let ts: TokenStream = src.parse().unwrap();
    match ts.into_iter().next() {
        Some(proc_macro2::TokenTree::Literal(l)) => l,
        other => panic!("not a literal: {other:?}"),
    }
}

#[test]
fn literal_reader_takes_floats_ints_and_strings() {
    assert_eq!(number(&lit("0.45")), Ok(Num::Number(0.45)));
    assert_eq!(number(&lit("6.8e-4")), Ok(Num::Number(6.8e-4)));
    assert_eq!(number(&lit("1_000.5")), Ok(Num::Number(1000.5)));
    assert_eq!(number(&lit("4000")), Ok(Num::Number(4000.0)));
    assert_eq!(number(&lit("0x10")), Ok(Num::Number(16.0)));
    assert_eq!(number(&lit("2f64")), Ok(Num::Number(2.0)));
    assert_eq!(number(&lit("\"tub\"")), Ok(Num::Str("tub".into())));
    // A literal that carries its own minus (as macro_rules! fragments can).
    assert_eq!(
        number(&Literal::f64_unsuffixed(-1.5)),
        Ok(Num::Number(-1.5))
    );
    assert_eq!(number(&Literal::i64_unsuffixed(-3)), Ok(Num::Number(-3.0)));
}

#[test]
fn literal_reader_rejects_what_is_not_a_finite_f64() {
    let e = number(&lit("1e999")).unwrap_err();
    assert!(e.contains("not a finite f64"), "{e}");
    let e = number(&lit("3u8")).unwrap_err();
    assert!(e.contains("suffix `u8`"), "{e}");
    let e = number(&lit("2.0f32")).unwrap_err();
    assert!(e.contains("suffix `f32`"), "{e}");
    assert!(number(&lit("'c'")).is_err());
    assert!(number(&lit("b\"x\"")).is_err());
}

#[test]
fn minus_is_a_separate_token_and_part_of_the_value_span() {
    let src = "m { gravity: [0.0, 0.0, -9.81], }";
    let mut diag = Diag::default();
    let m = syntax::parse(src.parse().unwrap(), &mut diag).unwrap();
    assert!(diag.is_empty());
    let syntax::Entry::Field(f) = &m.entries[0] else {
        panic!("a field")
    };
    let syntax::Value::Array(items, _) = &f.value else {
        panic!("an array")
    };
    let syntax::Value::Num(v, loc) = &items[2] else {
        panic!("a number")
    };
    assert_eq!(*v, -9.81);
    assert_eq!(at(loc), (1, src.find("-9.81").unwrap()));
    assert_eq!(loc.end.start().column, src.find("9.81").unwrap());
}

/// 1-based line and 0-based column of a location's first token.
fn at(loc: &Loc) -> (usize, usize) {
    let lc = loc.start.start();
    (lc.line, lc.column)
}

/// Where `needle` (its `nth` occurrence) starts in `src`, as (line, column).
fn pos(src: &str, needle: &str, nth: usize) -> (usize, usize) {
    let off = src
        .match_indices(needle)
        .nth(nth)
        .unwrap_or_else(|| panic!("`{needle}` #{nth} in source"))
        .0;
    let before = &src[..off];
    let line = before.matches('\n').count() + 1;
    let col = off - before.rfind('\n').map_or(0, |p| p + 1);
    (line, col)
}

fn only(d: Vec<Diagnostic>) -> Diagnostic {
    assert_eq!(d.len(), 1, "{d:#?}");
    d.into_iter().next().unwrap()
}

const TUB: &str = "tub { mass: 1.0, cog: [0.0, 0.0, 0.5], inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }
    speed { table: [[0.0, 0.0], [1.0, 100.0]] }";

fn machine(items: &str) -> String {
    format!("m {{\n    {TUB}\n{items}\n}}")
}

fn spring(name: &str, stiffness: &str) -> String {
    format!(
        "    spring {name} {{ a: {{ body: tub, point: [0.0, 0.0, 0.6] }}, b: {{ body: cabinet, point: [0.0, 0.0, 0.8] }}, stiffness: {stiffness}, free_length: 0.1 }}\n"
    )
}

fn here() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_valid_machine_fills_the_ir() {
    let src = machine(
        &(spring("front", "100.0")
            + "    sensor s1 { body: tub, point: [0.3, 0.0, 0.7], kind: acceleration }"),
    );
    let (_, model, _) =
        analyse(src.parse().unwrap(), &here()).unwrap_or_else(|d| panic!("{:#?}", d.list));
    assert_eq!(model.name, "m");
    assert_eq!(model.springs[0].name, "front");
    assert_eq!(model.springs[0].stiffness, 100.0);
    assert_eq!(
        model.sensors[0].kind,
        washdyn_model::ir::SensorKind::Acceleration
    );
    assert_eq!(model.speed.table, vec![[0.0, 0.0], [1.0, 100.0]]);
}

#[test]
fn checker_paths_map_to_the_value_token() {
    // springs[1].stiffness
    let src = machine(&(spring("front", "100.0") + &spring("rear", "-5.0")));
    let d = only(findings(&src, &here()));
    assert_eq!(at(&d.loc), pos(&src, "-5.0", 0));
    assert!(
        d.message
            .contains("spring `rear`: stiffness must be positive"),
        "{}",
        d.message
    );
}

#[test]
fn a_path_deeper_than_any_token_maps_to_the_deepest_prefix() {
    // speed.table[2] exists; the checker names the row, which is one bracket group.
    let src = "m { tub { mass: 1.0, cog: [0.0, 0.0, 0.5], inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }\n speed { table: [[0.0, 0.0], [5.0, 1.0], [4.0, 1.0]] } }";
    let d = only(findings(src, &here()));
    assert_eq!(at(&d.loc), pos(src, "[4.0", 0));

    // And a path below a recorded one (a matrix entry) falls back to the matrix.
    let mut diag = Diag::default();
    let m = syntax::parse(src.parse().unwrap(), &mut diag).unwrap();
    let b = tree::build(&m, &here(), &mut diag);
    let entry = Path::default()
        .key("tub")
        .key("inertia")
        .idx(1)
        .idx(2)
        .key("nothing");
    assert_eq!(at(&b.spans.locate(&entry)), pos(src, "0.0]", 1));
    let missing = Path::default().key("cabinet").key("nothing");
    assert_eq!(at(&b.spans.locate(&missing)), pos(src, "m {", 0));
}

#[test]
fn serde_errors_land_on_key_item_or_value() {
    // Unknown field: the key.
    let src = machine("    rotor drum { axis_point: [0.0, 0.0, 0.5], polar_inertai: 0.5 }");
    let d = findings(&src, &here());
    let unknown = d
        .iter()
        .find(|d| d.message.contains("unknown field"))
        .unwrap();
    assert_eq!(at(&unknown.loc), pos(&src, "polar_inertai", 0));
    assert!(
        unknown.message.contains("did you mean `polar_inertia`?"),
        "{}",
        unknown.message
    );

    // Missing field: the item's name.
    let src = machine("    rotor drum { axis_point: [0.0, 0.0, 0.5] }");
    let d = only(findings(&src, &here()));
    assert_eq!(at(&d.loc), pos(&src, "drum", 0));
    assert_eq!(d.message, "rotor `drum`: missing field `polar_inertia`");

    // Wrong type: the value.
    let src = machine("    rotor drum { axis_point: [0.0, 0.0, 0.5], polar_inertia: heavy }");
    let d = only(findings(&src, &here()));
    assert_eq!(at(&d.loc), pos(&src, "heavy", 0));
    assert!(
        d.message
            .starts_with("rotor `drum`, `polar_inertia`: invalid type"),
        "{}",
        d.message
    );
}

#[test]
fn every_broken_item_is_reported_and_broken_values_do_not_cascade() {
    let src = machine(
        "    rotor drum { axis_point: [0.0, 0.0, 0.5], polar_inertia: 1e999 }
    sensor s { body: drumm, point: [0.0, 0.0, 0.0], kind: acceleration }
    spring x { a: { body: tub point: [0.0, 0.0, 0.6] } }
    damper y { damping: 1.0 }",
    );
    let d = findings(&src, &here());
    let msgs: Vec<&str> = d.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(d.len(), 4, "{msgs:#?}");
    assert!(msgs[0].contains("not a finite f64"));
    // The syntax error inside spring x does not also report its missing fields.
    assert!(msgs.iter().any(|m| m.contains("expected `,`")));
    assert!(
        msgs.iter()
            .any(|m| m.contains("sensor `s`, `body`: unknown body `drumm`"))
    );
    assert!(msgs.iter().any(|m| m == &"damper `y`: missing field `a`"));
}

#[test]
fn a_variant_merges_into_its_base_and_inherited_paths_point_at_base() {
    let src = "compact {
        base: \"../models/data/reference.toml\",
        rotor drum { polar_inertia: 0.33 }
        spring spring_front { a: { point: [0.12, 0.0, 0.60] } }
        spring extra { a: { body: tub, point: [0.0, 0.0, 0.6] }, b: { body: cabinet, point: [0.0, 0.0, 0.8] }, stiffness: 1.0, free_length: 0.2 }
        scene elastic { effects: [unbalance.drum] }
        scene elastic_rigid_tub { effects: [unbalance.drum] }
        scene elastic_fine { effects: [unbalance.drum] }
        scene panel_curves { effects: [unbalance.drum] }
        scene cabinet_counterweights { effects: [unbalance.drum] }
    }";
    let (_, model, built) =
        analyse(src.parse().unwrap(), &here()).unwrap_or_else(|d| panic!("{:#?}", d.list));
    assert_eq!(model.name, "compact");
    let drum = model.rotors.iter().find(|r| r.name == "drum").unwrap();
    assert_eq!((drum.polar_inertia, drum.ratio), (0.33, 1.0));
    let front = model
        .springs
        .iter()
        .find(|s| s.name == "spring_front")
        .unwrap();
    // Deep merge: the point changed, the body stayed.
    assert_eq!(front.a.point, [0.12, 0.0, 0.60]);
    assert_eq!(front.a.body, washdyn_model::ir::BodyRef::Tub);
    assert_eq!(model.springs.len(), 4);
    assert!(built.files.iter().any(|f| f.ends_with("reference.toml")));

    let base_lit = pos(src, "\"../models", 0);
    // An item not redeclared: the base literal.
    let tub1 = built
        .spans
        .locate(&Path::default().key("sensors").idx(0).key("point"));
    assert!(tub1.from_base);
    assert_eq!(at(&tub1), base_lit);
    // A redeclared item's untouched field: its name, still marked as inherited.
    let ratio = built
        .spans
        .locate(&Path::default().key("rotors").idx(0).key("ratio"));
    assert!(ratio.from_base);
    assert_eq!(at(&ratio), pos(src, "drum", 0));
    // A redeclared field: its token.
    let pi = built
        .spans
        .locate(&Path::default().key("rotors").idx(0).key("polar_inertia"));
    assert!(!pi.from_base);
    assert_eq!(at(&pi), pos(src, "0.33", 0));
}

#[test]
fn base_file_problems_point_at_the_literal() {
    let src = "v { base: \"no/such.toml\" }";
    let d = only(findings(src, &here()));
    assert_eq!(at(&d.loc), pos(src, "\"no/such", 0));
    assert!(
        d.message
            .starts_with("base model: no/such.toml: cannot read"),
        "{}",
        d.message
    );
}

/// A scratch directory of its own per test (tests run in parallel).
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("washdyn-macros-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_speed_csv_is_read_relative_to_the_manifest_dir() {
    let dir = scratch("csv");
    std::fs::write(dir.join("run.csv"), "time_s, rpm\n0, 0\n2, 50\n1, 60\n").unwrap();
    let src = "m { tub { mass: 1.0, cog: [0.0, 0.0, 0.5], inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }\n speed { csv: \"run.csv\" } }";
    // The rows are read into `table`; the checker's complaint about row 2 lands on the file name.
    let d = only(findings(src, &dir));
    assert_eq!(at(&d.loc), pos(src, "\"run.csv\"", 0));
    assert!(d.message.contains("row 2"), "{}", d.message);

    std::fs::write(dir.join("run.csv"), "0, 0\n2, 50\n").unwrap();
    let (_, model, built) =
        analyse(src.parse().unwrap(), &dir).unwrap_or_else(|d| panic!("{:#?}", d.list));
    assert_eq!(model.speed.table, vec![[0.0, 0.0], [2.0, 50.0]]);
    assert_eq!(model.speed.csv.as_deref(), Some("run.csv"));
    assert_eq!(built.files, vec![dir.join("run.csv")]);

    std::fs::write(dir.join("run.csv"), "0, 0\n2, x\n").unwrap();
    let d = only(findings(src, &dir));
    assert!(
        d.message
            .starts_with("speed profile: run.csv:2:1: not a number"),
        "{}",
        d.message
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn table_and_csv_together_are_refused() {
    let src = "m { tub { mass: 1.0, cog: [0.0, 0.0, 0.5], inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }\n speed { table: [[0.0, 0.0]], csv: \"x.csv\" } }";
    let d = only(findings(src, FsPath::new("/nonexistent")));
    assert_eq!(at(&d.loc), pos(src, "\"x.csv\"", 0));
}

#[test]
fn syntax_errors_inside_an_item_do_not_stop_the_next_item() {
    let src = machine(
        "    rotor a { axis_point: [0.0, 0.0, 0.5], polar_inertia: }\n    rotor b { axis_point: [0.0, 0.0, 0.5], polar_inertia: 0.1, ratio: 0.0 }",
    );
    let d = findings(&src, &here());
    // The broken item stops the model from being built, so the checker (ratio) waits; but the
    // syntax error is where it is.
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(at(&d[0].loc), pos(&src, "}", 2));
}

#[test]
fn names_and_kinds_are_validated() {
    let src = machine("    spring { }\n    tub { }\n    rotr r { }");
    let d = findings(&src, &here());
    let msgs: Vec<&str> = d.iter().map(|d| d.message.as_str()).collect();
    assert!(
        msgs.contains(&"`spring` needs a name: `spring NAME { .. }`"),
        "{msgs:#?}"
    );
    assert!(msgs.contains(&"duplicate `tub` block"), "{msgs:#?}");
    assert!(
        msgs.iter().any(|m| m.contains("did you mean `rotor`?")),
        "{msgs:#?}"
    );
}

#[test]
fn an_elastic_entry_takes_support_and_stiffness_damping() {
    // The committed cabinet data with its feet as support springs (the stiffness its modes
    // were computed with, reference-machine.md: 2e5 N/m vertical, 5e4 horizontal), so the
    // strain energy shares stay within [0, 1].
    let dir = scratch("support");
    let committed = here().join("../models/fe/cabinet.modal.toml");
    let mut d = washdyn_model::ir::modal::read_file(&committed, "cabinet.modal.toml").unwrap();
    d.support_springs = (1..=4)
        .map(|k| washdyn_model::ir::modal::SupportSpring {
            point: format!("FOOT_{k}"),
            stiffness: [5e4, 5e4, 2e5],
        })
        .collect();
    std::fs::write(dir.join("cab.modal.toml"), d.to_toml()).unwrap();
    let entry = |keys: &str| {
        machine(&format!(
            "    elastic cabinet {{ file: \"cab.modal.toml\", damping: 0.02, {keys} }}"
        ))
    };
    let src = entry("support_damping: 0.06, stiffness_damping: 2e-4");
    let (_, model, _) =
        analyse(src.parse().unwrap(), &dir).unwrap_or_else(|d| panic!("{:#?}", d.list));
    assert_eq!(model.elastic[0].support_damping, Some(0.06));
    assert_eq!(model.elastic[0].stiffness_damping, 2e-4);
    // Out of range: the checker's finding lands on the value.
    let src = entry("support_damping: 1.5");
    let f = only(findings(&src, &dir));
    assert_eq!(at(&f.loc), pos(&src, "1.5", 0));
    assert!(f.message.contains("support_damping"), "{}", f.message);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gasket_loss_factor_one_number_or_six_and_a_wrong_count_at_its_token() {
    use washdyn_model::ir::LossFactor;
    let k = "[[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0, 1.0]]";
    let gasket = |eta: &str| {
        machine(&format!(
            "    gasket g {{ a: tub, b: cabinet, point: [0.3, 0.0, 0.5], stiffness: {k}, loss_factor: {eta} }}"
        ))
    };
    // No `damping`: it defaults to zero.
    let (_, model, _) = analyse(gasket("0.2").parse().unwrap(), &here())
        .unwrap_or_else(|d| panic!("{:#?}", d.list));
    assert_eq!(model.gaskets[0].loss_factor, Some(LossFactor::Uniform(0.2)));
    assert_eq!(model.gaskets[0].damping, [[0.0; 6]; 6]);
    let six = "[0.1, 0.2, 0.2, 0.3, 0.3, 0.3]";
    let (_, model, _) =
        analyse(gasket(six).parse().unwrap(), &here()).unwrap_or_else(|d| panic!("{:#?}", d.list));
    assert_eq!(
        model.gaskets[0]
            .loss_factor
            .as_ref()
            .unwrap()
            .per_direction(),
        [0.1, 0.2, 0.2, 0.3, 0.3, 0.3]
    );
    let src = gasket("[0.1, 0.2]");
    let d = only(findings(&src, &here()));
    assert_eq!(at(&d.loc), pos(&src, "[0.1, 0.2]", 0));
    assert!(d.message.contains("one number or 6"), "{}", d.message);
    let src = gasket("[0.1, 0.2, 0.2, -0.3, 0.3, 0.3]");
    let d = only(findings(&src, &here()));
    assert_eq!(at(&d.loc), pos(&src, "-0.3", 0));
    assert!(
        d.message
            .contains("gasket `g`: loss_factor must not be negative"),
        "{}",
        d.message
    );
}
